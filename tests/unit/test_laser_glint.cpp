// Laser glints: a short, flat, lone Radar Map segment seen near its normal is a candidate; it is
// a glint when it moved along its own line with the robot's foot since an earlier candidate.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "tactical/laser_glint.hpp"

using namespace lasonic;
using complement::RmSegment;
using geom::Vec2;

namespace {
// A pane along y = 2.5; the robot drives along y = 0. From (x, 0) the glass glints back over
// +-2 deg around (x, 2.5): a segment of 2 * 2.5 * tan 2 deg = 0.17 m, 8 returns, 1 cm RMS.
RmSegment glintFrom(double x, double y_pane = 2.5) {
  const double h = y_pane * std::tan(geom::deg2rad(2.0));
  return {{{x - h, y_pane}, {x + h, y_pane}}, 8, 0.01};
}
}  // namespace

TEST(LaserGlint, AShortFlatLoneSegmentFacingTheRobotIsACandidate) {
  const LaserGlintParams p;
  EXPECT_EQ(glintCandidates({glintFrom(1.0)}, {1.0, 0.0}, p).size(), 1u);
  // The same piece of glass seen from 1.5 m further along: its ends at 31-33 deg from its normal.
  EXPECT_TRUE(glintCandidates({glintFrom(1.0)}, {2.5, 0.0}, p).empty());
  // Curved (a person's chord): RMS 5 cm.
  RmSegment curved = glintFrom(1.0);
  curved.rms = 0.05;
  EXPECT_TRUE(glintCandidates({curved}, {1.0, 0.0}, p).empty());
  // Too few returns.
  RmSegment few = glintFrom(1.0);
  few.npoints = 3;
  EXPECT_TRUE(glintCandidates({few}, {1.0, 0.0}, p).empty());
  // Farther than max_range (5 m).
  EXPECT_TRUE(glintCandidates({glintFrom(1.0, 5.5)}, {1.0, 0.0}, p).empty());
  // Not alone: a wall piece goes on from its end (a surface that stays in view beside it).
  const RmSegment g = glintFrom(1.0);
  const RmSegment wall{{g.seg.b + Vec2(0.05, 0.0), {3.0, 2.5}}, 60, 0.01};
  const auto with_wall = glintCandidates({g, wall}, {1.0, 0.0}, p);
  EXPECT_TRUE(with_wall.empty());
  // A far wall 0.5 m behind does not touch it.
  const RmSegment far{{{-2.0, 3.0}, {4.0, 3.0}}, 300, 0.01};
  EXPECT_EQ(glintCandidates({g, far}, {1.0, 0.0}, p).size(), 1u);
  // Off, and non-finite input.
  LaserGlintParams off;
  off.max_incidence = 0;
  EXPECT_TRUE(glintCandidates({g}, {1.0, 0.0}, off).empty());
  EXPECT_TRUE(glintCandidates({g}, {std::nan(""), 0.0}, p).empty());
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(glintCandidates({{{{0.0, inf}, {0.1, 2.5}}, 8, 0.01}}, {0.0, 0.0}, p).empty());
}

TEST(LaserGlint, HitsAreOnePerReturnAlongTheSegment) {
  const RmSegment g = glintFrom(1.0);
  const std::vector<Vec2> hits = glintHits({g});
  ASSERT_EQ(hits.size(), 8u);
  EXPECT_NEAR((hits.front() - g.seg.a).norm(), 0.0, 1e-12);
  EXPECT_NEAR((hits.back() - g.seg.b).norm(), 0.0, 1e-12);
  for (const Vec2& h : hits) EXPECT_NEAR(h.y(), 2.5, 1e-12);
  // A malformed count is not more evidence.
  RmSegment huge = g;
  huge.npoints = 1'000'000;
  EXPECT_EQ(glintHits({huge}).size(), 64u);
  RmSegment none = g;
  none.npoints = 0;
  EXPECT_TRUE(glintHits({none}).empty());
}

TEST(GlintTracker, AGlintThatMovesWithTheRobotAlongItsLineIsConfirmed) {
  GlintTracker t;
  // 5 Hz scans, 0.45 m/s: 9 cm between scans.
  EXPECT_TRUE(t.update(1'000'000, {1.00, 0.0}, {glintFrom(1.00)}).empty());  // nothing earlier
  const auto second = t.update(1'200'000, {1.09, 0.0}, {glintFrom(1.09)});
  ASSERT_EQ(second.size(), 1u);
  EXPECT_NEAR(second[0].seg.a.x(), glintFrom(1.09).seg.a.x(), 1e-12);
  EXPECT_EQ(t.update(1'400'000, {1.18, 0.0}, {glintFrom(1.18)}).size(), 1u);
}

TEST(GlintTracker, AThingThatStaysOrMovesOnItsOwnIsNot) {
  // A pillar's (or a standing person's) facing piece: the robot drives on, the piece stays.
  {
    GlintTracker t;
    t.update(1'000'000, {1.00, 0.0}, {glintFrom(1.00)});
    EXPECT_TRUE(t.update(1'200'000, {1.09, 0.0}, {glintFrom(1.00)}).empty());
  }
  // A person walking towards the robot: the piece keeps facing it but leaves the line.
  {
    GlintTracker t;
    t.update(1'000'000, {1.00, 0.0}, {glintFrom(1.00, 2.5)});
    EXPECT_TRUE(t.update(1'200'000, {1.09, 0.0}, {glintFrom(1.09, 2.3)}).empty());
  }
  // A person crossing: moves along the line faster than the robot's foot.
  {
    GlintTracker t;
    t.update(1'000'000, {1.00, 0.0}, {glintFrom(1.00)});
    EXPECT_TRUE(t.update(1'200'000, {1.09, 0.0}, {glintFrom(1.25)}).empty());
  }
  // The robot stands: nothing tells a pane from a pillar, nothing is confirmed.
  {
    GlintTracker t;
    for (int k = 0; k < 5; ++k) EXPECT_TRUE(t.update(1'000'000 + k * 200'000, {1.0, 0.0}, {glintFrom(1.0)}).empty());
  }
  // Too long ago (confirm_s 1 s), or time going back: nothing earlier to confirm with.
  {
    GlintTracker t;
    t.update(1'000'000, {1.00, 0.0}, {glintFrom(1.00)});
    EXPECT_TRUE(t.update(2'300'000, {1.09, 0.0}, {glintFrom(1.09)}).empty());
    GlintTracker u;
    u.update(2'000'000, {1.00, 0.0}, {glintFrom(1.00)});
    EXPECT_TRUE(u.update(1'900'000, {1.09, 0.0}, {glintFrom(1.09)}).empty());
  }
}
