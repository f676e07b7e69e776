// lasonic-pilot: the operational level as a live process (README "Method, as implemented",
// steps 4-5). SONAR_COMPLEMENT + LASER_SCAN + ODOMETRY -> SECTOR_MAP (every update),
// AGM_OPERATIONAL (lower rate).
#include "lcmio/process.hpp"
#include "stages/pilot_stage.hpp"

int main(int argc, char** argv) {
  lasonic::ProcessMain pm("lasonic-pilot", "lasonic-pilot: operational Accumulative Grid Map and Sector Map");
  lasonic::PilotConfig cfg;
  return pm.run(
      argc, argv, [&](const lasonic::Config& root) { cfg = lasonic::pilotConfigFromRoot(root); },
      [&](lasonic::Node& node) {
        lasonic::PilotStage stage(node, cfg);
        return node.run();
      });
}
