// lasonic-sonar-driver: the simulated sonar ring. Subscribes SIM_STATE (truth), fires the
// groups one after another against the scenario's world, publishes SONAR_RING with the
// readings of each group, SONAR_TRUTH with their causes, and SONAR_GEOMETRY once per sim second.
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
  CLI::App app{"lasonic-sonar-driver: simulate the sonar ring against a scenario, driven by SIM_STATE"};
  std::string config_file, scenario_file, lcm_url = kDefaultLcmUrl;
  std::optional<uint64_t> seed;
  app.add_option("--config", config_file, "lasonic YAML config (section sonar)");
  app.add_option("--scenario", scenario_file, "scenario YAML (its sonar: section overrides the config)")->required();
  app.add_option("--lcm-url", lcm_url, "LCM URL");
  app.add_option("--seed", seed, "random seed (default: the scenario's)");
  CLI11_PARSE(app, argc, argv);
  setupLogging("lasonic-sonar-driver");

  std::optional<sim::SimSetup> setup;
  sim::SonarConfig cfg;
  try {
    setup = sim::loadSimSetup(config_file, scenario_file);
    cfg = sim::sonarConfigFor(*setup);
  } catch (const ConfigError& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  if (seed) setup->scenario.seed = *seed;

  Node node("lasonic-sonar-driver", lcm_url);
  sim::SonarDriverCore sonar(setup->scenario, cfg, setup->scenario.seed);
  const sonar_geometry_t geometry = sonar.geometry(0);
  spdlog::info("scenario {}: {} sonars in {} groups, a group every {} s, range {}..{} m, {} profile, beam scale {}",
               setup->scenario.name, geometry.num_sensors, geometry.num_groups, cfg.group_period_s, cfg.range_min,
               cfg.range_max, cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical", cfg.beam_scale);

  std::optional<int64_t> next_geometry_utime;  // SONAR_GEOMETRY at 1 Hz of sim time
  node.subscribe<sim_state_t>(channels::SIM_STATE, [&](const sim_state_t& st) {
    std::vector<sim::SonarDriverCore::Output> firings;
    try {
      firings = sonar.onSimState(st);
    } catch (const std::invalid_argument& e) {
      node.reportError("rejected.sim_state", e.what());
      return;
    }
    node.noteMessageTime(st.utime);
    if (!next_geometry_utime || st.utime >= *next_geometry_utime) {
      sonar_geometry_t g = sonar.geometry(st.utime);
      node.publish(channels::SONAR_GEOMETRY, g);
      next_geometry_utime = st.utime + 1'000'000;
    }
    for (sim::SonarDriverCore::Output& o : firings) {
      node.publish(channels::SONAR_RING, o.ring);
      node.publish(channels::SONAR_TRUTH, o.truth);
    }
  });
  return node.run();
}
