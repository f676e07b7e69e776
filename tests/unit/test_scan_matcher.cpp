// Scan matching: returns put back on the lines of an earlier scan recover the robot's motion
// where the walls constrain it, keep the odometry's where they do not, and so keep the
// navigator's frame from drifting with the odometry.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/config.hpp"
#include "tactical/scan_matcher.hpp"

using namespace lasonic;
using complement::RmSegment;
using complement::ScanPoint;
using geom::Pose2;
using geom::Segment;
using geom::Vec2;

namespace {

// A 6 m x 4 m room with a pillar-like box in it (something that breaks the symmetry).
std::vector<Segment> room() {
  return {{{0, 0}, {6, 0}},     {{6, 0}, {6, 4}},     {{6, 4}, {0, 4}},    {{0, 4}, {0, 0}},
          {{2.0, 2.8}, {3.0, 2.8}}, {{3.0, 2.8}, {3.0, 3.4}}, {{2.0, 2.8}, {2.0, 3.4}}};
}

// A corridor 2 m wide along x, with nothing across it.
std::vector<Segment> corridor() { return {{{-50, 1}, {50, 1}}, {{-50, -1}, {50, -1}}}; }

// The returns a 720-ray scanner at `truth` gets from `walls` (nearest hit, within 15 m), given
// in the frame where the robot is at `believed` (as the odometry places them).
std::vector<ScanPoint> scan(const std::vector<Segment>& walls, const Pose2& truth, const Pose2& believed,
                            double noise_seed = 0) {
  std::vector<ScanPoint> out;
  for (int i = 0; i < 720; ++i) {
    const double a = truth.theta + i * geom::kPi / 360;
    const Vec2 d = geom::unitVector(a);
    double best = 15.0;
    for (const Segment& w : walls) {
      const Vec2 e = w.b - w.a;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const Vec2 f = w.a - truth.position();
      const double t = (f.x() * e.y() - f.y() * e.x()) / den;
      const double u = (f.x() * d.y() - f.y() * d.x()) / den;
      if (t > 0.05 && u >= 0 && u <= 1 && t < best) best = t;
    }
    if (best >= 15.0) {
      out.push_back({});
      continue;
    }
    // A deterministic +-5 mm wobble in place of range noise.
    const double r = best + 0.005 * std::sin(1.7 * i + noise_seed);
    const Vec2 local = geom::unitVector(i * geom::kPi / 360) * r;
    out.push_back({believed.transform(local), r, true});
  }
  return out;
}

std::vector<RmSegment> segmentsOf(const std::vector<ScanPoint>& pts) {
  std::vector<RmSegment> segs;
  complement::appendScanSegments(pts, true, complement::RadarMapConfig{}, segs);
  return segs;
}

std::vector<Vec2> validPoints(const std::vector<ScanPoint>& pts) {
  std::vector<Vec2> out;
  for (const ScanPoint& p : pts)
    if (p.valid) out.push_back(p.p);
  return out;
}

}  // namespace

TEST(ScanMatcher, MatchRecoversASmallRigidMotion) {
  const Pose2 robot{2.0, 1.5, 0.3};
  const auto ref = scan(room(), robot, robot);
  std::vector<Segment> lines;
  for (const RmSegment& s : segmentsOf(ref)) lines.push_back(s.seg);
  ASSERT_GE(lines.size(), 5u);
  // The same place believed 6 cm and 0.03 rad off.
  const Pose2 believed{2.05, 1.47, 0.33};
  const auto pts = validPoints(scan(room(), robot, believed, 1.0));
  const ScanMatchParams p;
  const LineMatch m = matchPointsToLines(pts, lines, believed.position(), 0.1, 0.1, p);
  EXPECT_GE(m.pairs, 400);
  EXPECT_TRUE(m.constrained);  // walls every way: every direction fixed
  const Pose2 fixed = m.motion.compose(believed);
  EXPECT_NEAR(fixed.x, robot.x, 0.005);
  EXPECT_NEAR(fixed.y, robot.y, 0.005);
  EXPECT_NEAR(fixed.theta, robot.theta, 0.001);
}

TEST(ScanMatcher, APointThatStandsForNReturnsWeighsAsNCopies) {
  const std::vector<Segment> lines = {{{-5, 1}, {5, 1}}, {{2, -5}, {2, 5}}, {{-5, -1}, {5, -1}}};
  const std::vector<Vec2> once = {{0.3, 1.012}, {-0.8, 0.995}, {1.985, 0.2}, {2.01, -0.5}, {0.5, -0.99}};
  const std::vector<int> counts = {3, 1, 2, 1, 4};
  std::vector<Vec2> copies;
  for (size_t i = 0; i < once.size(); ++i) copies.insert(copies.end(), static_cast<size_t>(counts[i]), once[i]);
  ScanMatchParams p;
  p.min_pairs = 3;
  const LineMatch a = matchPointsToLines(once, lines, {0, 0}, 0.1, 0.1, p, counts);
  const LineMatch b = matchPointsToLines(copies, lines, {0, 0}, 0.1, 0.1, p);
  EXPECT_EQ(a.pairs, 11);  // returns, not points
  EXPECT_EQ(b.pairs, 11);
  EXPECT_NEAR(a.motion.x, b.motion.x, 1e-12);
  EXPECT_NEAR(a.motion.y, b.motion.y, 1e-12);
  EXPECT_NEAR(a.motion.theta, b.motion.theta, 1e-12);
  EXPECT_GT(std::abs(a.motion.y), 1e-4);  // (a motion there is: the returns sit off their lines)
  // Without the counts each point is one return: another motion.
  const LineMatch c = matchPointsToLines(once, lines, {0, 0}, 0.1, 0.1, p);
  EXPECT_EQ(c.pairs, 5);
  EXPECT_GT(std::abs(c.motion.y - a.motion.y), 1e-5);
}

TEST(ScanMatcher, ClusteredReturnsFixTheMotionAsAllReturnsDo) {
  // The drive of TheFrameStaysWithTheRoomWhileTheOdometryDrifts, with and without clustering the
  // returns (point_spacing): the same frame within a millimetre, from a third of the points.
  ScanMatchParams all;
  all.point_spacing = 0;
  ScanMatchParams clustered;
  clustered.point_spacing = 0.1;
  ScanMatcher a(all), b(clustered);
  Pose2 odo{1.0, 1.2, 0.0}, truth = odo;
  int pairs_a = 0, pairs_b = 0;
  for (int k = 0; k <= 30; ++k) {
    if (k > 0) {
      truth = truth.compose({0.08, 0, 0});
      odo = odo.compose({0.08 * 1.02, 0, 0.01 * 0.08});
    }
    const auto pts = scan(room(), truth, odo, k);
    const auto ra = a.update(pts, segmentsOf(pts), odo, odo.position());
    const auto rb = b.update(pts, segmentsOf(pts), odo, odo.position());
    EXPECT_EQ(ra.matched, rb.matched) << k;
    EXPECT_EQ(ra.constrained, rb.constrained) << k;
    pairs_a += ra.pairs, pairs_b += rb.pairs;
  }
  EXPECT_GT(pairs_a, 30 * 600);
  EXPECT_NEAR(pairs_b, pairs_a, 0.02 * pairs_a);  // pairs count returns
  const Pose2 na = a.toNavigator(odo), nb = b.toNavigator(odo);
  EXPECT_LT((na.position() - nb.position()).norm(), 0.001);
  EXPECT_LT(std::abs(geom::angleDiff(na.theta, nb.theta)), 0.0003);
  EXPECT_GT((na.position() - nb.position()).norm(), 0.0);  // (clustered: not the same numbers)
}

TEST(ScanMatcher, AlongACorridorThePriorKeepsTheOdometrysMotion) {
  const Pose2 robot{0.0, 0.2, 0.0};
  std::vector<Segment> lines;
  for (const RmSegment& s : segmentsOf(scan(corridor(), robot, robot))) lines.push_back(s.seg);
  // Believed 5 cm to the side (the walls tell) and 0.3 m ahead (nothing tells).
  const Pose2 believed{0.3, 0.25, 0.0};
  const auto pts = validPoints(scan(corridor(), robot, believed, 2.0));
  const LineMatch m = matchPointsToLines(pts, lines, believed.position(), 0.05, 0.02, ScanMatchParams{});
  EXPECT_FALSE(m.constrained);  // nothing fixes the position along the axis
  const Pose2 fixed = m.motion.compose(believed);
  EXPECT_NEAR(fixed.y, robot.y, 0.005);      // across: corrected
  EXPECT_NEAR(fixed.x, believed.x, 0.01);    // along: the prior's (odometry's) motion, not pulled
  EXPECT_NEAR(fixed.theta, robot.theta, 0.001);
}

TEST(ScanMatcher, APersonBesideAWallPullsLittle) {
  const Pose2 robot{2.0, 1.5, 0.0};
  std::vector<Segment> lines;
  for (const RmSegment& s : segmentsOf(scan(room(), robot, robot))) lines.push_back(s.seg);
  auto pts = validPoints(scan(room(), robot, robot, 3.0));
  // 40 returns of a person 0.15 m in front of the right wall (x = 6): they pair with that wall.
  for (int i = 0; i < 40; ++i) pts.push_back({5.85, 1.3 + 0.01 * i});
  const LineMatch m = matchPointsToLines(pts, lines, robot.position(), 0.1, 0.1, ScanMatchParams{});
  EXPECT_LT(m.motion.position().norm(), 0.004);
  EXPECT_LT(std::abs(m.motion.theta), 0.001);
}

TEST(ScanMatcher, NothingToPairWithGivesNoCorrection) {
  ScanMatcher sm;
  const Pose2 robot{2.0, 1.5, 0.0};
  const auto pts = scan(room(), robot, robot);
  sm.update(pts, segmentsOf(pts), robot, robot.position());
  // Open space: no returns at all.
  const std::vector<ScanPoint> none(720);
  const auto r = sm.update(none, {}, {2.5, 1.5, 0.0}, {2.5, 1.5});
  EXPECT_FALSE(r.matched);
  EXPECT_TRUE(r.new_keyframe);
  EXPECT_EQ(sm.correction().x, 0.0);
  EXPECT_EQ(sm.correction().y, 0.0);
  EXPECT_EQ(sm.correction().theta, 0.0);
}

TEST(ScanMatcher, TheFrameStaysWithTheRoomWhileTheOdometryDrifts) {
  // The robot drives 4 m along the room at 0.4 m/s (5 scans a second); the odometry's heading
  // drifts by 0.01 rad per metre and its distance reads 2 % long. The navigator's pose, relative
  // to where it started, follows the true motion; the odometry's does not.
  ScanMatcher sm;
  Pose2 odo{1.0, 1.2, 0.0};
  const Pose2 start_truth{1.0, 1.2, 0.0};
  Pose2 truth = start_truth;
  const Pose2 start_nav = sm.toNavigator(odo);
  int matched = 0;
  for (int k = 0; k <= 50; ++k) {
    if (k > 0) {
      const double step = 0.08;
      truth = truth.compose({step, 0, 0});
      odo = odo.compose({step * 1.02, 0, 0.01 * step});
    }
    const auto pts = scan(room(), truth, odo, k);
    const auto r = sm.update(pts, segmentsOf(pts), odo, odo.position());
    matched += r.matched ? 1 : 0;
  }
  EXPECT_GE(matched, 45);
  const Pose2 true_move = start_truth.inverse().compose(truth);
  const Pose2 odo_move = Pose2{1.0, 1.2, 0.0}.inverse().compose(odo);
  const Pose2 nav_move = start_nav.inverse().compose(sm.toNavigator(odo));
  EXPECT_GT((odo_move.position() - true_move.position()).norm(), 0.08);  // the odometry is off
  EXPECT_LT((nav_move.position() - true_move.position()).norm(), 0.01);
  EXPECT_LT(std::abs(geom::angleDiff(nav_move.theta, true_move.theta)), 0.002);
}

TEST(ScanMatcher, DisabledTheNavigatorsFrameIsTheOdometrysBitForBit) {
  ScanMatchParams p;
  p.enabled = false;
  ScanMatcher sm(p);
  const Pose2 robot{2.0, 1.5, 0.1};
  const Pose2 odo{2.07, 1.45, 0.13};
  const auto pts = scan(room(), robot, odo);
  const auto r = sm.update(pts, segmentsOf(pts), odo, odo.position());
  EXPECT_FALSE(r.matched);
  const Pose2 q = sm.toNavigator(Pose2{0.1234567, -7.654321, 3.1});
  EXPECT_EQ(q.x, 0.1234567);
  EXPECT_EQ(q.y, -7.654321);
  EXPECT_EQ(q.theta, 3.1);
}

TEST(ScanMatcher, NonFinitePointsAndDegenerateLinesAreSkipped) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Segment> lines = {{{0, 0}, {0, 0}}, {{nan, 0}, {1, 1}}, {{-5, 1}, {5, 1}}};
  const std::vector<Vec2> pts = {{0, 1.01}, {nan, 1}, {1, 0.99}, {2, 1.0}};
  const LineMatch m = matchPointsToLines(pts, lines, {0, 0}, 0.1, 0.1, ScanMatchParams{});
  EXPECT_EQ(m.pairs, 3);
  EXPECT_TRUE(std::isfinite(m.motion.x) && std::isfinite(m.motion.y) && std::isfinite(m.motion.theta));
}

TEST(ScanMatcher, ConfigKeysAndTheirRanges) {
  const ScanMatchParams d;
  const ScanMatchParams p = scanMatchParams(Config::fromString("enabled: false\ngate_m: 0.5\nkeyframe_turn_deg: 30\n"
                                                               "pose_drift_noise: 0.001\n"));
  EXPECT_FALSE(p.enabled);
  EXPECT_EQ(p.gate, 0.5);
  EXPECT_NEAR(p.keyframe_turn, geom::deg2rad(30), 1e-12);
  EXPECT_EQ(p.pose_noise.drift, 0.001);
  EXPECT_EQ(p.point_sigma, d.point_sigma);
  EXPECT_THROW(scanMatchParams(Config::fromString("gate: 0.5\n")), ConfigError);           // unknown key
  EXPECT_THROW(scanMatchParams(Config::fromString("point_sigma_m: 0\n")), ConfigError);    // out of range
  EXPECT_THROW(scanMatchParams(Config::fromString("min_pairs: 2\n")), ConfigError);
  EXPECT_EQ(scanMatchParams(Config::fromString("point_spacing_m: 0.05\n")).point_spacing, 0.05);
  EXPECT_THROW(scanMatchParams(Config::fromString("point_spacing_m: -0.1\n")), ConfigError);
}
