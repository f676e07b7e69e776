#pragma once
// One moment of a log, as the paper's Fig. 8 shows it (section 4): the newest Radar Map, the
// newest reading of every sonar (real, hypothetical, classified), both Accumulative Grid Maps,
// the Current Sensor Map and the Sector Map, each as it was at that moment, plus the truth.
//
// Time is message time (each message's utime), not the log's event timestamps: in a log
// recorded live by lcm-logger those are receive times, while the messages refer to each other
// by their own utime. A log is read in two passes: scanLog() finds its time span and channels,
// then a SnapshotCollector is fed the events in log order and asked for the moment(s) wanted;
// it keeps only a short history, so a log of any length renders in bounded memory.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sector_map_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_ring_t.hpp>

#include "core/geometry.hpp"
#include "lcmio/eventlog.hpp"
#include "sim/world_geometry.hpp"

namespace lasonic::render {

// The channels a Fig. 8 picture is made of, in the order they are listed to the user.
const std::vector<std::string>& drawnChannels();

struct LogInfo {
  std::string path;
  int64_t events = 0;
  int64_t start_utime = 0;  // [us] earliest message time on a drawn channel
  int64_t end_utime = 0;    // [us] latest
  std::map<std::string, int64_t> messages;     // drawn channel -> messages that decoded
  std::map<std::string, int64_t> undecodable;  // drawn channel -> events that did not decode
                                               // (or carried a time <= 0)
  // The SECTOR_MAP with the most sectors the sonar decided (its own value, a copy, or the
  // navigator's memory): the moment the laser alone would have shown least of what is there.
  // Ties go to the earliest; most_sonar_sectors is -1 when the log has no SECTOR_MAP.
  int64_t most_sonar_utime = 0;
  int most_sonar_sectors = -1;
  bool has(const std::string& channel) const { return messages.count(channel) > 0; }
  bool empty() const { return messages.empty(); }
  double durationS() const { return static_cast<double>(end_utime - start_utime) * 1e-6; }
  int64_t undecodableTotal() const;
};

// First pass over a log. Throws LogError if the file cannot be opened.
LogInfo scanLog(const std::string& path);

// One sonar reading, drawn as a beam from the sensor's pose (global = odometry frame).
struct SonarBeam {
  int sensor_id = -1;
  int64_t utime = 0;     // [us] firing time
  geom::Pose2 pose;      // sensor pose at firing; may be non-finite in a bad message
  double beam_width = 0; // [rad] full opening
  double range = 0;      // [m] real range (SONAR_RING, SONAR_COMPLEMENT) or hypothetical one
  bool echo = true;      // SONAR_RING: false when nothing came back (range = range_max)
  int cls = -1;          // SONAR_COMPLEMENT: complement_reading_t::CLASS_*; else -1
  double hypothetical = 0;  // SONAR_COMPLEMENT: the hypothetical range it was compared with
};

struct Snapshot {
  int64_t utime = 0;    // [us] the moment shown
  double t_s = 0;       // [s] from the log's start
  double duration_s = 0;
  std::string log_name;
  std::set<std::string> in_log;  // drawn channels the whole log holds

  std::optional<geom::Pose2> robot;  // odometry frame at utime (ODOMETRY, else a map's pose)
  double robot_radius = 0.35;        // [m] from the Sector Map if there is one

  std::optional<line_map_t> radar_map, agm_lines, current_sensor_map;
  std::optional<grid_map_t> agm_operational, agm_tactical;
  // The navigator's maps are in its own frame (the odometry corrected by scan matching): AGM_LINES
  // and CURRENT_SENSOR_MAP are moved into the odometry frame here, through their robot_pose and
  // the odometry at their time; AGM_TACTICAL's grid is drawn through this (odometry frame <-
  // navigator frame), empty when the frames agree or the odometry is unknown.
  std::optional<geom::Pose2> agm_tactical_frame;
  std::optional<sector_map_t> sector_map;
  // Newest reading of every sensor within the sonar window before utime.
  std::vector<SonarBeam> hypothesis, sonar, complement;
  double hypothesis_limit = 2.20;   // [m] SONAR_HYPOTHESIS range_limit
  double complement_tolerance = 0;  // [m] SONAR_COMPLEMENT tolerance
  int sonar_unplaced = 0;           // SONAR_RING readings without a pose to draw them at

  // Truth (SIM_STATE): the robot's true pose and the movers (true frame), if the log has it.
  std::optional<geom::Pose2> true_robot;
  std::vector<sim::MoverPose> movers;

  // Odometry frame <- true frame at utime (odometry pose ∘ true pose⁻¹), when both are known:
  // places the scenario's obstacles where the pipeline's maps (odometry frame) see them, as
  // lasonic-eval does for the AGM.
  std::optional<geom::Pose2> odomFromTrue() const;
};

class SnapshotCollector {
 public:
  struct Options {
    // A sensor's reading older than this (message time) is not part of "the current scan":
    // a full ring fires in 0.18 s (6 groups, 30 ms), so 1 s leaves out only dead sensors.
    double sonar_window_s = 1.0;
  };
  SnapshotCollector();
  explicit SnapshotCollector(Options opts);

  // One event of the log, in log order (message times may interleave a little in a live log).
  // Returns the message time of a message taken; nullopt for other channels (ignored) and for
  // events on a drawn channel that do not decode or carry a time <= 0 (counted in rejected()).
  std::optional<int64_t> add(const LogRecord& r);

  // The moment utime: for each channel the newest message at or before it (however old).
  Snapshot at(int64_t utime) const;

  // Drops history older than before_utime, but keeps every channel's newest message before it.
  void forget(int64_t before_utime);

  int64_t rejected() const { return rejected_; }

 private:
  template <typename T>
  struct Track {
    std::deque<T> items;  // ordered by utime
    void insert(T m);
    const T* newestAtOrBefore(int64_t utime) const;
    void forget(int64_t before);
  };
  std::optional<geom::Pose2> odometryAt(int64_t utime) const;

  Options opts_;
  Track<odometry_t> odometry_;
  Track<sim_state_t> sim_state_;
  Track<line_map_t> radar_map_, agm_lines_, csm_;
  Track<grid_map_t> agm_op_, agm_tac_;
  Track<sector_map_t> sector_map_;
  Track<sonar_ring_t> sonar_;
  Track<hypothetical_scan_t> hypothesis_;
  Track<complement_t> complement_;
  int64_t rejected_ = 0;
};

}  // namespace lasonic::render
