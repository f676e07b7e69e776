#pragma once
// The sector map's truth, sample by sample, and whether any sensor could have reported it
// (README "Evaluation", sector map): so that a score can tell physics from method.
//
// A scored sample is one sector of one SECTOR_MAP. Its truth is the nearest true surface point
// inside the sector (static obstacles and the movers at the map's time). A sample whose truth
// lies within sector_range of the robot's boundary is *observable* when the laser saw that point
// (the newest scan completed at or before the map's time returned from its obstacle within
// seen_radius of it, eval/laser_seen.hpp; without LASER_TRUTH: its material reflects the laser),
// or when a DIRECT sonar echo (SONAR_TRUTH, cause DIRECT) located that same obstacle within
// observe_radius of the point at or before the map's time (the echo's hit point, true world
// frame; a mover's echo counts where the mover was then).
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

#include "core/geometry.hpp"
#include "eval/evaluate.hpp"
#include "eval/metrics.hpp"
#include "sim/world_geometry.hpp"

namespace lasonic::eval {

// The nearest true surface point inside one sector.
struct SectorTruth {
  double distance = std::numeric_limits<double>::infinity();  // [m] from the boundary; inf: none
  geom::Vec2 point = geom::Vec2::Zero();                       // true world frame
  const sim::Primitive* primitive = nullptr;                   // its surface (obstacle, material)
};

// Per sector (the sector map's layout), for the robot at `robot` with the world's movers placed.
std::vector<SectorTruth> trueSectorHits(const sim::WorldGeometry& world, const geom::Pose2& robot,
                                        double robot_radius, int nsectors, double max_range);

// Where and when direct echoes located each obstacle. Points are bucketed per obstacle in
// cells of the radius and kept in time order, so a query looks at 9 short lists.
class LocatedPoints {
 public:
  explicit LocatedPoints(double radius = 0.30);
  double radius() const { return radius_; }
  void add(int obstacle, int64_t utime, const geom::Vec2& p);
  // Every DIRECT echo's hit point (cause DIRECT, true_range >= 0, finite hit point).
  void addDirectEchoes(const std::vector<sonar_truth_t>& truths);
  // ... only those whose reading was at most max_range: the range SONAR_RING reported for that
  // firing and sensor, or, without one in the log, the echo's true range. With a scenario, an
  // echo from a stretch two obstacles share (a box's side drawn on a wall) locates the one it is
  // counted as (sim::Scenario::canonicalObstacle), as the sector samples' truth is.
  void addDirectEchoes(const std::vector<sonar_truth_t>& truths, const std::vector<sonar_ring_t>& rings,
                       double max_range, const sim::Scenario* scenario = nullptr);
  // True if an echo located `obstacle` within the radius of p at a time <= utime.
  bool located(int obstacle, const geom::Vec2& p, int64_t utime) const;
  // The newest such echo's time, if any.
  std::optional<int64_t> lastLocated(int obstacle, const geom::Vec2& p, int64_t utime) const;
  // How many such echoes in [from, to].
  int countLocated(int obstacle, const geom::Vec2& p, int64_t from, int64_t to) const;
  size_t size() const { return n_; }

 private:
  struct Entry {
    int64_t utime;
    geom::Vec2 p;
  };
  struct Key {
    int obstacle;
    int64_t cx, cy;
    bool operator==(const Key& o) const { return obstacle == o.obstacle && cx == o.cx && cy == o.cy; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const;
  };
  int64_t cell(double v) const;
  double radius_;
  std::unordered_map<Key, std::vector<Entry>, KeyHash> buckets_;
  size_t n_ = 0;
};

// How an observable sample could be known (the first that applies): the laser saw it; echoes
// read within the hypothetical scan's range limit (the only ones the complement can classify)
// located it within the operational memory (EvalOptions::recent_echo_s) before the map — one
// echo (below a confirmation threshold of two, which a single crosstalk reading must not pass)
// or several; or only earlier, so that only a longer memory (the tactical map) could hold it;
// or only echoes read beyond that limit located it, which the method never uses.
enum class Cue : uint8_t { None = 0, Laser = 1, EchoOnce = 2, EchoRepeated = 3, EchoOld = 4, EchoFar = 5 };
inline constexpr int kCues = 6;

// One scored sample.
struct SectorSample {
  float truth = std::numeric_limits<float>::infinity();  // [m] from the boundary; inf: none in reach
  bool observable = false;  // meaningful when truth <= sector_range
  Cue cue = Cue::None;      // set when observable
  int16_t material = -1;    // index into SectorTruthTable::materials; -1: no truth
  int16_t obstacle = -1;    // the scenario's obstacle (as the scores count it); -1: none or a mover
  float x = std::numeric_limits<float>::quiet_NaN();  // [m] the truth point, true world frame
  float y = std::numeric_limits<float>::quiet_NaN();
};

// The truth of every scored SECTOR_MAP, computed once and shared by the pilot's scores and the
// baselines' (which are read out at the same times).
struct SectorTruthTable {
  std::vector<size_t> maps;          // indices into RunLog::sector_maps, in log order
  std::vector<size_t> offset;        // samples of map i: [offset[i], offset[i + 1])
  std::vector<SectorSample> samples;
  std::vector<std::string> materials;
  int64_t warmup = 0;                // maps_before_first_data
  double echo_memory_s = 0;          // [s] the operational memory the cues used (operationalMemory)
  const SectorSample* mapSamples(size_t i) const { return samples.data() + offset[i]; }
  int sectors(size_t i) const { return static_cast<int>(offset[i + 1] - offset[i]); }
};
SectorTruthTable sectorTruthTable(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen,
                                  const EvalOptions& o);
// The same with a LaserSeen built from the log.
SectorTruthTable sectorTruthTable(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o);

// The sector map's scoring rules (README "Evaluation", sector map), for SectorScore and the
// per-sample CSV alike. reported: [m], < 0 = nothing reported.
bool sectorMissed(double reported, const SectorSample& s, const EvalOptions& o);      // truth within range only
bool sectorFalseAlarm(double reported, const SectorSample& s, const EvalOptions& o);
const char* cueName(Cue c);  // "none", "laser", "echo_once", "echo_repeated", "echo_old", "echo_far"
const char* sectorSourceName(int source);  // sector_map_t::SOURCE_*: "none", "laser", ...; unknown: "none"

// Scores of one sector-map source against the samples (README "Evaluation", sector map).
class SectorScore {
 public:
  // reported: [m], < 0 = nothing reported; source: sector_map_t::SOURCE_*, -1 unknown.
  void add(double reported, const SectorSample& s, const EvalOptions& o, int source = -1);
  // Writes prefix.{missed_rate, observable_missed_rate, false_alarm_rate,
  // false_alarm_share_of_reports, mae_m, missed_by_material.*}; with `details` also
  // unobservable_share, observable_missed_by_cue.*, false_alarms_by_source.* and samples.*.
  void write(Metrics& m, const std::string& prefix, bool details, const std::vector<std::string>& materials) const;

 private:
  Ratio missed_, observable_missed_, unobservable_, false_alarm_, false_of_reports_;
  std::vector<Ratio> missed_by_material_;
  int64_t observable_missed_by_cue_[kCues] = {};
  double abs_err_ = 0;
  int64_t err_n_ = 0;
  int64_t false_by_source_[5] = {0, 0, 0, 0, 0};  // sector_map_t::SOURCE_*
};

}  // namespace lasonic::eval
