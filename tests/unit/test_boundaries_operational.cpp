// Boundaries and guards of the operational level that no other test pinned down: each test here
// was written against a changed rule (a comparison made inclusive, a check dropped) that every
// other unit test still passed, and fails with that change. The rule is named in each comment.
#include <gtest/gtest.h>
#include <cmath>
#include <vector>
#include "core/config.hpp"
#include "operational/agm.hpp"
#include "operational/laser_memory.hpp"
#include "operational/mover_prediction.hpp"
#include "operational/sector_map.hpp"
using namespace lasonic;
using geom::Vec2;

// The constructor refuses inconsistent parameters.
TEST(OperationalBoundaries, AgmCtorRejectsNeighbourhoodWiderThanWindow) {
  AgmParams p;
  p.size = 5;
  p.t = 3;
  EXPECT_THROW(AccumulativeGridMap{p}, std::invalid_argument);
}
TEST(OperationalBoundaries, AgmCtorRejectsRecenterMinAboveMax) {
  AgmParams p;
  p.recenter_max_cells = 2;
  p.recenter_min_cells = 3;
  EXPECT_THROW(AccumulativeGridMap{p}, std::invalid_argument);
}
// A G_T above g_max is never reached.
TEST(OperationalBoundaries, AgmConfigGThresholdAboveGMax) {
  EXPECT_THROW(agmParams(Config::fromString("agm: {g_max: 5, g_threshold: 6}").section("agm")), ConfigError);
}
// Exactly h_max_m driven is not "more than": kept.
TEST(OperationalBoundaries, AgmDistanceRevisionBoundary) {
  AgmParams p;
  p.size = 11;
  p.cell_size = 1.0;
  p.t = 1;
  p.g_threshold = 2;
  p.h_max = 1000;
  p.g_max = 5;
  p.h_max_m = 2.0;
  p.recenter_max_cells = 4;
  AccumulativeGridMap m(p);
  m.centreOn({0.5, 0.5});
  m.follow({0.5, 0.5}, 0);
  m.update({{6.5 - 5 + 0.0, 0.5}});  // any cell in the window
  int ix = 0, iy = 0;
  ASSERT_TRUE(m.cellAt({1.5, 0.5}, ix, iy));
  for (int i = 1; i <= 2; ++i) {
    m.follow({0.5 + i, 0.5}, 0);
    m.update({});
  }
  EXPECT_DOUBLE_EQ(m.odometer(), 2.0);
  EXPECT_EQ(m.g(ix, iy), 1);  // driven exactly h_max_m: kept
  m.follow({3.5, 0.5}, 0);
  m.update({});
  EXPECT_EQ(m.g(ix, iy), 0);
}
// Fewer than 3 sectors.
TEST(OperationalBoundaries, SectorMapRejectsTwoSectors) {
  SectorMapParams p;
  p.sectors = 2;
  EXPECT_THROW(SectorMap{p}, std::invalid_argument);
}
// Laser exactly laser_stale_s old is still fresh.
TEST(OperationalBoundaries, LaserExactlyStaleSOldIsFresh) {
  SectorMap s({});
  AgmParams ap;
  ap.g_threshold = 2;
  ap.h_max = 1000;
  AccumulativeGridMap agm(ap);
  s.setLaserPoints(0, {Vec2(1.35, 0)});
  EXPECT_FALSE(s.update(500'000, {0, 0, 0}, agm).laser_stale);
  EXPECT_TRUE(s.update(500'001, {0, 0, 0}, agm).laser_stale);
}
// A cluster seen 2 s apart is not "the scan before": no velocity, no mover.
namespace {
void blob(std::vector<TimedPoint>& scan, const Vec2& c, int64_t t) {
  const double a0 = std::atan2(-c.y(), -c.x());
  for (int i = -6; i <= 6; ++i) scan.push_back({c + 0.25 * geom::unitVector(a0 + i * 0.12), t});
}
}  // namespace
TEST(OperationalBoundaries, MoverPairsOnlyWithinOneSecond) {
  MoverPrediction mp;
  int movers = 0;
  for (int i = 0; i < 4; ++i) {  // 2 s apart, 1 m apart: 0.5 m/s each time, the same way
    std::vector<TimedPoint> s;
    blob(s, {1.5, -1.5 + 1.0 * i}, i * 2'000'000);
    mp.update(s, Vec2::Zero());
    movers += mp.movers();
  }
  EXPECT_EQ(movers, 0);
}
// A slow walker (0.35 m/s: above min_speed, below agree_speed) is not a mover on its first pairing.
TEST(OperationalBoundaries, SlowWalkerNotAMoverOnFirstPairing) {
  MoverPrediction mp;
  std::vector<int> movers;
  for (int i = 0; i < 3; ++i) {
    std::vector<TimedPoint> s;
    blob(s, {1.5, -0.7 + 0.07 * i}, i * 200'000);
    mp.update(s, Vec2::Zero());
    movers.push_back(mp.movers());
  }
  EXPECT_EQ(movers[1], 0);
  EXPECT_EQ(movers[2], 1);
}
// A runner (2 m/s) turning 20 deg between pairings agrees within half its speed.
TEST(OperationalBoundaries, FastTurningRunnerStaysAMover) {
  MoverPrediction mp;
  Vec2 c(1.5, -1.0);
  const double step = 2.0 * 0.2;  // 2 m/s, 0.2 s
  std::vector<Vec2> pos = {
      c, c + step * geom::unitVector(geom::deg2rad(90)),
      c + step * geom::unitVector(geom::deg2rad(90)) + step * geom::unitVector(geom::deg2rad(110))};
  int last = -1;
  for (int i = 0; i < 3; ++i) {
    std::vector<TimedPoint> s;
    blob(s, pos[i], i * 200'000);
    mp.update(s, Vec2::Zero());
    last = mp.movers();
  }
  EXPECT_EQ(last, 1);
}
// A coasting mover that walks beyond reach is dropped.
TEST(OperationalBoundaries, CoastingMoverBeyondReachIsDropped) {
  LaserMemory m({3.0, 2.0, 1.0});
  struct Blind {
    bool operator()(const Vec2&) const { return false; }
  };
  const SectorMap::MovingPoint seen{{-1.5, 0.0}, {-1.0, 0.0}, 0};  // 1.5 m away, walking away at 1 m/s
  m.update(0, Vec2::Zero(), {}, {seen}, Blind{});
  m.update(100'000, Vec2::Zero(), {}, {}, Blind{});
  ASSERT_EQ(m.coastingMovers().size(), 1u);          // at 1.6 m
  m.update(600'000, Vec2::Zero(), {}, {}, Blind{});  // at 2.1 m: beyond reach
  EXPECT_TRUE(m.coastingMovers().empty());
}
