#include "lcmio/process.hpp"

#include <spdlog/spdlog.h>

#include <iostream>

#include "core/cli.hpp"
#include "core/logging.hpp"

namespace lasonic {

ProcessMain::ProcessMain(std::string name, const std::string& description)
    : name_(std::move(name)), app_(description) {
  app_.add_option("--config", config_files_,
                  "lasonic YAML configuration (deploy/config/lasonic.yaml); repeat to layer a robot's overrides on it");
  app_.add_option("--lcm-url", lcm_url_, "LCM URL")->capture_default_str();
  app_.add_flag("--check-config", check_config_,
                "load and check the configuration (and scenario), then exit: 0 usable, 2 not; joins no LCM group");
  app_.add_flag("--print-config", print_config_,
                "as --check-config, and print every parameter this process reads: its value after all --config "
                "layers and the file it came from, or `default` (the code's, which is the shipped configuration's)");
}

int ProcessMain::run(int argc, char** argv, const std::function<void(const Config& root)>& configure,
                     const std::function<int(Node& node)>& body, Node::Options node_options) {
  if (const auto rc = parseCommandLine(app_, argc, argv)) return *rc;
  setupLogging(name_);
  // Start-up errors go to stderr as one plain line (the launcher's log shows it as it is).
  std::string report;
  try {
    const Config root = Config::loadConfiguration(config_files_);
    if (print_config_) {
      ConfigReport r;
      configure(root);
      report = configReportForProgram(name_, r.entries(), config_files_);
    } else {
      configure(root);
    }
  } catch (const ConfigError& e) {
    std::cerr << name_ << ": " << e.what() << "\n";
    return exit_code::kBadConfig;
  } catch (const std::exception& e) {
    std::cerr << name_ << ": start-up failed: " << e.what() << "\n";
    return exit_code::kFailure;
  }
  std::string files;
  for (const std::string& f : config_files_) files += " " + f;
  if (files.empty()) files = " (the built-in defaults)";
  if (print_config_) {
    std::cout << report;
    return exit_code::kOk;
  }
  if (check_config_) {
    std::cout << name_ << ": configuration usable" << files << "\n";
    return exit_code::kOk;
  }
  // Which build and which configuration, first in the process's log: what a log read later, or
  // the logs of two computers side by side, must be able to tell.
  spdlog::info("{}; configuration{}", versionString(), files);
  try {
    Node node(name_, lcm_url_, node_options);
    return body(node);
  } catch (const LcmUrlError& e) {
    std::cerr << name_ << ": " << e.what() << "\n";
    return exit_code::kFailure;
  } catch (const ConfigError& e) {
    std::cerr << name_ << ": " << e.what() << "\n";
    return exit_code::kBadConfig;
  } catch (const std::exception& e) {
    spdlog::critical("{}: {}", name_, e.what());
    return exit_code::kFailure;
  }
}

}  // namespace lasonic
