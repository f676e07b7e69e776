// SectorMap: sector geometry, laser moved into the current pose, sonar from the AGM, min and
// copy rules, staleness.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

#include "operational/laser_shadow.hpp"
#include "operational/sector_map.hpp"

using namespace lasonic;
using geom::kPi;
using geom::Pose2;
using geom::Vec2;

namespace {

constexpr double kDeg = kPi / 180.0;
constexpr int64_t kSec = 1'000'000;

AgmParams agmParams01() {
  AgmParams p;  // 100 x 100 cells of 0.1 m
  p.g_threshold = 2;
  p.h_max = 1000;
  return p;
}

// Makes a cell with Gp >= 2 around global point p (two hits in its cell).
void obstacle(AccumulativeGridMap& agm, const Vec2& p) { agm.update({p, p}); }

// Global point at `bearing` (robot frame) and distance `d` from the boundary of a robot at `pose`.
Vec2 pointAt(const Pose2& pose, double bearing, double d, double radius = 0.35) {
  return pose.transform(geom::unitVector(bearing) * (d + radius));
}

}  // namespace

TEST(SectorMap, SectorGeometry) {
  SectorMap s({});
  EXPECT_EQ(s.sectorOf(-kPi), 0);
  EXPECT_EQ(s.sectorOf(kPi), 0);  // pi and -pi are the same bearing
  EXPECT_EQ(s.sectorOf(0.0), 24);
  EXPECT_EQ(s.sectorOf(-0.1 * kDeg), 23);
  EXPECT_EQ(s.sectorOf(7.4 * kDeg), 24);
  EXPECT_EQ(s.sectorOf(7.5 * kDeg + 1e-9), 25);
  EXPECT_EQ(s.sectorOf(179.9 * kDeg), 47);
  EXPECT_EQ(s.sectorOf(2 * kPi + 1 * kDeg), 24);
}

TEST(SectorMap, LaserDistanceFromTheBoundaryAndMaxRange) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{1.0, 1.0, kPi / 2};  // facing global +y
  s.setLaserPoints(0, {{1.0, 3.0}, {1.0, 2.5}, {-3.0, 1.0}, {1.1, 1.0}});
  const auto& m = s.update(0, pose, agm);
  // (1, 2.5) is straight ahead, 1.5 m from the centre: 1.15 m from the boundary (the nearer
  // of the two points ahead).
  EXPECT_FLOAT_EQ(m.laser[24], 1.15f);
  EXPECT_FLOAT_EQ(m.distance[24], 1.15f);
  EXPECT_EQ(m.source[24], SectorSource::Laser);
  // (-3, 1) is 4 m to the left: beyond max_range (3 m from the boundary), not reported.
  EXPECT_FLOAT_EQ(m.laser[static_cast<size_t>(s.sectorOf(kPi / 2))], -1.0f);
  // (1.1, 1) is to the right, inside the robot's circle: distance 0.
  EXPECT_FLOAT_EQ(m.laser[static_cast<size_t>(s.sectorOf(-kPi / 2))], 0.0f);
  int known = 0;
  for (float d : m.laser) known += d >= 0;
  EXPECT_EQ(known, 2);
}

// setLaserPoints hands the previous list back emptied (its storage for the caller's next scan);
// the map then holds the new list alone.
TEST(SectorMap, SetLaserPointsHandsBackThePreviousListEmptied) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.0, 0.0, 0.0};
  std::vector<Vec2> first(100, Vec2(1.0, 0.0));  // 0.65 m ahead of the boundary
  EXPECT_TRUE(s.setLaserPoints(0, first).empty());
  std::vector<Vec2> back = s.setLaserPoints(1, {{0.0, 2.0}});  // 1.65 m to the left
  EXPECT_TRUE(back.empty());
  EXPECT_GE(back.capacity(), 100u);  // the first list's storage
  const auto& m = s.update(1, pose, agm);
  EXPECT_FLOAT_EQ(m.laser[24], -1.0f);  // the first list is gone
  EXPECT_FLOAT_EQ(m.laser[static_cast<size_t>(s.sectorOf(kPi / 2))], 1.65f);
}
TEST(SectorMap, LaserPointsAreMovedIntoTheCurrentPose) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  // Scan taken at pose A: a point 2 m ahead.
  const Pose2 a{0.0, 0.0, 0.0};
  s.setLaserPoints(0, {pointAt(a, 0.0, 1.65)});  // global (2, 0)
  // The robot has since driven 0.5 m forward and turned left by 90 deg: the point is now
  // 1.5 m to its right (bearing -90 deg).
  const Pose2 b{0.5, 0.0, kPi / 2};
  const auto& m = s.update(100'000, b, agm);
  const int right = s.sectorOf(-kPi / 2);
  EXPECT_NEAR(m.laser[right], 1.5 - 0.35, 1e-6);
  EXPECT_EQ(m.source[right], SectorSource::Laser);
  EXPECT_FLOAT_EQ(m.laser[24], -1.0f);
}

TEST(SectorMap, SonarCellAtItsNearestPointAndCopiedIntoNeighbours) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  agm.centreOn({0.05, 0.05});
  obstacle(agm, {1.05, 0.05});  // cell [1.0, 1.1) x [0, 0.1)
  s.setSonarTime(0);
  const auto& m = s.update(0, {0.05, 0.05, 0.0}, agm);
  // Nearest point of the cell: (1.0, 0.05), 0.95 m from the centre.
  EXPECT_NEAR(m.sonar[24], 0.60, 1e-6);
  EXPECT_EQ(m.source[24], SectorSource::Sonar);
  EXPECT_NEAR(m.distance[23], 0.60, 1e-6);
  EXPECT_EQ(m.source[23], SectorSource::SonarCopied);
  EXPECT_EQ(m.source[25], SectorSource::SonarCopied);
  for (int k : {22, 26, 0, 47}) {
    EXPECT_EQ(m.source[static_cast<size_t>(k)], SectorSource::None) << k;
    EXPECT_FLOAT_EQ(m.distance[static_cast<size_t>(k)], -1.0f);
  }
}

TEST(SectorMap, CellsBelowTheThresholdAreIgnored) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  agm.centreOn({0.05, 0.05});
  agm.update({{1.05, 0.05}});  // G = 1 < G_T: Gp = 0
  const auto& m = s.update(0, {0.05, 0.05, 0.0}, agm);
  EXPECT_EQ(m.source[24], SectorSource::None);
}

TEST(SectorMap, MinRuleAndSource) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});  // sonar 0.60 in sector 24, copies in 23 and 25
  s.setSonarTime(0);
  s.setLaserPoints(0, {pointAt(pose, 3.75 * kDeg, 0.50),     // sector 24: laser nearer
                       pointAt(pose, 3.75 * kDeg + 7.5 * kDeg, 0.90),   // 25: copy nearer
                       pointAt(pose, 3.75 * kDeg - 7.5 * kDeg, 0.60)}); // 23: tie -> laser
  const auto& m = s.update(0, pose, agm);
  EXPECT_NEAR(m.distance[24], 0.50, 1e-5);
  EXPECT_EQ(m.source[24], SectorSource::Laser);
  EXPECT_NEAR(m.sonar[24], 0.60, 1e-5);
  EXPECT_NEAR(m.distance[25], 0.60, 1e-5);
  EXPECT_EQ(m.source[25], SectorSource::SonarCopied);
  EXPECT_NEAR(m.laser[25], 0.90, 1e-5);
  EXPECT_NEAR(m.distance[23], 0.60, 1e-5);
  EXPECT_EQ(m.source[23], SectorSource::Laser);
}

TEST(SectorMap, CopyRuleSparesSectorsWithOwnSonarData) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});                        // sector 24: own 0.60
  obstacle(agm, pointAt(pose, 11.25 * kDeg, 1.50));   // sector 25: own, farther
  obstacle(agm, pointAt(pose, -26.25 * kDeg, 1.00));  // sector 20: own
  obstacle(agm, pointAt(pose, -11.25 * kDeg, 2.00));  // sector 22: own
  const auto& m = s.update(0, pose, agm);
  // 25 keeps its own (farther) value: the neighbour's copy does not overwrite it.
  EXPECT_EQ(m.source[25], SectorSource::Sonar);
  EXPECT_NEAR(m.sonar[25], 1.50, 0.1);
  // 26 gets 25's copy; 23 gets the nearer of 22's and 24's copies; 21 the nearer of 20's and 22's.
  EXPECT_EQ(m.source[26], SectorSource::SonarCopied);
  EXPECT_FLOAT_EQ(m.sonar[26], m.sonar[25]);
  EXPECT_EQ(m.source[23], SectorSource::SonarCopied);
  EXPECT_FLOAT_EQ(m.sonar[23], m.sonar[24]);
  EXPECT_EQ(m.source[21], SectorSource::SonarCopied);
  EXPECT_FLOAT_EQ(m.sonar[21], m.sonar[20]);
  EXPECT_EQ(m.source[19], SectorSource::SonarCopied);
  EXPECT_EQ(m.source[22], SectorSource::Sonar);
  EXPECT_EQ(m.source[27], SectorSource::None);
}

TEST(SectorMap, CopyOverOwnTakesANearerNeighbourIntoSectorsWithTheirOwn) {
  SectorMapParams p;
  p.copy_over_own = true;
  SectorMap s(p);
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});                        // sector 24: own 0.60
  obstacle(agm, pointAt(pose, 11.25 * kDeg, 1.50));   // sector 25: own, farther
  obstacle(agm, pointAt(pose, -11.25 * kDeg, 0.30));  // sector 22: own, nearer than 24
  const auto& m = s.update(0, pose, agm);
  // 25 takes 24's nearer value as a copy over its own; 24 keeps its own (its neighbours 23 and
  // 25 hold nothing nearer of their own); 23 gets the nearer of 22's and 24's.
  EXPECT_EQ(m.source[25], SectorSource::SonarCopied);
  EXPECT_FLOAT_EQ(m.sonar[25], m.sonar[24]);
  EXPECT_EQ(m.source[24], SectorSource::Sonar);
  EXPECT_NEAR(m.sonar[24], 0.60, 0.1);
  EXPECT_EQ(m.source[23], SectorSource::SonarCopied);
  EXPECT_FLOAT_EQ(m.sonar[23], m.sonar[22]);
  // A farther neighbour never replaces a sector's own value; copies are of own values only
  // (26 gets 25's own 1.50, not the copy 25 now holds).
  EXPECT_EQ(m.source[22], SectorSource::Sonar);
  EXPECT_NEAR(m.sonar[22], 0.30, 0.1);
  EXPECT_EQ(m.source[26], SectorSource::SonarCopied);
  EXPECT_NEAR(m.sonar[26], 1.50, 0.1);
  // The paper's rule keeps 25's own, farther value.
  SectorMap paper({});
  EXPECT_EQ(paper.update(0, pose, agm).source[25], SectorSource::Sonar);
}

// copy_held false: a cell the AGM keeps beyond h_max because no sound went through it gives its
// sector a value, and no copies; a fresh cell beside it still copies.
TEST(SectorMap, AHeldCellIsNotCopied) {
  AgmParams ap = agmParams01();
  ap.h_max = 2;
  ap.hold_unpassed = 10;
  AccumulativeGridMap agm(ap);
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});                       // sector 24, hit in cycle 1
  for (int i = 0; i < 3; ++i) agm.update({});        // H = 3 > h_max: held
  obstacle(agm, pointAt(pose, 33.75 * kDeg, 1.50));  // sector 28: fresh
  SectorMapParams p;
  p.copy_held = false;
  SectorMap s(p), paper({});
  const auto& m = s.update(0, pose, agm);
  EXPECT_EQ(m.source[24], SectorSource::Sonar);
  EXPECT_NEAR(m.sonar[24], 0.60, 0.1);
  EXPECT_EQ(m.source[23], SectorSource::None);
  EXPECT_EQ(m.source[25], SectorSource::None);
  EXPECT_EQ(m.source[27], SectorSource::SonarCopied);
  EXPECT_EQ(m.source[29], SectorSource::SonarCopied);
  // The paper's rule copies it.
  EXPECT_EQ(paper.update(0, pose, agm).source[25], SectorSource::SonarCopied);
}

TEST(SectorMap, CopyWrapsAroundTheRing) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, pointAt(pose, -kPi + 3.75 * kDeg, 1.0));  // sector 0
  const auto& m = s.update(0, pose, agm);
  EXPECT_EQ(m.source[0], SectorSource::Sonar);
  EXPECT_EQ(m.source[47], SectorSource::SonarCopied);
  EXPECT_EQ(m.source[1], SectorSource::SonarCopied);
}

TEST(SectorMap, StaleLaserIsHeldNeverFreer) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 a{0.0, 0.0, 0.0};
  s.setLaserPoints(0, {pointAt(a, 0.0, 1.0)});  // 1.0 ahead
  auto m = s.update(0, a, agm);
  EXPECT_FALSE(m.laser_stale);
  EXPECT_NEAR(m.laser[24], 1.0, 1e-6);
  // Fresh (0.4 s <= 0.5 s): the robot backs off, the value grows.
  m = s.update(400'000, {-0.2, 0.0, 0.0}, agm);
  EXPECT_FALSE(m.laser_stale);
  EXPECT_NEAR(m.laser[24], 1.2, 1e-6);
  // Stale (0.6 s): backing off further does not make the sector freer than the last fresh map.
  m = s.update(600'000, {-0.5, 0.0, 0.0}, agm);
  EXPECT_TRUE(m.laser_stale);
  EXPECT_NEAR(m.laser_age_s, 0.6, 1e-9);
  EXPECT_NEAR(m.laser[24], 1.2, 1e-6);
  EXPECT_EQ(m.source[24], SectorSource::Laser);
  // Driving towards it, the value shrinks...
  m = s.update(700'000, {0.3, 0.0, 0.0}, agm);
  EXPECT_NEAR(m.laser[24], 0.7, 1e-6);
  // ... and stays shrunk while stale.
  m = s.update(800'000, {-0.5, 0.0, 0.0}, agm);
  EXPECT_NEAR(m.laser[24], 0.7, 1e-6);
  // A fresh scan ends the hold.
  s.setLaserPoints(900'000, {pointAt({-0.5, 0.0, 0.0}, 0.0, 2.0)});
  m = s.update(900'000, {-0.5, 0.0, 0.0}, agm);
  EXPECT_FALSE(m.laser_stale);
  EXPECT_NEAR(m.laser[24], 2.0, 1e-6);
}

// StaleValues::Moved: the stale scan's points move with odometry like fresh ones; nothing is
// held, so backing off makes the sector freer and turning away leaves nothing behind.
TEST(SectorMap, StaleLaserMovedWithOdometryIsNotHeld) {
  SectorMapParams p;
  p.stale_values = StaleValues::Moved;
  SectorMap s(p);
  AccumulativeGridMap agm(agmParams01());
  s.setLaserPoints(0, {pointAt({0.0, 0.0, 0.0}, 0.0, 1.0)});  // 1.0 ahead
  auto m = s.update(0, {0.0, 0.0, 0.0}, agm);
  EXPECT_NEAR(m.laser[24], 1.0, 1e-6);
  // Driving towards it while stale, the value shrinks as with held_min...
  m = s.update(600'000, {0.3, 0.0, 0.0}, agm);
  ASSERT_TRUE(m.laser_stale);
  EXPECT_NEAR(m.laser[24], 0.7, 1e-6);
  // ... but backing off it grows again: the obstacle stays where it was seen.
  m = s.update(700'000, {-0.5, 0.0, 0.0}, agm);
  EXPECT_TRUE(m.laser_stale);
  EXPECT_NEAR(m.laser[24], 1.5, 1e-6);
  EXPECT_EQ(m.source[24], SectorSource::Laser);
  // Turned left by 87 deg, the obstacle is on the right (sector 12, -90..-82.5 deg) and nothing is
  // ahead.
  const double turn = 87.0 * kDeg;
  m = s.update(800'000, {-0.5, 0.0, turn}, agm);
  EXPECT_FLOAT_EQ(m.laser[24], -1.0f);
  EXPECT_NEAR(m.laser[12], 1.5, 1e-6);
  // The same turn with held_min keeps the nearest value the sector had (0.7) ahead.
  SectorMap h({});
  h.setLaserPoints(0, {pointAt({0.0, 0.0, 0.0}, 0.0, 1.0)});
  h.update(0, {0.0, 0.0, 0.0}, agm);
  h.update(600'000, {0.3, 0.0, 0.0}, agm);
  const auto& held = h.update(800'000, {-0.5, 0.0, turn}, agm);
  EXPECT_NEAR(held.laser[24], 0.7, 1e-6);
  EXPECT_NEAR(held.laser[12], 1.5, 1e-6);
}

// laserShadow: points only where the last scan has a shadow edge.
// The distance from p to the segment a..b.
double toSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

TEST(LaserShadow, ReturnsOfOneSurfaceGiveNoPoints) {
  // A wall 2 m ahead seen over +-30 deg, a reading every 0.5 deg: neighbours 2-2.4 cm apart.
  std::vector<Vec2> pts;
  for (int i = -60; i <= 60; ++i) pts.push_back({2.0, 2.0 * std::tan(i * 0.5 * kDeg)});
  std::vector<Vec2> out;
  laserShadow(pts, std::vector<uint8_t>(pts.size(), 1), {0, 0}, false, {}, out);
  EXPECT_TRUE(out.empty()) << out.size();
}

TEST(LaserShadow, JumpFromAnOccluderToTheWallBehindIsAnEdge) {
  const Vec2 wall{2.0, -0.5}, edge{1.0, 0.0}, occluder{1.0, 0.04};
  std::vector<Vec2> out;
  laserShadow({wall, edge, occluder}, {1, 1, 1}, {0, 0}, false, {}, out);
  // 1.118 m at most 5 cm apart: 22 points inside; the occluder's own 4 cm: none.
  ASSERT_EQ(out.size(), 22u);
  for (const Vec2& q : out) EXPECT_LT(toSegment(q, wall, edge), 1e-9) << q.transpose();
  for (size_t i = 1; i < out.size(); ++i) EXPECT_LE((out[i] - out[i - 1]).norm(), 0.05 + 1e-12);
  // The last reading does not neighbour the first unless the scan is a full circle.
  std::vector<Vec2> wrapped;
  laserShadow({edge, occluder, wall}, {1, 1, 1}, {0, 0}, false, {}, wrapped);
  EXPECT_EQ(wrapped.size(), 22u);
  wrapped.clear();
  laserShadow({occluder, wall, edge}, {1, 1, 1}, {0, 0}, true, {}, wrapped);
  EXPECT_EQ(wrapped.size(), 44u);  // occluder..wall and wall..edge (the wrap, edge..occluder, is 4 cm)
}

TEST(LaserShadow, BesideAnEmptyReadingTheRayBeyondTheReturnIsAnEdge) {
  LaserShadowParams p;
  p.reach = 2.0;
  std::vector<Vec2> out;
  laserShadow({{1.0, 0.0}, {0.0, 0.0}}, {1, 0}, {0, 0}, false, p, out);
  ASSERT_EQ(out.size(), 20u);  // 1.05 .. 2.00 m on the ray
  for (const Vec2& q : out) {
    EXPECT_NEAR(q.y(), 0.0, 1e-12);
    EXPECT_GT(q.x(), 1.0);
    EXPECT_LE(q.x(), 2.0 + 1e-9);
  }
  // Two empty readings, or a return beyond the reach: nothing; a NaN return is no return.
  out.clear();
  laserShadow({{1.0, 0.0}, {1.0, 0.1}}, {0, 0}, {0, 0}, false, p, out);
  laserShadow({{3.0, 0.0}, {0.0, 0.0}}, {1, 0}, {0, 0}, false, p, out);
  laserShadow({{std::nan(""), 0.0}, {0.0, 0.0}}, {1, 0}, {0, 0}, false, p, out);
  EXPECT_TRUE(out.empty());
  // No spacing, no reach, or no origin: nothing.
  for (const auto& [spacing, reach] : {std::pair{0.0, 2.0}, std::pair{0.05, 0.0}}) {
    LaserShadowParams q;
    q.spacing = spacing;
    q.reach = reach;
    laserShadow({{1.0, 0.0}, {0.0, 0.0}}, {1, 0}, {0, 0}, false, q, out);
  }
  laserShadow({{1.0, 0.0}, {0.0, 0.0}}, {1, 0}, {std::nan(""), 0.0}, false, p, out);
  EXPECT_TRUE(out.empty());
}

// StaleValues::Frontier: once the laser is stale, a sector that looks into a shadow of the last
// scan (here behind a post, seen from the side after driving on) reports its edge, where moved
// reports nothing; while fresh, the shadow counts for nothing.
TEST(SectorMap, StaleLaserFrontierReportsWhatTheLastScanDidNotSeeFree) {
  // A scan from the origin, a reading per degree over +-60 deg: a post of 0.3 m at x = 1
  // (|y| <= 0.15) in front of a wall at x = 3.
  std::vector<Vec2> returns;
  for (int i = -60; i <= 60; ++i) {
    const double t = std::tan(i * kDeg);
    returns.push_back(std::abs(t) <= 0.15 ? Vec2{1.0, t} : Vec2{3.0, 3.0 * t});
  }
  std::vector<Vec2> shadow;
  laserShadow(returns, std::vector<uint8_t>(returns.size(), 1), {0, 0}, false, {}, shadow);
  ASSERT_FALSE(shadow.empty());
  AccumulativeGridMap agm(agmParams01());
  const auto give = [&](SectorMap& s) {
    std::vector<Vec2> xy = returns;
    std::vector<uint8_t> valid(returns.size(), 1);
    s.setLaserScan(xy, valid, {0, 0}, false);
  };
  const auto run = [&](StaleValues rule, int64_t t, const Pose2& pose) {
    SectorMapParams p;
    p.stale_values = rule;
    SectorMap s(p);
    s.setLaserPoints(0, returns);
    give(s);
    s.update(0, {0.0, 0.0, 0.0}, agm);
    return s.update(t, pose, agm);
  };
  // Driven on to (1.5, 1.0), facing -y: straight ahead (sector 24) runs down x = 1.5 into the
  // post's shadow, whose edge from (1, 0.15) to (3, 0.45) it meets at y = 0.225.
  const Pose2 side{1.5, 1.0, -kPi / 2};
  const auto frontier = run(StaleValues::Frontier, kSec, side);
  ASSERT_TRUE(frontier.laser_stale);
  const double edge = 1.0 - 0.225 - 0.35;
  EXPECT_LE(frontier.laser[24], edge + 0.01);
  EXPECT_GT(frontier.laser[24], edge - 0.06);  // (the sector is 7.5 deg wide)
  EXPECT_EQ(frontier.source[24], SectorSource::Laser);
  const auto moved = run(StaleValues::Moved, kSec, side);
  EXPECT_TRUE(moved.laser[24] < 0 || moved.laser[24] > edge + 0.5) << moved.laser[24] << " " << frontier.laser[24];
  // Fresh (0.1 s), the same pose: the shadow is not reported.
  const auto fresh = run(StaleValues::Frontier, 100'000, side);
  ASSERT_FALSE(fresh.laser_stale);
  EXPECT_FLOAT_EQ(fresh.laser[24], moved.laser[24]);
  // A new scan clears the shadow: stale again, nothing of the old edges is left.
  SectorMapParams p;
  p.stale_values = StaleValues::Frontier;
  SectorMap s(p);
  s.setLaserPoints(0, returns);
  give(s);
  s.setLaserPoints(10'000, returns);
  EXPECT_FLOAT_EQ(s.update(kSec, side, agm).laser[24], moved.laser[24]);
}

TEST(SectorMap, StaleSonarIsHeldNeverFreer) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});
  s.setSonarTime(0);
  auto m = s.update(0, pose, agm);
  EXPECT_FALSE(m.sonar_stale);
  EXPECT_NEAR(m.sonar[24], 0.60, 1e-6);
  // Sonar silent for 1 s and the grid (say) emptied: the last fresh values are held, with
  // their sources, and the map says sonar is stale.
  AccumulativeGridMap empty(agmParams01());
  m = s.update(kSec, pose, empty);
  EXPECT_TRUE(m.sonar_stale);
  EXPECT_NEAR(m.sonar_age_s, 1.0, 1e-9);
  EXPECT_NEAR(m.distance[24], 0.60, 1e-6);
  EXPECT_EQ(m.source[24], SectorSource::Sonar);
  EXPECT_EQ(m.source[25], SectorSource::SonarCopied);
}

TEST(SectorMap, NeverHeardIsStaleWithAgeMinusOne) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  const auto& m = s.update(5 * kSec, {}, agm);
  EXPECT_TRUE(m.laser_stale);
  EXPECT_TRUE(m.sonar_stale);
  EXPECT_EQ(m.laser_age_s, -1);
  EXPECT_EQ(m.sonar_age_s, -1);
  for (auto src : m.source) EXPECT_EQ(src, SectorSource::None);
}

TEST(SectorMap, CellsTheScanExplainsAreNotSonarValues) {
  SectorMapParams p;
  p.laser_explains_radius = 0.10;
  p.sonar_cell_point = CellPoint::Centre;
  SectorMap s(p);
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});                 // ahead (sector 24), centre 1.0 m away
  obstacle(agm, {0.05, 1.05});                 // to the left (sector 36), centre 1.0 m away
  s.setSonarTime(0);
  // A laser point 8 cm from the first cell's centre (a thin pipe the scan holds); the second
  // cell's nearest laser point is 15 cm from its centre (beyond the radius).
  s.setLaserPoints(0, {{1.05, 0.13}, {0.20, 1.05}});
  const auto& m = s.update(0, pose, agm);
  EXPECT_FLOAT_EQ(m.sonar[24], -1.0f);          // explained: the laser reports it
  EXPECT_EQ(m.source[24], SectorSource::Laser);
  EXPECT_NEAR(m.sonar[36], 0.65, 1e-6);         // not explained: still the sonar's
  EXPECT_EQ(m.source[36], SectorSource::Sonar);
  // Once the scan is stale it explains nothing away: both cells count again.
  const auto& late = s.update(kSec, pose, agm);
  ASSERT_TRUE(late.laser_stale);
  EXPECT_NEAR(late.sonar[24], 0.65, 1e-6);
  // Radius 0 (the paper): every cell counts.
  SectorMap paper({});
  paper.setSonarTime(0);
  paper.setLaserPoints(0, {{1.05, 0.13}});
  EXPECT_GE(paper.update(0, pose, agm).sonar[24], 0.0f);
}

TEST(SectorMap, LaserConfirmedValuesAreNotCopied) {
  SectorMapParams p;
  p.copy_rule = CopyRule::UnlessLaserConfirmed;
  p.sonar_cell_point = CellPoint::Centre;
  SectorMap s(p);
  AccumulativeGridMap agm(agmParams01());
  const Pose2 pose{0.05, 0.05, 0.0};
  agm.centreOn(pose.position());
  obstacle(agm, {1.05, 0.05});                  // sector 24, sonar 0.65
  obstacle(agm, {0.05, 1.05});                  // sector 36, sonar 0.65
  s.setSonarTime(0);
  // The laser sees an obstacle 0.05 m from sector 24's sonar value (confirmed), and one 0.3 m
  // beyond sector 36's (not confirmed).
  s.setLaserPoints(0, {pointAt(pose, 1.0 * kDeg, 0.70), pointAt(pose, 91.0 * kDeg, 0.95)});
  const auto& m = s.update(0, pose, agm);
  EXPECT_EQ(m.source[23], SectorSource::None);
  EXPECT_EQ(m.source[25], SectorSource::None);
  EXPECT_EQ(m.source[35], SectorSource::SonarCopied);
  EXPECT_EQ(m.source[37], SectorSource::SonarCopied);
  // The paper's rule copies both.
  SectorMapParams q = p;
  q.copy_rule = CopyRule::Paper;
  SectorMap paper(q);
  paper.setSonarTime(0);
  paper.setLaserPoints(0, {pointAt(pose, 1.0 * kDeg, 0.70), pointAt(pose, 91.0 * kDeg, 0.95)});
  const auto& n = paper.update(0, pose, agm);
  EXPECT_EQ(n.source[23], SectorSource::SonarCopied);
  EXPECT_EQ(n.source[25], SectorSource::SonarCopied);
}

TEST(SectorMap, CellExtentCopiesOnlyIntoTheSectorsTheCellReaches) {
  SectorMapParams p;
  p.copy_rule = CopyRule::CellExtent;
  SectorMap s(p);
  AccumulativeGridMap agm(agmParams01());
  agm.centreOn({0.05, 0.05});
  obstacle(agm, {1.05, 0.05});  // centre on sector 24's right edge (bearing 0), 1 m away
  const Vec2 far = pointAt({0.05, 0.05, 0.0}, 3.75 * kDeg, 2.2);  // mid-sector 24, 2.55 m away
  obstacle(agm, far);
  s.setSonarTime(0);
  const auto& m = s.update(0, {0.05, 0.05, 0.0}, agm);
  EXPECT_EQ(m.source[24], SectorSource::Sonar);
  // The near cell's square (half-diagonal 4 deg at 1 m) reaches sector 23, not 25.
  EXPECT_EQ(m.source[23], SectorSource::SonarCopied);
  EXPECT_NEAR(m.distance[23], m.distance[24], 1e-6);
  EXPECT_EQ(m.source[25], SectorSource::None);
  // The paper copies into both neighbours.
  SectorMap paper({});
  const auto& q = paper.update(0, {0.05, 0.05, 0.0}, agm);
  EXPECT_EQ(q.source[25], SectorSource::SonarCopied);
}

TEST(SectorMap, RememberedOnlyAddsAndIsUnusedWhenStale) {
  SectorMap s({});
  AccumulativeGridMap agm(agmParams01());
  agm.centreOn({0.0, 0.0});
  const Pose2 pose{0.0, 0.0, 0.0};
  s.setSonarTime(0);
  s.setLaserPoints(0, {pointAt(pose, 3.75 * kDeg, 0.50)});   // sector 24: the laser at 0.5 m
  s.setRemembered(0, {pointAt(pose, 3.75 * kDeg, 1.20),      // sector 24: farther than the laser
                      pointAt(pose, 90.0 * kDeg + 3.75 * kDeg, 0.80)});  // sector 36: nothing else
  const auto& m = s.update(100'000, pose, agm);
  EXPECT_FALSE(m.remembered_stale);
  EXPECT_NEAR(m.remembered_age_s, 0.1, 1e-9);
  // Never frees: sector 24 keeps the laser's 0.5 m.
  EXPECT_EQ(m.source[24], SectorSource::Laser);
  EXPECT_NEAR(m.distance[24], 0.50, 1e-5);
  EXPECT_NEAR(m.remembered[24], 1.20, 1e-5);
  // Adds: sector 36 reports the remembered obstacle.
  EXPECT_EQ(m.source[36], SectorSource::Remembered);
  EXPECT_NEAR(m.distance[36], 0.80, 1e-5);
  // Older than remembered_stale_s (2 s): flagged and not used at all.
  s.setLaserPoints(2'500'000, {pointAt(pose, 3.75 * kDeg, 0.50)});
  s.setSonarTime(2'500'000);
  const auto& later = s.update(2'500'000, pose, agm);
  EXPECT_TRUE(later.remembered_stale);
  EXPECT_EQ(later.source[36], SectorSource::None);
  EXPECT_FLOAT_EQ(later.remembered[36], -1.0f);
}

TEST(SectorMap, RememberedCellsTheScanExplainsAreNotUsed) {
  const Pose2 pose{0.0, 0.0, 0.0};
  const Vec2 seen = pointAt(pose, 3.75 * kDeg, 1.0);
  // The scan (at time 0) sees `seen`; the memory (at `t_memory`) holds `cell`; the map at `now`.
  const auto mapWith = [&](double radius, const Vec2& cell, int64_t t_memory, int64_t now) {
    SectorMapParams p;
    p.laser_explains_radius = 0.10;
    p.remembered_explains_radius = radius;
    SectorMap s(p);
    AccumulativeGridMap agm(agmParams01());
    agm.centreOn({0.0, 0.0});
    s.setSonarTime(t_memory);
    s.setLaserPoints(0, {seen});
    s.setRemembered(t_memory, {cell});
    return SectorMapState(s.update(now, pose, agm));
  };
  for (const double radius : {0.0, 0.2}) {
    // A remembered cell 0.15 m in front of what the laser sees. 0: laser_explains_radius
    // (0.10 m) applies, the cell is 0.15 m away: used, nearer than the laser. 0.2 m: the scan
    // explains it.
    const SectorMapState m = mapWith(radius, seen + Vec2(-0.15, 0.0), 0, 0);
    EXPECT_EQ(m.source[24], radius > 0 ? SectorSource::Laser : SectorSource::Remembered) << radius;
    // A stale scan explains nothing away, with either radius: a cell on its point is remembered.
    const SectorMapState late = mapWith(radius, seen + Vec2(-0.02, 0.0), 900'000, 1'000'000);
    ASSERT_TRUE(late.laser_stale);
    EXPECT_NEAR(late.remembered[24], 0.98, 1e-3) << radius;  // (pointAt: from the boundary)
  }
}

// The laser values against the definition computed naively: every point moved into the pose,
// its sector from atan2, its distance max(0, |d| - radius), the minimum per sector.
TEST(SectorMap, LaserValuesEqualTheNaiveDefinition) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-4.0, 4.0), a(-kPi, kPi);
  for (int trial = 0; trial < 50; ++trial) {
    SectorMapParams p;
    p.sectors = trial % 2 ? 48 : 7;
    SectorMap s(p);
    std::vector<Vec2> points;
    // A scan-like ring (bearing order, where the sector rarely changes between points; parts
    // of it beyond the reach), then scattered points in no order.
    const Vec2 centre(u(rng) * 0.2, u(rng) * 0.2);
    for (int i = 0; i < 360; ++i) points.push_back(centre + geom::unitVector(i * kPi / 180) * (1.0 + 5.0 * std::abs(std::sin(i * 0.05))));
    for (int i = 0; i < 100; ++i) points.emplace_back(u(rng), u(rng));
    const Pose2 pose{u(rng) * 0.1, u(rng) * 0.1, a(rng)};
    s.setLaserPoints(0, points);
    const auto& st = s.update(0, pose, AccumulativeGridMap(agmParams01()));
    std::vector<float> naive(static_cast<size_t>(p.sectors), -1.0f);
    for (const Vec2& q : points) {
      const Vec2 l = pose.inverseTransform(q);
      if (l.norm() > p.robot_radius + p.max_range) continue;
      const float d = static_cast<float>(std::max(0.0, l.norm() - p.robot_radius));
      float& v = naive[static_cast<size_t>(s.sectorOf(std::atan2(l.y(), l.x())))];
      if (v < 0 || d < v) v = d;
    }
    ASSERT_EQ(st.laser, naive) << "trial " << trial;
  }
}

// A remembered cell's distance from the robot's boundary by the definition, or -1 when it lies
// beyond the reach (the naive side of the two tests below).
namespace {
double naiveRememberedDistance(const SectorMapParams& p, const Pose2& pose, const Vec2& q) {
  const Vec2 d = q - pose.position();
  if (!(d.norm() <= p.robot_radius + p.max_range)) return -1;
  const double dist = std::max(0.0, d.norm() - p.robot_radius);
  return dist > p.max_range ? -1 : dist;
}
}  // namespace

// The remembered values against the definition computed naively (distance from r^2 without the
// root beyond the reach, sector by rotation), for a grid's occupied cells around a robot anywhere.
TEST(SectorMap, RememberedValuesEqualTheNaiveDefinition) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-6.0, 6.0), a(-kPi, kPi), coin(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    SectorMapParams p;
    SectorMap s(p);
    std::vector<Vec2> cells;
    for (int iy = 0; iy < 100; ++iy)
      for (int ix = 0; ix < 100; ++ix)
        if (coin(rng) < 0.1) cells.emplace_back(-5.0 + (ix + 0.5) * 0.1, -5.0 + (iy + 0.5) * 0.1);
    const Pose2 pose{u(rng), u(rng), a(rng)};
    s.setRemembered(0, cells);
    const auto& st = s.update(0, pose, AccumulativeGridMap(agmParams01()));
    std::vector<float> naive(static_cast<size_t>(p.sectors), -1.0f);
    int near = 0;
    for (const Vec2& q : cells) {
      const double dist = naiveRememberedDistance(p, pose, q);
      if (dist < 0) continue;
      const Vec2 d = q - pose.position();
      ++near;
      float& v = naive[static_cast<size_t>(s.sectorOf(std::atan2(d.y(), d.x()) - pose.theta))];
      if (v < 0 || dist < v) v = static_cast<float>(dist);
    }
    ASSERT_EQ(st.remembered, naive) << "trial " << trial << ", " << near << " cells in reach";
  }
}

// The same with a scan whose points explain some of the cells (laser_explains_radius): a sector
// takes the nearest remembered cell the scan does not explain, however the cells are ordered
// (rememberedValues asks about a cell only when it would lower its sector's value).
TEST(SectorMap, RememberedValuesWithExplainedCellsEqualTheNaiveDefinition) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-3.0, 3.0), a(-kPi, kPi), coin(0.0, 1.0), jitter(-0.15, 0.15);
  for (int trial = 0; trial < 50; ++trial) {
    SectorMapParams p;
    p.laser_explains_radius = 0.10;
    SectorMap s(p);
    std::vector<Vec2> cells, scan;
    for (int iy = 0; iy < 80; ++iy)
      for (int ix = 0; ix < 80; ++ix)
        if (coin(rng) < 0.1) {
          cells.emplace_back(-4.0 + (ix + 0.5) * 0.1, -4.0 + (iy + 0.5) * 0.1);
          if (coin(rng) < 0.5) scan.push_back(cells.back() + Vec2(jitter(rng), jitter(rng)));
        }
    std::shuffle(cells.begin(), cells.end(), rng);  // any order
    const Pose2 pose{u(rng), u(rng), a(rng)};
    s.setLaserPoints(0, scan);
    s.setRemembered(0, cells);
    const AccumulativeGridMap agm(agmParams01());
    const double c = agm.cellSize();
    const auto& st = s.update(0, pose, agm);
    std::vector<float> naive(static_cast<size_t>(p.sectors), -1.0f);
    int explained = 0;
    for (const Vec2& q : cells) {
      const double dist = naiveRememberedDistance(p, pose, q);
      if (dist < 0) continue;
      const Vec2 d = q - pose.position();
      // The cell holding q is explained when a scan point lies within the radius of its centre.
      const Vec2 centre((std::floor(q.x() / c) + 0.5) * c, (std::floor(q.y() / c) + 0.5) * c);
      if (std::any_of(scan.begin(), scan.end(),
                      [&](const Vec2& l) { return (centre - l).norm() <= p.laser_explains_radius; })) {
        ++explained;
        continue;
      }
      float& v = naive[static_cast<size_t>(s.sectorOf(std::atan2(d.y(), d.x()) - pose.theta))];
      if (v < 0 || dist < v) v = static_cast<float>(dist);
    }
    ASSERT_GT(explained, 0) << "trial " << trial;
    ASSERT_EQ(st.remembered, naive) << "trial " << trial << ", " << explained << " cells explained";
  }
}

// The explained cells (decided per cell from the scan's points in buckets) against the brute
// force: a cell is explained exactly when some point of the scan lies within the radius of its
// centre. One obstacle cell per trial among a scan's worth of points around it, several maps
// per scan (the per-scan memo), cells at every offset from the buckets' grid, points in random
// and in bearing order (runs of points in one bucket).
namespace {
double edgeOrNeighbour(double edge, int k) {
  return k % 3 == 0 ? edge : std::nextafter(edge, k % 3 == 1 ? 1e9 : -1e9);
}
}  // namespace

TEST(SectorMap, ExplainedCellsEqualTheBruteForce) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.2, 0.2), far(-2.5, 2.5);
  int explained = 0, not_explained = 0;
  for (int trial = 0; trial < 400; ++trial) {
    SectorMapParams p;
    p.laser_explains_radius = 0.10;
    p.sonar_cell_point = CellPoint::Centre;
    SectorMap s(p);
    AccumulativeGridMap agm(agmParams01());
    const Pose2 pose{0.05, 0.05, 0.0};
    agm.centreOn(pose.position());
    // The obstacle cell, 1-2.5 m from the robot.
    const Vec2 cell_point(1.0 + std::abs(far(rng)) * 0.6, far(rng) * 0.6);
    obstacle(agm, cell_point);
    const Vec2 centre((std::floor(cell_point.x() / 0.1) + 0.5) * 0.1, (std::floor(cell_point.y() / 0.1) + 0.5) * 0.1);
    std::vector<Vec2> points;
    for (int i = 0; i < 40; ++i) points.emplace_back(far(rng), far(rng));  // elsewhere
    const int near = trial % 4;                                              // 0-3 points around the cell
    for (int i = 0; i < near; ++i) points.push_back(centre + Vec2(u(rng), u(rng)));
    if (trial % 3 == 1)  // points on cell edges (k * 0.1, and one ulp either side): floor(v / c) at an integer
      for (Vec2& q : points)
        for (int a = 0; a < 2; ++a) {
          const double edge = std::round(q[a] / 0.1) * 0.1;
          q[a] = edgeOrNeighbour(edge, trial + a);
        }
    if (trial % 2 == 0)  // in bearing order, as a scan comes: neighbours share buckets (runs)
      std::sort(points.begin(), points.end(), [](const Vec2& a, const Vec2& b) {
        return std::atan2(a.y() - 0.05, a.x() - 0.05) < std::atan2(b.y() - 0.05, b.x() - 0.05);
      });
    bool brute = false;
    for (const Vec2& q : points) brute = brute || (q - centre).norm() <= p.laser_explains_radius;
    s.setSonarTime(0);
    s.setLaserPoints(0, points);
    for (int map = 0; map < 3; ++map) {  // the second and third maps read the memo
      const auto& m = s.update(map * 1000, pose, agm);
      bool sonar = false;
      for (const float d : m.sonar) sonar = sonar || d >= 0;
      ASSERT_EQ(sonar, !brute) << "trial " << trial << " map " << map << ": cell centre " << centre.transpose();
    }
    (brute ? explained : not_explained) += 1;
  }
  EXPECT_GT(explained, 50);
  EXPECT_GT(not_explained, 50);
}

// The laser values (four points at a time, see laserValues) against the definition taken point
// by point -- r^2 beyond the reach skipped, the sector from atan2 of the point in the robot
// frame, a NaN distance counted as 0 -- on inputs that exercise every lane path: scans whose
// length is not a multiple of four, points exactly on sector edges (and one ulp either side),
// at the reach, NaN and infinite coordinates, scattered points, and 3 to 3600 sectors.
TEST(SectorMap, LaserValuesFourAtATimeEqualThePointByPointDefinition) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-4.0, 4.0), a(-kPi, kPi), coin(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const int sector_counts[] = {3, 7, 48, 48, 360, 3600};
  int edge_points = 0;
  for (int trial = 0; trial < 300; ++trial) {
    SectorMapParams p;
    p.sectors = sector_counts[trial % 6];
    SectorMap s(p);
    const Pose2 pose{u(rng) * 0.5, u(rng) * 0.5, trial % 5 == 0 ? 0.0 : a(rng)};
    const double reach = p.robot_radius + p.max_range;
    std::vector<Vec2> points;
    const int kind = trial % 4;
    const int count = 1 + static_cast<int>(coin(rng) * 800);
    for (int i = 0; i < count; ++i) {
      const double pick = coin(rng);
      if (kind == 0 || pick < 0.6) {  // scan-like: in bearing order, at varying range
        const double bearing = -kPi + 2 * kPi * i / count;
        points.push_back(pose.transform(geom::unitVector(bearing) * (0.2 + 4.0 * coin(rng))));
      } else if (pick < 0.8) {  // on a sector edge (in the robot frame), or one ulp beside it
        const int k = static_cast<int>(coin(rng) * p.sectors);
        const double edge = -kPi + k * (2.0 * kPi / p.sectors);
        Vec2 q = pose.transform(geom::unitVector(edge) * (0.5 + 2.5 * coin(rng)));
        const int side = static_cast<int>(coin(rng) * 3);
        if (side > 0) q.x() = std::nextafter(q.x(), side == 1 ? 1e9 : -1e9);
        points.push_back(q);
        ++edge_points;
      } else if (pick < 0.85) {  // at the reach
        const Vec2 d = geom::unitVector(a(rng)) * reach;
        points.push_back(pose.position() + d);
      } else if (pick < 0.9) {  // not from a valid scan
        const double bad[] = {nan, inf, -inf};
        points.emplace_back(coin(rng) < 0.5 ? bad[i % 3] : u(rng), coin(rng) < 0.5 ? bad[(i + 1) % 3] : u(rng));
      } else {
        points.emplace_back(u(rng), u(rng));
      }
    }
    if (trial % 7 == 0) points.emplace_back(pose.x, pose.y);  // at the robot's centre
    s.setLaserPoints(0, points);
    const auto& st = s.update(0, pose, AccumulativeGridMap(agmParams01()));
    std::vector<float> def(static_cast<size_t>(p.sectors), -1.0f);
    const double c = std::cos(pose.theta), sn = std::sin(pose.theta);
    for (const Vec2& q : points) {
      const double dx = q.x() - pose.x, dy = q.y() - pose.y;
      const double r2 = dx * dx + dy * dy;
      if (r2 > reach * reach) continue;
      const double lx = c * dx + sn * dy, ly = -sn * dx + c * dy;
      const float d = std::isnan(r2) ? 0.0f : static_cast<float>(std::max(0.0, std::sqrt(r2) - p.robot_radius));
      float& v = def[static_cast<size_t>(s.sectorOf(std::atan2(ly, lx)))];
      if (v < 0 || d < v) v = d;
    }
    ASSERT_EQ(st.laser, def) << "trial " << trial << ", " << points.size() << " points, " << p.sectors << " sectors";
  }
  EXPECT_GT(edge_points, 1000);
}

// The laser part's vector loops (AVX2 where the CPU has it, SSE2, none) against each other:
// bit-identical states for short random scans (0..40 points: none, fewer than a register's four,
// a few registers and a tail), with points on sector edges and one ulp beside them, at the reach
// and one ulp beyond it, beyond the reach, NaN and infinite, at the robot's centre; many sectors,
// so that a register's lanes straddle several; an infinite reach; moving returns.
TEST(SectorMap, LaserVectorPathsGiveBitIdenticalStates) {
  const SectorMap::VectorPath widest = SectorMap::vectorPath();
  struct Restore {  // (also when an assertion returns early)
    SectorMap::VectorPath path;
    ~Restore() { SectorMap::setVectorPath(path); }
  } restore{widest};
  if (widest != SectorMap::VectorPath::Avx2) std::cout << "(no AVX2 on this CPU: SSE2 against scalar only)\n";
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-4.0, 4.0), a(-kPi, kPi), coin(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const int sector_counts[] = {3, 7, 48, 360, 3600};
  const AccumulativeGridMap agm(agmParams01());
  for (int trial = 0; trial < 6000; ++trial) {
    SectorMapParams p;
    p.sectors = sector_counts[trial % 5];
    if (trial % 97 == 0) p.max_range = inf;
    const Pose2 pose{u(rng), u(rng), trial % 11 == 0 ? 0.0 : trial % 13 == 0 ? kPi / 2 : a(rng)};
    const double reach = p.robot_radius + p.max_range;
    const int count = trial % 41;
    const double turn = 2 * kPi * coin(rng);  // a scan-like run covers this much of the circle
    std::vector<Vec2> points;
    for (int i = 0; i < count; ++i) {
      const double pick = coin(rng);
      if (pick < 0.45) {  // scan-like: in bearing order, within and beyond the reach
        const double bearing = -kPi + turn * i / std::max(count, 1);
        points.push_back(pose.transform(geom::unitVector(bearing) * (0.1 + 4.5 * coin(rng))));
      } else if (pick < 0.7) {  // on a sector edge (robot frame), or one ulp beside it
        const int k = static_cast<int>(coin(rng) * p.sectors);
        Vec2 q = pose.transform(geom::unitVector(-kPi + k * (2.0 * kPi / p.sectors)) * (0.2 + 3.0 * coin(rng)));
        const int side = static_cast<int>(coin(rng) * 3);
        if (side > 0) q.y() = std::nextafter(q.y(), side == 1 ? inf : -inf);
        points.push_back(q);
      } else if (pick < 0.8) {  // at the reach, or one ulp beyond
        Vec2 q = pose.position() + geom::unitVector(a(rng)) * (std::isfinite(reach) ? reach : 1.0);
        if (coin(rng) < 0.5) q.x() = std::nextafter(q.x(), q.x() > pose.x ? inf : -inf);
        points.push_back(q);
      } else if (pick < 0.88) {  // not from a valid scan
        const double bad[] = {nan, inf, -inf};
        points.emplace_back(coin(rng) < 0.5 ? bad[i % 3] : u(rng), coin(rng) < 0.5 ? bad[(i + 1) % 3] : u(rng));
      } else if (pick < 0.9) {
        points.emplace_back(pose.x, pose.y);  // at the robot's centre
      } else {
        points.emplace_back(u(rng), u(rng));
      }
    }
    std::vector<SectorMap::MovingPoint> movers;
    if (trial % 3 == 0) movers.push_back({{u(rng), u(rng)}, {u(rng), u(rng)}, 0});
    SectorMapState first;
    for (const auto path : {SectorMap::VectorPath::Scalar, SectorMap::VectorPath::Sse2, SectorMap::VectorPath::Avx2}) {
      SectorMap::setVectorPath(path);
      SectorMap s(p);
      s.setLaserPoints(0, points);
      s.setLaserMovers(movers, 0.5);
      const SectorMapState st = s.update(200'000, pose, agm);
      if (path == SectorMap::VectorPath::Scalar) {
        first = st;
        continue;
      }
      // Bitwise, not by value: a float's sign of zero counts too.
      const auto same = [](const std::vector<float>& x, const std::vector<float>& y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
      };
      ASSERT_TRUE(same(st.laser, first.laser) && same(st.distance, first.distance) && st.source == first.source) << "trial " << trial << ", path " << static_cast<int>(SectorMap::vectorPath()) << ", "
                         << points.size() << " points, " << p.sectors << " sectors";
    }
  }
}

// cellIndices (two at a time) against clamp(floor(v / cell), -1e15, 1e15) one by one: values on
// cell edges and one ulp either side, negative, zero of both signs, huge, infinite, an odd count.
TEST(SectorMap, CellIndicesEqualTheFloorOfTheQuotient) {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(-50.0, 50.0), coin(0.0, 1.0);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  struct Restore {  // (the widest path again, also when an assertion returns early)
    SectorMap::VectorPath path;
    ~Restore() { SectorMap::setVectorPath(path); }
  } restore{SectorMap::vectorPath()};
  for (const double cell : {0.1, 0.05, 0.25, 0.07, 1e-9}) {
    std::vector<double> v;
    for (int i = 0; i < 2001; ++i) {
      const double pick = coin(rng);
      if (pick < 0.4) {
        v.push_back(u(rng));
      } else if (pick < 0.8) {  // a cell edge k * cell, or one ulp beside it
        const double edge = std::round(u(rng) / cell) * cell;
        v.push_back(i % 3 == 0 ? edge : std::nextafter(edge, i % 3 == 1 ? inf : -inf));
      } else {
        const double special[] = {0.0, -0.0, 1e20, -1e20, inf, -inf, 1e15 * cell, -1e15 * cell, 4.5e15, -4.5e15, nan};
        v.push_back(special[i % 11]);
      }
    }
    // Every vector path (AVX2 four, SSE2 two at a time, scalar), each count from 0 (the tails).
    for (const auto path : {SectorMap::VectorPath::Avx2, SectorMap::VectorPath::Sse2, SectorMap::VectorPath::Scalar}) {
      SectorMap::setVectorPath(path);
      for (const size_t count : {v.size(), size_t{0}, size_t{1}, size_t{3}, size_t{5}, size_t{7}}) {
        std::vector<int64_t> got(count);
        cellIndices(v.data(), count, cell, got.data());
        for (size_t i = 0; i < count; ++i) {
          const double q = std::floor(v[i] / cell);
          if (std::isnan(q)) continue;  // (the conversion of NaN is the scalar code's, whatever it is)
          ASSERT_EQ(got[i], static_cast<int64_t>(std::clamp(q, -1e15, 1e15)))
              << "v " << v[i] << " cell " << cell << " path " << static_cast<int>(path);
        }
      }
    }
  }
}
