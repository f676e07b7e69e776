// Complement extraction: classification, the Segment Map point, stale Radar Maps, the message
// layer's input checks, and the paper's Fig. 4 end to end (scan -> RM -> hypothesis -> classes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <limits>
#include <utility>

#include "complement/complement.hpp"
#include "complement/complement_config.hpp"
#include "complement/messages.hpp"
#include "complement_fixture.hpp"

using namespace lasonic;

// The generated CLASS_* are `static const` members without a definition: gtest's EXPECT_EQ
// takes references, so compare against local copies.
constexpr int8_t kComplementary = complement_reading_t::CLASS_COMPLEMENTARY;
constexpr int8_t kRedundant = complement_reading_t::CLASS_REDUNDANT;
constexpr int8_t kUnverifiable = complement_reading_t::CLASS_UNVERIFIABLE;
constexpr int8_t kInvalid = complement_reading_t::CLASS_INVALID;
constexpr int8_t kOutsideView = complement_reading_t::CLASS_OUTSIDE_VIEW;
using namespace lasonic::complement;
using geom::Pose2;

TEST(Classify, Boundaries) {
  // h = 1.0, tol = 0.25 (exact in binary, so the boundaries are exact).
  const double h = 1.0, tol = 0.25, lim = 2.20;
  EXPECT_EQ(classify(0.74, false, h, tol, lim), SonarClass::Complementary);
  EXPECT_EQ(classify(0.75, false, h, tol, lim), SonarClass::Redundant);  // |r - h| = tol
  EXPECT_EQ(classify(1.00, false, h, tol, lim), SonarClass::Redundant);
  EXPECT_EQ(classify(1.25, false, h, tol, lim), SonarClass::Redundant);
  EXPECT_EQ(classify(1.26, false, h, tol, lim), SonarClass::False);
  EXPECT_EQ(classify(2.20, false, h, tol, lim), SonarClass::False);
  EXPECT_EQ(classify(2.21, false, h, tol, lim), SonarClass::Unverifiable);  // beyond the limit
  EXPECT_EQ(classify(0.50, true, h, tol, lim), SonarClass::Unverifiable);   // no echo
  // Nothing in the RM (h = limit): a shorter echo is new information, one at the limit is not.
  EXPECT_EQ(classify(1.0, false, lim, tol, lim), SonarClass::Complementary);
  EXPECT_EQ(classify(2.0, false, lim, tol, lim), SonarClass::Redundant);
  EXPECT_STREQ(className(SonarClass::False), "false");
}

TEST(SegmentMap, PointOnTheAcousticAxisAtTheRealRange) {
  const auto p = segmentMapPoint({1.0, 2.0, geom::kPi / 2}, 0.5);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 2.5, 1e-12);
}

namespace {
RadarMap wallAhead(int64_t utime) {
  RadarMap rm;
  rm.utime = utime;
  rm.segments = {{{{1.0, -1.0}, {1.0, 1.0}}, 20, 0.0}};
  return rm;
}
SonarGroup oneForward(int64_t utime, double range, bool valid = true) {
  SonarGroup g;
  g.utime = utime;
  g.readings.push_back({3, range, false, {0, 0, 0}, valid});
  return g;
}
}  // namespace

TEST(ExtractComplement, FreshRadarMapClassifies) {
  const RadarMap rm = wallAhead(1'000'000);
  const auto out = extractComplement(oneForward(1'100'000, 0.5), Pose2{}, &rm, {});
  EXPECT_FALSE(out.radar_map_stale);
  EXPECT_EQ(out.radar_map_utime, 1'000'000);
  ASSERT_EQ(out.readings.size(), 1u);
  const auto& r = out.readings[0];
  EXPECT_EQ(r.sensor_id, 3);
  EXPECT_EQ(r.cls, SonarClass::Complementary);
  EXPECT_NEAR(r.hypothetical_range, 1.0, 1e-12);
  ASSERT_TRUE(r.end.has_value());
  EXPECT_NEAR(r.end->x(), 0.5, 1e-12);
}

TEST(ExtractComplement, AReadingAtAPolesDistanceIsThatPolesAndALongerOneIsNotFalse) {
  RadarMap rm = wallAhead(1'000'000);
  rm.poles = {{0.6, 0.05}};  // a pipe in front of the wall, inside the beam
  const double pipe = std::hypot(0.6, 0.05);
  const auto at = extractComplement(oneForward(1'100'000, pipe + 0.02), Pose2{}, &rm, {});
  ASSERT_EQ(at.readings.size(), 1u);
  EXPECT_EQ(at.readings[0].cls, SonarClass::Redundant);
  EXPECT_TRUE(at.readings[0].by_pole);
  EXPECT_NEAR(at.readings[0].hypothetical_range, pipe, 1e-12);
  // Nearer than the pipe: something else answered; between the pipe and the wall: the pipe was
  // not heard (a weak reflector), the lines decide; at the wall: redundant by the wall.
  const auto nearer = extractComplement(oneForward(1'100'000, 0.3), Pose2{}, &rm, {});
  EXPECT_EQ(nearer.readings[0].cls, SonarClass::Complementary);
  EXPECT_FALSE(nearer.readings[0].by_pole);
  const auto beyond = extractComplement(oneForward(1'100'000, 0.8), Pose2{}, &rm, {});
  EXPECT_EQ(beyond.readings[0].cls, SonarClass::Complementary);
  const auto wall = extractComplement(oneForward(1'100'000, 1.0), Pose2{}, &rm, {});
  EXPECT_EQ(wall.readings[0].cls, SonarClass::Redundant);
  EXPECT_FALSE(wall.readings[0].by_pole);
}

TEST(RightAngleCorners, WhereTwoLinesMeetSquare) {
  // An L (in either order and direction), a 60 deg bend, two lines 0.2 m apart, a straight run.
  const auto corners = [](std::vector<RmSegment> segs) { return rightAngleCorners(segs, 0.05, geom::deg2rad(10)); };
  const std::vector<RmSegment> l = {{{{1.2, -1.0}, {1.2, 1.2}}, 20, 0}, {{{1.21, 1.2}, {0.6, 1.2}}, 10, 0}};
  const auto found = corners(l);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].vertex.x(), 1.205, 1e-12);
  EXPECT_NEAR(found[0].vertex.y(), 1.2, 1e-12);
  EXPECT_EQ(corners({l[1], {{{1.2, 1.2}, {1.2, -1.0}}, 20, 0}}).size(), 1u);
  EXPECT_TRUE(corners({l[0], {{{1.2, 1.2}, {1.2 - 0.5, 1.2 + 0.5 * std::sqrt(3.0)}}, 10, 0}}).empty());  // 60 deg
  EXPECT_EQ(corners({l[0], {{{1.2, 1.2}, {1.2 - 0.5, 1.2 + 0.5 * std::tan(geom::deg2rad(8))}}, 10, 0}}).size(), 1u);
  EXPECT_TRUE(corners({l[0], {{{1.0, 1.2}, {0.4, 1.2}}, 10, 0}}).empty());                  // 0.2 m apart
  EXPECT_TRUE(corners({l[0], {{{1.2, 1.2}, {1.2, 2.0}}, 10, 0}}).empty());                  // straight on
  // Inside: in front of both walls' inner faces.
  EXPECT_TRUE(found[0].inside({0, 0}));
  EXPECT_FALSE(found[0].inside({1.5, 0}));  // behind the first wall
  EXPECT_FALSE(found[0].inside({0, 1.5}));  // behind the second
}

TEST(ExtractComplement, CrosstalkByWayOfACornerIsTheCornersNotComplementary) {
  // A corner at (1.2, 1.2) whose second wall ends at x = 0.6, so the listener's beam (up, +y,
  // from (0, 0.05)) sees nothing within the 2.20 m limit. The group's other sensor, at (0.05, 0)
  // facing +x, pings; the corner sends it back towards the listener: path |2v - e - p|.
  RadarMap rm;
  rm.utime = 1'000'000;
  rm.segments = {{{{1.2, -1.0}, {1.2, 1.2}}, 20, 0}, {{{1.2, 1.2}, {0.6, 1.2}}, 10, 0}};
  rm.corners = rightAngleCorners(rm.segments);  // (as every Radar Map the library builds)
  const geom::Vec2 v(1.2, 1.2), e(0.05, 0), p(0, 0.05);
  const double crosstalk = 0.5 * (2 * v - e - p).norm();  // 1.66 m
  const auto group = [&](double listener_range) {
    SonarGroup g;
    g.utime = 1'100'000;
    g.readings.push_back({0, 0, true, {e.x(), e.y(), 0}, true});                            // the emitter: no echo
    g.readings.push_back({6, listener_range, false, {p.x(), p.y(), geom::kPi / 2}, true});  // the listener
    return g;
  };
  ComplementParams params;
  const auto heard = extractComplement(group(crosstalk + 0.03), Pose2{}, &rm, params);
  ASSERT_EQ(heard.readings.size(), 2u);
  EXPECT_EQ(heard.readings[1].cls, SonarClass::Redundant);
  EXPECT_TRUE(heard.readings[1].by_crosstalk);
  EXPECT_NEAR(heard.readings[1].hypothetical_range, crosstalk, 1e-12);
  // Another range is something the laser does not see.
  const auto other = extractComplement(group(1.2), Pose2{}, &rm, params);
  EXPECT_EQ(other.readings[1].cls, SonarClass::Complementary);
  EXPECT_FALSE(other.readings[1].by_crosstalk);
  // Alone in its group, or with the paper's rule, the same reading stays complementary.
  SonarGroup alone = group(crosstalk);
  alone.readings.erase(alone.readings.begin());
  EXPECT_EQ(extractComplement(alone, Pose2{}, &rm, params).readings[0].cls, SonarClass::Complementary);
  params.crosstalk_corners = false;
  EXPECT_EQ(extractComplement(group(crosstalk), Pose2{}, &rm, params).readings[1].cls, SonarClass::Complementary);
  // A corner that is not right-angled sends nothing back to a neighbour.
  params.crosstalk_corners = true;
  rm.segments[1].seg.b = {1.2 - 0.6, 1.2 + 0.6 * std::tan(geom::deg2rad(30))};
  rm.corners = rightAngleCorners(rm.segments);
  EXPECT_EQ(extractComplement(group(crosstalk), Pose2{}, &rm, params).readings[1].cls, SonarClass::Complementary);
}

// extractComplement takes the robot's sin and cos once per group and the axis direction from the
// beam's edges: every reading's sensor pose, segment-map point and hypothesis must be bit for bit
// what Pose2::compose, segmentMapPoint and hypotheticalRange give, for any pose and mount.
TEST(ExtractComplement, SensorPosesAndEndsAreComposeAndSegmentMapPointBitForBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-5.0, 5.0), a(-10.0, 10.0), r(0.0, 3.0);
  RadarMap rm = wallAhead(1'000'000);
  rm.segments.push_back({{{-1.0, 2.0}, {2.0, 0.5}}, 20, 0.0});
  for (int trial = 0; trial < 500; ++trial) {
    const Pose2 robot{u(rng), u(rng), trial % 7 == 0 ? 1e5 * a(rng) : a(rng)};
    SonarGroup g;
    g.utime = 1'100'000;
    for (int k = 0; k < 4; ++k)
      g.readings.push_back({k, r(rng), k == 3, {0.3 * u(rng), 0.3 * u(rng), a(rng)}, true, k == 2 ? 0.4 : 0.0});
    const auto out = extractComplement(g, robot, &rm, {});
    ASSERT_EQ(out.readings.size(), g.readings.size());
    for (size_t k = 0; k < g.readings.size(); ++k) {
      const SonarReading& in = g.readings[k];
      const auto& c = out.readings[k];
      const Pose2 sensor = robot.compose(in.mount);
      ASSERT_TRUE(c.sensor_pose.has_value());
      const auto bits = [](double v) { uint64_t b; std::memcpy(&b, &v, sizeof b); return b; };
      ASSERT_EQ(bits(c.sensor_pose->x), bits(sensor.x)) << trial;
      ASSERT_EQ(bits(c.sensor_pose->y), bits(sensor.y)) << trial;
      ASSERT_EQ(bits(c.sensor_pose->theta), bits(sensor.theta)) << trial;
      IdealSonarModel model;
      if (in.beam_width > 0) model.beam_width = in.beam_width;
      ASSERT_EQ(bits(c.hypothetical_range), bits(hypotheticalRange(sensor, rm.segments, model))) << trial;
      if (in.no_echo) {
        ASSERT_FALSE(c.end.has_value());
        continue;
      }
      ASSERT_TRUE(c.end.has_value());
      const geom::Vec2 end = segmentMapPoint(sensor, in.range);
      ASSERT_EQ(bits(c.end->x()), bits(end.x())) << trial;
      ASSERT_EQ(bits(c.end->y()), bits(end.y())) << trial;
    }
  }
}

TEST(ExtractComplement, NoRadarMapYetIsStaleAndUnverifiable) {
  const auto out = extractComplement(oneForward(1'000'000, 0.5), Pose2{}, nullptr, {});
  EXPECT_TRUE(out.radar_map_stale);
  EXPECT_EQ(out.radar_map_utime, 0);
  EXPECT_EQ(out.readings[0].cls, SonarClass::Unverifiable);
  EXPECT_DOUBLE_EQ(out.readings[0].hypothetical_range, 2.20);
}

TEST(ExtractComplement, OldRadarMapIsStale) {
  const RadarMap rm = wallAhead(1'000'000);
  ComplementParams p;
  p.max_rm_age_us = 500'000;
  EXPECT_FALSE(extractComplement(oneForward(1'500'000, 0.5), Pose2{}, &rm, p).radar_map_stale);
  const auto out = extractComplement(oneForward(1'500'001, 0.5), Pose2{}, &rm, p);
  EXPECT_TRUE(out.radar_map_stale);
  EXPECT_EQ(out.readings[0].cls, SonarClass::Unverifiable);
  EXPECT_NEAR(out.readings[0].hypothetical_range, 1.0, 1e-12);  // still shown, never trusted
}

TEST(ExtractComplement, UnknownPoseOrRejectedReadingIsInvalid) {
  const RadarMap rm = wallAhead(0);
  const auto no_pose = extractComplement(oneForward(0, 0.5), std::nullopt, &rm, {});
  EXPECT_EQ(no_pose.readings[0].cls, SonarClass::Invalid);
  EXPECT_TRUE(std::isnan(no_pose.readings[0].hypothetical_range));
  EXPECT_FALSE(no_pose.readings[0].sensor_pose.has_value());
  const auto rejected = extractComplement(oneForward(0, 0.5, false), Pose2{}, &rm, {});
  EXPECT_EQ(rejected.readings[0].cls, SonarClass::Invalid);
  EXPECT_FALSE(rejected.readings[0].end.has_value());
}

// ---------------------------------------------------------------- the paper's Fig. 4
TEST(Fig4, GlassDoorAndRoundObstacleComplementarySpecularFalseWallsRedundant) {
  const fixture::World world = fixture::fig4Room();
  const Pose2 robot = fixture::fig4RobotPose();
  const auto traj = fixture::still(robot);
  std::vector<InputProblem> problems;
  const auto scan = laserScanFromMessage(fixture::simulateScan(world, traj, 0, 100'000), problems);
  ASSERT_TRUE(scan && problems.empty());
  const RadarMap rm = extractRadarMap(*scan, [&](int64_t t) { return std::optional(traj(t)); }, {});
  // Four walls, the top one broken by the (laser-transparent) glass door: five lines.
  ASSERT_EQ(rm.segments.size(), 5u);

  // The real ring: ideal echoes of the true world (door and obstacle included), except two
  // specular readings (too long, within the limit) and one beyond the limit.
  std::vector<double> real = fixture::trueRing(world, robot);
  const int kDoor = 6, kObstacle = 21, kSpecular1 = 3, kSpecular2 = 15, kBeyond = 9;
  EXPECT_NEAR(real[kDoor], 1.5, 1e-9);       // the door, 1.5 m from the sensor
  EXPECT_LT(real[kObstacle], 0.9);           // the round obstacle
  real[kSpecular1] = real[kSpecular2] = 2.15;
  real[kBeyond] = 2.8;
  std::vector<int> ids(24);
  for (int k = 0; k < 24; ++k) ids[static_cast<size_t>(k)] = k;
  const SonarGroup ring = sonarGroupFromMessage(fixture::sonarGroup(50'000, 0, ids, real), problems);
  ASSERT_TRUE(problems.empty());
  ComplementParams p;
  p.tolerance = 0.15;
  const auto out = extractComplement(ring, robot, &rm, p);
  ASSERT_FALSE(out.radar_map_stale);

  auto cls = [&](int k) { return out.readings[static_cast<size_t>(k)].cls; };
  EXPECT_EQ(cls(kDoor), SonarClass::Complementary);
  EXPECT_EQ(cls(kObstacle), SonarClass::Complementary);
  EXPECT_EQ(cls(kSpecular1), SonarClass::False);
  EXPECT_EQ(cls(kSpecular2), SonarClass::False);
  EXPECT_EQ(cls(kBeyond), SonarClass::Unverifiable);
  // Beams that only see walls: redundant (or unverifiable when the wall is beyond the limit).
  for (int k : {0, 12, 18}) EXPECT_EQ(cls(k), SonarClass::Redundant) << "sensor " << k;
  // Nothing else is complementary: every complementary reading is the door or the obstacle.
  for (const auto& r : out.readings) {
    if (r.cls != SonarClass::Complementary) continue;
    const auto& e = *r.end;
    const bool at_door = std::abs(e.y() - 3.6) < 0.05 && e.x() > 1.4 && e.x() < 2.6;
    const bool at_obstacle = std::abs((e - geom::Vec2(3.0, 0.9)).norm() - 0.2) < 0.3;
    EXPECT_TRUE(at_door || at_obstacle) << "sensor " << r.sensor_id << " at " << e.transpose();
  }
}

// ---------------------------------------------------------------- message layer
TEST(Messages, BadSonarReadingsAreInvalidAndNamed) {
  sonar_ring_t m = fixture::sonarGroup(0, 1, {0, 1, 2, 3, 4, 5}, {1.0, 1.0, 1.0, 1.0, 1.0, -1});
  m.range[2] = std::numeric_limits<float>::quiet_NaN();
  m.range[3] = -0.5f;
  m.range[4] = 1e9f;
  m.sensor_id[1] = 24;       // num_sensors is 24
  m.range[5] = std::numeric_limits<float>::quiet_NaN();  // no echo: the range is meaningless, fine
  std::vector<InputProblem> problems;
  const SonarGroup g = sonarGroupFromMessage(m, problems);
  ASSERT_EQ(g.readings.size(), 6u);
  EXPECT_TRUE(g.readings[0].valid);
  EXPECT_FALSE(g.readings[1].valid);
  EXPECT_FALSE(g.readings[2].valid);
  EXPECT_FALSE(g.readings[3].valid);
  EXPECT_FALSE(g.readings[4].valid);
  EXPECT_TRUE(g.readings[5].valid);
  ASSERT_EQ(problems.size(), 4u);
  EXPECT_EQ(problems[0].counter, "rejected.sonar_id");
  EXPECT_NE(problems[0].message.find("SONAR_RING.sensor_id[1] = 24"), std::string::npos);
  EXPECT_EQ(problems[1].counter, "rejected.sonar_range");
  EXPECT_NE(problems[1].message.find("SONAR_RING.range[2] = nan"), std::string::npos);
  EXPECT_NE(problems[2].message.find("SONAR_RING.range[3] = -0.5"), std::string::npos);
}

// The ends of a range: 0 (some drivers' "no reading") is no echo a transducer can hear and is
// refused, naming the flag to send; +inf without the flag is ROS's "nothing within range", so
// no echo, as the flag says; -inf is refused.
TEST(Messages, AZeroSonarRangeIsRefusedAndInfinityIsNoEcho) {
  const float inf = std::numeric_limits<float>::infinity();
  sonar_ring_t m = fixture::sonarGroup(0, 1, {0, 1, 2, 3, 4}, {0.0, 0.01, 0.025, 1.0, 1.0});
  m.range[3] = inf;
  m.range[4] = -inf;
  std::vector<InputProblem> problems;
  const SonarGroup g = sonarGroupFromMessage(m, problems);
  ASSERT_EQ(g.readings.size(), 5u);
  EXPECT_FALSE(g.readings[0].valid);
  EXPECT_FALSE(g.readings[1].valid);
  EXPECT_TRUE(g.readings[2].valid);
  EXPECT_FALSE(g.readings[2].no_echo);
  EXPECT_TRUE(g.readings[3].valid);
  EXPECT_TRUE(g.readings[3].no_echo);
  EXPECT_EQ(g.readings[3].range, m.range_max);
  EXPECT_FALSE(g.readings[4].valid);
  ASSERT_EQ(problems.size(), 3u);
  for (const InputProblem& p : problems) EXPECT_EQ(p.counter, "rejected.sonar_range");
  EXPECT_NE(problems[0].message.find("SONAR_RING.range[0] = 0 (nearer than any transducer hears"), std::string::npos)
      << problems[0].message;
  EXPECT_NE(problems[0].message.find("send no_echo = 1"), std::string::npos);
  EXPECT_NE(problems[1].message.find("SONAR_RING.range[1] = 0.01"), std::string::npos);
  EXPECT_NE(problems[2].message.find("SONAR_RING.range[4] = -inf (range_max"), std::string::npos) << problems[2].message;
}

TEST(Messages, BadLaserReadingsBecomeGapsBadScansAreRefused) {
  laser_scan_t m = fixture::simulateScan(fixture::fig4Room(), fixture::still({2, 1.8, 0}), 0, 100'000);
  m.ranges[10] = std::numeric_limits<float>::quiet_NaN();
  m.ranges[11] = 99.f;  // beyond range_max 15
  m.flags[12] = 7;
  m.offset_us[13] = -5;
  m.offset_us[14] = 2'000'000;  // two seconds into a scan: no scanner sweeps that slowly
  std::vector<InputProblem> problems;
  auto s = laserScanFromMessage(m, problems);
  ASSERT_TRUE(s.has_value());
  ASSERT_EQ(problems.size(), 5u);
  for (size_t i = 10; i <= 14; ++i) EXPECT_FALSE(s->readings[i].valid) << i;
  EXPECT_TRUE(s->readings[15].valid);
  EXPECT_NE(problems[0].message.find("LASER_SCAN.ranges[10] = nan"), std::string::npos);
  EXPECT_EQ(problems[4].counter, "rejected.laser_offset");
  EXPECT_NE(problems[4].message.find("LASER_SCAN.offset_us[14] = 2000000"), std::string::npos);
  EXPECT_EQ(s->readings[100].utime, m.offset_us[100]);

  laser_scan_t mismatched = m;
  mismatched.flags.pop_back();
  problems.clear();
  EXPECT_FALSE(laserScanFromMessage(mismatched, problems).has_value());
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].counter, "rejected.laser_scan");

  laser_scan_t bad_angles = m;
  bad_angles.angle_increment = 0;
  problems.clear();
  EXPECT_FALSE(laserScanFromMessage(bad_angles, problems).has_value());
}

TEST(Messages, EmptyScansAreRefused) {
  // Accepted, a scan without readings would read as "everything is free".
  laser_scan_t m = fixture::simulateScan(fixture::fig4Room(), fixture::still({2, 1.8, 0}), 0, 100'000);
  m.nranges = 0;
  m.ranges.clear();
  m.flags.clear();
  m.offset_us.clear();
  std::vector<InputProblem> problems;
  EXPECT_FALSE(laserScanFromMessage(m, problems).has_value());
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].counter, "rejected.laser_scan");
  EXPECT_NE(problems[0].message.find("nranges = 0"), std::string::npos) << problems[0].message;
}

TEST(Messages, ScansWithBadRangeLimitsAreRefused) {
  const laser_scan_t good = fixture::simulateScan(fixture::fig4Room(), fixture::still({2, 1.8, 0}), 0, 100'000);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const std::pair<float, float> limits[] = {
      {good.range_min, nan},  // every reading would pass "r <= range_max"
      {good.range_min, inf},
      {nan, good.range_max},
      {good.range_max, good.range_max},  // range_min >= range_max
      {20.f, good.range_max},
  };
  for (const auto& [lo, hi] : limits) {
    laser_scan_t m = good;
    m.range_min = lo;
    m.range_max = hi;
    std::vector<InputProblem> problems;
    EXPECT_FALSE(laserScanFromMessage(m, problems).has_value()) << lo << ".." << hi;
    ASSERT_EQ(problems.size(), 1u) << lo << ".." << hi;
    EXPECT_EQ(problems[0].counter, "rejected.laser_scan");
    EXPECT_NE(problems[0].message.find("range_max"), std::string::npos) << problems[0].message;
  }
}

TEST(Messages, OutputsCarryClassesAndNaNsForUnknowns) {
  const RadarMap rm = [] {
    RadarMap r;
    r.utime = 7;
    r.segments = {{{{1.0, -1.0}, {1.0, 1.0}}, 20, 0.001}};
    return r;
  }();
  const line_map_t lm = radarMapToMessage(rm);
  EXPECT_EQ(lm.nsegments, 1);
  EXPECT_EQ(lm.segments[0].source, 0);  // SOURCE_LASER
  SonarGroup g;
  g.utime = 9;
  g.group = 2;
  g.readings = {{0, 0.5, false, {}, true}, {1, 0.0, true, {}, true}};
  const ComplementParams p;
  const GroupComplement res = extractComplement(g, Pose2{}, &rm, p);
  const complement_t c = complementToMessage(res, p);
  EXPECT_EQ(c.nreadings, 2);
  EXPECT_EQ(c.group, 2);
  EXPECT_FLOAT_EQ(c.tolerance, 0.10f);
  EXPECT_EQ(c.readings[0].cls, kComplementary);
  EXPECT_EQ(c.readings[1].cls, kUnverifiable);
  EXPECT_TRUE(std::isnan(c.readings[1].end_x));  // no echo: no Segment Map point
  const hypothetical_scan_t h = hypothesisToMessage(res, p);
  EXPECT_EQ(h.nreadings, 2);
  EXPECT_NEAR(h.range[0], 1.0f, 1e-6);
  EXPECT_EQ(h.radar_map_utime, 7);
  // Into messages kept from group to group: a later group with fewer readings and no Radar Map
  // leaves nothing of the earlier one behind.
  complement_t kept_c = c;
  hypothetical_scan_t kept_h = h;
  SonarGroup g2;
  g2.utime = 11;
  g2.group = 3;
  g2.readings = {{4, 1.5, false, {}, true}};
  const GroupComplement res2 = extractComplement(g2, Pose2{}, nullptr, p);
  complementToMessageInto(kept_c, res2, p);
  hypothesisToMessageInto(kept_h, res2, p);
  const complement_t fresh_c = complementToMessage(res2, p);
  const hypothetical_scan_t fresh_h = hypothesisToMessage(res2, p);
  ASSERT_EQ(kept_c.getEncodedSize(), fresh_c.getEncodedSize());
  ASSERT_EQ(kept_h.getEncodedSize(), fresh_h.getEncodedSize());
  std::vector<uint8_t> a(static_cast<size_t>(kept_c.getEncodedSize())), b(a.size());
  kept_c.encode(a.data(), 0, static_cast<int>(a.size()));
  fresh_c.encode(b.data(), 0, static_cast<int>(b.size()));
  EXPECT_EQ(a, b);
  a.assign(static_cast<size_t>(kept_h.getEncodedSize()), 0);
  b.assign(a.size(), 1);
  kept_h.encode(a.data(), 0, static_cast<int>(a.size()));
  fresh_h.encode(b.data(), 0, static_cast<int>(b.size()));
  EXPECT_EQ(a, b);
  EXPECT_EQ(kept_c.nreadings, 1);
  EXPECT_EQ(kept_h.radar_map_utime, 0);
}

TEST(ComplementConfigTest, DefaultsOverridesAndKeyPathErrors) {
  const auto def = complementConfig(Config{});
  EXPECT_DOUBLE_EQ(def.params.tolerance, 0.10);
  EXPECT_DOUBLE_EQ(def.params.model.range_limit, 2.20);
  EXPECT_NEAR(def.params.model.beam_width, geom::deg2rad(30), 1e-12);
  const auto c = complementConfig(
      Config::fromString("complement: {tolerance: 0.2, rm_max_age_s: 1.5, radar_map: {min_points: 4}}")
          .section("complement"));
  EXPECT_DOUBLE_EQ(c.params.tolerance, 0.2);
  EXPECT_EQ(c.params.max_rm_age_us, 1'500'000);
  EXPECT_EQ(c.radar_map.min_points, 4);
  auto err = [](const std::string& yaml) {
    try {
      complementConfig(Config::fromString(yaml).section("complement"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("complement: {tolerence: 0.2}").find("complement.tolerence"), std::string::npos);
  EXPECT_NE(err("complement: {tolerance: -1}").find("complement.tolerance"), std::string::npos);
  // Values that would silence the sonar: every echo redundant, every Radar Map stale (the span
  // overflowed int64 microseconds), a memory whose span overflows.
  EXPECT_NE(err("complement: {tolerance: 2.2}").find("complement.tolerance"), std::string::npos);
  EXPECT_NE(err("complement: {rm_max_age_s: 1e13}").find("complement.rm_max_age_s"), std::string::npos);
  EXPECT_NE(err("complement: {late_echo_window_s: 1e13}").find("complement.late_echo_window_s"), std::string::npos);
  EXPECT_NE(err("complement: {poles: {memory_s: 1e13}}").find("complement.poles.memory_s"), std::string::npos);
  EXPECT_NE(err("complement: {radar_map: {split: 1}}").find("complement.radar_map.split"), std::string::npos);
  EXPECT_NE(err("complement: {beam_width_deg: 0}").find("beam_width_deg"), std::string::npos);
  EXPECT_TRUE(def.params.outside_view_complementary);
  EXPECT_FALSE(complementConfig(Config::fromString("complement: {outside_laser_view: paper}").section("complement"))
                   .params.outside_view_complementary);
  EXPECT_NE(err("complement: {outside_laser_view: maybe}").find("complement.outside_laser_view"), std::string::npos);
  EXPECT_TRUE(def.params.crosstalk_corners);
  EXPECT_FALSE(complementConfig(Config::fromString("complement: {crosstalk: paper}").section("complement"))
                   .params.crosstalk_corners);
  EXPECT_NE(err("complement: {crosstalk: no}").find("complement.crosstalk"), std::string::npos);
  EXPECT_TRUE(def.params.late_echoes);
  EXPECT_EQ(def.params.late_echo_window_us, 65'000);
  const auto paper = complementConfig(
      Config::fromString("complement: {late_echoes: paper, late_echo_window_s: 0.1}").section("complement"));
  EXPECT_FALSE(paper.params.late_echoes);
  EXPECT_EQ(paper.params.late_echo_window_us, 100'000);
  EXPECT_NE(err("complement: {late_echoes: yes}").find("complement.late_echoes"), std::string::npos);
  EXPECT_NE(err("complement: {late_echo_window_s: 0}").find("complement.late_echo_window_s"), std::string::npos);
}

TEST(MirrorHalfPath, IsTheWayByTheWallAsAMirrorWithinBothLobes) {
  // e at the origin facing 45 deg, p 1 m to its right facing 135 deg, a wall along y = 1: the
  // mirror point is (0.5, 1), 18.4 deg off both axes; the path |(0, 2) - (1, 0)| = sqrt(5).
  const geom::Segment wall{{-5, 1}, {5, 1}};
  const geom::Vec2 e(0, 0), p(1, 0), axis_e = geom::unitVector(geom::kPi / 4), axis_p = geom::unitVector(0.75 * geom::kPi);
  const double cos_lobe = std::cos(geom::deg2rad(30));
  const auto h = mirrorHalfPath(wall, e, axis_e, p, axis_p, cos_lobe);
  ASSERT_TRUE(h);
  EXPECT_NEAR(*h, 0.5 * std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(*mirrorHalfPath({wall.b, wall.a}, e, axis_e, p, axis_p, cos_lobe), *h, 1e-12);  // either direction
  EXPECT_FALSE(mirrorHalfPath(wall, e, axis_e, p, axis_p, std::cos(geom::deg2rad(15))));  // outside the lobes
  EXPECT_FALSE(mirrorHalfPath({{-5, 1}, {0.4, 1}}, e, axis_e, p, axis_p, cos_lobe));          // the wall ends before it
  EXPECT_FALSE(mirrorHalfPath(wall, e, axis_e, {1, 2}, axis_p, cos_lobe));                    // p behind the wall
  EXPECT_FALSE(mirrorHalfPath(wall, e, -axis_e, p, axis_p, cos_lobe));                        // e facing away
}

namespace {
// A hall whose far wall (x = 6) lies beyond the sonar's range: MOBOT-IV's ring at the origin,
// sensor 0 facing the wall pings at t0, sensor 1 (15 deg) listens 30 ms later. The wall
// mirrors sensor 0's ping to sensor 1 along |e' - p|; by then sound has gone 343 * 0.03 m.
struct LateEchoHall {
  RadarMap rm;
  std::vector<geom::Pose2> mounts = fixture::ringMounts();
  int64_t t0 = 1'000'000;
  LateEchoHall() {
    rm.utime = t0;
    rm.segments = {{{{6, -3}, {6, 3}}, 100, 0}};
    rm.corners = rightAngleCorners(rm.segments);
  }
  Ping ping(int id, int64_t utime) const { return {utime, mounts[static_cast<size_t>(id)], geom::deg2rad(30)}; }
  double arrival(int64_t dt_us) const {  // sensor 0's ping as sensor 1 reads it dt_us later
    const geom::Vec2 e = mounts[0].position(), p = mounts[1].position();
    const geom::Vec2 mirrored(12.0 - e.x(), e.y());
    return 0.5 * (mirrored - p).norm() - 0.5 * kSpeedOfSound * static_cast<double>(dt_us) * 1e-6;
  }
  SonarGroup listener(int64_t utime, double range) const {
    SonarGroup g;
    g.utime = utime;
    g.readings.push_back({1, range, false, mounts[1], true, geom::deg2rad(30)});
    return g;
  }
};
}  // namespace

TEST(FirstLateEcho, IsTheEarliestArrivalOfTheEarlierPings) {
  const LateEchoHall hall;
  const geom::Pose2& listener = hall.mounts[1];
  const double beam = geom::deg2rad(30);
  const int64_t t = hall.t0 + 30'000;
  const auto first = firstLateEcho(listener, beam, t, {hall.ping(0, hall.t0)}, hall.rm, 65'000);
  ASSERT_TRUE(first);
  EXPECT_NEAR(*first, hall.arrival(30'000), 1e-9);  // about 0.56 m
  EXPECT_GT(*first, 0.4);
  EXPECT_LT(*first, 0.7);
  // A ping 25 ms before arrives later in the window: the one of 30 ms before comes first.
  const auto both = firstLateEcho(listener, beam, t, {hall.ping(0, hall.t0 + 5'000), hall.ping(0, hall.t0)}, hall.rm, 65'000);
  EXPECT_NEAR(*both, *first, 1e-12);
  // Older than the window, fired at or after the listener, or back before it was heard: nothing.
  EXPECT_FALSE(firstLateEcho(listener, beam, t, {hall.ping(0, hall.t0)}, hall.rm, 29'000));
  EXPECT_FALSE(firstLateEcho(listener, beam, t, {hall.ping(0, t)}, hall.rm, 65'000));
  EXPECT_FALSE(firstLateEcho(listener, beam, hall.t0 + 40'000, {hall.ping(0, hall.t0)}, hall.rm, 65'000));  // 5.7 m < 6.9 m gone
  // A transducer facing away from the wall (sensor 12) neither sends nor hears it.
  EXPECT_FALSE(firstLateEcho(listener, beam, t, {hall.ping(12, hall.t0)}, hall.rm, 65'000));
  EXPECT_FALSE(firstLateEcho(hall.mounts[12], beam, t, {hall.ping(0, hall.t0)}, hall.rm, 65'000));
}

TEST(ExtractComplement, ALateEchoOfAnEarlierPingIsRedundantNotComplementary) {
  const LateEchoHall hall;
  const int64_t t = hall.t0 + 30'000;
  const double late = hall.arrival(30'000);
  const std::vector<Ping> earlier = {hall.ping(0, hall.t0)};
  ComplementParams p;
  // Without the earlier ping the hypothesis (nothing within 2.20 m) calls it complementary.
  EXPECT_EQ(extractComplement(hall.listener(t, late + 0.03), Pose2{}, &hall.rm, p).readings[0].cls,
            SonarClass::Complementary);
  const auto out = extractComplement(hall.listener(t, late + 0.03), Pose2{}, &hall.rm, p, earlier);
  EXPECT_EQ(out.readings[0].cls, SonarClass::Redundant);
  EXPECT_TRUE(out.readings[0].by_late_echo);
  EXPECT_NEAR(out.readings[0].hypothetical_range, late, 1e-9);
  // Another range, or the paper's rule: complementary.
  const auto other = extractComplement(hall.listener(t, late + 0.5), Pose2{}, &hall.rm, p, earlier);
  EXPECT_EQ(other.readings[0].cls, SonarClass::Complementary);
  EXPECT_FALSE(other.readings[0].by_late_echo);
  p.late_echoes = false;
  EXPECT_EQ(extractComplement(hall.listener(t, late), Pose2{}, &hall.rm, p, earlier).readings[0].cls,
            SonarClass::Complementary);
  // Behind a 270 deg scanner's view the explained reading stays redundant: it is no echo from
  // its arc (as crosstalk), so it is not taken for something the laser could not see there.
  p.late_echoes = true;
  RadarMap blind = hall.rm;
  blind.view.full_circle = false;
  blind.view.sensor = Pose2{};
  blind.view.angle_min = -geom::kPi;
  blind.view.angle_max = -geom::kPi / 2;
  const auto behind = extractComplement(hall.listener(t, late), Pose2{}, &blind, p, earlier);
  EXPECT_EQ(behind.readings[0].cls, SonarClass::Redundant);
  EXPECT_TRUE(behind.readings[0].by_late_echo);
  // A reading at a later arrival is not that echo: the first one would have been read.
  const std::vector<Ping> two = {hall.ping(0, hall.t0), hall.ping(0, hall.t0 + 5'000)};
  EXPECT_EQ(extractComplement(hall.listener(t, hall.arrival(25'000)), Pose2{}, &hall.rm, p, two).readings[0].cls,
            SonarClass::Complementary);
}

TEST(PingHistory, KeepsThePingsOfTheWindowBeforeTheGroup) {
  PingHistory h;
  auto group = [](int64_t utime, std::vector<int> ids) {
    GroupComplement g;
    g.utime = utime;
    for (int id : ids) {
      ClassifiedReading c;
      c.sensor_id = id;
      c.beam_width = 0.5;
      if (id >= 0) c.sensor_pose = geom::Pose2{0.1 * id, 0, 0};  // a negative id: no pose, no ping
      if (id == 99) c.sensor_pose->theta = std::numeric_limits<double>::quiet_NaN();  // a broken mount: no ping
      g.readings.push_back(c);
    }
    return g;
  };
  EXPECT_TRUE(h.before(0, 65'000).empty());
  h.add(group(0, {0, 6, -1, 99}));
  h.add(group(30'000, {1, 7}));
  EXPECT_EQ(h.before(60'000, 65'000).size(), 4u);
  const auto& kept = h.before(70'000, 65'000);  // the first group is 70 ms old
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].utime, 30'000);
  EXPECT_NEAR(kept[1].sensor.x, 0.7, 1e-12);
  EXPECT_DOUBLE_EQ(kept[1].beam_width, 0.5);
  h.clear();
  EXPECT_TRUE(h.before(70'000, 65'000).empty());
}

TEST(ExtractComplement, EachReadingsHypothesisUsesItsOwnBeam) {
  // A pole 1 m ahead, 13.5 deg off the axis: inside a 30 deg beam (+-15), outside a 25 deg one
  // (+-12.5, a Pioneer transducer). The ring message says which transducer fired.
  RadarMap rm;
  rm.utime = 0;
  const double a = geom::deg2rad(13.5);
  const geom::Vec2 pole(std::cos(a), std::sin(a));
  rm.segments = {{{pole, pole + geom::Vec2(0.0, 0.01)}, 2, 0.0}};
  SonarGroup g;
  g.readings.push_back({1, 2.0, false, {0, 0, 0}, true, geom::deg2rad(30.0)});
  g.readings.push_back({2, 2.0, false, {0, 0, 0}, true, geom::deg2rad(25.0)});
  const auto out = extractComplement(g, Pose2{}, &rm, {});
  EXPECT_NEAR(out.readings[0].hypothetical_range, 1.0, 0.01);
  EXPECT_NEAR(out.readings[1].hypothetical_range, IdealSonarModel{}.range_limit, 1e-9);
  EXPECT_NEAR(out.readings[1].beam_width, geom::deg2rad(25.0), 1e-12);
  // ...and the message carries it to the pilot and the navigator.
  const complement_t m = complementToMessage(out, {});
  EXPECT_NEAR(m.readings[1].beam_width, geom::deg2rad(25.0), 1e-6);
  EXPECT_NEAR(m.beam_width, geom::deg2rad(30.0), 1e-6);  // the widest
}

// A 270 deg scanner cannot see behind: its Radar Map's lack of a line says nothing there.
TEST(LaserView, CoversTheScannersFieldOfViewOnly) {
  LaserView v;
  v.full_circle = false;
  v.sensor = {0.1, 0.0, geom::kPi / 2};  // mounted 0.1 m ahead, robot facing +y
  v.angle_min = geom::deg2rad(-135.0);
  v.angle_max = geom::deg2rad(135.0);
  EXPECT_TRUE(v.covers({0.1, 2.0}));     // straight ahead of the sensor
  EXPECT_TRUE(v.covers({2.1, 0.0}));     // 90 deg right
  EXPECT_TRUE(v.covers({-0.9, -0.9}));   // 135 deg left: the last reading's direction
  EXPECT_FALSE(v.covers({-0.9, -1.1}));  // just beyond it
  EXPECT_FALSE(v.covers({0.1, -2.0}));   // straight behind
  v.full_circle = true;
  EXPECT_TRUE(v.covers({0.1, -2.0}));
}

TEST(ExtractComplement, AnEchoFromBeyondTheLasersViewIsOutsideViewNotRedundant) {
  // A wall along the robot's right (y = -1, x in [-3, 3]) that the Radar Map holds; the
  // scanner sees +-135 deg. A rear-right transducer (axis -150 deg) and a right one (-90 deg)
  // both hear the wall at the hypothesis' range.
  RadarMap rm;
  rm.utime = 0;
  rm.segments = {{{{-3.0, -1.0}, {3.0, -1.0}}, 200, 0.0}};
  rm.view.full_circle = false;
  rm.view.sensor = Pose2{};
  rm.view.angle_min = geom::deg2rad(-135.0);
  rm.view.angle_max = geom::deg2rad(135.0);
  SonarGroup g;
  const double beam = geom::deg2rad(25.0);
  g.readings.push_back({1, 0.0, false, {0, 0, geom::deg2rad(-150.0)}, true, beam});
  g.readings.push_back({2, 0.0, false, {0, 0, geom::deg2rad(-90.0)}, true, beam});
  // Each at its hypothesis (redundant by the paper's rule).
  const auto probe = extractComplement(g, Pose2{}, &rm, {});
  for (size_t i = 0; i < 2; ++i) g.readings[i].range = probe.readings[i].hypothetical_range;
  ComplementParams paper;
  paper.outside_view_complementary = false;
  const auto by_paper = extractComplement(g, Pose2{}, &rm, paper);
  EXPECT_EQ(by_paper.readings[0].cls, SonarClass::Redundant);
  EXPECT_EQ(by_paper.readings[1].cls, SonarClass::Redundant);
  const auto out = extractComplement(g, Pose2{}, &rm, {});  // the default
  EXPECT_EQ(out.readings[0].cls, SonarClass::OutsideView);  // its arc reaches behind the scanner
  EXPECT_EQ(out.readings[1].cls, SonarClass::Redundant);    // wholly in view: the laser has it
  EXPECT_STREQ(className(SonarClass::OutsideView), "outside_view");
  // A full-circle scanner sees everywhere: the paper's classes.
  rm.view.full_circle = true;
  EXPECT_EQ(extractComplement(g, Pose2{}, &rm, {}).readings[0].cls, SonarClass::Redundant);
  // The message carries the class, and its consumers read it back as a usable echo.
  const complement_t m = complementToMessage(out, {});
  EXPECT_EQ(m.readings[0].cls, kOutsideView);
  std::vector<InputProblem> problems;
  const auto back = complementFromMessage(m, problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].cls, SonarClass::OutsideView);
  EXPECT_TRUE(back[0].usable);
  EXPECT_NEAR(back[0].range, g.readings[0].range, 1e-6);
  // A redundant reading comes back with its range, hypothesis and pose (the sound it passed:
  // the tactical level's pass-through); malformed, it is named, counted and not used.
  EXPECT_EQ(back[1].cls, SonarClass::Redundant);
  EXPECT_TRUE(back[1].usable);
  ASSERT_TRUE(back[1].sensor_pose.has_value());
  EXPECT_NEAR(back[1].range, g.readings[1].range, 1e-6);
  EXPECT_NEAR(back[1].hypothetical_range, probe.readings[1].hypothetical_range, 1e-6);
  complement_t bad = m;
  bad.readings[1].hypothetical_range = std::numeric_limits<float>::quiet_NaN();
  problems.clear();
  const auto rejected = complementFromMessage(bad, problems);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].counter, "rejected.complement_range");
  EXPECT_NE(problems[0].message.find("readings[1].hypothetical_range"), std::string::npos) << problems[0].message;
  EXPECT_FALSE(rejected[1].usable);
  bad = m;
  bad.readings[1].sensor_pose.theta = std::numeric_limits<double>::infinity();
  problems.clear();
  EXPECT_FALSE(complementFromMessage(bad, problems)[1].usable);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].counter, "rejected.complement_pose");
}

// Unverifiable readings (an echo beyond the range limit, or none) come back from the message with
// the hypothesis as far as their sound is known to have gone, and whether there was an echo (the
// tactical level's pass-through); a stale Radar Map's are not usable, malformed ones are named.
TEST(ExtractComplement, UnverifiableReadingsComeBackWithTheirHypothesis) {
  RadarMap rm;
  rm.utime = 0;
  rm.segments = {{{{1.5, -3.0}, {1.5, 3.0}}, 200, 0.0}};  // a wall 1.5 m ahead
  SonarGroup g;
  const double beam = geom::deg2rad(30.0);
  g.readings.push_back({0, 2.9, false, {0, 0, 0.0}, true, beam});               // beyond the limit
  g.readings.push_back({1, 0.0, true, {0, 0, geom::deg2rad(180.0)}, true, beam});  // no echo, open space
  const auto out = extractComplement(g, Pose2{}, &rm, {});
  ASSERT_EQ(out.readings.size(), 2u);
  EXPECT_EQ(out.readings[0].cls, SonarClass::Unverifiable);
  EXPECT_EQ(out.readings[1].cls, SonarClass::Unverifiable);
  const complement_t m = complementToMessage(out, {});
  std::vector<InputProblem> problems;
  const auto back = complementFromMessage(m, problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(back.size(), 2u);
  EXPECT_TRUE(back[0].usable);
  EXPECT_TRUE(back[0].echo);
  EXPECT_NEAR(back[0].range, 2.9, 1e-6);
  EXPECT_NEAR(back[0].hypothetical_range, 1.5, 0.01);  // the wall the sound turned away from
  ASSERT_TRUE(back[0].sensor_pose.has_value());
  EXPECT_TRUE(back[1].usable);
  EXPECT_FALSE(back[1].echo);
  EXPECT_NEAR(back[1].hypothetical_range, IdealSonarModel{}.range_limit, 1e-6);  // nothing within the limit
  // No fresh Radar Map: no hypothesis to trust, nothing usable (and nothing to complain about).
  complement_t stale = m;
  stale.radar_map_stale = 1;
  problems.clear();
  const auto unused = complementFromMessage(stale, problems);
  EXPECT_TRUE(problems.empty());
  EXPECT_FALSE(unused[0].usable);
  EXPECT_FALSE(unused[1].usable);
  // A hypothesis beyond the range limit, or an echo's range out of bounds: named, not used.
  complement_t bad = m;
  bad.readings[1].hypothetical_range = 2.0f * bad.range_limit;
  bad.readings[0].range = -1.0f;
  problems.clear();
  const auto rejected = complementFromMessage(bad, problems);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].counter, "rejected.complement_range");
  EXPECT_NE(problems[0].message.find("readings[0].range"), std::string::npos) << problems[0].message;
  EXPECT_NE(problems[1].message.find("readings[1].hypothetical_range"), std::string::npos) << problems[1].message;
  EXPECT_FALSE(rejected[0].usable);
  EXPECT_FALSE(rejected[1].usable);
}

// Sensors fired together whose axes lie closer than the sum of their openings hear each
// other's pings by way of a wall; the ring's default groups (axes 90 deg apart) never do.
TEST(OverlappingBeams, PairsOfAGroupCloserThanTheSumOfTheirOpenings) {
  const auto reading = [](int id, double theta_deg, double beam_deg, bool valid = true) {
    return SonarReading{id, 1.0, false, {0, 0, geom::deg2rad(theta_deg)}, valid, geom::deg2rad(beam_deg)};
  };
  SonarGroup ring;  // 4 of 24, 90 deg apart, 30 deg beams
  for (int k = 0; k < 4; ++k) ring.readings.push_back(reading(6 * k, 90.0 * k, 30));
  EXPECT_TRUE(overlappingBeams(ring, geom::deg2rad(30)).empty());

  SonarGroup g;
  g.readings = {reading(3, 170, 30), reading(1, -160, 30), reading(2, 0, 60), reading(0, 80, 25)};
  // 3-1: 30 deg apart across +-180 (< 60); 2-0: 80 deg (< 60 + 25); 3-0: 90 (> 55).
  const auto pairs = overlappingBeams(g, geom::deg2rad(30));
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].a, 1);
  EXPECT_EQ(pairs[0].b, 3);
  EXPECT_NEAR(pairs[0].apart, geom::deg2rad(30), 1e-12);
  EXPECT_EQ(pairs[1].a, 0);
  EXPECT_EQ(pairs[1].b, 2);
  EXPECT_NEAR(pairs[1].width_a, geom::deg2rad(25), 1e-12);  // sensor 0's own beam
  EXPECT_NEAR(pairs[1].width_b, geom::deg2rad(60), 1e-12);

  // At exactly the sum the midway point lies one opening off each axis: still heard.
  g.readings = {reading(0, -30, 30), reading(1, 30, 30)};
  EXPECT_EQ(overlappingBeams(g, geom::deg2rad(30)).size(), 1u);

  // A reading without its own beam uses the model's; rejected readings are left out.
  g.readings = {reading(0, 0, 0), reading(1, 65, 0), reading(2, 10, 30, false)};
  EXPECT_TRUE(overlappingBeams(g, geom::deg2rad(30)).empty());
  EXPECT_EQ(overlappingBeams(g, geom::deg2rad(40)).size(), 1u);
}
