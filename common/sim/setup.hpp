#pragma once
// Start-up shared by the simulator's executables: the optional --config file, the scenario and
// the sensor configs with their precedence: code defaults <- the --config file's section <- the
// scenario's override section. Every step throws ConfigError naming file and key.
#include <string>
#include <vector>

#include "core/config.hpp"
#include "sim/drivers.hpp"
#include "sim/scenario.hpp"

namespace lasonic::sim {

struct SimSetup {
  Config config;  // root of the --config file (an empty map without one)
  Scenario scenario;
};

inline SimSetup loadSimSetup(const std::vector<std::string>& config_files, const std::string& scenario_file) {
  SimSetup s;
  s.config = Config::loadConfiguration(config_files);
  s.scenario = loadScenario(scenario_file);
  return s;
}

inline LaserConfig laserConfigFor(const SimSetup& s) {
  return laserConfig(s.scenario.laser, laserConfig(s.config.section("laser")));
}

inline SonarConfig sonarConfigFor(const SimSetup& s) {
  return sonarConfig(s.scenario.sonar, sonarConfig(s.config.section("sonar")));
}

inline OdometryConfig odometryConfigFor(const SimSetup& s) {
  return odometryConfig(s.scenario.odometry, odometryConfig(s.config.section("odometry")));
}

}  // namespace lasonic::sim
