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
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <vector>

#include "core/cli.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "sim/drivers.hpp"
#include "core/same_file.hpp"
#include "sim/setup.hpp"
#include "sim/sim_state_check.hpp"

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
  bool check_config = false;
  app.add_option("--scenario", scenario_file, "scenario YAML")->required();
  app.add_option("--out", out_file, "LCM log file to write (required unless --check-config)");
  app.add_flag("--check-config", check_config,
               "load and check the configuration, scenario and options, say what would be simulated, then exit: "
               "0 usable, 2 not; writes nothing");
  app.add_option("--duration", duration, "sim seconds (default: the scenario's duration_s)");
  sim::addSeedOption(app, seed);
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
  if (out_file.empty() && !check_config) {
    std::cerr << "lasonic-sim: --out is required (lasonic-sim --help lists the options)\n";
    return kExitBadCommandLine;
  }
  try {
    sim::checkSeedOption(seed);
  } catch (const ConfigError& e) {
    std::cerr << "lasonic-sim: " << e.what() << "\n";
    return 2;
  }

  for (const std::string& input : config_files)
    if (lasonic::sameExistingFile(out_file, input)) {
      std::cerr << "lasonic-sim: --out " << out_file << " is the --config file " << input << ": not overwritten\n";
      return 2;
    }
  if (lasonic::sameExistingFile(out_file, scenario_file)) {
    std::cerr << "lasonic-sim: --out " << out_file << " is the --scenario file " << scenario_file << ": not overwritten\n";
    return 2;
  }
  // Sim time is counted in int64 microseconds; a day of it (sim::bounds::kMaxDurationS) is the longest run.
  const auto duration_ok = [](double d) { return std::isfinite(d) && d > 0 && d <= sim::bounds::kMaxDurationS; };
  if (duration && !duration_ok(*duration)) {
    std::cerr << "lasonic-sim: --duration must be in (0, " << sim::bounds::kMaxDurationS
              << "] sim seconds (at most a day)\n";
    return 2;
  }

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
  } catch (const std::exception& e) {
    std::cerr << "lasonic-sim: start-up failed: " << e.what() << "\n";
    return 1;
  }
  if (robot_speed && !(*robot_speed > 0 && *robot_speed <= sim::bounds::kMaxRobotSpeed)) {
    std::cerr << "lasonic-sim: --robot-speed must be in (0, 5] m/s\n";
    return 2;
  }
  sim::Scenario& scenario = setup->scenario;
  if (duration) scenario.duration_s = *duration;
  if (robot_speed) {
    if (same_path && scenario.robot.speed > 0) scenario.duration_s *= scenario.robot.speed / *robot_speed;
    scenario.robot.speed = *robot_speed;
    if (!duration_ok(scenario.duration_s)) {  // --same-path with a much slower robot
      std::cerr << "lasonic-sim: --robot-speed " << *robot_speed << " --same-path would simulate "
                << scenario.duration_s << " s: more than a day (" << sim::bounds::kMaxDurationS << " s)\n";
      return 2;
    }
  }
  if (seed) scenario.seed = *seed;
  // A path through an obstacle is driven through it (the robot follows its path blind, a mover
  // too): said, not refused, since a robot may be meant to pass close (README "Scenario format").
  for (const sim::RobotOverlap& o : sim::robotOverlaps(scenario))
    std::cerr << "lasonic-sim: warning: " << scenario_file << ": " << sim::describeRobotOverlap(scenario, o) << "\n";
  for (const sim::MoverOverlap& o : sim::moverOverlaps(scenario))
    std::cerr << "lasonic-sim: warning: " << scenario_file << ": " << sim::describeMoverOverlap(scenario, o) << "\n";
  if (check_config) {
    std::cout << "lasonic-sim: configuration usable";
    for (const std::string& f : config_files) std::cout << " " << f;
    if (config_files.empty()) std::cout << " (the built-in defaults)";
    std::printf(", scenario %s: %s, %.1f sim s, robot at %.2f m/s, seed %llu, laser %s, sonar %s\n",
                scenario_file.c_str(), scenario.name.c_str(), scenario.duration_s, scenario.robot.speed,
                static_cast<unsigned long long>(scenario.seed),
                laser_cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical",
                sonar_cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical");
    return 0;
  }

  const auto wall0 = std::chrono::steady_clock::now();
  std::map<std::string, int64_t> counts;
  int64_t sim_utime = 0;
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
      sim_utime = utime;
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
  } catch (const std::exception& e) {
    // Nothing a scenario or config can hold should get here (they are bounded when read); if
    // something does, say where instead of aborting.
    std::fprintf(stderr, "lasonic-sim: the simulation failed at sim time %.3f s: %s (%s is incomplete)\n",
                 static_cast<double>(sim_utime - sim::WorldCore::kStartUtime) * 1e-6, e.what(), out_file.c_str());
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
