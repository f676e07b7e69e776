// Boundaries and guards of line generation, complement extraction, the message checks, the clock
// and the configuration reader that no other test pinned down: each test here was written against
// a changed rule (a comparison made inclusive, a check dropped) that every other unit test still
// passed, and fails with that change. The rule is named in each comment.
#include <gtest/gtest.h>
#include <cmath>
#include <vector>
#include "complement/complement.hpp"
#include "complement/messages.hpp"
#include "complement_fixture.hpp"
#include "core/config.hpp"
#include "lcmio/lengths.hpp"
#include "lcmio/time_reset.hpp"
#include "tactical/line_generation.hpp"
using namespace lasonic;
using namespace lasonic::complement;
using geom::Pose2;
using geom::Vec2;

// `min_length` drops lines shorter than it.
TEST(Boundaries, LinesShorterThanMinLengthAreDropped) {
  LineGenerationParams p;
  p.gp_threshold = 1;
  p.min_length = 1.0;
  std::vector<CandidateCell> cells;
  for (int i = 0; i <= 4; ++i) cells.push_back({Vec2(-0.2 + 0.1 * i, 1.0), 10, 1});  // 0.5 m with the extension
  EXPECT_TRUE(generateLines(cells, {0, 0, geom::kPi / 2}, 0.1, p).empty());
  p.min_length = 0.4;
  EXPECT_EQ(generateLines(cells, {0, 0, geom::kPi / 2}, 0.1, p).size(), 1u);
}
// A gap of exactly max_gap is not "wider than" it.
TEST(Boundaries, GapOfExactlyMaxGapDoesNotSplit) {
  std::vector<PolarCell> cells;
  for (double x : {0.0, 0.5}) {
    PolarCell c;
    c.cell.centre = Vec2(x, 1.0);
    c.bearing = std::atan2(1.0, x);
    c.range = 1;
    cells.push_back(c);
  }
  std::swap(cells[0], cells[1]);  // bearing order
  // widest gap picks the wrap-around one (also 0.5): both gaps equal, one run expected
  EXPECT_EQ(splitAtGaps(cells, 0.5).size(), 1u);
}
// A Radar Map built long AFTER the firing is stale too ("either direction").
TEST(Boundaries, RadarMapFromTheFutureIsStale) {
  RadarMap rm;
  rm.utime = 3'000'000;
  rm.segments = {{{{1.0, -1.0}, {1.0, 1.0}}, 20, 0.0}};
  SonarGroup g;
  g.utime = 1'000'000;
  g.readings.push_back({3, 0.5, false, {0, 0, 0}, true});
  ComplementParams p;
  p.max_rm_age_us = 500'000;
  const auto out = extractComplement(g, Pose2{}, &rm, p);
  EXPECT_TRUE(out.radar_map_stale);
  EXPECT_EQ(out.readings[0].cls, SonarClass::Unverifiable);
}
// A beam of pi or wider in the reading is not used for the hypothesis.
TEST(Boundaries, ImplausibleBeamWidthFallsBackToTheModel) {
  RadarMap rm;
  rm.utime = 1'000'000;
  rm.segments = {{{{1.0, -1.0}, {1.0, 1.0}}, 20, 0.0}};
  SonarGroup g;
  g.utime = 1'000'000;
  SonarReading r{3, 0.5, false, {0, 0, 0}, true};
  r.beam_width = 4.0;
  g.readings.push_back(r);
  ComplementParams p;
  const auto out = extractComplement(g, Pose2{}, &rm, p);
  EXPECT_DOUBLE_EQ(out.readings[0].beam_width, p.model.beam_width);
}
// A cluster shorter than min_length (0.15 m) gives no segment.
TEST(Boundaries, ShortClusterGivesNoSegment) {
  LaserScan scan;
  for (int i = 0; i < 10; ++i) scan.readings.push_back({0, 0.01 * i, 1.0, true});  // 10 points, 9 cm
  const RadarMap rm = extractRadarMap(scan, [](int64_t) { return std::optional(geom::Pose2{}); }, {});
  EXPECT_TRUE(rm.segments.empty());
}
// The last reading's own direction is inside the view.
TEST(Boundaries, LaserViewCoversItsLastReadingsDirectionExactly) {
  LaserView v;
  v.full_circle = false;
  v.sensor = {0, 0, 0};
  v.angle_min = -geom::kPi / 2;
  v.angle_max = geom::kPi / 2;
  EXPECT_TRUE(v.covers({0.0, 1.0}));
}
// A 360 deg scanner that lost the reading at its seam (359 readings 1 deg apart) is still full circle.
TEST(Boundaries, FullCircleWithOneReadingShort) {
  laser_scan_t m = fixture::simulateScan(fixture::fig4Room(), fixture::still({2, 1.8, 0}), 0, 100'000);
  const int n = 359;
  m.angle_min = -geom::kPi;
  m.angle_increment = static_cast<float>(geom::deg2rad(1.0));
  m.ranges.assign(n, 1.0f);
  m.flags.assign(n, 0);
  m.offset_us.assign(n, 0);
  m.nranges = n;
  std::vector<InputProblem> problems;
  const auto s = laserScanFromMessage(m, problems);
  ASSERT_TRUE(s.has_value());
  EXPECT_TRUE(s->full_circle);
}
// `angle_min` beyond +-4 pi is refused.
TEST(Boundaries, AngleMinBeyondFourPiIsRefused) {
  laser_scan_t m = fixture::simulateScan(fixture::fig4Room(), fixture::still({2, 1.8, 0}), 0, 100'000);
  m.angle_min = 100.0f;
  std::vector<InputProblem> problems;
  EXPECT_FALSE(laserScanFromMessage(m, problems).has_value());
}
// TimeReset boundaries.
TEST(Boundaries, TimeResetExactlyOneSecondBackIsNoRestart) {
  TimeReset c;
  EXPECT_FALSE(c.jumpedBack("A", 5'000'000));
  EXPECT_FALSE(c.jumpedBack("A", 4'000'000));  // exactly kJumpUs back: not "more than"
}
TEST(Boundaries, TimeResetExactlyOneSecondAheadIsNotHeld) {
  TimeReset c;
  EXPECT_EQ(c.admit("A", 10'000'000).kind, TimeReset::Admission::Ok);
  EXPECT_EQ(c.admit("B", 11'000'000).kind, TimeReset::Admission::Ok);
}
TEST(Boundaries, TimeResetHeldTimeRepeatedIsAStep) {
  TimeReset c;
  c.admit("ODO", 10'000'000);
  EXPECT_EQ(c.admit("ODO", 15'000'000).kind, TimeReset::Admission::HeldAhead);
  const auto a = c.admit("ODO", 15'000'000);  // the same time again: goes on from the held time
  EXPECT_TRUE(a.stepped_from.has_value());
  EXPECT_FALSE(a.stray.has_value());
}
// `grid_map_t` width * height must equal the cell count.
TEST(Boundaries, GridMapWidthHeightMismatchThrows) {
  grid_map_t m{};
  m.g.assign(9, 0);
  m.h.assign(9, 0);
  m.gp.assign(9, 0);
  m.width = 2;
  m.height = 4;
  EXPECT_THROW(setLengths(m), std::logic_error);
}
// A sector map without remembered distances gets -1 everywhere.
TEST(Boundaries, SectorMapWithoutRememberedIsFilled) {
  sector_map_t m{};
  m.distance.assign(48, 1.f);
  m.source.assign(48, 0);
  m.laser_distance.assign(48, 1.f);
  m.sonar_distance.assign(48, -1.f);
  ASSERT_NO_THROW(setLengths(m));
  ASSERT_EQ(m.remembered_distance.size(), 48u);
  EXPECT_EQ(m.remembered_distance[7], -1.f);
}
// An int key with an open lower bound refuses the bound itself.
TEST(Boundaries, IntOpenLowerBound) {
  const Config c = Config::fromString("n: 0\n");
  EXPECT_THROW(c.get("n", 1, Range::positive()), ConfigError);
}
// RequirePoints needs min_points points.
TEST(Boundaries, RequirePointsMinimum) {
  const Config c = Config::fromString("pts: [[0, 0], [1, 0]]\n");
  EXPECT_THROW(c.requirePoints("pts", 3), ConfigError);
}
