// lasonic-complement: complement extraction as a live process (README "Method, as implemented",
// steps 1-3). LASER_SCAN + ODOMETRY -> RADAR_MAP; SONAR_RING -> SONAR_HYPOTHESIS, SONAR_COMPLEMENT.
#include "lcmio/process.hpp"
#include "stages/complement_stage.hpp"

int main(int argc, char** argv) {
  lasonic::ProcessMain pm("lasonic-complement",
                          "lasonic-complement: Radar Map, hypothetical sonar scan and complementary sonar readings");
  lasonic::ComplementConfig cfg;
  return pm.run(
      argc, argv, [&](const lasonic::Config& root) { cfg = lasonic::complementConfig(root.section("complement")); },
      [&](lasonic::Node& node) {
        lasonic::ComplementStage stage(node, cfg);
        return node.run();
      });
}
