// HypotheticalScan: the ideal sonar (circular sector) on the Radar Map.
#include <gtest/gtest.h>

#include <cmath>

#include "complement/hypothetical_scan.hpp"

using namespace lasonic;
using namespace lasonic::complement;
using geom::Pose2;

namespace {
std::vector<RmSegment> rm(std::vector<geom::Segment> segs) {
  std::vector<RmSegment> out;
  for (const auto& s : segs) out.push_back({s, 10, 0.0});
  return out;
}
const IdealSonarModel kModel;  // 30 deg, 2.20 m
}  // namespace

TEST(HypotheticalScan, WallStraightAhead) {
  EXPECT_NEAR(hypotheticalRange({0, 0, 0}, rm({{{1, -1}, {1, 1}}}), kModel), 1.0, 1e-12);
}

TEST(HypotheticalScan, NoSegmentGivesTheLimit) {
  EXPECT_DOUBLE_EQ(hypotheticalRange({0, 0, 0}, {}, kModel), 2.20);
  // Beyond the limit.
  EXPECT_DOUBLE_EQ(hypotheticalRange({0, 0, 0}, rm({{{2.5, -1}, {2.5, 1}}}), kModel), 2.20);
}

TEST(HypotheticalScan, SegmentBehindTheSensorIsIgnored) {
  EXPECT_DOUBLE_EQ(hypotheticalRange({0, 0, 0}, rm({{{-0.5, -1}, {-0.5, 1}}}), kModel), 2.20);
}

TEST(HypotheticalScan, SegmentCrossingOnlyTheBeamEdge) {
  // The segment misses the acoustic axis and enters the sector across its left edge (15 deg):
  // the nearest point inside is where it crosses that edge. A single-ray model would say 2.20.
  const geom::Segment s{{1.0, 0.5}, {2.0, 0.3}};  // y = 0.7 - 0.2 x
  const double x = 0.7 / (0.2 + std::tan(geom::deg2rad(15)));
  const double expected = x / std::cos(geom::deg2rad(15));
  EXPECT_NEAR(hypotheticalRange({0, 0, 0}, rm({s}), kModel), expected, 1e-9);
  // Just outside the edge: not seen.
  const geom::Segment outside{{1.0, 0.5}, {2.0, 0.56}};
  EXPECT_DOUBLE_EQ(hypotheticalRange({0, 0, 0}, rm({outside}), kModel), 2.20);
}

TEST(HypotheticalScan, NearestPointNotOnTheAxis) {
  // An oblique wall: its nearest point inside the beam lies off the axis (perpendicular foot).
  const geom::Segment s{{2.0, -1.0}, {0.0, 1.0}};  // x + y = 1: foot at (0.5, 0.5), 45 deg: outside
  // The nearest point inside the +-15 deg sector lies on the edge at +15 deg.
  const double expected = 1.0 / (std::cos(geom::deg2rad(15)) + std::sin(geom::deg2rad(15)));
  EXPECT_NEAR(hypotheticalRange({0, 0, 0}, rm({s}), kModel), expected, 1e-9);
  // Turned towards the foot, the foot itself is the answer.
  EXPECT_NEAR(hypotheticalRange({0, 0, geom::kPi / 4}, rm({s}), kModel), std::sqrt(0.5), 1e-9);
}

TEST(HypotheticalScan, SensorLookingThroughAGapOfTheRadarMap) {
  // Wall y = 1 with a doorway x in [-0.6, 0.6]; looking straight through it: the limit.
  const auto walls = rm({{{-3, 1}, {-0.6, 1}}, {{0.6, 1}, {3, 1}}});
  EXPECT_DOUBLE_EQ(hypotheticalRange({0, 0, geom::kPi / 2}, walls, kModel), 2.20);
  // Standing in the doorway, looking along the wall: the wall's end.
  EXPECT_NEAR(hypotheticalRange({0, 1, 0}, walls, kModel), 0.6, 1e-12);
}

TEST(HypotheticalScan, NearestOfSeveralSegmentsAndOneRangePerSensor) {
  const auto segs = rm({{{1.5, -1}, {1.5, 1}}, {{0.8, -0.1}, {0.8, 0.1}}, {{-1, -1}, {-1, 1}}});
  const auto h = hypotheticalScan({{0, 0, 0}, {0, 0, geom::kPi}, {0, 0, geom::kPi / 2}}, segs, kModel);
  ASSERT_EQ(h.size(), 3u);
  EXPECT_NEAR(h[0], 0.8, 1e-12);
  EXPECT_NEAR(h[1], 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(h[2], 2.20);
}

TEST(HypotheticalScan, WiderBeamSeesMore) {
  const auto s = rm({{{1.0, 0.4}, {1.0, 0.6}}});  // at ~22-31 deg off the axis
  EXPECT_DOUBLE_EQ(hypotheticalRange({0, 0, 0}, s, kModel), 2.20);
  IdealSonarModel wide;
  wide.beam_width = geom::deg2rad(50);
  EXPECT_NEAR(hypotheticalRange({0, 0, 0}, s, wide), std::hypot(1.0, 0.4), 1e-9);
}
