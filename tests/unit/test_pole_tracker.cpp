// Poles: small clusters that stay put in the odometry frame predict the ideal sonar's echo;
// glints of glass (sliding along the pane as the robot moves) do not.
#include <gtest/gtest.h>

#include <cmath>

#include "complement/hypothetical_scan.hpp"
#include "complement/pole_tracker.hpp"
#include "complement/radar_map.hpp"

using namespace lasonic;
using namespace lasonic::complement;
using geom::Vec2;

namespace {
PoleConfig on() {
  PoleConfig c;
  c.min_points = 1;
  return c;
}
std::vector<std::vector<Vec2>> one(Vec2 p) { return {{p}}; }
}  // namespace

TEST(PoleTracker, OffWithoutMinPoints) {
  PoleConfig off;
  off.min_points = 0;
  PoleTracker t{off};
  EXPECT_TRUE(t.update(0, {0, 0}, one({1, 1})).empty());
  EXPECT_TRUE(t.update(200000, {0.5, 0}, one({1, 1})).empty());
}

TEST(PoleTracker, AStillPoleSeenFromTwoPositionsIsAPole) {
  PoleTracker t{on()};
  EXPECT_TRUE(t.update(0, {0, 0}, one({0.1, 1.5})).empty());  // seen once: not yet
  const auto p = t.update(400000, {0.12, 0}, {{{0.105, 1.5}, {0.11, 1.51}}});
  ASSERT_EQ(p.size(), 2u);  // every point of the cluster
  EXPECT_DOUBLE_EQ(p[0].x(), 0.105);
}

TEST(PoleTracker, DrivingStraightAtAPaneDecidesNothing) {
  // The glint of a pane ahead (x = 2) stays at the foot of the perpendicular while the robot
  // drives at it: motion along the line of sight, so no pole.
  PoleTracker t{on()};
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(t.update(200000 * i, {0.1 * i, 0}, one({2, 0})).empty()) << i;
}

TEST(PoleTracker, AGlintSlidingAlongThePaneIsNot) {
  // A pane along y = 1; the robot drives along x; the glint is the foot of the perpendicular.
  PoleTracker t{on()};
  for (int i = 0; i < 10; ++i) {
    const double x = 0.06 * i;  // 0.3 m/s at 5 scans/s
    EXPECT_TRUE(t.update(200000 * i, {x, 0}, one({x, 1.0})).empty()) << i;
  }
}

TEST(PoleTracker, NeedsTheBaseline) {
  // The robot standing still: the same cluster twice says nothing about what it is.
  PoleTracker t{on()};
  EXPECT_TRUE(t.update(0, {0, 0}, one({0, 1})).empty());
  EXPECT_TRUE(t.update(200000, {0.05, 0}, one({0, 1})).empty());
  EXPECT_EQ(t.update(400000, {0.11, 0}, one({0, 1})).size(), 1u);
}

// A pole found while the robot moved stays one while the robot stands (or turns on the spot: no
// motion across any line of sight), as long as each scan sees it where it was found; not with
// keep_confirmed off (every scan needs its own baseline within memory_s).
TEST(PoleTracker, APoleFoundStaysOneWhileTheRobotStands) {
  for (const bool keep : {true, false}) {
    SCOPED_TRACE(keep ? "keep_confirmed" : "off");
    PoleConfig c = on();
    c.keep_confirmed = keep;
    PoleTracker t{c};
    t.update(0, {0, 0}, one({0, 1}));
    ASSERT_EQ(t.update(400000, {0.12, 0}, one({0, 1})).size(), 1u);  // found: the robot moved 0.12 m
    int poles = 0;
    for (int i = 3; i <= 50; ++i) poles += static_cast<int>(t.update(200000 * i, {0.12, 0}, one({0.005, 1.0})).size());  // stands 10 s
    EXPECT_EQ(poles, keep ? 48 : 8);  // off: only while the scan of 0 s is within memory_s (2.0 s)
  }
}

TEST(PoleTracker, AFoundPoleIsLeftWhereItWasFound) {
  PoleTracker t{on()};
  ASSERT_TRUE(on().keep_confirmed);  // shipped
  t.update(0, {0, 0}, one({0, 1}));
  ASSERT_EQ(t.update(400000, {0.12, 0}, one({0, 1})).size(), 1u);
  // Seen where it was found while the robot stands, after every scan with a baseline has gone:
  // still the pole; 2 cm off, still (within match); 4 cm off, not where it was found (a leg
  // creeping away does not drag the pole along).
  for (int i = 3; i <= 13; ++i) EXPECT_EQ(t.update(200000 * i, {0.12, 0}, one({0, 1})).size(), 1u) << i;
  EXPECT_EQ(t.update(2800000, {0.12, 0}, one({0.02, 1})).size(), 1u);
  EXPECT_TRUE(t.update(3000000, {0.12, 0}, one({0.04, 1})).empty());
  // Unseen for longer than memory_s, it is forgotten: seen again from the same place, not a pole.
  PoleTracker u{on()};
  u.update(0, {0, 0}, one({0, 1}));
  ASSERT_EQ(u.update(400000, {0.12, 0}, one({0, 1})).size(), 1u);
  EXPECT_TRUE(u.update(1400000, {0.12, 0}, {}).empty());
  EXPECT_TRUE(u.update(2500000, {0.12, 0}, one({0, 1})).empty());
  EXPECT_TRUE(u.update(2700000, {0.12, 0}, one({0, 1})).empty());
}

TEST(PoleTracker, ForgetsAfterItsMemoryAndOnAClockGoingBack) {
  PoleTracker t{on()};
  t.update(0, {0, 0}, one({0.5, 1}));
  EXPECT_TRUE(t.update(2500000, {1, 0}, one({0.5, 1})).empty());  // 2.5 s later: forgotten
  EXPECT_EQ(t.update(2600000, {0, 0}, one({0.5, 1})).size(), 1u);  // (the one of 2.5 s is kept)
  PoleTracker u{on()};
  u.update(1000000, {0, 0}, one({0.5, 1}));
  EXPECT_TRUE(u.update(500000, {1, 0}, one({0.5, 1})).empty());  // time went back: afresh
}

TEST(PoleTracker, MinPointsAndNonFiniteCentroids) {
  PoleConfig c = on();
  c.min_points = 2;
  PoleTracker t{c};
  t.update(0, {0, 0}, one({0.25, 1}));
  EXPECT_TRUE(t.update(400000, {0.5, 0}, one({0.25, 1})).empty());  // one point: not a candidate
  PoleTracker u{on()};
  const double nan = std::nan("");
  u.update(0, {0, 0}, one({nan, 1}));
  EXPECT_TRUE(u.update(400000, {0.5, 0}, one({nan, 1})).empty());
}

TEST(PoleTracker, ManyCandidatesMatchTheOneThatStaysPut) {
  // A scan of many one-point clusters (garbage, rain) and one pole among them: only the pole,
  // whatever its place in the list.
  PoleTracker t{on()};
  std::vector<std::vector<Vec2>> first, second;
  for (int i = 0; i < 500; ++i) {
    first.push_back({{0.01 * i - 2.5, 2.0 + 0.001 * i}});
    second.push_back({{0.01 * i - 2.5 + 0.005, 3.0}});  // within match in x, not in y
  }
  first.insert(first.begin() + 123, {{0.3, 1.5}});
  second.push_back({{0.305, 1.5}});
  t.update(0, {0, 0}, first);
  const auto p = t.update(400000, {0.2, 0}, second);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_DOUBLE_EQ(p[0].x(), 0.305);
}

TEST(PoleEcho, AReadingAtAPolesDistanceInsideTheBeamIsThatPole) {
  const IdealSonarModel model;  // 30 deg, 2.20 m
  const double d = std::hypot(1.0, 0.1);
  const std::vector<Vec2> poles{{1.0, 0.1}, {1.5, -0.05}};
  ASSERT_TRUE(poleEcho({0, 0, 0}, poles, d + 0.05, 0.10, model).has_value());
  EXPECT_DOUBLE_EQ(*poleEcho({0, 0, 0}, poles, d + 0.05, 0.10, model), d);
  EXPECT_DOUBLE_EQ(*poleEcho({0, 0, 0}, poles, 1.45, 0.10, model), std::hypot(1.5, 0.05));  // the nearer in range
  // A reading matching no pole (shorter: something nearer answered; longer: the pole was not
  // heard), a pole outside the beam or beyond the limit, no poles: nothing.
  EXPECT_FALSE(poleEcho({0, 0, 0}, poles, 0.8, 0.10, model).has_value());
  EXPECT_FALSE(poleEcho({0, 0, 0}, poles, 2.0, 0.10, model).has_value());
  EXPECT_FALSE(poleEcho({0, 0, 0}, {{1.0, 0.6}}, std::hypot(1.0, 0.6), 0.10, model).has_value());
  EXPECT_FALSE(poleEcho({0, 0, 0}, {{2.5, 0.0}}, 2.5, 0.10, model).has_value());
  EXPECT_FALSE(poleEcho({0, 0, 0}, {}, 1.0, 0.10, model).has_value());
  EXPECT_FALSE(poleEcho({0, 0, 0}, poles, std::nan(""), 0.10, model).has_value());
}

TEST(PoleCandidates, ClustersWithoutASegmentOnly) {
  // A wall 2 m ahead (a segment) and a pipe 1 m ahead on the left (two points): the pipe is the
  // one candidate.
  LaserScan scan;
  scan.full_circle = false;
  for (int i = -40; i <= 40; ++i) {
    const double a = geom::deg2rad(0.5 * i);
    LaserReading r;
    r.angle = a;
    r.valid = true;
    r.range = (i == 20 || i == 21) ? 1.0 : 2.0 / std::cos(a);
    scan.readings.push_back(r);
  }
  RadarMapConfig cfg;
  const PoseLookup at = [](int64_t) { return std::optional<geom::Pose2>(geom::Pose2{}); };
  cfg.pole_min_points = 0;
  EXPECT_TRUE(extractRadarMap(scan, at, cfg).pole_candidates.empty());  // off
  cfg.pole_min_points = 3;
  EXPECT_TRUE(extractRadarMap(scan, at, cfg).pole_candidates.empty());  // two points: too few
  cfg.pole_min_points = 1;
  const RadarMap rm = extractRadarMap(scan, at, cfg);
  ASSERT_EQ(rm.pole_candidates.size(), 1u);
  EXPECT_EQ(rm.pole_candidates[0].size(), 2u);
  EXPECT_NEAR(rm.pole_candidates[0][0].norm(), 1.0, 1e-12);
  EXPECT_FALSE(rm.segments.empty());
}
