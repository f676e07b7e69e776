// lasonic-complement: complement extraction as a live process (DESIGN.md steps 1-3).
// LASER_SCAN + ODOMETRY -> RADAR_MAP; SONAR_RING -> SONAR_HYPOTHESIS, SONAR_COMPLEMENT.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <iostream>

#include "core/config.hpp"
#include "core/logging.hpp"
#include "lcmio/node.hpp"
#include "stages/complement_stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{"lasonic-complement: Radar Map, hypothetical sonar scan and complementary sonar readings"};
  std::string config_file;
  std::string url = lasonic::kDefaultLcmUrl;
  app.add_option("--config", config_file, "YAML configuration; its `complement:` section is used")
      ->check(CLI::ExistingFile);
  app.add_option("--lcm-url", url, "LCM URL")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  lasonic::setupLogging("lasonic-complement");
  lasonic::ComplementConfig cfg;
  try {
    const lasonic::Config root = config_file.empty() ? lasonic::Config{} : lasonic::Config::loadFile(config_file);
    cfg = lasonic::complementConfig(root.section("complement"));
  } catch (const lasonic::ConfigError& e) {
    std::cerr << "lasonic-complement: " << e.what() << "\n";
    return 2;
  }
  try {
    lasonic::Node node("lasonic-complement", url);
    lasonic::ComplementStage stage(node, cfg);
    return node.run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
