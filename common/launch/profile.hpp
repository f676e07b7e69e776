#pragma once
// Host profile: the processes one computer runs, as lasonic-launch reads it (deploy/hosts/*.yaml;
// README "Deploying on two computers"). Pure: parsing, variable expansion and the restart
// back-off; the process handling is in supervisor.hpp.
//
//   host: pilot                        # a name for messages
//   lcm_url: "udpm://...?ttl=1&..."    # ${lcm_url} in commands
//   vars: {config: deploy/config/lasonic.yaml}   # ${name}: --set NAME=VALUE, then vars, then
//                                                # the environment; ${bin}: lasonic-launch's dir
//   restart: {initial_delay_s: 0.5, max_delay_s: 10, reset_after_s: 30}
//   stop_timeout_s: 5                  # SIGINT, then SIGKILL after this long
//   finish_grace_s: 1                  # after a `finish` process ended, before stopping the rest
//   processes:                         # started in this order, stopped in the reverse order
//     - name: lasonic-complement       # also the log's name: <log dir>/<name>.txt
//       command: [lasonic-complement, --config, "${config}", --lcm-url, "${lcm_url}"]
//       restart: always                # always | on-failure | never
//       start_delay_s: 0               # after the launcher started
//       optional: false                # true: a missing executable is a warning, not an error
//       finish: false                  # true: when it exits 0 the launcher stops everything
//       enabled: true                  # false (or "${var}" expanding to 0/false/""): not started
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"

namespace lasonic::launch {

enum class RestartPolicy { Always, OnFailure, Never };

// The longest time a profile's delays and timeouts, or --max-time, may give: 1e6 s (11.6 days),
// far beyond any delay or run a host means, and far inside what the supervisor's clock arithmetic
// holds (milliseconds in 64 bits): a value such as 1e300 overflowed it and acted at once.
inline constexpr double kMaxSeconds = 1e6;

struct ProcessSpec {
  std::string name;
  std::vector<std::string> command;  // expanded; command[0] is the executable
  RestartPolicy restart = RestartPolicy::Always;
  double start_delay_s = 0;
  bool optional = false;
  bool finish = false;
  bool enabled = true;
};

struct BackoffParams {
  double initial_delay_s = 0.5;  // the first restart after a crash: quick, a process usually just died
  double max_delay_s = 10.0;     // one that keeps dying is retried at most this rarely
  double reset_after_s = 30.0;   // up this long counts as healthy: the next crash starts afresh
};

struct HostProfile {
  std::string host;
  std::string lcm_url;
  BackoffParams backoff;
  double stop_timeout_s = 5.0;
  double finish_grace_s = 1.0;
  std::vector<ProcessSpec> processes;
};

// Reads a profile; ${...} are expanded from `overrides` (--set), the profile's vars, then the
// environment; `builtins` (bin, lcm_url, ...) are always known. Throws ConfigError naming the key
// path (an unknown ${name} too).
HostProfile loadProfile(const Config& root, const std::map<std::string, std::string>& overrides,
                        const std::map<std::string, std::string>& builtins);

// "${a}/x" with a = "b" -> "b/x"; "$$" -> "$". Unknown names call `unknown` (which throws).
std::string expand(const std::string& text, const std::map<std::string, std::string>& vars,
                   const std::function<void(const std::string&)>& unknown);

// The files a lasonic process reads at start-up that `spec`'s command names, as (option, file):
// "--config FILE", "--config=FILE", and the same for --scenario. (lasonic-launch --check looks
// for them.)
std::vector<std::pair<std::string, std::string>> filesNamed(const ProcessSpec& spec);

// Delay before restart number `consecutive` (1 = the first after a healthy run): initial * 2^(n-1),
// capped.
double restartDelay(const BackoffParams& p, int consecutive);

}  // namespace lasonic::launch
