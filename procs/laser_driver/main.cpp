// lasonic-laser-driver: the simulated laser range scanner. Subscribes SIM_STATE (truth), casts
// each reading against the scenario's world at its own time, publishes LASER_SCAN and, for
// evaluation, LASER_TRUTH (the obstacle that returned each reading).
#include <spdlog/spdlog.h>

#include <cmath>
#include <optional>
#include <stdexcept>

#include "lcmio/process.hpp"
#include "lcmio/time_reset.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"
#include "sim/sim_state_check.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  ProcessMain pm("lasonic-laser-driver",
                 "lasonic-laser-driver: simulate the laser scanner against a scenario, driven by SIM_STATE");
  std::string scenario_file;
  std::optional<uint64_t> seed;
  sim::addDriverOptions(pm, scenario_file, seed);

  std::optional<sim::SimSetup> setup;
  sim::LaserConfig cfg;
  auto configure = [&](const Config& root) {
    sim::checkSeedOption(seed);
    setup = sim::SimSetup{root, sim::loadScenario(scenario_file)};
    cfg = sim::laserConfigFor(*setup);
    if (seed) setup->scenario.seed = *seed;
  };
  return pm.run(argc, argv, configure, [&](Node& node) {
    std::optional<sim::LaserDriverCore> laser;
    laser.emplace(setup->scenario, cfg, setup->scenario.seed);
    TimeReset clock;  // a restarted lasonic-sim-world starts its clock again: start afresh too
    spdlog::info("scenario {}: {} readings over {} deg at {} Hz, range {}..{} m, noise {} m, {} profile",
                 setup->scenario.name, cfg.readings, cfg.fov_deg, cfg.scan_rate_hz, cfg.range_min, cfg.range_max,
                 cfg.noise_std, cfg.profile == sim::SensorProfile::Ideal ? "ideal" : "physical");
    node.subscribe<sim_state_t>(channels::SIM_STATE, [&](const sim_state_t& st) {
      if (!sim::admitSimState(node, clock, laser, st, setup->scenario, cfg)) return;
      std::vector<sim::LaserDriverCore::Output> scans;
      try {
        scans = laser->onSimState(st);
      } catch (const std::invalid_argument& e) {
        node.reportError("rejected.sim_state", e.what());
        return;
      }
      node.noteMessageTime(st.utime);
      for (sim::LaserDriverCore::Output& o : scans) {
        laser_scan_t& scan = o.scan;
        // Never publish a reading a consumer cannot use as what it claims to be.
        for (size_t i = 0; i < scan.ranges.size(); ++i)
          if (scan.flags[i] == laser_scan_t::FLAG_OK &&
              !(std::isfinite(scan.ranges[i]) && scan.ranges[i] >= 0 && scan.ranges[i] <= scan.range_max)) {
            scan.flags[i] = laser_scan_t::FLAG_NO_RETURN;
            node.reportError("invalid_readings", "LASER_SCAN.ranges[" + std::to_string(i) + "] = " +
                                                     std::to_string(scan.ranges[i]) + " came out of the simulation: sent as no return");
          }
        node.publish(channels::LASER_SCAN, scan);
        node.publish(channels::LASER_TRUTH, o.truth);
      }
    });
    return node.run();
  });
}
