// Baseline mappers (common/baselines/): HIMM increments, decrements, the growth-rate operator and
// its clamps; the log-odds cone clears free space and marks the arc; naive fusion keeps a
// specular ghost that complement extraction drops; the shared window and the SectorMap
// read-out of any occupancy window.
#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "baselines/grid_window.hpp"
#include "baselines/himm.hpp"
#include "baselines/log_odds.hpp"
#include "baselines/naive_fusion.hpp"
#include "complement/complement.hpp"
#include "operational/sector_map.hpp"

using namespace lasonic;
using namespace lasonic::baselines;
using geom::kPi;
using geom::Pose2;
using geom::Vec2;

namespace {
constexpr double kBeam = 30.0 * kPi / 180.0;
// The occupancy-layer flag of the window cell holding p.
bool occupied(const OccupancyWindow& w, const Vec2& p) {
  const auto gx = static_cast<int64_t>(std::floor(p.x() / w.cell_size)) - w.origin_x;
  const auto gy = static_cast<int64_t>(std::floor(p.y() / w.cell_size)) - w.origin_y;
  return w.occupied[static_cast<size_t>(gy * w.size + gx)] != 0;
}
}  // namespace

TEST(GridWindow, SegmentTraversalVisitsContiguousCellsFromStartToEnd) {
  for (const auto& [a, b] : std::vector<std::pair<Vec2, Vec2>>{
           {{0.05, 0.05}, {0.95, 0.35}}, {{0.55, 0.55}, {-0.73, 0.12}}, {{0.2, 0.2}, {0.2, -0.9}},
           {{0.0, 0.0}, {0.3, 0.3}}, {{1.23, -0.4}, {1.23, -0.4}}}) {
    std::vector<std::pair<int64_t, int64_t>> cells;
    forEachCellOnSegment(a, b, 0.1, [&](int64_t x, int64_t y) {
      cells.emplace_back(x, y);
      return true;
    });
    ASSERT_FALSE(cells.empty());
    EXPECT_EQ(cells.front(), std::make_pair(int64_t(std::floor(a.x() / 0.1)), int64_t(std::floor(a.y() / 0.1))));
    EXPECT_EQ(cells.back(), std::make_pair(int64_t(std::floor(b.x() / 0.1)), int64_t(std::floor(b.y() / 0.1))));
    for (size_t i = 1; i < cells.size(); ++i)  // 4-connected steps, no cell twice
      EXPECT_EQ(std::abs(cells[i].first - cells[i - 1].first) + std::abs(cells[i].second - cells[i - 1].second), 1);
    const std::set<std::pair<int64_t, int64_t>> distinct(cells.begin(), cells.end());
    EXPECT_EQ(distinct.size(), cells.size());
    // Every visited cell is crossed by the segment (its centre lies within half a diagonal).
    for (const auto& [x, y] : cells) {
      const Vec2 c((static_cast<double>(x) + 0.5) * 0.1, (static_cast<double>(y) + 0.5) * 0.1);
      EXPECT_LE(geom::distance({a, b}, c), 0.0708) << x << "," << y;
    }
  }
}

TEST(GridWindow, FollowKeepsGlobalCellsAndForgetsLeavers) {
  GridWindow<int> w({10, 1.0, 2}, 0);
  w.follow({0.5, 0.5});  // window centred on cell (0, 0): cells -5..4
  ASSERT_TRUE(w.inWindow(3, 0));
  w.value(w.index(3, 0)) = 7;
  w.setOccupied(w.index(3, 0), true);
  w.value(w.index(-5, 0)) = 9;
  EXPECT_FALSE(w.follow({2.5, 0.5}));  // 2 cells off: within the slack
  EXPECT_TRUE(w.follow({3.5, 0.5}));   // 3 cells off: re-centred on cell 3 (cells -2..7)
  EXPECT_EQ(w.value(w.index(3, 0)), 7);
  EXPECT_EQ(w.occupancy().occupied[w.index(3, 0)], 1);
  EXPECT_FALSE(w.inWindow(-5, 0));
  EXPECT_EQ(w.value(w.index(7, 0)), 0);  // new cells start empty
  EXPECT_EQ(w.occupancy().origin_x, -2);
}

// ------------------------------------------------------------------------------ HIMM

namespace {
HimmParams himmTestParams() {
  HimmParams p;  // 100 x 100 cells of 0.1 m, I+ 3, I- 1, CVmax 15, threshold 4
  return p;
}
}  // namespace

TEST(Himm, IncrementOnTheAxisDecrementInFrontClamp) {
  HimmGrid g(himmTestParams());
  const Pose2 s{0.05, 0.05, 0.0};  // sensor in cell (0, 0), looking along +x
  g.follow(s.position());
  g.insert(s, 1.0, false, 3.0);  // hit at (1.05, 0.05): cell (10, 0)
  EXPECT_EQ(g.cv({1.05, 0.05}), 3);
  EXPECT_FALSE(occupied(g.occupancy(), {1.05, 0.05}));
  EXPECT_EQ(g.cv({1.05, 0.15}), 0);  // off the axis: untouched
  g.insert(s, 1.0, false, 3.0);
  EXPECT_EQ(g.cv({1.05, 0.05}), 6);  // second increment: now an obstacle (>= 4)
  EXPECT_TRUE(occupied(g.occupancy(), {1.05, 0.05}));
  for (int i = 0; i < 10; ++i) g.insert(s, 1.0, false, 3.0);
  EXPECT_EQ(g.cv({1.05, 0.05}), 15);  // CVmax
  // A shorter reading on the same axis: the old cell is not decremented (it lies behind the
  // new hit); a longer one decrements every cell in front of its own hit, the old one too.
  g.insert(s, 0.5, false, 3.0);
  EXPECT_EQ(g.cv({1.05, 0.05}), 15);
  EXPECT_EQ(g.cv({0.55, 0.05}), 3);
  g.insert(s, 1.5, false, 3.0);
  EXPECT_EQ(g.cv({1.05, 0.05}), 14);
  EXPECT_EQ(g.cv({0.55, 0.05}), 2);
  EXPECT_EQ(g.cv({1.55, 0.05}), 3);
  // Decrements stop at 0.
  for (int i = 0; i < 5; ++i) g.insert(s, 2.0, false, 3.0);
  EXPECT_EQ(g.cv({0.55, 0.05}), 0);
}

// A cell whose certainty value equals the threshold is an obstacle (CV >= threshold): with the
// threshold at one increment, one echo marks its cell.
TEST(Himm, ACellAtExactlyTheThresholdIsAnObstacle) {
  HimmParams p = himmTestParams();
  p.threshold = p.increment;
  HimmGrid g(p);
  const Pose2 s{0.05, 0.05, 0.0};
  g.follow(s.position());
  g.insert(s, 1.0, false, 3.0);
  EXPECT_EQ(g.cv({1.05, 0.05}), p.threshold);
  EXPECT_TRUE(occupied(g.occupancy(), {1.05, 0.05}));
}

TEST(Himm, GrowthRateOperatorAddsHalfTheNeighbours) {
  HimmGrid g(himmTestParams());
  const Pose2 s{0.05, 0.05, 0.0};
  g.follow(s.position());
  for (int i = 0; i < 3; ++i) g.insert(s, 1.0, false, 3.0);  // cell (10, 0): 9 (GRO: no neighbours)
  ASSERT_EQ(g.cv({1.05, 0.05}), 9);
  const Pose2 s2{0.05, 0.15, 0.0};  // one row up: cell (10, 1) is a neighbour of (10, 0)
  g.insert(s2, 1.0, false, 3.0);
  EXPECT_EQ(g.cv({1.05, 0.15}), 3 + 9 / 2);  // I+ plus half the neighbours' CV
  // Without the operator the same reading adds only I+.
  HimmParams p = himmTestParams();
  p.growth_rate_operator = false;
  HimmGrid plain(p);
  plain.follow(s.position());
  for (int i = 0; i < 3; ++i) plain.insert(s, 1.0, false, 3.0);
  plain.insert(s2, 1.0, false, 3.0);
  EXPECT_EQ(plain.cv({1.05, 0.15}), 3);
}

TEST(Himm, NoEchoClearsTheWholeAxisOnlyWhenConfigured) {
  HimmGrid g(himmTestParams());
  const Pose2 s{0.05, 0.05, 0.0};
  g.follow(s.position());
  g.insert(s, 2.0, false, 3.0);
  g.insert(s, 2.0, false, 3.0);
  ASSERT_EQ(g.cv({2.05, 0.05}), 6);
  g.insert(s, 0.0, true, 3.0);
  EXPECT_EQ(g.cv({2.05, 0.05}), 5);
  HimmParams p = himmTestParams();
  p.no_echo_clears = false;
  HimmGrid keep(p);
  keep.follow(s.position());
  keep.insert(s, 2.0, false, 3.0);
  keep.insert(s, 0.0, true, 3.0);
  EXPECT_EQ(keep.cv({2.05, 0.05}), 3);
}

TEST(Baselines, HugeRangesTouchOnlyTheWindow) {
  // A malformed range_max or reading (finite but absurd) must cost the window, not the range.
  HimmGrid h(himmTestParams());
  LogOddsGrid l(LogOddsParams{});
  const Pose2 s{0.05, 0.05, 0.3};
  h.follow(s.position());
  l.follow(s.position());
  h.insert(s, 2.0, false, 3.0);
  h.insert(s, 2.0, false, 3.0);
  const Vec2 hit = s.transform({2.0, 0.0});
  ASSERT_EQ(h.cv(hit), 6);
  h.insert(s, 0.0, true, 1e12);
  EXPECT_EQ(h.cv(hit), 5);
  h.insert(s, 1e12, false, 1e12);
  EXPECT_EQ(h.cv(hit), 4);
  l.insertSonar(s, 0.0, true, kBeam, 1e12);
  EXPECT_LT(l.probability(hit), 0.5);
  l.insertLaser(s.position(), s.transform({1e12, 0.0}));
  EXPECT_LT(l.probability(s.transform({3.0, 0.0})), 0.5);
}

TEST(Himm, ConfigKeysAndErrors) {
  const auto p = himmParams(Config::fromString("{increment: 2, threshold: 5, cell_size: 0.05}"));
  EXPECT_EQ(p.increment, 2);
  EXPECT_EQ(p.threshold, 5);
  EXPECT_DOUBLE_EQ(p.window.cell_size, 0.05);
  EXPECT_THROW(himmParams(Config::fromString("{threshold: 99}")), ConfigError);
  EXPECT_THROW(himmParams(Config::fromString("{colour: red}")), ConfigError);
}

// ------------------------------------------------------------------------------ log odds

TEST(LogOdds, ConeClearsFreeSpaceAndMarksTheArc) {
  LogOddsGrid g(LogOddsParams{});
  const Pose2 s{0.0, 0.0, 0.0};
  g.follow(s.position());
  g.insertSonar(s, 1.5, false, kBeam, 3.0);
  EXPECT_LT(g.probability({0.75, 0.05}), 0.5);   // on the axis before the arc: free
  EXPECT_LT(g.probability({1.05, 0.25}), 0.5);   // off the axis but inside the cone: free too
  EXPECT_GT(g.probability({1.45, 0.05}), 0.5);   // on the arc
  EXPECT_GT(g.probability({1.45, 0.35}), 0.5);   // on the arc, 13 deg off the axis
  EXPECT_DOUBLE_EQ(g.probability({1.05, 0.55}), 0.5);  // outside the cone (28 deg): untouched
  EXPECT_DOUBLE_EQ(g.probability({2.05, 0.05}), 0.5);  // behind the arc: untouched
  // One sonar reading is weak evidence: not yet an obstacle (p 0.65 < 0.7); a second one is.
  EXPECT_FALSE(occupied(g.occupancy(), {1.45, 0.05}));
  g.insertSonar(s, 1.5, false, kBeam, 3.0);
  EXPECT_TRUE(occupied(g.occupancy(), {1.45, 0.05}));
}

TEST(LogOdds, RepeatedFreeReadingsClearAnObstacleAndLaserMarksItsEnd) {
  LogOddsGrid g(LogOddsParams{});
  const Pose2 s{0.0, 0.0, 0.0};
  g.follow(s.position());
  const Vec2 cell{1.05, 0.05};
  for (int i = 0; i < 3; ++i) g.insertLaser(s.position(), cell);
  EXPECT_GT(g.probability(cell), 0.95);
  EXPECT_LT(g.probability({0.55, 0.05}), 0.3);  // the ray before its end: free
  // Longer sonar echoes along the same axis (a specular or transparent obstacle the sound
  // does not hear) clear it: free space is cleared.
  for (int i = 0; i < 10; ++i) g.insertSonar(s, 2.5, false, kBeam, 3.0);
  EXPECT_LT(g.probability(cell), 0.5);
  // No echo clears the whole cone only when configured.
  LogOddsParams p;
  p.no_echo_clears = false;
  LogOddsGrid keep(p);
  keep.follow(s.position());
  keep.insertLaser(s.position(), cell);
  const double before = keep.probability(cell);
  keep.insertSonar(s, 0.0, true, kBeam, 3.0);
  EXPECT_DOUBLE_EQ(keep.probability(cell), before);
  g.insertSonar(s, 0.0, true, kBeam, 3.0);
  EXPECT_LT(g.probability({2.5, 0.05}), 0.5);
}

TEST(LogOdds, ConfigRejectsNonsense) {
  EXPECT_THROW(logOddsParams(Config::fromString("{sonar_free: 0.6}")), ConfigError);
  EXPECT_THROW(logOddsParams(Config::fromString("{laser_occupied: 1.0}")), ConfigError);
  EXPECT_THROW(logOddsParams(Config::fromString("{occupied_threshold: 0.99}")), ConfigError);
  EXPECT_DOUBLE_EQ(logOddsParams(Config::fromString("{sonar_occupied: 0.7}")).sonar_occupied, 0.7);
}

// A probability of 0.5 is no evidence either way: an "occupied" reading must lie above it, a
// "free" one below it.
TEST(LogOdds, AnEvenProbabilityIsNoEvidence) {
  for (const char* bad : {"{sonar_occupied: 0.5}", "{laser_occupied: 0.5}", "{sonar_free: 0.5}", "{laser_free: 0.5}"})
    EXPECT_THROW(logOddsParams(Config::fromString(bad)), ConfigError) << bad;
  EXPECT_DOUBLE_EQ(logOddsParams(Config::fromString("{sonar_occupied: 0.51}")).sonar_occupied, 0.51);
}

// ------------------------------------------------------------------------------ naive fusion

TEST(NaiveFusion, KeepsASpecularGhostThatComplementExtractionDrops) {
  // A laser-visible wall 1.0 m ahead of the sensor; the sound mirrored off it and came back the
  // long way: the sensor reads 2.0 m (specular). The Radar Map's hypothesis is 1.0 m.
  const double wall = 1.0, reading = 2.0, tol = 0.10, limit = 2.20;
  EXPECT_EQ(complement::classify(reading, false, wall, tol, limit), complement::SonarClass::False);

  NaiveFusionParams p;  // the pilot's defaults: neighbours bearing, evidence placement, G_T 2
  NaiveFusion naive(p);
  const Pose2 sensor{0.35, 0.0, 0.0};
  for (int i = 0; i < 2; ++i)
    naive.insertGroup(i * 30'000, {{0, sensor, reading, true}}, Vec2(0, 0), 0.0);
  int ix = 0, iy = 0;
  ASSERT_TRUE(naive.agm().cellAt(sensor.transform({reading, 0.0}), ix, iy));
  EXPECT_GE(naive.agm().gp(ix, iy), 2);  // a confirmed ghost 1 m behind the wall

  // The pilot's read-out (laser points on the wall) reports it as an obstacle in that sector...
  SectorMap map({});
  std::vector<Vec2> wall_points;
  for (double y = -1.0; y <= 1.0; y += 0.01) wall_points.push_back({sensor.x + wall, y});
  map.setLaserPoints(0, wall_points);
  map.setSonarTime(30'000);
  const auto& st = map.update(30'000, {0, 0, 0}, naive.agm());
  EXPECT_EQ(st.source[24], SectorSource::Laser);  // ... behind the wall, which the laser sees nearer
  // ... and a ghost where the laser sees nothing would be reported: without the wall it is sonar.
  SectorMap blind({});
  blind.setSonarTime(30'000);
  EXPECT_EQ(blind.update(30'000, {0, 0, 0}, naive.agm()).source[24], SectorSource::Sonar);
  // A reading without an echo is no hit.
  NaiveFusion quiet(p);
  for (int i = 0; i < 2; ++i) quiet.insertGroup(i * 30'000, {{0, sensor, reading, false}}, Vec2(0, 0), 0.0);
  EXPECT_EQ(quiet.agm().g(ix, iy), 0);
}

// Naive fusion counts the ring's groups as the pilot does, group 0 among them: a ring of four
// groups fired in turn gives the AGM a memory of h_max_ring_cycles x 4 update cycles.
TEST(NaiveFusion, TheMemoryFollowsARingOfFourGroupsCountingGroupZero) {
  NaiveFusionParams p;
  p.h_max_ring_cycles = 3;
  NaiveFusion naive(p);
  for (int i = 0; i < 12; ++i) naive.insertGroup(i * 30'000, {}, Vec2(0, 0), 0.0, i % 4);
  EXPECT_EQ(naive.agm().params().h_max, 12);
}

// ------------------------------------------------------------------------------ read-out

TEST(SectorMapReadout, AnyOccupancyWindowReadsLikeTheAgm) {
  AgmParams ap;
  ap.h_max = 1000;
  AccumulativeGridMap agm(ap);
  agm.centreOn({0, 0});
  const std::vector<Vec2> pts = {{1.0, 0.2}, {-0.8, 1.3}, {0.3, -2.0}, {2.2, 2.2}};
  for (const Vec2& p : pts) agm.update({p, p});
  OccupancyWindow w;
  w.origin_x = agm.originX();
  w.origin_y = agm.originY();
  w.size = agm.size();
  w.cell_size = agm.cellSize();
  w.occupied.assign(static_cast<size_t>(w.size * w.size), 0);
  for (int iy = 0; iy < w.size; ++iy)
    for (int ix = 0; ix < w.size; ++ix)
      w.occupied[static_cast<size_t>(iy * w.size + ix)] = agm.gp(ix, iy) >= 2 ? 1 : 0;
  SectorMap a({}), b({});
  a.setSonarTime(0);
  b.setSonarTime(0);
  const Pose2 pose{0.1, -0.2, 0.7};
  const auto& sa = a.update(0, pose, agm);
  const auto& sb = b.update(0, pose, w);
  int reported = 0;
  for (size_t k = 0; k < sa.distance.size(); ++k) {
    EXPECT_FLOAT_EQ(sa.distance[k], sb.distance[k]) << k;
    EXPECT_EQ(sa.source[k], sb.source[k]) << k;
    reported += sa.distance[k] >= 0;
  }
  EXPECT_GE(reported, 4);
  w.occupied.pop_back();
  EXPECT_THROW(b.update(0, pose, w), std::invalid_argument);
}
