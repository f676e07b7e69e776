// Boundaries of the sector-map scoring that no other test pinned down (README "Evaluation"): each
// test here was written against a changed rule (the tolerance or the range left out, a guard
// dropped) that every other unit test still passed, and fails with that change.
#include <gtest/gtest.h>
#include <algorithm>
#include "eval/evaluate.hpp"
#include "eval/observability.hpp"
#include "sim_state_fixture.hpp"
using namespace lasonic;
using namespace lasonic::eval;
namespace {
sim::Scenario boxRoom() {
  return sim::parseScenario(Config::fromString(R"(
name: t
duration_s: 10
seed: 1
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[4,0],[4,4],[0,4]]}
  - {shape: circle, material: mesh, center: [3.0, 2.0], radius: 0.1}
robot: {radius: 0.35, path: [[2,2],[2.5,2]], speed: 0.1}
)"));
}
sector_map_t exactLaserMap(const sim::Scenario& sc, int n = 48) {
  sector_map_t sm{};
  sm.utime = 500'000; sm.robot_radius = 0.35f; sm.max_range = 3.0f; sm.nsectors = n;
  sim::WorldGeometry world(sc);
  const auto truth = trueSectorDistances(world, {2, 2, 0}, 0.35, n, 3.0);
  for (int k = 0; k < n; ++k) {
    sm.distance.push_back(static_cast<float>(truth[k])); sm.laser_distance.push_back(static_cast<float>(truth[k]));
    sm.sonar_distance.push_back(-1); sm.remembered_distance.push_back(-1);
    sm.source.push_back(int8_t{sector_map_t::SOURCE_LASER});
  }
  return sm;
}
}  // namespace
// a report within the tolerance short of the truth is no false alarm.
TEST(EvalBoundaries, ReportWithinToleranceShortIsNoFalseAlarm) {
  EvalOptions o; SectorSample s; s.truth = 1.0f;
  EXPECT_FALSE(sectorFalseAlarm(1.0 - 0.5 * o.sector_tolerance, s, o));
  EXPECT_TRUE(sectorFalseAlarm(1.0 - 2.0 * o.sector_tolerance, s, o));
}
// a report beyond sector_range is no false alarm.
TEST(EvalBoundaries, ReportBeyondSectorRangeIsNoFalseAlarm) {
  EvalOptions o; SectorSample s; s.truth = 3.0f;
  EXPECT_FALSE(sectorFalseAlarm(o.sector_range + 0.3, s, o));
}
// a map from before the first sonar group is counted, not scored.
TEST(EvalBoundaries, MapBeforeFirstSonarIsWarmup) {
  const auto sc = boxRoom();
  RunLog log;
  log.sim_states = {lasonic::testing::state(0, 2, 2, 0), lasonic::testing::state(1'000'000, 2, 2, 0)};
  sector_map_t sm = exactLaserMap(sc);
  sm.sonar_age_s = -1;
  log.sector_maps.push_back(sm);
  Metrics m;
  evalSectorMap(log, sc, EvalOptions{}, m);
  EXPECT_EQ(m.number("sector_map.maps_before_first_data"), 1.0);
  EXPECT_EQ(m.number("sector_map.maps"), 0.0);
}
// a map of fewer than 3 sectors is malformed: not scored.
TEST(EvalBoundaries, TwoSectorMapIsNotScored) {
  const auto sc = boxRoom();
  RunLog log;
  log.sim_states = {lasonic::testing::state(0, 2, 2, 0), lasonic::testing::state(1'000'000, 2, 2, 0)};
  log.sector_maps.push_back(exactLaserMap(sc, 2));
  Metrics m;
  evalSectorMap(log, sc, EvalOptions{}, m);
  EXPECT_EQ(m.number("sector_map.maps"), 0.0);
}
