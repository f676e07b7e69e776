// laserJoinPoints: a face-on echo of a plane that continues a Radar Map segment, within the beam's
// footprint of its end, joins its foot to that end; anything else joins nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "tactical/laser_join.hpp"

using namespace lasonic;
using geom::Pose2;
using geom::Segment;
using geom::Vec2;

namespace {
const double kBeam = geom::deg2rad(30);
// A wall at y = 4 up to x = 2.1, then a glass door to 3.0, then the wall again (the Radar Map
// holds the two wall pieces only).
const std::vector<Segment> kWalls = {{{0.0, 4.0}, {2.1, 4.0}}, {{3.0, 4.0}, {5.0, 4.0}}};
// A transducer 0.55 m below the door at x, facing it.
Pose2 facingDoor(double x) { return {x, 3.45, M_PI / 2}; }
}  // namespace

TEST(LaserJoin, AFootNearTheWallsEndJoinsIt) {
  // Foot (2.3, 4.0), 0.2 m from the end (2.1, 4.0): within 0.55 tan 15 deg + 0.1 = 0.247 m.
  const auto pts = laserJoinPoints(facingDoor(2.3), 0.55, kBeam, kWalls, {});
  ASSERT_GE(pts.size(), 4u);
  EXPECT_NEAR((pts.front() - Vec2(2.3, 4.0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((pts.back() - Vec2(2.1, 4.0)).norm(), 0.0, 1e-9);
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_NEAR(pts[i].y(), 4.0, 1e-9);
    EXPECT_TRUE(pts[i].x() >= 2.1 - 1e-9 && pts[i].x() <= 2.3 + 1e-9) << pts[i].transpose();
    if (i > 0) {
      EXPECT_LE((pts[i] - pts[i - 1]).norm(), 0.05 + 1e-9);  // every half cell
    }
  }
  // The other end of the door, from its own side: joins (3.0, 4.0).
  const auto right = laserJoinPoints(facingDoor(2.85), 0.55, kBeam, kWalls, {});
  ASSERT_FALSE(right.empty());
  EXPECT_NEAR((right.back() - Vec2(3.0, 4.0)).norm(), 0.0, 1e-9);
}

TEST(LaserJoin, TheNearerEndWinsAndNoGapWiderThanTheFootprintIsBridged) {
  // In the door's middle both ends are 0.45 m away: farther than the footprint, nothing.
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.55), 0.55, kBeam, kWalls, {}).empty());
  // A farther transducer has a wider footprint: 1.5 m away, 1.5 tan 15 deg + 0.1 = 0.50 m.
  const auto far = laserJoinPoints({2.55, 2.5, M_PI / 2}, 1.5, kBeam, kWalls, {});
  ASSERT_FALSE(far.empty());
  EXPECT_NEAR(far.back().x(), 2.1, 1e-9);  // both 0.45 m: the first segment's end
  const auto nearer_right = laserJoinPoints({2.6, 2.5, M_PI / 2}, 1.5, kBeam, kWalls, {});
  ASSERT_FALSE(nearer_right.empty());
  EXPECT_NEAR(nearer_right.back().x(), 3.0, 1e-9);
  // A doorway (1 m) beside a pane is never closed from 1.5 m either.
  const std::vector<Segment> doorway = {{{0.0, 4.0}, {2.1, 4.0}}};
  EXPECT_TRUE(laserJoinPoints({3.1, 2.5, M_PI / 2}, 1.5, kBeam, doorway, {}).empty());
}

TEST(LaserJoin, OnlyAnEchoOfThatPlaneJoins) {
  // Shorter than the perpendicular (a pole in front of the door): no.
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), 0.40, kBeam, kWalls, {}).empty());
  // Within half a cell of it (range noise): yes.
  EXPECT_FALSE(laserJoinPoints(facingDoor(2.3), 0.59, kBeam, kWalls, {}).empty());
  // The perpendicular outside the beam: a transducer facing 20 deg away from the door's normal.
  EXPECT_TRUE(laserJoinPoints({2.3, 3.45, M_PI / 2 + geom::deg2rad(20)}, 0.55, kBeam, kWalls, {}).empty());
  // Inside a wider beam it is.
  EXPECT_FALSE(laserJoinPoints({2.3, 3.45, M_PI / 2 + geom::deg2rad(20)}, 0.55, geom::deg2rad(50), kWalls, {}).empty());
  // Alongside the segment (the foot on the wall the laser sees): nothing to join.
  EXPECT_TRUE(laserJoinPoints(facingDoor(1.5), 0.55, kBeam, kWalls, {}).empty());
  // A segment shorter than min_line_length (a person's chord, 0.4 m) is not a wall.
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), 0.55, kBeam, {{{1.7, 4.0}, {2.1, 4.0}}}, {}).empty());
  EXPECT_FALSE(laserJoinPoints(facingDoor(2.3), 0.55, kBeam, {{{1.5, 4.0}, {2.1, 4.0}}}, {}).empty());
  // No Radar Map, no join.
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), 0.55, kBeam, {}, {}).empty());
}

TEST(LaserJoin, NonFiniteInputJoinsNothing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(laserJoinPoints({nan, 3.45, M_PI / 2}, 0.55, kBeam, kWalls, {}).empty());
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), nan, kBeam, kWalls, {}).empty());
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), -0.55, kBeam, kWalls, {}).empty());
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), 0.55, nan, kWalls, {}).empty());
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), 0.55, kBeam, {{{nan, 4.0}, {2.1, 4.0}}}, {}).empty());
  EXPECT_TRUE(laserJoinPoints(facingDoor(2.3), 0.55, kBeam, {{{2.1, 4.0}, {2.1, 4.0}}}, {}).empty());  // a point
}
