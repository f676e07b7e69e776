// lasonic-sim: the whole simulated robot (world, odometry, laser, sonar) in one process, as fast
// as the CPU allows, written to an LCM log. The same library code as the live processes, so the
// same statistics; deterministic: same scenario and seed, byte-identical log.
//
// Log order, per world tick: SIM_STATE, ODOMETRY, SONAR_GEOMETRY (every second), then the
// measurements completed by that tick. Every event is stamped with the sim time at which a live
// driver would have published it (the tick's utime), so event timestamps never go backwards; a
// measurement's own time (e.g. a scan's first reading) is its message utime.
#include <CLI/CLI.hpp>

#include <chrono>
#include <iostream>
#include <map>
#include <optional>
#include <vector>

#include "core/cli.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  CLI::App app{"lasonic-sim: simulate a scenario faster than real time into an LCM log"};
  std::string scenario_file, out_file;
  std::vector<std::string> config_files;
  std::optional<double> duration;
  std::optional<uint64_t> seed;
  std::optional<double> robot_speed;
  bool same_path = false;
  std::string profile;
  app.add_option("--scenario", scenario_file, "scenario YAML")->required();
  app.add_option("--out", out_file, "LCM log file to write")->required();
  app.add_option("--duration", duration, "sim seconds (default: the scenario's duration_s)");
  app.add_option("--seed", seed, "random seed (default: the scenario's)");
  app.add_option("--robot-speed", robot_speed,
                 "the robot's speed along its path [m/s], overriding the scenario's robot.speed (the same scene "
                 "driven faster or slower)");
  app.add_flag("--same-path", same_path,
               "with --robot-speed: the scenario's duration_s scaled by its robot.speed / the new speed, so the "
               "robot covers the same path (turns on the spot still take as long); without it a slower robot "
               "covers less of its path in the same time")
      ->needs("--robot-speed")
      ->excludes("--duration");
  app.add_option("--config", config_files,
                 "lasonic YAML config (sections odometry, laser, sonar); repeat to layer overrides");
  app.add_option("--profile", profile,
                 "sensor profile of both laser and sonar, overriding config and scenario: physical (the default) "
                 "or ideal (the method's idealised sensors)")
      ->check(CLI::IsMember({"physical", "ideal"}));
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;

  std::optional<sim::SimSetup> setup;
  sim::OdometryConfig odo_cfg;
  sim::LaserConfig laser_cfg;
  sim::SonarConfig sonar_cfg;
  try {
    setup = sim::loadSimSetup(config_files, scenario_file);
    odo_cfg = sim::odometryConfigFor(*setup);
    laser_cfg = sim::laserConfigFor(*setup);
    sonar_cfg = sim::sonarConfigFor(*setup);
    if (!profile.empty()) {
      const auto p = profile == "ideal" ? sim::SensorProfile::Ideal : sim::SensorProfile::Physical;
      laser_cfg.profile = sonar_cfg.profile = p;
    }
  } catch (const ConfigError& e) {
    std::cerr << "lasonic-sim: " << e.what() << "\n";
    return 2;
  }
  if (duration && *duration <= 0) {
    std::cerr << "lasonic-sim: --duration must be > 0\n";
    return 2;
  }
  if (robot_speed && !(*robot_speed > 0 && *robot_speed <= 5)) {
    std::cerr << "lasonic-sim: --robot-speed must be in (0, 5] m/s\n";
    return 2;
  }
  sim::Scenario& scenario = setup->scenario;
  if (duration) scenario.duration_s = *duration;
  if (robot_speed) {
    if (same_path && scenario.robot.speed > 0) scenario.duration_s *= scenario.robot.speed / *robot_speed;
    scenario.robot.speed = *robot_speed;
  }
  if (seed) scenario.seed = *seed;

  const auto wall0 = std::chrono::steady_clock::now();
  std::map<std::string, int64_t> counts;
  try {
    LogWriter log(out_file);
    auto write = [&](const char* channel, int64_t timestamp, auto& msg) {
      log.write(channel, timestamp, msg);
      ++counts[channel];
    };
    sim::WorldCore world(scenario, odo_cfg);
    sim::LaserDriverCore laser(scenario, laser_cfg, scenario.seed);
    sim::SonarDriverCore sonar(scenario, sonar_cfg, scenario.seed);
    for (int64_t utime = world.startUtime(); !world.finished(utime); utime += world.periodUs()) {
      sim_state_t st = world.stateAt(utime);
      odometry_t od = world.odometry();
      write(channels::SIM_STATE, utime, st);
      if (world.odometryDue(utime)) write(channels::ODOMETRY, utime, od);
      if ((utime - world.startUtime()) % 1'000'000 < world.periodUs()) {
        sonar_geometry_t g = sonar.geometry(utime);
        write(channels::SONAR_GEOMETRY, utime, g);
      }
      for (sim::LaserDriverCore::Output& o : laser.onSimState(st)) {
        write(channels::LASER_SCAN, utime, o.scan);
        write(channels::LASER_TRUTH, utime, o.truth);
      }
      for (sim::SonarDriverCore::Output& o : sonar.onSimState(st)) {
        write(channels::SONAR_RING, utime, o.ring);
        write(channels::SONAR_TRUTH, utime, o.truth);
      }
    }
  } catch (const LogError& e) {
    std::cerr << "lasonic-sim: " << e.what() << "\n";
    return 1;
  }

  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  int64_t events = 0;
  std::string per_channel;
  for (const auto& [channel, n] : counts) {
    events += n;
    per_channel += (per_channel.empty() ? "" : ", ") + channel + " " + std::to_string(n);
  }
  std::printf("lasonic-sim: %s: %lld events (%s), %.1f sim s in %.2f wall s (real-time factor %.0f), seed %llu, "
              "laser %s, sonar %s -> %s\n",
              scenario.name.c_str(), static_cast<long long>(events), per_channel.c_str(), scenario.duration_s, wall_s,
              wall_s > 0 ? scenario.duration_s / wall_s : 0.0, static_cast<unsigned long long>(scenario.seed),
              laser_cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical",
              sonar_cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical", out_file.c_str());
  return 0;
}
