#pragma once
// The simulated MOBOT-IV, as library classes. The live processes (lasonic-sim-world,
// lasonic-laser-driver, lasonic-sonar-driver) and the offline lasonic-sim are thin shells
// over these, so both produce the same statistics.
//
// Time: everything is driven by SIM_STATE (sim time). WorldCore produces SIM_STATE and
// ODOMETRY; the drivers consume SIM_STATE in time order and emit a measurement once the
// truth up to its time is known, interpolating the truth between consecutive states.
#include <cstdint>
#include <random>
#include <vector>

#include <lasonic/laser_scan_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_geometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

#include "sim/scenario.hpp"
#include "sim/world_geometry.hpp"

namespace lasonic::sim {

// Independent random stream per consumer, derived from the scenario seed.
uint64_t deriveSeed(uint64_t seed, const char* stream);

// ---------------------------------------------------------------- world + odometry
struct OdometryConfig {
  double rate_hz = 50;            // ODOMETRY and SIM_STATE rate
  double trans_noise = 0.01;      // [m/sqrt(m)] std-dev of distance error per sqrt(metre) driven
  double rot_noise = 0.005;       // [rad/sqrt(rad)] heading error per sqrt(radian) turned
  double drift_noise = 0.002;     // [rad/sqrt(m)] heading error per sqrt(metre) driven (wheel-base drift)
};
OdometryConfig odometryConfig(const Config& c, OdometryConfig base = {});  // throws ConfigError

class WorldCore {
 public:
  WorldCore(const Scenario& s, const OdometryConfig& c);
  // True state at utime (robot path following, movers); utime must not go backwards.
  sim_state_t stateAt(int64_t utime);
  // Odometry integrated (with drift) up to the last stateAt() call.
  odometry_t odometry() const;
  int64_t periodUs() const;
  bool finished(int64_t utime) const;  // past duration_s
};

// ---------------------------------------------------------------- laser
struct LaserConfig {
  double scan_rate_hz = 5;        // scans per second (2 per revolution on MOBOT-IV)
  int readings = 720;             // per scan
  double fov_deg = 360;           // field of view, centred on the sensor's x axis
  double range_max = 15.0;        // [m]
  double range_min = 0.05;        // [m]
  double noise_std = 0.01;        // [m]
  geom::Pose2 mount{0, 0, 0};     // sensor pose in the robot frame
};
LaserConfig laserConfig(const Config& c, LaserConfig base = {});

class LaserDriverCore {
 public:
  LaserDriverCore(const Scenario& s, const LaserConfig& c, uint64_t seed);
  // Scans completed by the time of this state (usually 0 or 1).
  std::vector<laser_scan_t> onSimState(const sim_state_t& st);
};

// ---------------------------------------------------------------- sonar
struct SonarSensor {
  geom::Pose2 mount;              // robot frame
  double beam_width = 0;          // [rad]
  int group = 0;
};
struct SonarConfig {
  std::vector<SonarSensor> sensors;   // default: MOBOT-IV ring of 24, 15 deg apart, 6 groups of 4
  double range_max = 3.0;             // [m]
  double range_min = 0.10;            // [m]
  double group_period_s = 0.03;       // between consecutive groups
  int rays_per_beam = 31;
  double noise_std = 0.01;            // [m] + noise_rel * range
  double noise_rel = 0.01;
  double multipath_prob = 0.5;        // specular miss -> a too-long reading (else no echo)
  double crosstalk_prob = 0.02;       // per reading
  double foreign_prob = 0.01;         // per reading
};
SonarConfig sonarConfig(const Config& c, SonarConfig base = {});

class SonarDriverCore {
 public:
  SonarDriverCore(const Scenario& s, const SonarConfig& c, uint64_t seed);
  struct Output {
    sonar_ring_t ring;
    sonar_truth_t truth;
  };
  std::vector<Output> onSimState(const sim_state_t& st);
  sonar_geometry_t geometry(int64_t utime) const;
};

}  // namespace lasonic::sim
