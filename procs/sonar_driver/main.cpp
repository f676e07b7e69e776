// lasonic-sonar-driver: the simulated sonar ring. Subscribes SIM_STATE (truth), fires the
// groups one after another against the scenario's world, publishes SONAR_RING with the
// readings of each group, SONAR_TRUTH with their causes, and SONAR_GEOMETRY once per sim second.
#include <spdlog/spdlog.h>

#include <optional>
#include <stdexcept>

#include "lcmio/process.hpp"
#include "lcmio/time_reset.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"
#include "sim/sim_state_check.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  ProcessMain pm("lasonic-sonar-driver",
                 "lasonic-sonar-driver: simulate the sonar ring against a scenario, driven by SIM_STATE");
  std::string scenario_file;
  std::optional<uint64_t> seed;
  sim::addDriverOptions(pm, scenario_file, seed);

  std::optional<sim::SimSetup> setup;
  sim::SonarConfig cfg;
  auto configure = [&](const Config& root) {
    sim::checkSeedOption(seed);
    setup = sim::SimSetup{root, sim::loadScenario(scenario_file)};
    cfg = sim::sonarConfigFor(*setup);
    if (seed) setup->scenario.seed = *seed;
  };
  return pm.run(argc, argv, configure, [&](Node& node) {
    std::optional<sim::SonarDriverCore> sonar;
    sonar.emplace(setup->scenario, cfg, setup->scenario.seed);
    TimeReset clock;  // a restarted lasonic-sim-world starts its clock again: start afresh too
    const sonar_geometry_t geometry = sonar->geometry(0);
    spdlog::info("scenario {}: {} sonars in {} groups, a group every {} s (+ up to {} s), range {}..{} m, {} profile, "
                 "beam scale {}",
                 setup->scenario.name, geometry.num_sensors, geometry.num_groups, cfg.group_period_s,
                 cfg.group_jitter_s, cfg.range_min, cfg.range_max,
                 cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical", cfg.beam_scale);
    std::optional<int64_t> next_geometry_utime;  // SONAR_GEOMETRY at 1 Hz of sim time
    node.subscribe<sim_state_t>(channels::SIM_STATE, [&](const sim_state_t& st) {
      const int64_t resets = node.counter("time_resets");
      if (!sim::admitSimState(node, clock, sonar, st, setup->scenario, cfg)) return;
      if (node.counter("time_resets") != resets) next_geometry_utime.reset();
      std::vector<sim::SonarDriverCore::Output> firings;
      try {
        firings = sonar->onSimState(st);
      } catch (const std::invalid_argument& e) {
        node.reportError("rejected.sim_state", e.what());
        return;
      }
      node.noteMessageTime(st.utime);
      if (!next_geometry_utime || st.utime >= *next_geometry_utime) {
        sonar_geometry_t g = sonar->geometry(st.utime);
        node.publish(channels::SONAR_GEOMETRY, g);
        next_geometry_utime = st.utime + 1'000'000;
      }
      for (sim::SonarDriverCore::Output& o : firings) {
        node.publish(channels::SONAR_RING, o.ring);
        node.publish(channels::SONAR_TRUTH, o.truth);
      }
    });
    return node.run();
  });
}
