// RadarMap: placement with per-reading poses, clusters, iterative end-point fit, TLS refit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>

#include "complement/messages.hpp"
#include "complement/radar_map.hpp"
#include "complement/shared_placement.hpp"
#include "complement_fixture.hpp"
#include "core/pose_history.hpp"

using namespace lasonic;
using namespace lasonic::complement;
using geom::Segment;
using geom::Vec2;

namespace {

LaserScan plain(const laser_scan_t& m) {
  std::vector<InputProblem> problems;
  auto s = laserScanFromMessage(m, problems);
  EXPECT_TRUE(problems.empty());
  return *s;
}

fixture::World rectangleRoom() {
  fixture::World w;
  w.laser_visible = {{{0, 0}, {5, 0}}, {{5, 0}, {5, 4}}, {{5, 4}, {0, 4}}, {{0, 4}, {0, 0}}};
  return w;
}

// True if some RM segment has both endpoints within tol of the wall's (either orientation).
bool hasWall(const RadarMap& rm, const Segment& wall, double tol) {
  for (const auto& s : rm.segments) {
    const bool fwd = (s.seg.a - wall.a).norm() < tol && (s.seg.b - wall.b).norm() < tol;
    const bool rev = (s.seg.a - wall.b).norm() < tol && (s.seg.b - wall.a).norm() < tol;
    if (fwd || rev) return true;
  }
  return false;
}

// Largest distance of an RM segment endpoint from the nearest true wall.
double offWalls(const RadarMap& rm, const fixture::World& w) {
  double worst = 0;
  for (const auto& s : rm.segments)
    for (const Vec2& p : {s.seg.a, s.seg.b}) {
      double best = 1e9;
      for (const auto& wall : w.laser_visible) best = std::min(best, geom::distance(wall, p));
      worst = std::max(worst, best);
    }
  return worst;
}

// Odometry at 50 Hz along a trajectory, as the stage would hold it.
PoseHistory historyOf(const fixture::Trajectory& traj, int64_t t0, int64_t t1) {
  PoseHistory h;
  for (int64_t t = t0; t <= t1; t += 20'000) h.add(t, traj(t));
  return h;
}

}  // namespace

TEST(RadarMap, RectangleRoomGivesFourWallsWithCornersWithin2cm) {
  const auto traj = fixture::still({2.0, 1.5, 0.3});
  // angle_min = -pi puts the scan's seam in the middle of the left wall: it must stay one line.
  const LaserScan scan = plain(fixture::simulateScan(rectangleRoom(), traj, 1'000'000, 100'000));
  ASSERT_TRUE(scan.full_circle);
  const RadarMap rm = extractRadarMap(scan, [&](int64_t t) { return std::optional(traj(t)); }, {});
  ASSERT_EQ(rm.segments.size(), 4u);
  for (const auto& wall : rectangleRoom().laser_visible) EXPECT_TRUE(hasWall(rm, wall, 0.02));
  // Noise-free: the rms comes only from the corner reading each wall shares with its neighbour.
  for (const auto& s : rm.segments) EXPECT_LT(s.rms, 0.005);
  EXPECT_EQ(rm.source_utime, 1'000'000);
  EXPECT_GT(rm.utime, 1'090'000);
}

// A scanner mounted upside down sweeps clockwise: its LASER_SCAN lists the same readings from
// the other end, angle_increment < 0, each reading still at its own time. Read as such, it is the
// same scan: the LaserScan's readings run counter-clockwise, and the Radar Map of a moving robot
// (each reading placed with its own pose) is the counter-clockwise scanner's, its times the
// earliest and the latest reading's.
TEST(RadarMap, AClockwiseScanIsTheSameScanReadTheOtherWay) {
  const int64_t t0 = 5'000'000, dur = 200'000;
  const auto traj = fixture::moving({1.5, 1.5, 0.0}, t0, 1.0, 0.0, 1.0);
  const laser_scan_t ccw = fixture::simulateScan(rectangleRoom(), traj, t0, dur);
  laser_scan_t cw = ccw;  // reading i of cw is reading n-1-i of ccw
  const size_t n = ccw.ranges.size();
  std::reverse(cw.ranges.begin(), cw.ranges.end());
  std::reverse(cw.flags.begin(), cw.flags.end());
  std::reverse(cw.offset_us.begin(), cw.offset_us.end());
  cw.angle_min = ccw.angle_min + static_cast<double>(n - 1) * ccw.angle_increment;
  cw.angle_increment = -ccw.angle_increment;
  const LaserScan a = plain(ccw), b = plain(cw);
  ASSERT_EQ(a.readings.size(), b.readings.size());
  EXPECT_EQ(a.full_circle, b.full_circle);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_EQ(a.readings[i].utime, b.readings[i].utime) << i;
    EXPECT_EQ(a.readings[i].range, b.readings[i].range) << i;
    EXPECT_EQ(a.readings[i].valid, b.readings[i].valid) << i;
    EXPECT_NEAR(a.readings[i].angle, b.readings[i].angle, 1e-12) << i;
  }
  const PoseHistory odo = historyOf(traj, t0 - 100'000, t0 + dur + 100'000);
  const RadarMap ra = extractRadarMap(a, odo, {}), rb = extractRadarMap(b, odo, {});
  EXPECT_EQ(rb.source_utime, t0);
  EXPECT_EQ(rb.utime, ra.utime);
  EXPECT_EQ(rb.source_utime, ra.source_utime);
  ASSERT_EQ(ra.segments.size(), rb.segments.size());
  for (size_t k = 0; k < ra.segments.size(); ++k) {
    EXPECT_LT((ra.segments[k].seg.a - rb.segments[k].seg.a).norm(), 1e-9) << k;
    EXPECT_LT((ra.segments[k].seg.b - rb.segments[k].seg.b).norm(), 1e-9) << k;
  }
  EXPECT_LT(offWalls(rb, rectangleRoom()), 0.02);

  // A problem names the index the sender gave the reading.
  cw.ranges[3] = std::numeric_limits<float>::quiet_NaN();
  std::vector<InputProblem> problems;
  const auto bad = laserScanFromMessage(cw, problems);
  ASSERT_TRUE(bad.has_value());
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].message.find("LASER_SCAN.ranges[3] = nan"), std::string::npos) << problems[0].message;
  EXPECT_FALSE(bad->readings[n - 1 - 3].valid);
  EXPECT_EQ(bad->readings[3].valid, a.readings[3].valid);
}

// A full-circle scan of 720 readings (0.5 deg apart) taken over 0.2 s, by increasing angle,
// counter-clockwise in time (clockwise: the latest reading first).
LaserScan fullCircle(bool clockwise) {
  LaserScan s;
  s.full_circle = true;
  const size_t n = 720;
  for (size_t i = 0; i < n; ++i) {
    LaserReading r;
    r.angle = -geom::kPi + static_cast<double>(i) * 2 * geom::kPi / n;
    const auto k = static_cast<int64_t>(clockwise ? n - 1 - i : i);
    r.utime = 1'000'000 + k * 200'000 / static_cast<int64_t>(n);
    r.range = 2.0;
    r.valid = true;
    s.readings.push_back(r);
  }
  return s;
}

// A robot that turns during a full-circle scan against its sweep leaves a wedge at the seam that
// no reading looked into: the view knowing the first reading's pose is the part covered. With
// the sweep, or by less than a reading's spacing, it stays a full circle.
TEST(RadarMap, AFullCircleScanTurnedAgainstLeavesAWedgeAtItsSeam) {
  const geom::Pose2 last{0, 0, 0.0};
  const geom::Pose2 turned_right{0, 0, 0.1}, turned_left{0, 0, -0.1};  // the first reading's heading
  const auto at = [](double bearing) { return geom::unitVector(bearing); };
  // Counter-clockwise sweep, the robot turning clockwise (heading 0.1 -> 0): the first reading,
  // at -pi in its own frame, lies at -pi + 0.1 in the last one's.
  const LaserScan ccw = fullCircle(false);
  const LaserView v = laserViewOf(ccw, last, turned_right);
  EXPECT_FALSE(v.full_circle);
  EXPECT_NEAR(v.angle_min, -geom::kPi + 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(v.angle_max, ccw.readings.back().angle);
  EXPECT_FALSE(v.covers(at(-geom::kPi + 0.05)));  // in the wedge
  EXPECT_FALSE(v.covers(at(geom::kPi - 0.001)));  // beyond the last reading (pi - 0.0087)
  EXPECT_TRUE(v.covers(at(-geom::kPi + 0.15)));
  EXPECT_TRUE(v.covers(at(0.0)));
  EXPECT_TRUE(laserViewOf(ccw, last, turned_left).full_circle);  // with the sweep: overlap, no wedge
  EXPECT_TRUE(laserViewOf(ccw, last, geom::Pose2{0, 0, 0.008}).full_circle);  // less than 0.5 deg
  EXPECT_TRUE(laserViewOf(ccw, last).full_circle);
  // Clockwise sweep (a scanner upside down), the robot turning counter-clockwise: the first
  // reading, the last by angle (pi - 0.0087), lies at pi - 0.0087 - 0.1.
  const LaserScan cw = fullCircle(true);
  const LaserView w = laserViewOf(cw, last, turned_left);
  EXPECT_FALSE(w.full_circle);
  EXPECT_DOUBLE_EQ(w.angle_min, cw.readings.front().angle);
  EXPECT_NEAR(w.angle_max, cw.readings.back().angle - 0.1, 1e-12);
  EXPECT_FALSE(w.covers(at(geom::kPi - 0.05)));
  EXPECT_TRUE(w.covers(at(geom::kPi - 0.15)));
  EXPECT_TRUE(laserViewOf(cw, last, turned_right).full_circle);
  // A scanner of less than a full turn keeps its view.
  LaserScan part = ccw;
  part.full_circle = false;
  part.readings.resize(540);
  const LaserView p = laserViewOf(part, last, turned_right);
  EXPECT_DOUBLE_EQ(p.angle_min, part.readings.front().angle);
  EXPECT_DOUBLE_EQ(p.angle_max, part.readings.back().angle);
}

// A reading whose time offset is rejected (outside the scan's sweep) says nothing, wherever it
// lies in the scan: the Radar Map's times stay the earliest and the latest of the other readings,
// for a counter-clockwise and a clockwise scan alike, and the map is seen from the same pose (not
// from none, which would make the complement keep its previous Radar Map).
TEST(RadarMap, ARejectedTimeOffsetDoesNotMoveTheMapsTimes) {
  const int64_t t0 = 5'000'000, dur = 200'000;
  const auto traj = fixture::moving({1.5, 1.5, 0.0}, t0, 1.0, 0.0, 1.0);
  const PoseHistory odo = historyOf(traj, t0 - 100'000, t0 + dur + 100'000);
  for (const bool clockwise : {false, true}) {
    laser_scan_t m = fixture::simulateScan(rectangleRoom(), traj, t0, dur);
    if (clockwise) {  // a clockwise scanner: the directions reversed, reading 0 still taken first
      const size_t n = m.ranges.size();
      std::reverse(m.ranges.begin(), m.ranges.end());
      std::reverse(m.flags.begin(), m.flags.end());
      m.angle_min += static_cast<double>(n - 1) * m.angle_increment;
      m.angle_increment = -m.angle_increment;
    }
    const RadarMap good = extractRadarMap(plain(m), odo, {});
    m.offset_us[100] = -40'000;     // before the scan began
    m.offset_us[300] = 30'000'000;  // half a minute after it
    std::vector<InputProblem> problems;
    const auto scan = laserScanFromMessage(m, problems);
    ASSERT_TRUE(scan.has_value());
    EXPECT_EQ(problems.size(), 2u);
    EXPECT_EQ(firstReadingTime(*scan), t0) << clockwise;
    EXPECT_EQ(lastReadingTime(*scan), good.utime) << clockwise;
    const RadarMap rm = extractRadarMap(*scan, odo, {});
    EXPECT_EQ(rm.source_utime, good.source_utime) << clockwise;
    EXPECT_EQ(rm.utime, good.utime) << clockwise;
    EXPECT_EQ(rm.robot_pose.x, good.robot_pose.x) << clockwise;  // seen from the pose at its latest reading
    EXPECT_EQ(rm.robot_pose.theta, good.robot_pose.theta) << clockwise;
  }
}

TEST(RadarMap, MotionDuringTheScanIsCorrectedByInterpolatedPoses) {
  // 1 m/s and 1 rad/s during a 200 ms scan: 20 cm and 11 deg of motion between first and last ray.
  const int64_t t0 = 5'000'000, dur = 200'000;
  const auto traj = fixture::moving({1.5, 1.5, 0.0}, t0, 1.0, 0.0, 1.0);
  const LaserScan scan = plain(fixture::simulateScan(rectangleRoom(), traj, t0, dur));
  const PoseHistory odo = historyOf(traj, t0 - 100'000, t0 + dur + 100'000);

  const RadarMap corrected = extractRadarMap(scan, [&](int64_t t) { return odo.at(t); }, {});
  // The robot turned 11 deg during the scan, so the left wall is seen twice (at the start and at
  // the end of the scan, from 20 cm apart): two overlapping pieces, both in place.
  EXPECT_EQ(corrected.segments.size(), 5u);
  EXPECT_LT(offWalls(corrected, rectangleRoom()), 0.02);
  for (const auto& wall : {rectangleRoom().laser_visible[0], rectangleRoom().laser_visible[1],
                           rectangleRoom().laser_visible[2]})
    EXPECT_TRUE(hasWall(corrected, wall, 0.02));

  // One pose for the whole scan (no motion correction): walls come out bent and displaced.
  const auto start = odo.at(t0);
  const RadarMap uncorrected = extractRadarMap(scan, [&](int64_t) { return start; }, {});
  EXPECT_GT(offWalls(uncorrected, rectangleRoom()), 0.10);
}

// The placement from a PoseHistory (interval by interval, the robot's rotation by angle
// addition while it turns) is the placement with its at() to within 1e-12 m (a few 1e-16 of the
// rotation's cos and sin), with the same readings placed.
TEST(RadarMap, PlacementFromAHistoryIsThePlacementWithItsLookup) {
  const int64_t t0 = 5'000'000, dur = 200'000;
  const auto traj = fixture::moving({1.5, 1.5, 0.0}, t0, 1.0, 0.0, 1.0);
  const LaserScan scan = plain(fixture::simulateScan(rectangleRoom(), traj, t0, dur));
  // The history ends inside the scan (the last readings are held or have no pose) and starts
  // after its first reading's time minus the extrapolation limit.
  PoseHistory odo(5'000'000, 30'000);
  for (int64_t t = t0 + 15'000; t <= t0 + 150'000; t += 20'000) odo.add(t, traj(t));
  int missing_a = 0, missing_b = 0;
  const auto a = placeReadings(scan, odo, &missing_a);
  const auto b = placeReadings(scan, [&](int64_t t) { return odo.at(t); }, &missing_b);
  EXPECT_EQ(missing_a, missing_b);
  EXPECT_GT(missing_a, 0);
  ASSERT_EQ(a.size(), b.size());
  int placed = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].valid, b[i].valid) << i;
    ASSERT_NEAR(a[i].p.x(), b[i].p.x(), 1e-12) << i;
    ASSERT_NEAR(a[i].p.y(), b[i].p.y(), 1e-12) << i;
    ASSERT_EQ(a[i].range, b[i].range) << i;
    placed += a[i].valid;
  }
  EXPECT_GT(placed, 400);
  const RadarMap ra = extractRadarMap(scan, odo, {}), rb = extractRadarMap(scan, [&](int64_t t) { return odo.at(t); }, {});
  ASSERT_EQ(ra.segments.size(), rb.segments.size());
  for (size_t i = 0; i < ra.segments.size(); ++i) {
    EXPECT_LT((ra.segments[i].seg.a - rb.segments[i].seg.a).norm(), 1e-9);
    EXPECT_LT((ra.segments[i].seg.b - rb.segments[i].seg.b).norm(), 1e-9);
  }
  EXPECT_EQ(ra.robot_pose.x, rb.robot_pose.x);
  EXPECT_EQ(ra.robot_pose.theta, rb.robot_pose.theta);
}

TEST(RadarMap, GapsStayGaps) {
  // A wall at y = 3 with a window (no laser return) over x in [2.5, 3.5].
  fixture::World w;
  w.laser_visible = {{{0, 3}, {2.5, 3}}, {{3.5, 3}, {6, 3}}};
  const auto traj = fixture::still({3.0, 1.0, 0.0});
  const LaserScan scan = plain(fixture::simulateScan(w, traj, 0, 100'000));
  const RadarMap rm = extractRadarMap(scan, [&](int64_t t) { return std::optional(traj(t)); }, {});
  ASSERT_EQ(rm.segments.size(), 2u);
  for (const auto& s : rm.segments) {
    const double lo = std::min(s.seg.a.x(), s.seg.b.x()), hi = std::max(s.seg.a.x(), s.seg.b.x());
    EXPECT_TRUE(hi <= 2.5 + 0.02 || lo >= 3.5 - 0.02) << "segment bridges the window: " << lo << ".." << hi;
  }
}

TEST(RadarMap, ReadingsWithoutPoseAreGapsAndCounted) {
  const auto traj = fixture::still({2.0, 1.5, 0.0});
  const LaserScan scan = plain(fixture::simulateScan(rectangleRoom(), traj, 0, 100'000));
  int no_pose = 0;
  const RadarMap rm = extractRadarMap(scan, [](int64_t) { return std::optional<geom::Pose2>(); }, {}, &no_pose);
  EXPECT_TRUE(rm.segments.empty());
  EXPECT_EQ(no_pose, 720);
}

TEST(SplitClusters, BreaksAtRangeJumpsAndGapsAndJoinsAcrossTheSeam) {
  auto pt = [](double x, double y) { return ScanPoint{{x, y}, 1.0, true}; };
  std::vector<ScanPoint> pts = {pt(0, 0), pt(0.05, 0), pt(0.10, 0), pt(1.0, 0), pt(1.05, 0), ScanPoint{}, pt(-0.05, 0)};
  const RadarMapConfig cfg;  // jump threshold at 1 m: 0.15 m
  const auto linear = splitClusters(pts, false, cfg);
  ASSERT_EQ(linear.size(), 3u);
  EXPECT_EQ(linear[0].points.size(), 3u);
  EXPECT_EQ(linear[1].points.size(), 2u);
  EXPECT_EQ(linear[2].points.size(), 1u);
  // Full circle: the last point neighbours the first, so {-0.05, 0, 0.05, 0.10} is one cluster.
  const auto circle = splitClusters(pts, true, cfg);
  ASSERT_EQ(circle.size(), 2u);
  EXPECT_EQ(circle[1].points.size(), 4u);
  EXPECT_FALSE(circle[1].closed);
  // Nothing breaks the circle: one closed cluster.
  const std::vector<ScanPoint> ring = {pt(0, 0), pt(0.05, 0), pt(0.05, 0.05), pt(0, 0.05)};
  const auto closed = splitClusters(ring, true, cfg);
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_TRUE(closed[0].closed);
}

TEST(IterativeEndPointFit, SplitsAnLAtItsCorner) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= 10; ++i) pts.emplace_back(0.1 * i, 0.0);
  for (int i = 1; i <= 10; ++i) pts.emplace_back(1.0, 0.1 * i);
  const auto parts = iterativeEndPointFit(pts, {0, pts.size() - 1}, 0.03);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].first, 0u);
  EXPECT_EQ(parts[0].last, 10u);  // the corner belongs to both
  EXPECT_EQ(parts[1].first, 10u);
  EXPECT_EQ(parts[1].last, 20u);
  // A straight run within the threshold is not split.
  EXPECT_EQ(iterativeEndPointFit(pts, {0, 10}, 0.03).size(), 1u);
}

// Two walls split at their corner end where their lines meet, unless that is farther than
// max_shift from either end (no corner of these two: a gap, or a third surface between them) or
// the lines are within 10 deg of parallel (their intersection is ill-conditioned).
TEST(JoinCorner, EndsBothAtTheIntersectionOnlyWithinMaxShift) {
  const auto segment = [](Vec2 a, Vec2 b) {
    RmSegment s;
    s.seg = {a, b};
    return s;
  };
  RmSegment a = segment({0, 0}, {0.95, 0}), b = segment({1, 0.05}, {1, 1});
  joinCorner(a, b, 0.1);
  EXPECT_NEAR((a.seg.b - Vec2(1, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((b.seg.a - Vec2(1, 0)).norm(), 0, 1e-12);
  EXPECT_EQ(a.seg.a, Vec2(0, 0));
  EXPECT_EQ(b.seg.b, Vec2(1, 1));

  // The corner 0.2 m from a's end: farther than max_shift 0.1 (and than 0.15), nothing moves;
  // within 0.25, both end there.
  for (const double max_shift : {0.1, 0.15, 0.25}) {
    a = segment({0, 0}, {0.8, 0});
    b = segment({1, 0.05}, {1, 1});
    joinCorner(a, b, max_shift);
    const bool joined = max_shift > 0.2;
    EXPECT_EQ((a.seg.b - Vec2(1, 0)).norm() < 1e-12, joined) << max_shift;
    EXPECT_EQ((a.seg.b - Vec2(0.8, 0)).norm() < 1e-12, !joined) << max_shift;
    EXPECT_EQ((b.seg.a - Vec2(1, 0.05)).norm() < 1e-12, !joined) << max_shift;
  }
  // ... and from b's end likewise.
  a = segment({0, 0}, {0.95, 0});
  b = segment({1, 0.2}, {1, 1});
  joinCorner(a, b, 0.1);
  EXPECT_EQ(a.seg.b, Vec2(0.95, 0));
  EXPECT_EQ(b.seg.a, Vec2(1, 0.2));

  // Lines 8 deg apart are left alone even where they meet beside both ends; 12 deg apart, joined.
  const auto at = [](double deg, double len) { return Vec2(len * std::cos(deg * M_PI / 180), len * std::sin(deg * M_PI / 180)); };
  a = segment({-1, 0}, {0, 0});
  b = segment(at(8, 0.01), at(8, 1));
  joinCorner(a, b, 10.0);
  EXPECT_EQ(a.seg.b, Vec2(0, 0));
  EXPECT_EQ(b.seg.a, at(8, 0.01));
  b = segment(at(12, 0.01), at(12, 1));
  joinCorner(a, b, 0.1);
  EXPECT_NEAR(a.seg.b.norm(), 0, 1e-12);
  EXPECT_NEAR(b.seg.a.norm(), 0, 1e-12);
}

namespace {
// The definition: split at the first point farthest from the chord (geom::distance) until all
// are within the threshold.
void referenceFit(const std::vector<Vec2>& p, size_t i, size_t j, double thr, std::vector<IndexRange>& out) {
  double dmax = -1;
  size_t kmax = i;
  for (size_t k = i + 1; k < j; ++k) {
    const double d = geom::distance(Segment{p[i], p[j]}, p[k]);
    if (d > dmax) {
      dmax = d;
      kmax = k;
    }
  }
  if (dmax < thr) {
    out.push_back({i, j});
    return;
  }
  referenceFit(p, i, kmax, thr, out);
  referenceFit(p, kmax, j, thr, out);
}
}  // namespace

// The fit compares squared distances; it splits where the definition (roots, first of equal
// roots) does: noisy polylines, exact ties, and distances within a few ulp of each other and
// of the threshold.
TEST(IterativeEndPointFit, SplitsWhereTheDefinitionSplits) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int splits = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Vec2> pts;
    const int n = 5 + trial % 60;
    for (int k = 0; k < n; ++k) {
      const double x = 0.05 * k;
      double y = 0.02 * u(rng) + (k > n / 2 ? 0.3 * (x - 0.025 * n) : 0.0);
      if (trial % 3 == 0) y = (k % 4 == 1 || k % 4 == 2) ? 0.07 : 0.0;  // exact ties
      if (trial % 3 == 1 && k % 5 == 2) y = std::nextafter(0.07, trial % 2 ? 1.0 : 0.0);  // near ties
      pts.emplace_back(x, y);
    }
    const double thr = trial % 3 == 2 ? 0.03 : 0.07;  // 0.07: distances at the threshold
    std::vector<IndexRange> expected;
    referenceFit(pts, 0, pts.size() - 1, thr, expected);
    const auto got = iterativeEndPointFit(pts, {0, pts.size() - 1}, thr);
    ASSERT_EQ(got.size(), expected.size()) << trial;
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].first, expected[k].first) << trial;
      EXPECT_EQ(got[k].last, expected[k].last) << trial;
    }
    splits += static_cast<int>(got.size()) - 1;
  }
  EXPECT_GT(splits, 300);
}

TEST(FitLine, TotalLeastSquaresWithEndpointsProjected) {
  // Points alternating +-1 cm about y = 2 x: TLS recovers the line; endpoints lie on it.
  std::vector<Vec2> pts;
  const Vec2 n = Vec2(-2, 1).normalized();
  for (int i = 0; i <= 20; ++i) pts.push_back(Vec2(0.05 * i, 0.1 * i) + ((i % 2) ? 0.01 : -0.01) * n);
  const RmSegment s = fitLine(pts, {0, pts.size() - 1});
  EXPECT_NEAR(s.rms, 0.01, 1e-3);
  EXPECT_EQ(s.npoints, 21);
  const Vec2 d = (s.seg.b - s.seg.a).normalized();
  EXPECT_NEAR(std::abs(d.dot(Vec2(1, 2).normalized())), 1.0, 1e-4);
  EXPECT_NEAR(s.seg.a.dot(n), 0.0, 2e-3);
  EXPECT_NEAR(s.seg.b.dot(n), 0.0, 2e-3);
}

TEST(RadarMap, ShortOrSparseClustersAreDropped) {
  // A thin pole gives a handful of points: no segment.
  LaserScan scan;
  for (int i = 0; i < 4; ++i) scan.readings.push_back({0, 0.01 * i, 1.0, true});
  const RadarMap rm = extractRadarMap(scan, [](int64_t) { return std::optional(geom::Pose2{}); }, {});
  EXPECT_TRUE(rm.segments.empty());
}

// SharedPlacement: the stored placement is taken only for the same scan and an equal history
// (then it is placeReadings' result, bit for bit); a history that differs in one pose by one ulp,
// has one pose more, or other limits, or a scan that differs in one range by one ulp, is placed
// afresh -- and that result too is placeReadings'.
namespace {
bool samePlacement(const std::vector<ScanPoint>& a, const std::vector<ScanPoint>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].valid != b[i].valid || std::memcmp(&a[i].p, &b[i].p, sizeof a[i].p) != 0 ||
        std::memcmp(&a[i].range, &b[i].range, sizeof a[i].range) != 0)
      return false;
  return true;
}
}  // namespace

TEST(SharedPlacement, TakenOnlyForTheSameScanAndAnEqualHistory) {
  const int64_t t0 = 5'000'000, dur = 200'000;
  const auto traj = fixture::moving({1.5, 1.5, 0.0}, t0, 1.0, 0.0, 1.0);
  const LaserScan scan = plain(fixture::simulateScan(rectangleRoom(), traj, t0, dur));
  // Two stages' histories of the same odometry (the history ends inside the scan: some readings
  // have no pose).
  const auto history = [&](int64_t max_extrapolation_us) {
    PoseHistory h(5'000'000, max_extrapolation_us);
    for (int64_t t = t0 - 100'000; t <= t0 + 150'000; t += 20'000) h.add(t, traj(t));
    return h;
  };
  const PoseHistory a = history(30'000), b = history(30'000);
  SharedPlacement shared;
  int missing = -1, expected_missing = -1;
  const std::vector<ScanPoint> expected = placeReadings(scan, a, &expected_missing);
  EXPECT_GT(expected_missing, 0);
  EXPECT_TRUE(samePlacement(shared.place(scan, a, &missing), expected));
  EXPECT_EQ(missing, expected_missing);
  missing = -1;
  EXPECT_TRUE(samePlacement(shared.place(scan, b, &missing), expected));  // the other stage's history
  EXPECT_EQ(missing, expected_missing);
  EXPECT_EQ(shared.computed(), 1);
  EXPECT_EQ(shared.reused(), 1);

  // One pose one ulp apart (where the scan's readings take their poses from).
  PoseHistory c(5'000'000, 30'000);
  for (int64_t t = t0 - 100'000; t <= t0 + 150'000; t += 20'000) {
    geom::Pose2 p = traj(t);
    if (t == t0 + 60'000) p.x = std::nextafter(p.x, 1e9);
    c.add(t, p);
  }
  EXPECT_FALSE(c.sameAs(a));
  const std::vector<ScanPoint> from_c = placeReadings(scan, c);
  EXPECT_FALSE(samePlacement(from_c, expected));  // (the difference shows in the placement)
  EXPECT_TRUE(samePlacement(shared.place(scan, c), from_c));
  EXPECT_EQ(shared.computed(), 2);

  // One pose more; other limits.
  PoseHistory d = history(30'000);
  d.add(t0 + 170'000, traj(t0 + 170'000));
  EXPECT_FALSE(d.sameAs(a));
  EXPECT_TRUE(samePlacement(shared.place(scan, d), placeReadings(scan, d)));
  EXPECT_EQ(shared.computed(), 3);
  const PoseHistory e = history(80'000);
  EXPECT_FALSE(e.sameAs(a));
  EXPECT_TRUE(samePlacement(shared.place(scan, e, &missing), placeReadings(scan, e, &expected_missing)));
  EXPECT_EQ(missing, expected_missing);
  EXPECT_EQ(shared.computed(), 4);

  // The same history, a scan with one range one ulp longer.
  LaserScan other = scan;
  for (LaserReading& r : other.readings)
    if (r.valid) {
      r.range = std::nextafter(r.range, 1e9);
      break;
    }
  EXPECT_FALSE(sameScan(other, scan));
  EXPECT_TRUE(samePlacement(shared.place(other, a), placeReadings(other, a)));
  EXPECT_TRUE(samePlacement(shared.place(scan, a), expected));
  EXPECT_EQ(shared.computed(), 6);
  EXPECT_EQ(shared.reused(), 1);
  // Back to what is stored: taken again.
  EXPECT_TRUE(samePlacement(shared.place(scan, b), expected));
  EXPECT_EQ(shared.reused(), 2);
}

// The shared scan (lasonic-replay: both stages read each LASER_SCAN): laserScanFromMessage's
// scan and problems for the same message, bit for bit; any other message computed afresh.
TEST(SharedPlacement, ScanFromTheSameMessageOnly) {
  laser_scan_t m{};
  m.utime = 1'000'000;
  m.angle_min = -1.0;
  m.angle_increment = 0.01;
  m.range_min = 0.1f;
  m.range_max = 10.0f;
  for (int i = 0; i < 50; ++i) {
    m.ranges.push_back(1.0f + 0.01f * static_cast<float>(i));
    m.flags.push_back(int8_t{laser_scan_t::FLAG_OK});
    m.offset_us.push_back(i * 100);
  }
  m.ranges[3] = 20.0f;  // beyond range_max: a problem
  m.flags[7] = 5;       // unknown flag: a problem
  m.nranges = 50;
  const auto sameScanAndProblems = [](SharedPlacement& shared, const laser_scan_t& msg) {
    std::vector<InputProblem> want_p, got_p = {{"earlier", "kept"}};
    const std::optional<LaserScan> want = laserScanFromMessage(msg, want_p);
    const std::optional<LaserScan>& got = shared.scanFrom(msg, got_p);
    ASSERT_EQ(got.has_value(), want.has_value());
    if (want) {
      EXPECT_TRUE(sameScan(*got, *want));
    }
    ASSERT_EQ(got_p.size(), want_p.size() + 1);  // appended after what was there
    for (size_t i = 0; i < want_p.size(); ++i) {
      EXPECT_EQ(got_p[i + 1].counter, want_p[i].counter);
      EXPECT_EQ(got_p[i + 1].message, want_p[i].message);
    }
  };
  SharedPlacement shared;
  sameScanAndProblems(shared, m);
  sameScanAndProblems(shared, m);  // reused
  laser_scan_t n = m;
  n.ranges[10] = std::nextafter(n.ranges[10], 2.0f);  // one bit
  sameScanAndProblems(shared, n);
  std::vector<InputProblem> p;
  EXPECT_FALSE(sameScan(*shared.scanFrom(n, p), *laserScanFromMessage(m, p)));
  n = m;
  n.offset_us[20] += 1;
  sameScanAndProblems(shared, n);
  n = m;
  n.range_max = 0.5f;  // every reading but none beyond: other problems
  sameScanAndProblems(shared, n);
  n = m;
  n.nranges = 49;  // inconsistent: no scan
  sameScanAndProblems(shared, n);
  sameScanAndProblems(shared, m);
}

namespace {
// Restores the widest vector path when a test ends (also when an assertion returns early).
struct RestoreVectorPath {
  VectorPath path = vectorPath();
  ~RestoreVectorPath() { setVectorPath(path); }
};

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool samePoints(const std::vector<ScanPoint>& a, const std::vector<ScanPoint>& b, size_t& at) {
  if (a.size() != b.size()) return at = 0, false;
  for (at = 0; at < a.size(); ++at)
    if (a[at].valid != b[at].valid || !sameBits(a[at].p.x(), b[at].p.x()) || !sameBits(a[at].p.y(), b[at].p.y()) ||
        !sameBits(a[at].range, b[at].range))
      return false;
  return true;
}

// The placement's definition, reading by reading: the cursor's pose and rotation (atRotated) at
// the reading's time, the reading in the robot frame through the mount (Pose2::transform's
// operations), the point (x + c lx - s ly, y + s lx + c ly).
std::vector<ScanPoint> placedOneByOne(const LaserScan& scan, const PoseHistory& h, int& missing) {
  std::vector<ScanPoint> out(scan.readings.size());
  PoseHistory::Cursor cursor(h);
  const double mc = std::cos(scan.mount.theta), ms = std::sin(scan.mount.theta);
  missing = 0;
  for (size_t i = 0; i < scan.readings.size(); ++i) {
    const LaserReading& r = scan.readings[i];
    if (!r.valid) continue;
    double c = 1, s = 0;
    const auto robot = cursor.atRotated(r.utime, c, s);
    if (!robot) {
      ++missing;
      continue;
    }
    const double x = r.range * std::cos(r.angle), y = r.range * std::sin(r.angle);
    const double lx = scan.mount.x + mc * x - ms * y, ly = scan.mount.y + ms * x + mc * y;
    out[i] = {Vec2(robot->x + c * lx - s * ly, robot->y + s * lx + c * ly), r.range, true};
  }
  return out;
}
}  // namespace

// placeReadings' vector loops (AVX2 where the CPU has it, SSE2, none) against the definition
// one reading at a time, bit for bit: random scans of 0..60 readings (none, fewer than a
// register's lanes, a tail) over random odometry histories (small and large turns, intervals of
// a few microseconds, readings on interval ends, before and after the history, out of time
// order, invalid, NaN, infinite and huge ranges, turns across +-pi, far-off positions).
TEST(RadarMap, PlacementVectorPathsEqualTheDefinitionBitForBit) {
  RestoreVectorPath restore;
  if (vectorPath() != VectorPath::Avx2) std::cout << "(no AVX2 on this CPU: SSE2 against scalar only)\n";
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> coin(0.0, 1.0), pos(-50.0, 50.0), ang(-geom::kPi, geom::kPi);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  int vector_lanes = 0, missing_total = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // The history: every 2..40 ms, heading steps up to 0.05 rad (small turns) or up to 2 rad.
    PoseHistory h(5'000'000, trial % 3 == 0 ? 0 : 200'000);
    const int64_t t0 = 1'000'000 + static_cast<int64_t>(coin(rng) * 1e6);
    const bool big_turns = trial % 4 == 1;
    geom::Pose2 p{pos(rng), pos(rng), ang(rng)};
    int64_t t = t0;
    const int entries = 1 + static_cast<int>(coin(rng) * 12);
    for (int k = 0; k < entries; ++k) {
      h.add(t, p);
      t += trial % 7 == 0 ? 1 + static_cast<int64_t>(coin(rng) * 5) : 2'000 + static_cast<int64_t>(coin(rng) * 38'000);
      p.x += 0.05 * (coin(rng) - 0.5);
      p.y += 0.05 * (coin(rng) - 0.5);
      p.theta = geom::normalizeAngle(p.theta + (big_turns ? 4.0 : 0.1) * (coin(rng) - 0.5));
    }
    const int64_t t_end = t;
    LaserScan scan;
    scan.mount = {coin(rng) < 0.3 ? 0.0 : 0.3 * (coin(rng) - 0.5), 0.1 * (coin(rng) - 0.5),
                  trial % 5 == 0 ? 0.0 : ang(rng)};
    const int n = trial % 61;
    scan.utime = t0 - 30'000 + static_cast<int64_t>(coin(rng) * 60'000);
    int64_t rt = scan.utime;
    for (int i = 0; i < n; ++i) {
      LaserReading r;
      const double pick = coin(rng);
      rt += static_cast<int64_t>(coin(rng) * static_cast<double>(t_end - t0 + 60'000) / std::max(n, 1) * 2);
      r.utime = pick < 0.05 ? t0 - 300'000 + static_cast<int64_t>(coin(rng) * static_cast<double>(t_end - t0 + 600'000))  // anywhere
                            : rt;
      r.angle = -geom::kPi + 2 * geom::kPi * i / std::max(n, 1);
      r.range = 0.1 + 10 * coin(rng);
      r.valid = coin(rng) > 0.05;
      if (pick > 0.97) r.range = coin(rng) < 0.5 ? nan : (coin(rng) < 0.5 ? inf : 1e300);
      scan.readings.push_back(r);
    }
    // Some readings exactly on the history's entries (an interval's end, and just after its start).
    for (auto& r : scan.readings)
      if (coin(rng) < 0.1) r.utime = t0 + (coin(rng) < 0.5 ? 0 : 1);
    int missing_def = 0;
    const std::vector<ScanPoint> def = placedOneByOne(scan, h, missing_def);
    missing_total += missing_def;
    for (const VectorPath path : {VectorPath::Scalar, VectorPath::Sse2, VectorPath::Avx2}) {
      setVectorPath(path);
      int missing = -1;
      const std::vector<ScanPoint> got = placeReadings(scan, h, &missing);
      size_t at = 0;
      ASSERT_TRUE(samePoints(got, def, at)) << "trial " << trial << ", path " << static_cast<int>(vectorPath())
                                            << ", reading " << at << " of " << n;
      ASSERT_EQ(missing, missing_def) << "trial " << trial;
    }
    PoseHistory::Cursor cursor(h);
    for (size_t i = 0; i + 2 <= scan.readings.size(); i += 2)
      vector_lanes += scan.readings[i].valid && scan.readings[i + 1].valid && cursor.seriesAt(scan.readings[i].utime) &&
                      cursor.seriesAt(scan.readings[i + 1].utime);
  }
  EXPECT_GT(vector_lanes, 5000);  // the vector loops were exercised
  EXPECT_GT(missing_total, 100);  // and readings without a pose
}

// The readings' directions are kept from scan to scan and reused only for the very same angle:
// one angle changed by one ulp (at each place in a group of four, valid or not) is noticed, on
// every vector path.
TEST(RadarMap, PlacementNoticesOneAngleChangedByOneUlp) {
  RestoreVectorPath restore;
  PoseHistory h(5'000'000, 0);
  h.add(1'000'000, {1.0, 2.0, 0.3});
  h.add(1'040'000, {1.02, 2.01, 0.31});
  LaserScan scan;
  scan.mount = {0.1, 0.0, 0.2};
  scan.utime = 1'001'000;
  for (int i = 0; i < 67; ++i) {
    LaserReading r;
    r.utime = scan.utime + 500 * i;
    r.angle = -2.0 + 0.06 * i;
    r.range = 1.0 + 0.01 * i;
    r.valid = i % 9 != 4;
    scan.readings.push_back(r);
  }
  for (const VectorPath path : {VectorPath::Scalar, VectorPath::Sse2, VectorPath::Avx2}) {
    setVectorPath(path);
    for (const size_t j : {size_t{0}, size_t{1}, size_t{2}, size_t{3}, size_t{13}, size_t{40}, size_t{66}}) {
      LaserScan changed = scan;
      placeReadings(scan, h);  // (the directions of `scan` kept)
      changed.readings[j].angle = std::nextafter(changed.readings[j].angle, 10.0);
      changed.readings[j].valid = true;
      int missing_def = 0, missing = -1;
      const std::vector<ScanPoint> def = placedOneByOne(changed, h, missing_def);
      size_t at = 0;
      EXPECT_TRUE(samePoints(placeReadings(changed, h, &missing), def, at))
          << "path " << static_cast<int>(vectorPath()) << ", reading " << j << " changed, differs at " << at;
      EXPECT_EQ(missing, missing_def);
    }
  }
}

namespace {
// splitClusters' definition, pair by pair: point i continues the cluster of point i-1 when both
// are valid and (p_i - p_{i-1}).norm() <= jump_abs + jump_rel * min(range_{i-1}, range_i); a full
// circle starts at a break, or is one closed cluster.
std::vector<Cluster> clustersByDefinition(const std::vector<ScanPoint>& pts, bool full_circle, const RadarMapConfig& cfg) {
  const size_t n = pts.size();
  std::vector<Cluster> out;
  if (n == 0) return out;
  const auto brk = [&](size_t i) {
    if (i == 0 && !full_circle) return true;
    const ScanPoint& a = pts[i == 0 ? n - 1 : i - 1];
    const ScanPoint& b = pts[i];
    return !a.valid || !b.valid || (a.p - b.p).norm() > cfg.jump_abs + cfg.jump_rel * std::min(a.range, b.range);
  };
  size_t start = n;
  for (size_t i = 0; i < n && start == n; ++i)
    if (brk(i)) start = i;
  if (start == n) {
    Cluster all;
    for (const auto& p : pts) all.points.push_back(p.p);
    all.closed = true;
    out.push_back(all);
    return out;
  }
  Cluster cur;
  for (size_t k = 0; k < n; ++k) {
    const size_t i = (start + k) % n;
    if (k > 0 && brk(i) && !cur.points.empty()) out.push_back(cur), cur.points.clear();
    if (pts[i].valid) cur.points.push_back(pts[i].p);
  }
  if (!cur.points.empty()) out.push_back(cur);
  return out;
}

bool sameClusters(const std::vector<Cluster>& a, const std::vector<Cluster>& b) {
  if (a.size() != b.size()) return false;
  for (size_t c = 0; c < a.size(); ++c) {
    if (a[c].closed != b[c].closed || a[c].points.size() != b[c].points.size()) return false;
    for (size_t k = 0; k < a[c].points.size(); ++k)
      if (!sameBits(a[c].points[k].x(), b[c].points[k].x()) || !sameBits(a[c].points[k].y(), b[c].points[k].y()))
        return false;
  }
  return true;
}
}  // namespace

// splitClusters' jump test in vector loops (AVX2 where the CPU has it, SSE2, none) against the
// definition with the root (norm()): random point lists of 0..50 points, with neighbours at the
// threshold and one or two ulps either side of it, equal ranges of both signs of zero, invalid
// points, NaN and infinite coordinates and ranges, thresholds of zero, tiny and huge, full
// circles with and without a break.
TEST(RadarMap, ClusterVectorPathsEqualTheDefinition) {
  RestoreVectorPath restore;
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> coin(0.0, 1.0), pos(-20.0, 20.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  int near_threshold = 0, clusters = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    RadarMapConfig cfg;
    const int kind = trial % 10;
    if (kind == 1) cfg.jump_abs = 0, cfg.jump_rel = 0;  // t = 0: outside the squares' range
    if (kind == 2) cfg.jump_abs = 1e-160, cfg.jump_rel = 0;
    if (kind == 3) cfg.jump_abs = 1e200;
    if (kind == 4) cfg.jump_rel = -0.5;  // t may be negative
    if (kind == 5) cfg.jump_abs = 0.5 * coin(rng), cfg.jump_rel = 0.2 * coin(rng);
    const bool full_circle = trial % 3 == 0;
    const int n = trial % 51;
    std::vector<ScanPoint> pts;
    Vec2 p(pos(rng), pos(rng));
    for (int i = 0; i < n; ++i) {
      ScanPoint sp;
      sp.range = 0.1 + 8 * coin(rng);
      if (coin(rng) < 0.1 && !pts.empty()) sp.range = pts.back().range;  // a tie in min()
      if (coin(rng) < 0.03) sp.range = coin(rng) < 0.5 ? 0.0 : -0.0;
      const double pick = coin(rng);
      if (pick < 0.45 && !pts.empty()) {  // at the threshold from the previous point, or an ulp or two beside it
        const double t = cfg.jump_abs + cfg.jump_rel * std::min(pts.back().range, sp.range);
        const Vec2 dir = coin(rng) < 0.5 ? Vec2(1, 0) : geom::unitVector(2 * geom::kPi * coin(rng));
        p = pts.back().p + dir * t;
        const int ulps = static_cast<int>(coin(rng) * 5) - 2;
        for (int u = 0; u < std::abs(ulps); ++u) p.x() = std::nextafter(p.x(), ulps > 0 ? inf : -inf);
        ++near_threshold;
      } else if (pick < 0.8) {
        p += Vec2(0.3 * (coin(rng) - 0.5), 0.3 * (coin(rng) - 0.5));
      } else if (pick < 0.83) {
        p = Vec2(coin(rng) < 0.5 ? nan : inf, pos(rng));
      } else if (pick < 0.85) {
        sp.range = coin(rng) < 0.5 ? nan : inf;
      } else {
        p = Vec2(pos(rng), pos(rng));
      }
      sp.p = p;
      sp.valid = coin(rng) > 0.06;
      pts.push_back(sp);
    }
    const std::vector<Cluster> def = clustersByDefinition(pts, full_circle, cfg);
    clusters += static_cast<int>(def.size());
    for (const VectorPath path : {VectorPath::Scalar, VectorPath::Sse2, VectorPath::Avx2}) {
      setVectorPath(path);
      ASSERT_TRUE(sameClusters(splitClusters(pts, full_circle, cfg), def))
          << "trial " << trial << ", path " << static_cast<int>(vectorPath()) << ", " << n << " points";
    }
  }
  EXPECT_GT(near_threshold, 20000);
  EXPECT_GT(clusters, 20000);
}

// The scan scanFrom returns, passed on to place() (as both stages do in lasonic-replay), is
// known by its generation rather than compared: the stored placement is taken for the same
// message's scan and an equal history, and computed afresh for the next message's scan (in the
// same object), for an equal copy of a scan, and after a copy was placed.
TEST(SharedPlacement, TheScanFromAMessageIsKnownWithoutAComparison) {
  const int64_t t0 = 5'000'000, dur = 200'000;
  const auto traj = fixture::moving({1.5, 1.5, 0.0}, t0, 1.0, 0.0, 1.0);
  const laser_scan_t m1 = fixture::simulateScan(rectangleRoom(), traj, t0, dur);
  laser_scan_t m2 = m1;
  m2.ranges[100] = std::nextafter(m2.ranges[100], 100.0f);  // one bit in one reading
  PoseHistory a(5'000'000, 30'000), b(5'000'000, 30'000);
  for (int64_t t = t0 - 100'000; t <= t0 + 250'000; t += 20'000) a.add(t, traj(t)), b.add(t, traj(t));
  SharedPlacement shared;
  std::vector<InputProblem> p;
  const LaserScan s1 = *laserScanFromMessage(m1, p), s2 = *laserScanFromMessage(m2, p);
  const std::vector<ScanPoint> want1 = placeReadings(s1, a), want2 = placeReadings(s2, a);
  ASSERT_FALSE(samePlacement(want1, want2));
  EXPECT_TRUE(samePlacement(shared.place(*shared.scanFrom(m1, p), a), want1));
  EXPECT_TRUE(samePlacement(shared.place(*shared.scanFrom(m1, p), b), want1));  // the other stage
  EXPECT_EQ(shared.computed(), 1);
  EXPECT_EQ(shared.reused(), 1);
  EXPECT_TRUE(samePlacement(shared.place(*shared.scanFrom(m2, p), a), want2));  // the next message
  EXPECT_EQ(shared.computed(), 2);
  EXPECT_TRUE(samePlacement(shared.place(*shared.scanFrom(m2, p), b), want2));
  EXPECT_EQ(shared.reused(), 2);
  EXPECT_TRUE(samePlacement(shared.place(s2, b), want2));  // an equal copy: placed afresh
  EXPECT_EQ(shared.computed(), 3);
  EXPECT_TRUE(samePlacement(shared.place(s2, a), want2));  // the copy again: compared and taken
  EXPECT_EQ(shared.reused(), 3);
  EXPECT_TRUE(samePlacement(shared.place(*shared.scanFrom(m2, p), a), want2));  // after a copy: afresh
  EXPECT_EQ(shared.computed(), 4);
  EXPECT_TRUE(samePlacement(shared.place(s1, a), want1));
  EXPECT_TRUE(samePlacement(shared.place(*shared.scanFrom(m1, p), a), want1));
  EXPECT_EQ(shared.computed(), 6);
  EXPECT_EQ(shared.reused(), 3);
}

// The same ranges, in order.
::testing::AssertionResult sameSplits(const std::vector<IndexRange>& got, const std::vector<IndexRange>& want) {
  if (got.size() != want.size())
    return ::testing::AssertionFailure() << got.size() << " ranges, the definition " << want.size();
  for (size_t k = 0; k < got.size(); ++k)
    if (got[k].first != want[k].first || got[k].last != want[k].last)
      return ::testing::AssertionFailure() << "range " << k << ": [" << got[k].first << ", " << got[k].last
                                           << "], the definition [" << want[k].first << ", " << want[k].last << "]";
  return ::testing::AssertionSuccess();
}

// The end-point fit's distances in vector loops (AVX2 where the CPU has it, SSE2, none) split
// where the definition does (roots, the first of equal roots): polylines with exact and
// near ties, points beyond the chord's ends (u clamped, -0 included), chords of zero length
// (equal ends), NaN and infinite points, thresholds at the distances.
TEST(IterativeEndPointFit, VectorPathsSplitWhereTheDefinitionSplits) {
  RestoreVectorPath restore;
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0), coin(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  int splits = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<Vec2> pts;
    const int n = 2 + trial % 70;
    for (int k = 0; k < n; ++k) {
      const double x = trial % 5 == 3 ? 0.05 * k - 0.5 * coin(rng) : 0.05 * k;  // some beyond the ends
      double y = 0.02 * u(rng) + (k > n / 2 ? 0.3 * (x - 0.025 * n) : 0.0);
      if (trial % 3 == 0) y = (k % 4 == 1 || k % 4 == 2) ? 0.07 : 0.0;  // exact ties
      if (trial % 3 == 1 && k % 5 == 2) y = std::nextafter(0.07, trial % 2 ? 1.0 : 0.0);  // near ties
      if (trial % 6 == 4) {  // from a level chord, distances a few ulp apart, rising (or falling) along it
        y = 0.0;
        if (k > 0 && k + 1 < n) {
          y = 0.07;
          for (int step = 0; step < (trial % 12 == 4 ? k : n - k) / 2; ++step) y = std::nextafter(y, 1.0);
        }
      }
      pts.emplace_back(x, y);
      if (coin(rng) < 0.02 && trial % 6 != 4) pts.back() = Vec2(coin(rng) < 0.5 ? nan : inf, y);
    }
    if (trial % 7 == 0) pts.back() = pts.front();  // a chord of zero length
    if (trial % 11 == 0) pts.back() = Vec2(-0.0, 0.0), pts.front() = Vec2(0.0, -0.0);
    const double thr = trial % 3 == 2 ? 0.03 : 0.07;  // 0.07: distances at the threshold
    std::vector<IndexRange> expected;
    referenceFit(pts, 0, pts.size() - 1, thr, expected);
    splits += static_cast<int>(expected.size()) - 1;
    for (const VectorPath path : {VectorPath::Scalar, VectorPath::Sse2, VectorPath::Avx2}) {
      setVectorPath(path);
      ASSERT_TRUE(sameSplits(iterativeEndPointFit(pts, {0, pts.size() - 1}, thr), expected))
          << "trial " << trial << ", path " << static_cast<int>(vectorPath());
    }
  }
  EXPECT_GT(splits, 3000);
}

// Long runs (16 points and more) are screened with approximate distances before the exact ones
// are taken (AVX2): they split where the definition does, also where the largest distances are
// exact ties or a few ulp apart, far from the origin (odometry after a long run: the
// approximation's error grows with the coordinates), with chords of all lengths.
TEST(IterativeEndPointFit, ScreenedLongRunsSplitWhereTheDefinitionSplits) {
  RestoreVectorPath restore;
  std::mt19937 rng(36);
  std::uniform_real_distribution<double> u(-1.0, 1.0), coin(0.0, 1.0);
  const double offsets[] = {0.0, 37.5, -1.3e3, 2.2e5, -4.1e7};
  int splits = 0, ties = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 16 + trial % 300;
    const double off = offsets[trial % 5], scale = trial % 7 == 0 ? 1e-3 : (trial % 7 == 1 ? 40.0 : 1.0);
    const double angle = 0.3 * (trial % 11);
    const Vec2 dir(std::cos(angle), std::sin(angle)), nrm(-dir.y(), dir.x());
    std::vector<Vec2> pts;
    for (int k = 0; k < n; ++k) {
      const double along = scale * 0.05 * k;
      double across = scale * 0.01 * u(rng);
      if (trial % 4 == 0 && k % 9 == 4) across = scale * 0.07;  // exact ties of the largest
      if (trial % 4 == 1 && k % 9 == 4) {  // largest a few ulp apart
        across = scale * 0.07;
        for (int step = 0; step < static_cast<int>(coin(rng) * 4); ++step) across = std::nextafter(across, 1.0);
      }
      pts.push_back(Vec2(off, -off) + along * dir + across * nrm);
    }
    const double thr = scale * (trial % 3 == 0 ? 0.03 : 0.07);
    std::vector<IndexRange> expected;
    referenceFit(pts, 0, pts.size() - 1, thr, expected);
    splits += static_cast<int>(expected.size()) - 1;
    ties += trial % 4 < 2;
    for (const VectorPath path : {VectorPath::Scalar, VectorPath::Avx2}) {
      setVectorPath(path);
      ASSERT_TRUE(sameSplits(iterativeEndPointFit(pts, {0, pts.size() - 1}, thr), expected))
          << "trial " << trial << ", path " << static_cast<int>(vectorPath());
    }
  }
  EXPECT_GT(splits, 2000);
  EXPECT_GT(ties, 900);
}

// The end-point fit's squared distances in each vector path, bit for bit the squared norm of
// closestPoint(chord, p) - p: random chords (and chords of zero length, tiny and huge ones),
// points before, on and beyond the chord's ends, on the chord's line, NaN and infinite, counts
// 0..40 (a register's lanes and a tail).
TEST(IterativeEndPointFit, ChordDistancesOfEveryVectorPathAreTheDefinitionBitForBit) {
  RestoreVectorPath restore;
  std::mt19937 rng(34);
  std::uniform_real_distribution<double> u(-3.0, 3.0), coin(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 4000; ++trial) {
    Segment chord{{u(rng), u(rng)}, {u(rng), u(rng)}};
    if (trial % 13 == 0) chord.b = chord.a;
    if (trial % 17 == 0) chord.b = chord.a + Vec2(1e-160, -1e-160);
    if (trial % 19 == 0) chord.b = chord.a * 1e200;
    if (trial % 23 == 0) chord.a.x() = nan;
    std::vector<Vec2> pts;
    const int n = trial % 41;
    for (int k = 0; k < n; ++k) {
      const double pick = coin(rng);
      const double t = 1.4 * coin(rng) - 0.2;  // before, on and beyond the ends
      if (pick < 0.5) pts.push_back(chord.a + t * (chord.b - chord.a) + Vec2(0.1 * u(rng), 0.1 * u(rng)));
      else if (pick < 0.7) pts.push_back(chord.a + t * (chord.b - chord.a));  // on the line
      else if (pick < 0.75) pts.push_back(k % 2 ? chord.a : chord.b);
      else if (pick < 0.8) pts.emplace_back(coin(rng) < 0.5 ? nan : inf, u(rng));
      else pts.emplace_back(u(rng), u(rng));
    }
    std::vector<double> want(pts.size());
    for (size_t k = 0; k < pts.size(); ++k) want[k] = (geom::closestPoint(chord, pts[k]) - pts[k]).squaredNorm();
    for (const VectorPath path : {VectorPath::Scalar, VectorPath::Sse2, VectorPath::Avx2}) {
      setVectorPath(path);
      std::vector<double> got(pts.size() + 1, -7.0);
      chordSquaredDistances(chord, pts.data(), pts.size(), got.data());
      for (size_t k = 0; k < pts.size(); ++k)
        ASSERT_TRUE(sameBits(got[k], want[k])) << "trial " << trial << ", path " << static_cast<int>(vectorPath())
                                               << ", point " << k << ": " << got[k] << " vs " << want[k];
      ASSERT_EQ(got[pts.size()], -7.0);  // nothing written beyond count
    }
  }
}

// laserScanFromMessage four readings at a time (AVX2 where the CPU has it) against the
// reading-by-reading loop: the same scan (every field of every reading) and the same problems,
// for random messages of 1..60 readings with returns at range_min and range_max and one ulp
// either side, zero of both signs, negative, NaN and infinite ranges, no-return and unknown
// flags, negative offsets, offsets at the limit of a scan's sweep and one beyond.
TEST(LaserScanFromMessage, VectorPathGivesTheSameScanAndProblems) {
  RestoreVectorPath restore;
  if (vectorPath() != VectorPath::Avx2) std::cout << "(no AVX2 on this CPU: the scalar loop only)\n";
  std::mt19937 rng(35);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  const float nanf = std::numeric_limits<float>::quiet_NaN(), inff = std::numeric_limits<float>::infinity();
  int vector_groups = 0;
  LaserScan reused;  // laserScanFromMessageInto, message after message into the same scan
  for (int trial = 0; trial < 4000; ++trial) {
    laser_scan_t m{};
    m.utime = 1'000'000 + static_cast<int64_t>(coin(rng) * 1e9);
    m.angle_min = -2.0 + coin(rng);
    m.angle_increment = 0.001 + 0.02 * coin(rng);
    m.range_min = static_cast<float>(0.5 * coin(rng));
    m.range_max = static_cast<float>(1.0 + 20 * coin(rng));
    const int n = 1 + trial % 60;
    const double clean = coin(rng);  // some messages nearly all common readings
    for (int i = 0; i < n; ++i) {
      float r = static_cast<float>(25 * coin(rng));
      int8_t flag = laser_scan_t::FLAG_OK;
      int32_t off = i * 100;
      if (coin(rng) > clean) {
        const double pick = coin(rng);
        if (pick < 0.15) r = m.range_min;
        else if (pick < 0.3) r = m.range_max;
        else if (pick < 0.4) r = std::nextafter(m.range_max, inff);
        else if (pick < 0.5) r = std::nextafter(m.range_min, -inff);
        else if (pick < 0.55) r = coin(rng) < 0.5 ? 0.0f : -0.0f;
        else if (pick < 0.6) r = -1.0f;
        else if (pick < 0.65) r = nanf;
        else if (pick < 0.7) r = coin(rng) < 0.5 ? inff : -inff;
        else if (pick < 0.8) flag = laser_scan_t::FLAG_NO_RETURN;
        else if (pick < 0.85) flag = static_cast<int8_t>(2 + static_cast<int>(coin(rng) * 100));
        else if (pick < 0.9) off = -1 - static_cast<int32_t>(coin(rng) * 1000);
        else if (pick < 0.95) off = input_limits::kMaxLaserOffsetUs + (coin(rng) < 0.5 ? 0 : 1);
      }
      m.ranges.push_back(r);
      m.flags.push_back(flag);
      m.offset_us.push_back(off);
    }
    m.nranges = n;
    std::vector<InputProblem> want_p, got_p;
    setVectorPath(VectorPath::Scalar);
    const std::optional<LaserScan> want = laserScanFromMessage(m, want_p);
    setVectorPath(VectorPath::Avx2);
    const std::optional<LaserScan> got = laserScanFromMessage(m, got_p);
    ASSERT_TRUE(want && got) << "trial " << trial;
    ASSERT_EQ(got->readings.size(), want->readings.size());
    for (size_t i = 0; i < want->readings.size(); ++i) {
      const LaserReading& a = got->readings[i];
      const LaserReading& b = want->readings[i];
      ASSERT_TRUE(a.utime == b.utime && sameBits(a.angle, b.angle) && sameBits(a.range, b.range) && a.valid == b.valid)
          << "trial " << trial << ", reading " << i;
    }
    ASSERT_TRUE(sameScan(*got, *want)) << "trial " << trial;
    std::vector<InputProblem> into_p;
    ASSERT_TRUE(laserScanFromMessageInto(m, into_p, reused)) << "trial " << trial;
    ASSERT_TRUE(sameScan(reused, *want)) << "trial " << trial << ": what the previous message left shows";
    ASSERT_EQ(into_p.size(), want_p.size()) << "trial " << trial;
    ASSERT_EQ(got_p.size(), want_p.size()) << "trial " << trial;
    for (size_t i = 0; i < want_p.size(); ++i) {
      ASSERT_EQ(got_p[i].counter, want_p[i].counter) << "trial " << trial;
      ASSERT_EQ(got_p[i].message, want_p[i].message) << "trial " << trial;
    }
    for (int i = 0; i + 4 <= n; i += 4) {  // groups the vector loop can take
      bool common = true;
      for (int k = i; k < i + 4; ++k)
        common = common && m.flags[k] == laser_scan_t::FLAG_OK && m.offset_us[k] >= 0 &&
                 m.offset_us[k] <= input_limits::kMaxLaserOffsetUs && m.ranges[k] >= 0 && m.ranges[k] <= m.range_max;
      vector_groups += common;
    }
  }
  EXPECT_GT(vector_groups, 1500);  // (the vector loop was exercised)
}
