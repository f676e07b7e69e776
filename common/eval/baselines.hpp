#pragma once
// Baseline mappers scored on the same log as lasonic (README "Evaluation", baselines): each
// runs on the log's raw channels (ODOMETRY, LASER_SCAN, SONAR_RING; poses from ODOMETRY), is
// read out by the pilot's own SectorMap (same parameters) at the times of the pilot's
// SECTOR_MAP messages, and is scored against the same truth samples:
// - sonar_himm:   Borenstein & Koren's HIMM, sonar only (baselines/himm.hpp);
// - naive_fusion: every echo into the pilot's operational AGM, no complement extraction, plus
//                 the laser (baselines/naive_fusion.hpp);
// - log_odds:     an Elfes-style grid, cone model, laser and sonar, free space cleared, plus the
//                 laser points (baselines/log_odds.hpp).
// - laser_only:   the newest scan alone, moved into the current pose (what a laser-only robot
//                 would report; the pilot's own laser part also moves people on, see
//                 operational/mover_prediction.hpp).
#include <functional>
#include <optional>
#include <vector>

#include "baselines/himm.hpp"
#include "baselines/log_odds.hpp"
#include "baselines/naive_fusion.hpp"
#include "complement/complement.hpp"
#include "complement/radar_map.hpp"
#include "core/config.hpp"
#include "core/pose_history.hpp"
#include "eval/evaluate.hpp"
#include "eval/observability.hpp"
#include "operational/sector_map.hpp"

namespace lasonic::eval {

// The log's raw sensor channels (ODOMETRY, LASER_SCAN, SONAR_RING) handed out in time order, as
// the pipeline's stages would see them: a scan at the time of its last reading (when it is
// complete), odometry first at equal times, poses kept in a PoseHistory, scans and firing
// groups validated by the complement's message layer and dropped when not newer than the
// previous one. Used by the baselines and by the MRPT peer (procs/mrpt_peer).
class RawChannelReplay {
 public:
  explicit RawChannelReplay(const RunLog& log);
  struct Handlers {
    // A usable scan: the message, its parsed readings, each reading placed in the odometry frame
    // with the pose at its own time (gaps invalid), and the time of its last reading.
    std::function<void(const laser_scan_t&, const complement::LaserScan&, const std::vector<complement::ScanPoint>&,
                       int64_t newest)>
        laser;
    // A firing group: the message, its parsed readings, the robot's pose at the firing time.
    std::function<void(const sonar_ring_t&, const complement::SonarGroup&, const std::optional<geom::Pose2>&)> sonar;
  };
  // Hands out every event up to and including utime that has not been handed out yet.
  void advanceTo(int64_t utime, const Handlers& h);
  const PoseHistory& poses() const { return poses_; }
  double speed() const { return speed_; }  // [m/s] newest ODOMETRY.v

 private:
  struct Event {
    int64_t t;
    int kind;  // 0 odometry, 1 laser, 2 sonar
    size_t i;
  };
  const RunLog* log_;
  std::vector<Event> events_;
  size_t next_ = 0;
  PoseHistory poses_;
  double speed_ = 0;
  std::optional<int64_t> last_scan_, last_ring_;
};

// The scored maps of a truth table (indices into it) in time order.
std::vector<size_t> mapsInTimeOrder(const RunLog& log, const SectorTruthTable& truth);

struct BaselinesConfig {
  bool enabled = true;
  SectorMapParams readout;           // the pilot's sector map (pilot section)
  baselines::NaiveFusionParams naive_fusion;  // the pilot's AGM and placement (pilot section)
  baselines::HimmParams himm;
  baselines::LogOddsParams log_odds;
};
// Reads the `pilot:` and `baselines:` sections of a configuration file's root. Throws
// ConfigError naming the key path.
BaselinesConfig baselinesConfig(const Config& root);

// Writes baselines.<name>.sector_map.* for sonar_himm, naive_fusion and log_odds.
void evalBaselines(const RunLog& log, const SectorTruthTable& truth, const BaselinesConfig& cfg,
                   const EvalOptions& o, Metrics& m);

}  // namespace lasonic::eval
