// lasonic-sim-world: the simulated robot's world. Publishes the truth (SIM_STATE: robot pose,
// movers) and the drifting dead reckoning (ODOMETRY) at odometry.rate_hz, paced against the wall
// clock (sim time = --rate x wall time), until the scenario's duration, then exits 0.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <thread>

#include "lcmio/process.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  ProcessMain pm("lasonic-sim-world",
                 "lasonic-sim-world: publish SIM_STATE (truth) and ODOMETRY for a scenario, in real time");
  std::string scenario_file;
  std::optional<double> rate, duration;
  std::optional<uint64_t> seed;
  pm.app().add_option("--scenario", scenario_file, "scenario YAML")->required();
  pm.app().add_option("--rate", rate, "sim seconds per wall second (default: sim_world.rate, 1.0)");
  pm.app().add_option("--duration", duration, "sim seconds to run (default: the scenario's duration_s)");
  pm.app().add_option("--seed", seed, "random seed (default: the scenario's)");

  std::optional<sim::SimSetup> setup;
  sim::OdometryConfig odo;
  auto configure = [&](const Config& root) {
    const Config own = root.section("sim_world");
    own.allowOnly({"rate"});
    if (!rate) rate = own.get("rate", 1.0, Range::positive());
    if (*rate <= 0) throw ConfigError("--rate must be > 0");
    if (duration && *duration <= 0) throw ConfigError("--duration must be > 0");
    setup = sim::SimSetup{root, sim::loadScenario(scenario_file)};
    odo = sim::odometryConfigFor(*setup);
    if (duration) setup->scenario.duration_s = *duration;
    if (seed) setup->scenario.seed = *seed;
  };
  return pm.run(argc, argv, configure, [&](Node& node) {
    const sim::Scenario& scenario = setup->scenario;
    sim::WorldCore world(scenario, odo);
    spdlog::info("scenario {} ({}): {} s at {}x real time, {} Hz, seed {}", scenario.name, scenario_file,
                 scenario.duration_s, *rate, odo.rate_hz, scenario.seed);
    using Clock = std::chrono::steady_clock;
    const Clock::time_point wall0 = Clock::now();
    int64_t published = 0;
    for (int64_t utime = world.startUtime(); !world.finished(utime); utime += world.periodUs()) {
      const auto due = wall0 + std::chrono::microseconds(static_cast<int64_t>(
                                   static_cast<double>(utime - world.startUtime()) / *rate));
      // Short naps, so that SIGINT is answered promptly even at slow rates.
      while (!Node::shutdownRequested() && Clock::now() < due)
        std::this_thread::sleep_for(std::min<Clock::duration>(due - Clock::now(), std::chrono::milliseconds(50)));
      if (Node::shutdownRequested()) break;
      sim_state_t st = world.stateAt(utime);
      odometry_t od = world.odometry();
      node.publish(channels::SIM_STATE, st);
      if (world.odometryDue(utime)) node.publish(channels::ODOMETRY, od);
      node.noteMessageTime(utime);
      ++published;
      node.spinOnce(0);  // heartbeat
    }
    node.publishStatus();
    spdlog::info("{}: {} SIM_STATE published, {} errors", Node::shutdownRequested() ? "interrupted" : "finished",
                 published, node.errors());
    return 0;
  });
}
