// RadarMapMemory: earlier scans' Radar Map lines where the newest scan does not look, and the
// classification that uses them (SeenBefore).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "complement/complement.hpp"
#include "complement/messages.hpp"
#include "complement/radar_map_memory.hpp"
#include "stages/inputs.hpp"

using namespace lasonic;
using namespace lasonic::complement;
using geom::Pose2;
using geom::Vec2;

namespace {

constexpr int8_t kSeenBefore = complement_reading_t::CLASS_SEEN_BEFORE;  // (a copy: EXPECT_EQ takes references)

// A 270 deg scanner at the origin facing `heading`: blind within 45 deg of straight behind.
LaserView view270(double heading) {
  LaserView v;
  v.full_circle = false;
  v.sensor = Pose2{0, 0, heading};
  v.angle_min = geom::deg2rad(-135.0);
  v.angle_max = geom::deg2rad(135.0);
  return v;
}

RadarMap mapOf(int64_t utime, double heading, std::vector<RmSegment> segments) {
  RadarMap rm;
  rm.utime = utime;
  rm.view = view270(heading);
  rm.robot_pose = Pose2{0, 0, heading};
  rm.segments = std::move(segments);
  return rm;
}

// A wall along y = -1 from x = 0.5 to 3: seen obliquely from the origin (26.6 deg off its normal
// at the near end).
const RmSegment kWall{{{0.5, -1.0}, {3.0, -1.0}}, 60, 0.005};

}  // namespace

TEST(RadarMapMemory, ClipKeepsOnlyWhatTheViewDoesNotLookAt) {
  const LaserView facing_left = view270(geom::kPi);  // blind within 45 deg of +x
  std::vector<RmSegment> out;
  clipOutsideView(kWall, facing_left, out);
  // The wall's bearings run from -63.4 deg (x = 0.5) to -18.4 deg (x = 3); the blind wedge
  // starts at -45 deg, x = 1.
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].seg.a.x(), 1.0, 1e-9);
  EXPECT_NEAR(out[0].seg.b.x(), 3.0, 1e-9);
  EXPECT_NEAR(out[0].seg.a.y(), -1.0, 1e-9);
  EXPECT_EQ(out[0].npoints, kWall.npoints);
  out.clear();
  clipOutsideView(kWall, view270(0.0), out);  // facing +x: all of it in view
  EXPECT_TRUE(out.empty());
  clipOutsideView({{{-3.0, -0.2}, {-3.0, 0.2}}, 10, 0.0}, view270(0.0), out);  // wholly behind
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].seg.length(), 0.4, 1e-12);
  out.clear();
  // A wall across the blind wedge, both ends in view: the middle piece.
  clipOutsideView({{{-2.0, -3.0}, {-2.0, 3.0}}, 10, 0.0}, view270(0.0), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].seg.a.y(), -2.0, 1e-9);
  EXPECT_NEAR(out[0].seg.b.y(), 2.0, 1e-9);
  out.clear();
  LaserView full = view270(0.0);
  full.full_circle = true;
  clipOutsideView(kWall, full, out);
  EXPECT_TRUE(out.empty());
}

TEST(RadarMapMemory, AGlassGlintSeenOnlyFaceOnIsNotKept) {
  // 0.2 m of a pane 1 m ahead, face-on: both ends within 5.7 deg of its normal.
  EXPECT_TRUE(seenOnlyNearNormal({{1.0, -0.1}, {1.0, 0.1}}, Vec2::Zero(), geom::deg2rad(10.0)));
  EXPECT_FALSE(seenOnlyNearNormal(kWall.seg, Vec2::Zero(), geom::deg2rad(10.0)));
  RadarMapMemory m(3.0, geom::deg2rad(10.0));
  m.update(mapOf(0, 0.0, {{{{1.0, -0.1}, {1.0, 0.1}}, 12, 0.002}, kWall}));
  m.update(mapOf(100'000, geom::kPi, {}));  // turned round: both behind
  EXPECT_EQ(m.maps(), 1u);
  EXPECT_EQ(m.lines(), 1u);  // the wall's blind part, not the glint
}

TEST(RadarMapMemory, TheNewestEarlierScanThatSawTheArcWithinMemoryS) {
  RadarMapMemory m(1.0);
  EXPECT_TRUE(m.enabled());
  EXPECT_FALSE(RadarMapMemory(0.0).enabled());
  m.update(mapOf(0, 0.0, {kWall}));               // facing +x: sees the wall
  m.update(mapOf(500'000, geom::kPi, {}));         // facing -x: the wall's far part is behind
  const Pose2 rear{0, 0, geom::deg2rad(-30.0)};    // a transducer looking at it (25 deg beam)
  const double beam = geom::deg2rad(25.0);
  EXPECT_FALSE(arcSeen(rear, 1.3, beam, view270(geom::kPi)));  // the newest scan cannot see there
  const std::vector<RmSegment>* before = m.seenBefore(rear, 1.3, beam);
  ASSERT_NE(before, nullptr);
  ASSERT_EQ(before->size(), 1u);
  EXPECT_NEAR((*before)[0].seg.a.x(), 1.0, 1e-9);
  // Where no earlier scan looked either (straight behind the first one, beside the second's
  // blind wedge): nothing.
  EXPECT_EQ(m.seenBefore(Pose2{0, 0, geom::kPi}, 1.3, beam), nullptr);
  // memory_s after the first scan it is still there; a newer scan 1 us later drops it.
  m.update(mapOf(1'000'000, geom::kPi, {}));
  EXPECT_NE(m.seenBefore(rear, 1.3, beam), nullptr);
  m.update(mapOf(1'000'001, geom::kPi, {}));
  EXPECT_EQ(m.seenBefore(rear, 1.3, beam), nullptr);
  // An older map than the newest is ignored; a full-circle scan forgets everything.
  m.update(mapOf(0, 0.0, {kWall}));
  EXPECT_EQ(m.maps(), 2u);
  RadarMap full = mapOf(1'100'000, 0.0, {});
  full.view.full_circle = true;
  m.update(full);
  EXPECT_EQ(m.maps(), 0u);
}

// The pilot's test for a SeenBefore echo: a laser return in the echo's own sector (7.5 deg about
// its axis) within the tolerance of its range.
TEST(RadarMapMemory, TheLaserReportsAnEchoOnlyInItsSectorAtItsRange) {
  const Pose2 sensor{1.0, 0.0, geom::kPi / 2};  // looking along +y
  const double sector = geom::deg2rad(7.5), tol = 0.1;
  const auto at = [&](double bearing_deg, double r) {
    const double a = geom::kPi / 2 + geom::deg2rad(bearing_deg);
    return std::vector<Vec2>{{1.0 + r * std::cos(a), r * std::sin(a)}};
  };
  EXPECT_TRUE(laserReportsEcho(at(0, 1.0), sensor, 1.0, tol, sector));
  EXPECT_TRUE(laserReportsEcho(at(3.5, 1.09), sensor, 1.0, tol, sector));
  EXPECT_FALSE(laserReportsEcho(at(4.0, 1.0), sensor, 1.0, tol, sector));   // the next sector
  EXPECT_FALSE(laserReportsEcho(at(0, 1.12), sensor, 1.0, tol, sector));    // beyond the tolerance
  EXPECT_FALSE(laserReportsEcho(at(0, 0.85), sensor, 1.0, tol, sector));    // nearer than it
  EXPECT_FALSE(laserReportsEcho({}, sensor, 1.0, tol, sector));
  EXPECT_FALSE(laserReportsEcho(at(0, 1.0), sensor, std::nan(""), tol, sector));
}

// The laser reports the echo's surface within the tolerance on either side of its range: a
// return 8 cm nearer than a 1 m echo (tolerance 0.1 m) is the same surface.
TEST(RadarMapMemory, AReturnNearerThanTheEchoWithinTheToleranceReportsIt) {
  const Pose2 sensor{1.0, 0.0, geom::kPi / 2};  // looking along +y
  const double sector = geom::deg2rad(7.5), tol = 0.1;
  const std::vector<Vec2> nearer = {{1.0, 0.92}};
  EXPECT_TRUE(laserReportsEcho(nearer, sensor, 1.0, tol, sector));
  EXPECT_FALSE(laserReportsEcho(nearer, sensor, 1.0, 0.05, sector));
}

// A rear transducer hears the wall the robot has turned away from. By the newest scan's lines
// (none there) its echo is complementary; by the lines the earlier scan saw there it is the
// wall's (redundant) or passed it (false): SeenBefore, which the pilot leaves out and the
// navigator keeps. A shorter echo stays complementary; without the memory nothing changes.
TEST(RadarMapMemory, AnEchoOfAWallSeenBeforeIsSeenBeforeNotComplementary) {
  RadarMapMemory memory(3.0, geom::deg2rad(10.0));
  memory.update(mapOf(0, 0.0, {kWall}));
  const RadarMap now = mapOf(100'000, geom::kPi, {});
  memory.update(now);
  SonarGroup g;
  g.utime = 120'000;
  const double beam = geom::deg2rad(25.0);
  // The wall's nearest point inside the -30 deg +- 12.5 deg beam: at -42.5 deg, 1 / sin(42.5 deg).
  const double wall = 1.0 / std::sin(geom::deg2rad(42.5));
  for (const double range : {wall, wall + 0.5, 0.8})
    g.readings.push_back({static_cast<int>(g.readings.size()), range, false, {0, 0, geom::deg2rad(-30.0)}, true, beam});
  const ComplementParams p;
  const auto without = extractComplement(g, Pose2{}, &now, p);
  for (const auto& r : without.readings) EXPECT_EQ(r.cls, SonarClass::Complementary);
  const auto with = extractComplement(g, Pose2{}, &now, p, {}, &memory);
  EXPECT_EQ(with.readings[0].cls, SonarClass::SeenBefore);  // redundant on the remembered wall
  EXPECT_NEAR(with.readings[0].hypothetical_range, wall, 1e-9);
  EXPECT_EQ(with.readings[1].cls, SonarClass::SeenBefore);  // passed it (false)
  EXPECT_EQ(with.readings[2].cls, SonarClass::Complementary);  // nearer than the wall
  EXPECT_STREQ(className(SonarClass::SeenBefore), "seen_before");
  // Over the message: the class comes back as an echo for the navigator, not for the pilot.
  const complement_t msg = complementToMessage(with, p);
  EXPECT_EQ(msg.readings[0].cls, kSeenBefore);
  std::vector<InputProblem> problems;
  const auto back = complementFromMessage(msg, problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].cls, SonarClass::SeenBefore);
  EXPECT_TRUE(back[0].usable);
  const auto pilot = toGroupReadings(back, g.utime, false), navigator = toGroupReadings(back, g.utime, true);
  EXPECT_FALSE(pilot[0].echo);
  EXPECT_TRUE(navigator[0].echo);
  EXPECT_TRUE(pilot[2].echo && navigator[2].echo);
  // A class beyond the last is still rejected by name.
  complement_t bad = msg;
  bad.readings[0].cls = kSeenBefore + 1;
  problems.clear();
  EXPECT_EQ(complementFromMessage(bad, problems).size(), 2u);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].counter, "rejected.complement_class");
}

// A transducer at the edge of a 270 deg scanner's view hears the wall the scan sees there: the
// newest lines explain its echo (redundant), but its arc reaches beyond the view, so it is
// outside_view and keeps the newest lines' hypothesis (the pilot tells such an echo by it); the
// lines an earlier scan saw behind are not asked. An echo that passed the wall (false by the
// newest lines) is judged on them: seen_before.
TEST(RadarMapMemory, AnOutsideViewEchoTheNewestLinesExplainKeepsTheirHypothesis) {
  RadarMapMemory memory(3.0, geom::deg2rad(10.0));
  const RmSegment whole{{{-3.0, -1.0}, {3.0, -1.0}}, 120, 0.005};
  memory.update(mapOf(0, -geom::kPi / 2, {whole}));  // facing the wall: all of it in view
  const RadarMap now = mapOf(100'000, 0.0, {{{{-1.0, -1.0}, {3.0, -1.0}}, 80, 0.005}});  // to -135 deg
  memory.update(now);
  SonarGroup g;
  g.utime = 120'000;
  const double beam = geom::deg2rad(25.0);
  // Axis at -135 deg: the beam spans -147.5 .. -122.5 deg; the wall's nearest point in it is at
  // -122.5 deg (in view), 1 / sin(57.5 deg) away.
  const double wall = 1.0 / std::sin(geom::deg2rad(57.5));
  for (const double range : {wall, wall + 0.5})
    g.readings.push_back({static_cast<int>(g.readings.size()), range, false, {0, 0, geom::deg2rad(-135.0)}, true, beam});
  const ComplementParams p;
  const auto c = extractComplement(g, Pose2{}, &now, p, {}, &memory);
  ASSERT_EQ(c.readings.size(), 2u);
  EXPECT_EQ(c.readings[0].cls, SonarClass::OutsideView);
  EXPECT_NEAR(c.readings[0].hypothetical_range, wall, 1e-6);
  EXPECT_EQ(c.readings[1].cls, SonarClass::SeenBefore);
  // Over the message the pilot gets that hypothesis back.
  std::vector<InputProblem> problems;
  const auto back = complementFromMessage(complementToMessage(c, p), problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].cls, SonarClass::OutsideView);
  EXPECT_NEAR(back[0].hypothetical_range, wall, 1e-5);
}
