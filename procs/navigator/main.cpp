// lasonic-navigator: the tactical level as a live process (Jörg 1995 sec. 3.4).
// SONAR_COMPLEMENT + RADAR_MAP + ODOMETRY -> AGM_TACTICAL, AGM_LINES, CURRENT_SENSOR_MAP
// (at its own rate, independent of the pilot's; it may run on another host).
#include "lcmio/process.hpp"
#include "stages/navigator_stage.hpp"

int main(int argc, char** argv) {
  lasonic::ProcessMain pm("lasonic-navigator",
                          "lasonic-navigator: tactical Accumulative Grid Map, line generation and Current Sensor Map");
  lasonic::NavigatorConfig cfg;
  return pm.run(
      argc, argv, [&](const lasonic::Config& root) { cfg = lasonic::navigatorConfigFromRoot(root); },
      [&](lasonic::Node& node) {
        lasonic::NavigatorStage stage(node, cfg);
        return node.run();
      });
}
