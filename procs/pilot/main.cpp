// lasonic-pilot: the operational level as a live process (DESIGN.md steps 4-5).
// SONAR_COMPLEMENT + LASER_SCAN + ODOMETRY -> SECTOR_MAP (every update), AGM_OPERATIONAL (lower rate).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <iostream>

#include "core/config.hpp"
#include "core/logging.hpp"
#include "lcmio/node.hpp"
#include "stages/pilot_stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{"lasonic-pilot: operational Accumulative Grid Map and Sector Map"};
  std::string config_file;
  std::string url = lasonic::kDefaultLcmUrl;
  app.add_option("--config", config_file, "YAML configuration; its `pilot:` section is used")
      ->check(CLI::ExistingFile);
  app.add_option("--lcm-url", url, "LCM URL")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  lasonic::setupLogging("lasonic-pilot");
  lasonic::PilotConfig cfg;
  try {
    const lasonic::Config root = config_file.empty() ? lasonic::Config{} : lasonic::Config::loadFile(config_file);
    cfg = lasonic::pilotConfig(root.section("pilot"));
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-pilot: " << e.what() << "\n";
    return 2;
  }
  try {
    lasonic::Node node("lasonic-pilot", url);
    lasonic::PilotStage stage(node, cfg);
    return node.run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
