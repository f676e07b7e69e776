#pragma once
// ProcessMain: the one way a live lasonic process starts and ends (every main in procs/ that
// talks LCM goes through it):
//   - command line (CLI11): --config FILE (repeatable: later files override earlier ones' keys),
//     --lcm-url URL, --help, plus the process's own options;
//   - logging (spdlog, named after the process; LASONIC_LOG_LEVEL);
//   - configuration: the --config file loaded, then the process's configure step; a ConfigError
//     (a message naming file and key) exits 2; --check-config stops there (exit 0 when usable,
//     joining no LCM group: what `lasonic-launch --check` runs for each process); --print-config
//     too, after printing every parameter the process read with its value in effect and the
//     file it came from (or `default`);
//   - the Node on --lcm-url: an unusable URL exits 1 with a clear message (LCM 1.3.1 reports a
//     bad URL by !good(), never by aborting);
//   - SIGINT / SIGTERM: the Node's loop ends, a last PROCESS_STATUS goes out, exit 0;
//   - anything else thrown: logged, exit 1.
// Exit codes: 0 done or stopped by a signal; 1 LCM unusable or an unexpected failure; 2 bad
// command line, configuration or scenario.
//
//   int main(int argc, char** argv) {
//     ProcessMain pm("lasonic-pilot", "lasonic-pilot: operational AGM and Sector Map");
//     PilotConfig cfg;
//     return pm.run(argc, argv,
//                   [&](const Config& root) { cfg = pilotConfig(root.section("pilot")); },
//                   [&](Node& node) { PilotStage stage(node, cfg); return node.run(); });
//   }
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "lcmio/node.hpp"

namespace lasonic {

namespace exit_code {
inline constexpr int kOk = 0;
inline constexpr int kFailure = 1;  // LCM unusable, or an unexpected failure
inline constexpr int kBadConfig = 2;  // bad command line, configuration or scenario
}  // namespace exit_code

class ProcessMain {
 public:
  ProcessMain(std::string name, const std::string& description);

  // Add the process's own options here before run().
  CLI::App& app() { return app_; }
  const std::string& name() const { return name_; }
  const std::vector<std::string>& configFiles() const { return config_files_; }
  const std::string& lcmUrl() const { return lcm_url_; }

  // configure: reads what the process needs from the --config root (an empty map without
  // --config); throw ConfigError for bad values. body: runs the process on its Node and returns
  // its exit code (usually node.run()).
  int run(int argc, char** argv, const std::function<void(const Config& root)>& configure,
          const std::function<int(Node& node)>& body, Node::Options node_options = {});

 private:
  std::string name_;
  CLI::App app_;
  std::vector<std::string> config_files_;
  std::string lcm_url_ = kDefaultLcmUrl;
  bool check_config_ = false;
  bool print_config_ = false;
};

}  // namespace lasonic
