// lasonic-laser-driver: the simulated laser range scanner. Subscribes SIM_STATE (truth), casts
// each reading against the scenario's world at its own time, publishes LASER_SCAN and, for
// evaluation, LASER_TRUTH (the obstacle that returned each reading).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <optional>
#include <stdexcept>

#include "core/logging.hpp"
#include "lcmio/node.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  CLI::App app{"lasonic-laser-driver: simulate the laser scanner against a scenario, driven by SIM_STATE"};
  std::string config_file, scenario_file, lcm_url = kDefaultLcmUrl;
  std::optional<uint64_t> seed;
  app.add_option("--config", config_file, "lasonic YAML config (section laser)");
  app.add_option("--scenario", scenario_file, "scenario YAML")->required();
  app.add_option("--lcm-url", lcm_url, "LCM URL");
  app.add_option("--seed", seed, "random seed (default: the scenario's)");
  CLI11_PARSE(app, argc, argv);
  setupLogging("lasonic-laser-driver");

  std::optional<sim::SimSetup> setup;
  sim::LaserConfig cfg;
  try {
    setup = sim::loadSimSetup(config_file, scenario_file);
    cfg = sim::laserConfigFor(*setup);
  } catch (const ConfigError& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  if (seed) setup->scenario.seed = *seed;

  Node node("lasonic-laser-driver", lcm_url);
  sim::LaserDriverCore laser(setup->scenario, cfg, setup->scenario.seed);
  spdlog::info("scenario {}: {} readings over {} deg at {} Hz, range {}..{} m, noise {} m, {} profile",
               setup->scenario.name, cfg.readings, cfg.fov_deg, cfg.scan_rate_hz, cfg.range_min, cfg.range_max,
               cfg.noise_std, cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical");

  node.subscribe<sim_state_t>(channels::SIM_STATE, [&](const sim_state_t& st) {
    std::vector<sim::LaserDriverCore::Output> scans;
    try {
      scans = laser.onSimState(st);
    } catch (const std::invalid_argument& e) {
      node.reportError("rejected.sim_state", e.what());
      return;
    }
    node.noteMessageTime(st.utime);
    for (sim::LaserDriverCore::Output& o : scans) {
      node.publish(channels::LASER_SCAN, o.scan);
      node.publish(channels::LASER_TRUTH, o.truth);
    }
  });
  return node.run();
}
