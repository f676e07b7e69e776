#pragma once
// The check every simulated driver makes of an incoming SIM_STATE before simulating from it:
// the drivers cast rays against the movers it names, so an unknown mover id, a non-finite
// value or an absurd time must be refused here, with the field named (counted as
// rejected.sim_state by the driver).
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <lasonic/sim_state_t.hpp>

#include "lcmio/time_reset.hpp"
#include "sim/scenario.hpp"

namespace lasonic::sim {

inline std::optional<std::string> simStateProblem(const sim_state_t& st, const Scenario& scenario) {
  if (!plausibleUtime(st.utime)) return "SIM_STATE.utime = " + std::to_string(st.utime) + " is not a time";
  const std::pair<const char*, double> fields[] = {{"robot_pose.x", st.robot_pose.x},
                                                   {"robot_pose.y", st.robot_pose.y},
                                                   {"robot_pose.theta", st.robot_pose.theta},
                                                   {"v", st.v},
                                                   {"omega", st.omega}};
  // 1000 km, 1000 m/s: far beyond any simulated room, and where doubles still resolve 1e-10 m;
  // a pose of 1e30 m is finite but turns ray casting into NaN.
  constexpr double kMaxCoordinate = bounds::kMaxCoordinate, kMaxSpeed = 1e3;
  for (const auto& [name, v] : fields) {
    if (!std::isfinite(v)) return std::string("SIM_STATE.") + name + " is not finite";
    const double limit = name[0] == 'r' ? kMaxCoordinate : kMaxSpeed;
    if (std::abs(v) > limit) return std::string("SIM_STATE.") + name + " = " + std::to_string(v) + " is absurd";
  }
  for (size_t i = 0; i < st.movers.size(); ++i) {
    const mover_state_t& m = st.movers[i];
    const std::string at = "SIM_STATE.movers[" + std::to_string(i) + "]";
    if (m.id < 0 || static_cast<size_t>(m.id) >= scenario.movers.size())
      return at + ".id = " + std::to_string(m.id) + " (the scenario has " + std::to_string(scenario.movers.size()) +
             " movers)";
    if (!(std::abs(m.x) <= kMaxCoordinate && std::abs(m.y) <= kMaxCoordinate && m.radius >= 0 &&
          m.radius <= kMaxCoordinate))
      return at + ": x, y must be finite and within 1000 km, radius in [0, 1000 km]";
  }
  return std::nullopt;
}

}  // namespace lasonic::sim

// ---- what both simulated drivers' mains share (header-only: used by procs/ only)
#include <spdlog/spdlog.h>

#include "lcmio/process.hpp"

namespace lasonic::sim {

// --seed of every simulator executable: an integer in [0, 2^63 - 1], as a scenario's `seed`
// (CLI11 alone would read -1 as 2^64 - 1).
inline CLI::Option* addSeedOption(CLI::App& app, std::optional<uint64_t>& seed) {
  return app.add_option("--seed", seed, "random seed, an integer >= 0 (default: the scenario's)")
      ->check(CLI::NonNegativeNumber);
}
// After parsing: a seed above a scenario's largest (CLI11 lets 2^63 .. 2^64 - 1 through) is a
// ConfigError (exit 2).
inline void checkSeedOption(const std::optional<uint64_t>& seed) {
  if (seed && *seed > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
    throw ConfigError("--seed must be an integer in [0, 2^63 - 1], as a scenario's seed");
}

inline void addDriverOptions(ProcessMain& pm, std::string& scenario_file, std::optional<uint64_t>& seed) {
  pm.app().add_option("--scenario", scenario_file, "scenario YAML (its sensor section overrides the config)")->required();
  addSeedOption(pm.app(), seed);
}

// The gate every SIM_STATE passes in a driver: a bad one is counted (rejected.sim_state) and
// dropped (nullptr); one whose time jumped back (a restarted lasonic-sim-world) is counted
// (time_resets) and gets a fresh core, as at start. Returns the core to simulate with.
template <typename Core, typename CoreConfig>
Core* admitSimState(Node& node, TimeReset& clock, std::optional<Core>& core, const sim_state_t& st,
                    const Scenario& scenario, const CoreConfig& cfg) {
  if (const auto problem = simStateProblem(st, scenario)) {
    node.reportError("rejected.sim_state", *problem + ": dropped");
    return nullptr;
  }
  if (!core || clock.jumpedBack("SIM_STATE", st.utime)) {
    if (core) {
      node.count("time_resets");
      spdlog::warn("SIM_STATE.utime = {} jumps back: the world restarted; starting afresh", st.utime);
    }
    core.emplace(scenario, cfg, scenario.seed);
  }
  return &*core;
}

}  // namespace lasonic::sim
