// lasonic-sim-world: the simulated robot's world. Publishes the truth (SIM_STATE: robot pose,
// movers) and the drifting dead reckoning (ODOMETRY) at odometry.rate_hz, paced against the wall
// clock (sim time = --rate x wall time), until the scenario's duration, then exits 0.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <thread>

#include "lcmio/process.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"
#include "sim/sim_state_check.hpp"

using namespace lasonic;

namespace {
// Sim seconds per wall second. At a hundredth of real time a 60 s scenario takes 100 minutes,
// the slowest a live run is watched; at 100 times a 50 Hz world sends a SIM_STATE every 0.2 ms,
// faster than the drivers simulate a scan (faster than real time is lasonic-sim's job).
constexpr double kMinRate = 0.01, kMaxRate = 100;
}  // namespace

int main(int argc, char** argv) {
  ProcessMain pm("lasonic-sim-world",
                 "lasonic-sim-world: publish SIM_STATE (truth) and ODOMETRY for a scenario, in real time");
  std::string scenario_file;
  std::optional<double> rate, duration;
  std::optional<uint64_t> seed;
  pm.app().add_option("--scenario", scenario_file, "scenario YAML")->required();
  pm.app().add_option("--rate", rate, "sim seconds per wall second (default: sim_world.rate, 1.0)");
  pm.app().add_option("--duration", duration, "sim seconds to run (default: the scenario's duration_s)");
  sim::addSeedOption(pm.app(), seed);

  std::optional<sim::SimSetup> setup;
  sim::OdometryConfig odo;
  auto configure = [&](const Config& root) {
    sim::checkSeedOption(seed);
    const Config own = root.section("sim_world");
    own.allowOnly({"rate"});
    if (!rate) rate = own.get("rate", 1.0, Range::between(kMinRate, kMaxRate));
    if (!(std::isfinite(*rate) && *rate >= kMinRate && *rate <= kMaxRate)) {
      std::ostringstream os;
      os << "--rate must be in [" << kMinRate << ", " << kMaxRate << "] sim seconds per wall second";
      throw ConfigError(os.str());
    }
    // Sim time is counted in int64 microseconds; a day of it (sim::bounds::kMaxDurationS) is the longest run.
    if (duration && !(std::isfinite(*duration) && *duration > 0 && *duration <= sim::bounds::kMaxDurationS)) {
      std::ostringstream os;
      os << "--duration must be in (0, " << sim::bounds::kMaxDurationS << "] sim seconds (at most a day)";
      throw ConfigError(os.str());
    }
    setup = sim::SimSetup{root, sim::loadScenario(scenario_file)};
    odo = sim::odometryConfigFor(*setup);
    // The drivers read the laser and sonar sections with this scenario's overrides: refused
    // here too, so that the world does not run on alone when they exit.
    sim::laserConfigFor(*setup);
    sim::sonarConfigFor(*setup);
    if (duration) setup->scenario.duration_s = *duration;
    if (seed) setup->scenario.seed = *seed;
    // Said, not refused: the robot may be meant to pass close (README "Scenario format").
    for (const sim::RobotOverlap& o : sim::robotOverlaps(setup->scenario))
      spdlog::warn("{}: {}", scenario_file, sim::describeRobotOverlap(setup->scenario, o));
    for (const sim::MoverOverlap& o : sim::moverOverlaps(setup->scenario))
      spdlog::warn("{}: {}", scenario_file, sim::describeMoverOverlap(setup->scenario, o));
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
