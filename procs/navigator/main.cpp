// lasonic-navigator: the tactical level as a live process (Jörg 1995 sec. 3.4).
// SONAR_COMPLEMENT + RADAR_MAP + ODOMETRY -> AGM_TACTICAL, AGM_LINES, CURRENT_SENSOR_MAP
// (at its own rate, independent of the pilot's; it may run on another host).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <iostream>

#include "core/config.hpp"
#include "core/logging.hpp"
#include "lcmio/node.hpp"
#include "stages/navigator_stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{"lasonic-navigator: tactical Accumulative Grid Map, line generation and Current Sensor Map"};
  std::string config_file;
  std::string url = lasonic::kDefaultLcmUrl;
  app.add_option("--config", config_file, "YAML configuration; its `navigator:` section is used")
      ->check(CLI::ExistingFile);
  app.add_option("--lcm-url", url, "LCM URL")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  lasonic::setupLogging("lasonic-navigator");
  lasonic::NavigatorConfig cfg;
  try {
    const lasonic::Config root = config_file.empty() ? lasonic::Config{} : lasonic::Config::loadFile(config_file);
    cfg = lasonic::navigatorConfig(root.section("navigator"));
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-navigator: " << e.what() << "\n";
    return 2;
  }
  try {
    lasonic::Node node("lasonic-navigator", url);
    lasonic::NavigatorStage stage(node, cfg);
    return node.run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
