#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/geometry.hpp"

using namespace lasonic::geom;

TEST(Geometry, NormalizeAngle) {
  EXPECT_NEAR(normalizeAngle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-kPi), kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(2 * kPi + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(angleDiff(-3.1, 3.1), 2 * kPi - 6.2, 1e-12);
}

TEST(Geometry, PoseComposeInverse) {
  const Pose2 a{1, 2, 0.5}, b{-0.3, 0.7, 2.9};
  const Pose2 ab = a.compose(b);
  const Vec2 p(0.4, -1.2);
  const Vec2 direct = ab.transform(p), chained = a.transform(b.transform(p));
  EXPECT_NEAR((direct - chained).norm(), 0, 1e-12);
  const Pose2 id = a.compose(a.inverse());
  EXPECT_NEAR(id.x, 0, 1e-12);
  EXPECT_NEAR(id.y, 0, 1e-12);
  EXPECT_NEAR(id.theta, 0, 1e-12);
  EXPECT_NEAR((a.inverseTransform(a.transform(p)) - p).norm(), 0, 1e-12);
}

TEST(Geometry, InterpolateTakesShortestArc) {
  const Pose2 a{0, 0, 3.0}, b{2, 4, -3.0};
  const Pose2 m = interpolate(a, b, 0.5);
  EXPECT_NEAR(m.x, 1, 1e-12);
  EXPECT_NEAR(m.y, 2, 1e-12);
  EXPECT_NEAR(std::abs(m.theta), kPi, 1e-9);  // across +-pi, not through 0
}

TEST(Geometry, RaySegment) {
  const Segment s{{2, -1}, {2, 1}};
  EXPECT_NEAR(*intersect(Ray{{0, 0}, {1, 0}}, s), 2.0, 1e-12);
  EXPECT_FALSE(intersect(Ray{{0, 0}, {-1, 0}}, s));                // behind
  EXPECT_FALSE(intersect(Ray{{0, 0}, unitVector(deg2rad(60))}, s));  // passes above the end
  EXPECT_FALSE(intersect(Ray{{0, 0}, {0, 1}}, Segment{{0, 1}, {0, 2}}).has_value() == false &&
               false);  // collinear rays are treated as grazing (no hit): checked next
  EXPECT_FALSE(intersect(Ray{{0, 0}, {0, 1}}, Segment{{0, 1}, {0, 2}}));
}

TEST(Geometry, RayCircle) {
  const Circle c{{3, 0}, 0.5};
  EXPECT_NEAR(*intersect(Ray{{0, 0}, {1, 0}}, c), 2.5, 1e-12);
  EXPECT_FALSE(intersect(Ray{{0, 0}, {0, 1}}, c));
  EXPECT_NEAR(*intersect(Ray{{3, 0.1}, {1, 0}}, c), 0.0, 1e-12);  // inside
  // tangent-ish ray just above
  EXPECT_FALSE(intersect(Ray{{0, 0.51}, {1, 0}}, c));
}

TEST(Geometry, IncidenceAngle) {
  const Segment wall{{1, -1}, {1, 1}};
  EXPECT_NEAR(incidenceAngle({1, 0}, normal(wall)), 0.0, 1e-12);
  EXPECT_NEAR(rad2deg(incidenceAngle(unitVector(deg2rad(45)), normal(wall))), 45.0, 1e-9);
}

TEST(Geometry, SectorContains) {
  const Sector s{{0, 0}, 0.0, deg2rad(30), 2.2};
  EXPECT_TRUE(s.contains({1, 0}));
  EXPECT_TRUE(s.contains(Vec2(2.0, 0.0) + Vec2(0, 0.5)));   // 14 deg
  EXPECT_FALSE(s.contains({1, 0.5}));                       // 26.6 deg
  EXPECT_FALSE(s.contains({2.3, 0}));
  EXPECT_FALSE(s.contains({-1, 0}));
}

TEST(Geometry, NearestInSectorHeadOnWall) {
  const Sector s{{0, 0}, 0.0, deg2rad(30), 2.2};
  EXPECT_NEAR(*nearestInSector(s, Segment{{1.5, -3}, {1.5, 3}}), 1.5, 1e-12);
}

TEST(Geometry, NearestInSectorObliqueWallIsCloserThanAxis) {
  // A wall at 45 deg across the beam: the nearest point inside the beam is on the beam's edge.
  const Sector s{{0, 0}, 0.0, deg2rad(30), 2.2};
  const Segment wall{{1, -1}, {3, 1}};  // crosses the axis at x = 2
  const double d = *nearestInSector(s, wall);
  // Nearest point of the line to the apex is at 45 deg (outside the beam), so the answer is
  // where the lower edge (-15 deg) meets the wall: solve t*(cos,sin)(-15) on y = x - 2.
  const double a = deg2rad(-15);
  const double t = 2.0 / (std::cos(a) - std::sin(a));
  EXPECT_NEAR(d, t, 1e-9);
  EXPECT_LT(d, 2.0);
}

TEST(Geometry, NearestInSectorEdgeOnlyAndBehind) {
  const Sector s{{0, 0}, 0.0, deg2rad(30), 2.2};
  // Crosses only the edge region of the beam: from outside (above the +15 deg edge) to inside.
  const Segment edge{{1.0, 0.6}, {1.0, 0.2}};
  const auto d = nearestInSector(s, edge);
  ASSERT_TRUE(d);
  EXPECT_NEAR(*d, std::hypot(1.0, 0.2), 1e-9);
  // Fully behind the sensor: invisible, even though its mirror image would be inside.
  EXPECT_FALSE(nearestInSector(s, Segment{{-1.5, -1}, {-1.5, 1}}));
  // Beyond the radius.
  EXPECT_FALSE(nearestInSector(s, Segment{{2.5, -1}, {2.5, 1}}));
  // Outside the wedge.
  EXPECT_FALSE(nearestInSector(s, Segment{{0.5, 1}, {1.5, 2}}));
}

TEST(Geometry, NearestInSectorCircle) {
  const Sector s{{0, 0}, kPi / 2, deg2rad(30), 2.2};
  EXPECT_NEAR(*nearestInSector(s, Circle{{0, 1.5}, 0.1}), 1.4, 1e-12);
  EXPECT_FALSE(nearestInSector(s, Circle{{1.5, 1.5}, 0.1}));
  // Centre outside the wedge but the disc reaches over the edge.
  const auto d = nearestInSector(s, Circle{{0.5, 1.5}, 0.2});
  ASSERT_TRUE(d);
  EXPECT_GT(*d, 1.4);
}

TEST(Geometry, NearestPointInSectorAgreesWithDistance) {
  const Sector s{{0, 0}, 0.0, deg2rad(30), 2.2};
  // Oblique wall: the point lies on the beam's lower edge, at the distance nearestInSector gives.
  const Segment wall{{1, -1}, {3, 1}};
  const auto p = nearestPointInSector(s, wall);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->norm(), *nearestInSector(s, wall), 1e-9);
  EXPECT_NEAR(std::atan2(p->y(), p->x()), deg2rad(-15), 1e-9);
  EXPECT_NEAR(p->y(), p->x() - 2.0, 1e-9);  // on the wall
  // Circle straight ahead: the point facing the apex; centre beside the wedge: on an edge.
  const auto c = nearestPointInSector(s, Circle{{1.5, 0}, 0.1});
  ASSERT_TRUE(c);
  EXPECT_NEAR((*c - Vec2(1.4, 0)).norm(), 0.0, 1e-12);
  const Circle side{{1.5, 0.5}, 0.2};
  const auto e = nearestPointInSector(s, side);
  ASSERT_TRUE(e);
  EXPECT_NEAR(e->norm(), *nearestInSector(s, side), 1e-9);
  EXPECT_NEAR(std::atan2(e->y(), e->x()), deg2rad(15), 1e-9);
  EXPECT_NEAR((*e - side.center).norm(), side.radius, 1e-9);
  EXPECT_FALSE(nearestPointInSector(s, Segment{{2.5, -1}, {2.5, 1}}));  // beyond the radius
  EXPECT_FALSE(nearestPointInSector(s, Circle{{-1.5, 0}, 0.1}));        // behind
}

#include "core/pose_history.hpp"

TEST(PoseHistory, InterpolatesAndRefusesGoingBackwards) {
  lasonic::PoseHistory h(10'000'000, 100'000);
  EXPECT_FALSE(h.at(0));
  EXPECT_EQ(h.add(1'000'000, {0, 0, 0}), lasonic::PoseHistory::AddResult::Ok);
  EXPECT_EQ(h.add(2'000'000, {1, 2, 0.2}), lasonic::PoseHistory::AddResult::Ok);
  EXPECT_EQ(h.add(1'500'000, {9, 9, 0}), lasonic::PoseHistory::AddResult::WentBackwards);
  const auto p = h.at(1'250'000);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 0.25, 1e-12);
  EXPECT_NEAR(p->y, 0.5, 1e-12);
  EXPECT_NEAR(p->theta, 0.05, 1e-12);
  EXPECT_NEAR(h.at(2'050'000)->x, 1.0, 1e-12);  // held within the extrapolation limit
  EXPECT_FALSE(h.at(2'200'000));
  EXPECT_FALSE(h.at(800'000));
}

// Odometry every 100 ms (a Pioneer's 10 Hz), the robot driving 0.4 m/s while turning 0.8 rad/s:
// a reading 60 ms after the newest odometry is placed where the robot went on to. After a pause
// longer than the limit there is no velocity to go on with: the newest pose is held.
TEST(PoseHistory, BeyondTheNewestGoesOnAtTheLastVelocity) {
  lasonic::PoseHistory h(10'000'000, 200'000);
  ASSERT_EQ(h.add(1'000'000, {1.0, 2.0, 3.10}), lasonic::PoseHistory::AddResult::Ok);
  EXPECT_NEAR(h.at(1'050'000)->x, 1.0, 1e-12);  // one pose: held
  ASSERT_EQ(h.add(1'100'000, {1.04, 2.0, 3.18}), lasonic::PoseHistory::AddResult::Ok);
  const auto p = h.at(1'160'000);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 1.064, 1e-12);
  EXPECT_NEAR(p->y, 2.0, 1e-12);
  EXPECT_NEAR(p->theta, 3.228 - 2 * lasonic::geom::kPi, 1e-12);  // across +-pi
  EXPECT_FALSE(h.at(1'300'001));
  ASSERT_EQ(h.add(1'400'000, {2.0, 2.0, 0.0}), lasonic::PoseHistory::AddResult::Ok);  // 300 ms gap
  EXPECT_NEAR(h.at(1'450'000)->x, 2.0, 1e-12);
  EXPECT_NEAR(h.at(1'450'000)->theta, 0.0, 1e-12);
}

// at() keeps a search hint; queries in any order (in order, backwards, random, around pop_front)
// give exactly what a history without any hint (a fresh copy per query) gives.
TEST(PoseHistory, QueriesInAnyOrderGiveTheSamePoses) {
  using lasonic::PoseHistory;
  PoseHistory h(200'000);
  std::vector<std::pair<int64_t, lasonic::geom::Pose2>> added;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int64_t> t(-50'000, 400'000);
  int interpolated = 0;
  for (int64_t s = 0; s <= 300'000; s += 20'000) {
    added.push_back({s, {u(rng), u(rng), 3.0 * u(rng)}});
    h.add(added.back().first, added.back().second);
    std::vector<int64_t> queries;
    for (int k = 0; k < 30; ++k) queries.push_back(t(rng));
    for (int64_t q = s - 40'000; q <= s + 10'000; q += 1'111) queries.push_back(q);  // scan-like runs
    for (const int64_t q : queries) {
      PoseHistory fresh(200'000);
      for (const auto& [ta, pa] : added) fresh.add(ta, pa);
      const auto a = h.at(q), b = fresh.at(q);
      ASSERT_EQ(a.has_value(), b.has_value()) << q;
      if (!a) continue;
      ASSERT_EQ(a->x, b->x) << q;
      ASSERT_EQ(a->y, b->y) << q;
      ASSERT_EQ(a->theta, b->theta) << q;
      interpolated += q % 20'000 != 0 && q > 0 && q < s;
    }
  }
  EXPECT_GT(interpolated, 200);
}

// A Cursor gives exactly at()'s poses, for queries in any order, at the entries' own times (the
// newest entry's pose itself, not an interpolation at s = 1) and outside the history.
TEST(PoseHistory, CursorGivesAtsPoses) {
  using lasonic::PoseHistory;
  PoseHistory h(200'000, 30'000);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int64_t> t(-50'000, 400'000);
  int interpolated = 0;
  for (int64_t s = 0; s <= 300'000; s += 20'000) {
    h.add(s, {u(rng), u(rng), 3.0 * u(rng)});
    std::vector<int64_t> queries;
    for (int k = 0; k < 30; ++k) queries.push_back(t(rng));
    for (int64_t q = s - 60'000; q <= s + 40'000; q += 1'111) queries.push_back(q);  // scan-like runs
    for (int64_t q = s - 60'000; q <= s + 1; q += 20'000) queries.insert(queries.end(), {q - 1, q, q + 1});
    PoseHistory::Cursor cursor(h), rotating(h);
    for (const int64_t q : queries) {
      const auto a = cursor.at(q), b = h.at(q);
      double c = 2, sn = 2;
      const auto r = rotating.atRotated(q, c, sn);
      ASSERT_EQ(a.has_value(), b.has_value()) << q;
      ASSERT_EQ(r.has_value(), b.has_value()) << q;
      if (!a) continue;
      ASSERT_EQ(a->x, b->x) << q;
      ASSERT_EQ(a->y, b->y) << q;
      ASSERT_EQ(a->theta, b->theta) << q;
      ASSERT_EQ(r->x, b->x) << q;
      ASSERT_EQ(r->theta, b->theta) << q;
      // The rotation: within a few 1e-16 of cos and sin of the heading (angle addition).
      ASSERT_NEAR(c, std::cos(b->theta), 1e-15) << q;
      ASSERT_NEAR(sn, std::sin(b->theta), 1e-15) << q;
      interpolated += q % 20'000 != 0 && q > 0 && q < s;
    }
  }
  EXPECT_GT(interpolated, 300);
}

// atRotated while turning slowly (the angle-addition path, |turn| <= 0.1 rad per interval),
// across the +-pi seam: cos and sin within a few 1e-16 of the heading's.
TEST(PoseHistory, CursorRotationWhileTurning) {
  using lasonic::PoseHistory;
  PoseHistory h;
  for (int64_t t = 0; t <= 2'000'000; t += 20'000)
    h.add(t, {0.01 * static_cast<double>(t) * 1e-6, 0, lasonic::geom::normalizeAngle(2.9 + 4.9 * static_cast<double>(t) * 1e-6)});
  PoseHistory::Cursor cursor(h);
  double worst = 0;
  for (int64_t q = 1; q < 2'000'000; q += 139) {
    double c = 2, s = 2;
    const auto p = cursor.atRotated(q, c, s);
    ASSERT_TRUE(p);
    ASSERT_EQ(p->theta, h.at(q)->theta);
    worst = std::max({worst, std::abs(c - std::cos(p->theta)), std::abs(s - std::sin(p->theta))});
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_GT(worst, 0.0);  // (not the library's own cos and sin: angle addition)
}

// The shared total-least-squares axis: points along a known line give its angle, a zero spread
// across it, and the spread along it.
TEST(PrincipalAxes, PointsOnALineGiveItsAngleAndNoSpreadAcrossIt) {
  const double a = deg2rad(30.0);
  const Vec2 d = unitVector(a);
  double sxx = 0, syy = 0, sxy = 0;
  for (int k = -2; k <= 2; ++k) {
    const Vec2 p = 0.1 * k * d;  // centroid 0
    sxx += p.x() * p.x(), syy += p.y() * p.y(), sxy += p.x() * p.y();
  }
  const PrincipalAxes ax = principalAxes(sxx, syy, sxy);
  EXPECT_NEAR(ax.angle, a, 1e-12);
  EXPECT_NEAR(ax.minor, 0.0, 1e-15);
  EXPECT_NEAR(ax.major, 0.1, 1e-12);  // 0.01 * (4 + 1 + 0 + 1 + 4)
}

TEST(PrincipalAxes, AnAxisAlignedScatterHasItsVariancesAsEigenvalues) {
  const PrincipalAxes x = principalAxes(4.0, 1.0, 0.0);
  EXPECT_DOUBLE_EQ(x.angle, 0.0);
  EXPECT_DOUBLE_EQ(x.major, 4.0);
  EXPECT_DOUBLE_EQ(x.minor, 1.0);
  const PrincipalAxes y = principalAxes(1.0, 4.0, 0.0);
  EXPECT_NEAR(std::abs(y.angle), kPi / 2, 1e-15);
  EXPECT_DOUBLE_EQ(y.major, 4.0);
  EXPECT_DOUBLE_EQ(y.minor, 1.0);
  // The same scatter turned by 30 deg: the same eigenvalues, the axis turned with it.
  const double c = std::cos(deg2rad(30.0)), sn = std::sin(deg2rad(30.0));
  const PrincipalAxes t = principalAxes(4 * c * c + sn * sn, 4 * sn * sn + c * c, 3 * c * sn);
  EXPECT_NEAR(t.angle, deg2rad(30.0), 1e-12);
  EXPECT_NEAR(t.major, 4.0, 1e-12);
  EXPECT_NEAR(t.minor, 1.0, 1e-12);
  // A round scatter: both equal, never a negative minor from rounding.
  const PrincipalAxes r = principalAxes(1e-3, 1e-3, 0.0);
  EXPECT_GE(r.minor, 0.0);
  EXPECT_DOUBLE_EQ(r.major, r.minor);
}
