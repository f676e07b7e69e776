#pragma once
// Scoring a run against the simulator's ground truth (DESIGN.md "Evaluation"). Each section
// is a function of the decoded log and the scenario, so it can be tested on hand-made data.
// The definitions are in README.md, section "Evaluation"; keep both in step.
#include <string>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/laser_truth_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sector_map_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

#include "eval/metrics.hpp"
#include "sim/scenario.hpp"
#include "sim/world_geometry.hpp"

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
  std::vector<grid_map_t> agm_operational;
  int64_t undecodable = 0;  // events on known channels that did not decode
};

// Throws LogError if the file cannot be read.
RunLog loadRunLog(const std::string& path);

struct EvalOptions {
  double range_limit = 2.20;       // [m] the ideal sonar's limit (overridden by SONAR_HYPOTHESIS)
  double sector_range = 2.0;       // [m] sector map: obstacles this close to the boundary must be seen
  double sector_tolerance = 0.10;  // [m]
};

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
void evalComplement(const RunLog& log, const EvalOptions& o, Metrics& m);
// True free distance per sector (from the robot's boundary; +inf when nothing within
// max_range), for the robot at `robot` with the world's movers already placed.
std::vector<double> trueSectorDistances(const sim::WorldGeometry& world, const geom::Pose2& robot,
                                        double robot_radius, int nsectors, double max_range);
void evalSectorMap(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m);
void evalAgmOperational(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m);

Metrics evaluate(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o = {});

}  // namespace lasonic::eval
