#pragma once

// Scoring a run against the simulator's ground truth (README "Evaluation"). Each section
// is a function of the decoded log and the scenario, so it can be tested on hand-made data.
// The definitions are in README.md, section "Evaluation"; keep both in step.
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/laser_truth_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sector_map_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

#include "eval/metrics.hpp"
#include "lcmio/time_reset.hpp"
#include "eval/sparse_grid_map.hpp"
#include "sim/scenario.hpp"
#include "sim/world_geometry.hpp"
#include "core/odometry_error.hpp"
#include "tactical/line_generation.hpp"
#include "tactical/scan_matcher.hpp"

namespace lasonic::eval {

struct RunLog {
  std::vector<sim_state_t> sim_states;
  std::vector<odometry_t> odometry;
  std::vector<laser_scan_t> laser_scans;
  std::vector<laser_truth_t> laser_truths;
  std::vector<sonar_ring_t> sonar_rings;
  std::vector<sonar_truth_t> sonar_truths;
  std::vector<hypothetical_scan_t> hypotheses;
  std::vector<complement_t> complements;
  std::vector<sector_map_t> sector_maps;
  // The grids without their zero cells (eval/sparse_grid_map.hpp): three quarters of a log's bytes.
  std::vector<SparseGridMap> agm_operational;
  std::vector<SparseGridMap> agm_tactical;
  std::vector<line_map_t> current_sensor_maps;
  int64_t undecodable = 0;  // events on known channels that did not decode
  // SIM_STATE's time in the order logged, summed over the passes of a looped or concatenated
  // log (the vectors above are sorted by time, which interleaves the passes).
  PassSpan sim_time;
  // No message on any channel the evaluation reads (an empty log, or another project's).
  bool empty() const {
    return sim_states.empty() && odometry.empty() && laser_scans.empty() && laser_truths.empty() &&
           sonar_rings.empty() && sonar_truths.empty() && hypotheses.empty() && complements.empty() &&
           sector_maps.empty() && agm_operational.empty() && agm_tactical.empty() && current_sensor_maps.empty();
  }
};

// Throws LogError if the file cannot be read.
RunLog loadRunLog(const std::string& path);

// Whether a log was simulated from the scenario it is scored against. `error`: the log's
// SIM_STATE holds movers the scenario does not have (or the other way round), so no truth can be
// computed, a truth channel names an obstacle the scenario does not have, or the robot's true
// pose leaves the scenario's path by more than kOffPathErrorM (the simulated robot drives its
// legs exactly); `warning`: it leaves it by more than kOffPathWarningM (a waypoint edited after
// the run), or else the robot's first true pose lies more than 0.5 m from the scenario's first
// waypoint (a live log recorded after the start may do that). Empty when they agree or the log
// has no SIM_STATE.
inline constexpr double kOffPathErrorM = sim::kRobotOffPathM;
inline constexpr double kOffPathWarningM = 0.02;
struct ScenarioMatch {
  std::string error, warning;
};
ScenarioMatch checkLogMatchesScenario(const RunLog& log, const sim::Scenario& scenario);
// Empty, or a warning that the pilot's robot_radius (SECTOR_MAP) is not the scenario's
// robot.radius by more than 1 cm: the sector map is then measured, and scored, from the pilot's
// boundary, not the simulated body's (a robot overlay not layered: README "Another robot").
std::string robotRadiusWarning(const RunLog& log, const sim::Scenario& scenario);

struct EvalOptions {
  double range_limit = 2.20;       // [m] the ideal sonar's limit (overridden by SONAR_HYPOTHESIS)
  double sector_range = 2.0;       // [m] sector map: obstacles this close to the boundary must be seen
  double sector_tolerance = 0.10;  // [m]
  double located_radius = 0.30;    // [m] a direct echo's hit point this close locates a boundary point
  double line_tolerance = 0.10;    // [m] lines: within this of a boundary point / a true surface
  double observe_radius = 0.30;    // [m] an echo this near a surface point located it (observability)
  // [s] An echo this recent is within the operational memory: the shipped operational AGM forgets
  // a cell that is not heard again in h_max = 18 update cycles of 30 ms (observable_missed_by_cue).
  // Used as given only where the memory below cannot be worked out.
  double recent_echo_s = 0.54;
  // The operational AGM's h_max in update cycles (pilot.agm.h_max; 0: recent_echo_s as given).
  // (Three ring cycles of MOBOT-IV's 6 groups, of the Pioneer's 8: below.)
  // One SONAR_RING message is one update cycle, so the memory in seconds is h_max times the log's
  // median interval between rings: 0.61 s for MOBOT-IV's ring (18 cycles of 30 ms + up to 8 ms
  // jitter per group), 1.05 s for the Pioneer's (24 cycles of 40 ms + jitter).
  int operational_h_max = 0;
  // pilot.h_max_ring_cycles (> 0: h_max is that many times the firing groups per ring cycle,
  // counted in the log's SONAR_RING groups as the pilot counts them; operational_h_max until then).
  double operational_h_max_ring_cycles = 0;
  double seen_radius = 0.10;       // [m] a laser return this near a point (same obstacle) saw it
  bool breakdown = false;          // also agm_tactical.breakdown.*, lines.breakdown.* (why points are missed)
  // Also every scored sector sample of the pilot's SECTOR_MAP as one CSV row (writeSectorSampleHeader
  // first): where the misses and false alarms are, sample by sample. Not owned.
  std::ostream* samples_csv = nullptr;
  // With breakdown: also every sample the breakdown looks at (a located laser-invisible boundary
  // point inside one AGM_TACTICAL map, not seen by the laser then) as one CSV row
  // (writeTacticalSampleHeader first): whether the map holds it, and else why not; whether a sonar
  // line covers it, and else why not. Not owned.
  std::ostream* tactical_samples_csv = nullptr;
  // Also every classified sonar reading of SONAR_COMPLEMENT joined with its truth as one CSV row
  // (writeComplementSampleHeader first): its cause, class and hypothetical range, and for each
  // complement.* rate it counts in, whether it counted as right there. Not owned.
  std::ostream* complement_samples_csv = nullptr;
  // The breakdown redoes the navigator's line generation and its forgetting by distance, so it
  // needs the run's `navigator:` keys (evalOptions(config); defaults: the code's).
  LineGenerationParams lines;
  double forget_after_m = 0;       // [m] navigator.agm.h_max_m (0: never)
  double forget_sigma_m = 0.08;    // [m] navigator.agm.forget_sigma_m (0: never)
  // The error model forget_sigma_m is applied with: navigator.scan_matching.pose_*_noise (or,
  // with scan matching off, navigator.agm.odometry_*_noise).
  OdometryNoise odometry = ScanMatchParams{}.pose_noise;
};
// The options for a run made with `config` (the navigator's line generation and h_max_m, for the
// breakdown; the pilot's h_max, for the observability cues). Throws ConfigError naming the key path.
EvalOptions evalOptions(const Config& config);

// The CSV columns of EvalOptions::samples_csv.
void writeSectorSampleHeader(std::ostream& out);
// The CSV columns of EvalOptions::tactical_samples_csv.
void writeTacticalSampleHeader(std::ostream& out);
// The CSV columns of EvalOptions::complement_samples_csv.
void writeComplementSampleHeader(std::ostream& out);

struct SectorTruthTable;  // eval/observability.hpp
class LaserSeen;          // eval/laser_seen.hpp
struct BaselinesConfig;   // eval/baselines.hpp

// The truth at any time, interpolated between SIM_STATE messages.
class TruthTrack {
 public:
  explicit TruthTrack(const std::vector<sim_state_t>& states);
  bool empty() const { return states_->empty(); }
  geom::Pose2 robotAt(int64_t utime) const;
  std::vector<sim::MoverPose> moversAt(int64_t utime) const;

 private:
  size_t bracket(int64_t utime, double& s) const;
  const std::vector<sim_state_t>* states_;
};

// Sensor statistics: counts, sonar causes and reflector kinds (SONAR_TRUTH), laser returns by
// the material that returned them (LASER_TRUTH; needs the scenario to name the materials).
void evalSensors(const RunLog& log, const sim::Scenario& sc, Metrics& m);
// "Laser-invisible" means, scan by scan, that the laser did not see it (eval/laser_seen.hpp);
// without LASER_TRUTH (or SIM_STATE) the functions below fall back to the material rule
// (Scenario::laserVisible, SONAR_TRUTH laser_visible / nearest_laser_visible). Each overload
// without a LaserSeen builds one from the log.
// sensors.laser_truth (1: per scan, 0: by material) and sensors.laser_scans_without_truth.
void evalLaserTruth(const LaserSeen& seen, Metrics& m);
void evalComplement(const RunLog& log, const EvalOptions& o, Metrics& m);
// With the scenario, an echo from a surface drawn on another's counts as from the one the laser
// sees best (sim::Scenario::canonicalObstacle).
void evalComplement(const RunLog& log, const LaserSeen& seen, const EvalOptions& o, Metrics& m,
                    const sim::Scenario* sc = nullptr);
// True free distance per sector (from the robot's boundary; +inf when nothing within
// max_range), for the robot at `robot` with the world's movers already placed.
std::vector<double> trueSectorDistances(const sim::WorldGeometry& world, const geom::Pose2& robot,
                                        double robot_radius, int nsectors, double max_range);
void evalSectorMap(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m);
// The same with the truth computed once (eval/observability.hpp).
void evalSectorMap(const RunLog& log, const SectorTruthTable& truth, const EvalOptions& o, Metrics& m);
void evalAgmOperational(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m);
void evalAgmOperational(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o,
                        Metrics& m);

// Boundary points (every `spacing` metres) of the scenario's static obstacles, each with its
// obstacle index and the surface (index into Scenario::statics: one side of a box or polyline,
// or a circle) it lies on.
struct BoundaryPoint {
  geom::Vec2 p;
  int obstacle = -1;
  int surface = -1;
};
std::vector<BoundaryPoint> staticBoundary(const sim::Scenario& sc, double spacing = 0.05);
// Only the obstacles whose material does not reflect the laser (the material rule).
std::vector<BoundaryPoint> laserInvisibleBoundary(const sim::Scenario& sc, double spacing = 0.05);
// The boundary the sonar-only scores look at: every static obstacle when the laser's truth says
// per scan what it saw (a point counts only while the laser does not see it), else the
// laser-invisible materials' (the fallback).
std::vector<BoundaryPoint> sonarOnlyCandidates(const sim::Scenario& sc, const LaserSeen& seen, double spacing = 0.05);
// For each point, the earliest firing time of a DIRECT echo (SONAR_TRUTH) with a measured range
// within range_limit (what the complement can keep) whose hit point lies on the point's own
// surface (within 1 cm of it: a corner lies on both sides) and within `radius` of the point, the
// point in the transducer's line of sight (SONAR_RING mount on the true pose; nothing static in
// between), or INT64_MAX if none ever did: when the point was located. An echo locates the
// surface that answered, not the back of a bin or of a box behind it. With `seen` (and its truth
// available) the sonar alone must have located it: the newest scan at the firing saw neither the
// echo's hit point nor the point (no return of their obstacle within seen_radius), and echoes
// before the first scan locate nothing.
std::vector<int64_t> locatedTimes(const RunLog& log, const sim::Scenario& sc, const std::vector<BoundaryPoint>& pts,
                                  double radius, const LaserSeen* seen = nullptr, double seen_radius = 0.10,
                                  double range_limit = std::numeric_limits<double>::infinity());
// The hypothetical scan's range limit: SONAR_HYPOTHESIS's, else the option's.
double hypothesisRangeLimit(const RunLog& log, const EvalOptions& o);
// [s] The operational AGM's memory: operational_h_max times the median interval between the
// log's SONAR_RING messages, else recent_echo_s.
double operationalMemory(const RunLog& log, const EvalOptions& o);

// Tactical level (AGM_TACTICAL, CURRENT_SENSOR_MAP); definitions in the README.
void evalAgmTactical(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m);
void evalAgmTactical(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o,
                     Metrics& m);
void evalLines(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m);
void evalLines(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o, Metrics& m);
// Why located points are missed by the tactical AGM and its lines (agm_tactical.breakdown.*,
// lines.breakdown.*; README "Evaluation").
void evalTacticalBreakdown(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o,
                           Metrics& m);

// baselines: the baseline mappers' configuration (nullptr: the code's defaults).
Metrics evaluate(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o = {},
                 const BaselinesConfig* baselines = nullptr);

}  // namespace lasonic::eval
