// echoBearing / SonarBearingTracker: the neighbour-aware one-cell sensor model against ideal
// sonar readings (geom::nearestInSector: the first echo is the nearest point in the beam).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "operational/sonar_bearing.hpp"

using namespace lasonic;
using geom::deg2rad;
using geom::Vec2;

namespace {

const SonarBearingParams kP{};  // 30 deg beam, 0.10 m similar, no age limit (the tracker's cycle)
constexpr double kRingRadius = 0.35;
constexpr double kHalfCell = 0.05;

// A sensor of a ring centred at the origin, facing outwards at `deg`.
geom::Pose2 ringSensor(double deg) {
  const double a = deg2rad(deg);
  return {kRingRadius * std::cos(a), kRingRadius * std::sin(a), a};
}

template <typename Shape>
std::optional<SonarEcho> idealEcho(double deg, const Shape& s, int64_t utime = 0) {
  const geom::Pose2 p = ringSensor(deg);
  const auto r = geom::nearestInSector(geom::Sector{p.position(), p.theta, kP.beam_width, 3.0}, s);
  if (!r) return std::nullopt;
  return SonarEcho{utime, *r, p};
}

// Echoes of a 24-sensor ring (15 deg apart) of one shape; each sensor's point against all others.
template <typename Shape>
std::vector<std::pair<double, Vec2>> ringPoints(const Shape& s, bool axis = false) {
  std::vector<std::pair<double, SonarEcho>> echoes;
  for (int k = 0; k < 24; ++k)
    if (const auto e = idealEcho(k * 15.0, s)) echoes.emplace_back(k * 15.0, *e);
  std::vector<std::pair<double, Vec2>> out;
  for (size_t i = 0; i < echoes.size(); ++i) {
    std::vector<SonarEcho> others;
    for (size_t j = 0; j < echoes.size(); ++j)
      if (j != i) others.push_back(echoes[j].second);
    const SonarEcho& e = echoes[i].second;
    out.emplace_back(echoes[i].first, axis ? e.sensor.position() + e.range * geom::unitVector(e.sensor.theta)
                                           : echoPoint(e, others, kP));
  }
  return out;
}

}  // namespace

TEST(EchoBearing, NoNeighbourIsExactlyTheAxis) {
  const SonarEcho e{1'000'000, 1.5, ringSensor(33.0)};
  EXPECT_EQ(echoBearing(e, {}, kP), e.sensor.theta);
  // Too old (with an age limit of 0.25 s), not overlapping (30 deg away), or from the future:
  // ignored.
  SonarBearingParams aged = kP;
  aged.max_age_s = 0.25;
  const std::vector<SonarEcho> ignored = {{1'000'000 - 260'000, 1.5, ringSensor(48.0)},
                                          {1'000'000, 1.5, ringSensor(63.0)},
                                          {1'000'000, 1.5, ringSensor(3.0)},
                                          {1'000'001, 1.5, ringSensor(18.0)}};
  EXPECT_EQ(echoBearing(e, ignored, aged), e.sensor.theta);
  EXPECT_NE(echoBearing(e, {ignored[0]}, kP), e.sensor.theta);  // no limit: the old one counts
  // Longer neighbours say nothing either.
  EXPECT_EQ(echoBearing(e, {{1'000'000, 1.7, ringSensor(18.0)}, {1'000'000, 1.9, ringSensor(48.0)}}, kP),
            e.sensor.theta);
}

TEST(EchoBearing, DecisionTable) {
  const SonarEcho e{0, 1.5, ringSensor(0.0)};
  const SonarEcho left_similar{0, 1.45, ringSensor(15.0)}, left_shorter{0, 1.2, ringSensor(15.0)};
  const SonarEcho right_similar{0, 1.55, ringSensor(-15.0)}, right_shorter{0, 1.3, ringSensor(-15.0)};
  const SonarEcho right_longer{0, 2.0, ringSensor(-15.0)};
  EXPECT_NEAR(echoBearing(e, {left_similar}, kP), deg2rad(7.5), 1e-12);     // bisector
  EXPECT_NEAR(echoBearing(e, {right_similar}, kP), deg2rad(-7.5), 1e-12);
  EXPECT_NEAR(echoBearing(e, {left_shorter}, kP), deg2rad(15.0), 1e-12);    // beam edge
  EXPECT_NEAR(echoBearing(e, {right_shorter}, kP), deg2rad(-15.0), 1e-12);
  EXPECT_NEAR(echoBearing(e, {left_shorter, right_longer}, kP), deg2rad(15.0), 1e-12);
  EXPECT_NEAR(echoBearing(e, {left_similar, right_longer}, kP), deg2rad(7.5), 1e-12);
  // Something on both sides: the axis.
  EXPECT_EQ(echoBearing(e, {left_similar, right_similar}, kP), 0.0);
  EXPECT_EQ(echoBearing(e, {left_shorter, right_shorter}, kP), 0.0);
  EXPECT_EQ(echoBearing(e, {left_shorter, right_similar}, kP), 0.0);
  // Across the +-pi seam.
  const SonarEcho back{0, 1.5, {0, 0, deg2rad(175.0)}};
  EXPECT_NEAR(geom::angleDiff(echoBearing(back, {{0, 1.2, {0, 0, deg2rad(-170.0)}}}, kP), deg2rad(-170.0)), 0.0,
              1e-12);
}

TEST(EchoBearing, EstimateHalfwidths) {
  const SonarEcho e{0, 1.5, ringSensor(0.0)};
  const SonarEcho left_similar{0, 1.45, ringSensor(15.0)}, left_shorter{0, 1.2, ringSensor(15.0)};
  const SonarEcho right_similar{0, 1.55, ringSensor(-15.0)};
  EXPECT_NEAR(echoBearingEstimate(e, {}, kP).halfwidth, deg2rad(15.0), 1e-12);  // the paper's b/2
  const BearingEstimate bis = echoBearingEstimate(e, {left_similar}, kP);
  EXPECT_NEAR(bis.bearing, deg2rad(7.5), 1e-12);
  EXPECT_NEAR(bis.halfwidth, deg2rad(7.5), 1e-12);  // the 15 deg overlap of the two beams
  EXPECT_EQ(echoBearingEstimate(e, {left_shorter}, kP).halfwidth, 0.0);  // the beam edge
  EXPECT_NEAR(echoBearingEstimate(e, {left_similar, right_similar}, kP).halfwidth, deg2rad(15.0), 1e-12);
  // A pipe anywhere between two axes lies within the estimate's halfwidth, seen from each sensor.
  for (double b = 0.0; b <= 15.0; b += 0.5) {
    const geom::Circle pipe{1.2 * geom::unitVector(deg2rad(b)), 0.01};
    std::vector<SonarEcho> echoes;
    for (int k = 0; k < 24; ++k)
      if (const auto x = idealEcho(k * 15.0, pipe)) echoes.push_back(*x);
    for (size_t i = 0; i < echoes.size(); ++i) {
      std::vector<SonarEcho> others;
      for (size_t j = 0; j < echoes.size(); ++j)
        if (j != i) others.push_back(echoes[j]);
      const BearingEstimate est = echoBearingEstimate(echoes[i], others, kP);
      const Vec2 to_pipe = pipe.center - echoes[i].sensor.position();
      const double err = std::abs(geom::angleDiff(std::atan2(to_pipe.y(), to_pipe.x()), est.bearing)) -
                         std::asin(pipe.radius / to_pipe.norm());
      EXPECT_LE(err, est.halfwidth + 1e-9) << "pipe at " << b << " deg, sensor " << i;
    }
  }
}

TEST(EchoBearing, ObliqueWallCellsLieOnTheWall) {
  // A wall 1 m to the left of the ring centre (y = 1), seen obliquely by the sensors at 30, 45
  // and 60 deg: their first echoes are at their beam edges towards the wall's foot (90 deg).
  const geom::Segment wall{{-3.0, 1.0}, {3.0, 1.0}};
  const auto pts = ringPoints(wall);
  const auto axis = ringPoints(wall, true);
  int checked = 0;
  double worst_axis = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double deg = pts[i].first;
    if (deg < 30.0 || deg > 60.0) continue;
    ++checked;
    EXPECT_NEAR(pts[i].second.y(), 1.0, kHalfCell) << "sensor at " << deg << " deg";
    worst_axis = std::max(worst_axis, 1.0 - axis[i].second.y());
  }
  EXPECT_EQ(checked, 3);
  EXPECT_GT(worst_axis, 0.2);  // the axis model's ghost line in front of the wall
  // The mirrored side (120 .. 150 deg) too.
  for (const auto& [deg, p] : pts) {
    if (deg >= 120.0 && deg <= 150.0) {
      EXPECT_NEAR(p.y(), 1.0, kHalfCell) << "sensor at " << deg << " deg";
    }
  }
}

TEST(EchoBearing, PipeBetweenTwoAxesWithinHalfTheSpacing) {
  // A 2 cm pipe 1.2 m from the ring centre at bearings between the axes at 0 and 15 deg: every
  // sensor that hears it places it within 7.5 deg (as seen from that sensor) of the pipe.
  double worst = 0, worst_axis = 0;
  for (double b = 0.0; b <= 15.0; b += 1.0) {
    const geom::Circle pipe{1.2 * geom::unitVector(deg2rad(b)), 0.01};
    const auto pts = ringPoints(pipe);
    const auto axis = ringPoints(pipe, true);
    ASSERT_FALSE(pts.empty());
    for (size_t i = 0; i < pts.size(); ++i) {
      const geom::Pose2 s = ringSensor(pts[i].first);
      // Angle between the point's bearing and the nearest bearing that meets the pipe.
      const Vec2 to_pipe = pipe.center - s.position();
      const double truth = std::atan2(to_pipe.y(), to_pipe.x());
      const double half_width = std::asin(pipe.radius / to_pipe.norm());
      const auto err = [&](const Vec2& p) {
        return std::max(0.0, std::abs(geom::angleDiff(std::atan2(p.y() - s.y, p.x() - s.x), truth)) - half_width);
      };
      worst = std::max(worst, err(pts[i].second));
      worst_axis = std::max(worst_axis, err(axis[i].second));
    }
  }
  EXPECT_LE(worst, deg2rad(7.5) + 1e-9);
  EXPECT_GT(worst_axis, deg2rad(12.0));  // the axis: up to half the beam
}

TEST(SonarBearingTracker, LatestEchoPerSensor) {
  SonarBearingTracker t(kP);
  const SonarEcho e{100'000, 1.5, ringSensor(0.0)};
  EXPECT_EQ(t.bearing(0, e), 0.0);
  t.record(1, 70'000, SonarEcho{70'000, 1.2, ringSensor(15.0)});
  EXPECT_NEAR(t.bearing(0, e), deg2rad(15.0), 1e-12);
  const Vec2 p = t.place(0, e);
  EXPECT_NEAR(p.x(), kRingRadius + 1.5 * std::cos(deg2rad(15.0)), 1e-12);
  EXPECT_NEAR(p.y(), 1.5 * std::sin(deg2rad(15.0)), 1e-12);
  // Its own earlier echo is never a neighbour.
  t.record(0, 0, SonarEcho{0, 1.2, ringSensor(0.0)});
  EXPECT_NEAR(t.bearing(0, e), deg2rad(15.0), 1e-12);
  // Sensor 1's latest reading has no echo: it no longer counts.
  t.record(1, 90'000, std::nullopt);
  EXPECT_EQ(t.bearing(0, e), 0.0);
}

TEST(SonarBearingTracker, EverNewSensorIdsDoNotGrowWithoutBound) {
  SonarBearingTracker t(kP);
  // Malformed messages with a new id each, then a real neighbour: it still counts.
  for (int id = 100; id < 5100; ++id) t.record(id, 0, SonarEcho{0, 2.9, ringSensor(180.0)});
  EXPECT_LE(t.sensors(), SonarBearingTracker::kMaxSensors);
  t.record(1, 70'000, SonarEcho{70'000, 1.2, ringSensor(15.0)});
  EXPECT_NEAR(t.bearing(0, SonarEcho{100'000, 1.5, ringSensor(0.0)}), deg2rad(15.0), 1e-12);
}

// The neighbours of an echo are the readings of this ring cycle, taken from the firings: any
// ring's timing works without a key, a neighbour that has not fired since is not one.
TEST(SonarBearingTracker, ThisRingCycleComesFromTheFirings) {
  SonarBearingTracker t(kP);
  // A slow ring: sensor 0 fires every 0.6 s; its neighbour 1 fired 0.5 s before its echo.
  t.record(0, 0, std::nullopt);
  t.record(1, 100'000, SonarEcho{100'000, 1.2, ringSensor(15.0)});
  const SonarEcho e{600'000, 1.5, ringSensor(0.0)};
  EXPECT_NEAR(t.bearing(0, e), deg2rad(15.0), 1e-12);
  // A neighbour that last fired before the sensor's previous firing is of the cycle before
  // (it fell silent): not one.
  t.record(0, 600'000, SonarEcho{600'000, 1.5, ringSensor(0.0)});
  EXPECT_EQ(t.bearing(0, SonarEcho{1'200'000, 1.5, ringSensor(0.0)}), 0.0);
  // After a gap (the sonar stopped for 5 s: a cycle far beyond 1.5 times the one before), only
  // what fired within 1.5 cycles (0.9 s) counts.
  t.record(1, 1'300'000, SonarEcho{1'300'000, 1.2, ringSensor(15.0)});
  EXPECT_EQ(t.bearing(0, SonarEcho{6'200'000, 1.5, ringSensor(0.0)}), 0.0);
  t.record(1, 6'000'000, SonarEcho{6'000'000, 1.2, ringSensor(15.0)});
  EXPECT_NEAR(t.bearing(0, SonarEcho{6'200'000, 1.5, ringSensor(0.0)}), deg2rad(15.0), 1e-12);
  // A fixed age limit instead (params().max_age_s > 0) drops the slow ring's neighbour.
  SonarBearingParams fixed = kP;
  fixed.max_age_s = 0.25;
  SonarBearingTracker f(fixed);
  f.record(0, 0, std::nullopt);
  f.record(1, 100'000, SonarEcho{100'000, 1.2, ringSensor(15.0)});
  EXPECT_EQ(f.bearing(0, e), 0.0);
}

// The firing groups of one ring cycle, counted from the groups' firings: a lost message or a
// malformed group id does not change the count; nothing is known before a group fires again.
TEST(RingGroups, CountsTheGroupsOfOneRingCycle) {
  RingGroups mobot;
  for (int k = 0; k < 6; ++k) mobot.fired(k);
  EXPECT_EQ(mobot.perCycle(), 0);
  for (int k = 6; k < 60; ++k) mobot.fired(k % 6);
  EXPECT_EQ(mobot.perCycle(), 6);
  RingGroups pioneer;
  for (int k = 0; k < 80; ++k)
    if (k != 43) pioneer.fired(k % 8);  // group 3's message of the sixth cycle lost
  EXPECT_EQ(pioneer.perCycle(), 8);
  for (const int bad : {-1, RingGroups::kMaxGroups, 30000}) pioneer.fired(bad);
  EXPECT_EQ(pioneer.perCycle(), 8);
  RingGroups changed;  // a driver restarted with another grouping: the newest counts win
  for (int k = 0; k < 40; ++k) changed.fired(k % 6);
  for (int k = 0; k < 40; ++k) changed.fired(k % 4);
  EXPECT_EQ(changed.perCycle(), 4);
  EXPECT_EQ(changed.hMax(3, 18), 12);  // three ring cycles of 4 groups
  EXPECT_EQ(changed.hMax(0, 18), 18);  // the paper's unit: the fallback
  EXPECT_EQ(RingGroups{}.hMax(3, 18), 18);  // not counted yet
}

TEST(RingGroups, TimesTheRingCycleAtItsQuickest) {
  // MOBOT-IV's driver: 6 groups, each 30 ms after the one before plus 0-8 ms at random. The mean
  // cycle is ~0.204 s; the ring's own period, 0.18 s, is what a person walking past can meet.
  RingGroups ring;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int64_t> jitter(0, 8000);
  int64_t t = 1'000'000;
  EXPECT_EQ(ring.shortestCycleS(), 0.0);
  for (int k = 0; k < 400; ++k) {
    ring.fired(k % 6, t);
    if (k == 3) { EXPECT_EQ(ring.shortestCycleS(), 0.0); }   // not counted yet
    if (k == 60) { EXPECT_EQ(ring.shortestCycleS(), 0.0); }  // counted, but not yet timed
    if (k == 64) { EXPECT_GT(ring.shortestCycleS(), 0.0); }  // 64 intervals
    t += 30'000 + jitter(rng);
  }
  EXPECT_GE(ring.shortestCycleS(), 0.18);
  EXPECT_LT(ring.shortestCycleS(), 0.18 + 6 * 0.00125);
  // A firing time going backwards or repeated is no interval; a lost message is a long one; an
  // interval under half the median (a duplicate 1 ms after its original) is none either.
  const double before = ring.shortestCycleS();
  ring.fired(0, t - 500'000);
  ring.fired(1, t - 500'000);
  ring.fired(2, t + 90'000);
  ring.fired(3, t + 91'000);
  ring.fired(4, t + 131'000);
  EXPECT_DOUBLE_EQ(ring.shortestCycleS(), before);
  // Without times (fired(group)) nothing is timed.
  RingGroups untimed;
  for (int k = 0; k < 40; ++k) untimed.fired(k % 6);
  EXPECT_EQ(untimed.perCycle(), 6);
  EXPECT_EQ(untimed.shortestCycleS(), 0.0);
}

namespace {
std::vector<BeamAxis> evenRing(int n, double beam_deg, double jitter_deg = 0, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> off(-jitter_deg, jitter_deg);
  std::vector<BeamAxis> r;
  for (int i = 0; i < n; ++i)
    r.push_back({geom::deg2rad(360.0 * i / n + (jitter_deg > 0 ? off(rng) : 0.0)), geom::deg2rad(beam_deg)});
  return r;
}
}  // namespace

TEST(RingBeams, MostBeamsOverOneBearing) {
  const double margin = geom::deg2rad(1.0);
  // MOBOT-IV: 24 beams of 30 deg, 15 deg apart: every bearing in two beams; every other beam
  // touches, and does not count however its mount was measured (+-0.5 deg).
  EXPECT_EQ(maxBeamOverlap(evenRing(24, 30), margin), 2);
  for (unsigned seed = 1; seed <= 20; ++seed) EXPECT_EQ(maxBeamOverlap(evenRing(24, 30, 0.5, seed), margin), 2);
  // Without the margin a mount measured a little off makes touching beams a third.
  int three = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) three += maxBeamOverlap(evenRing(24, 30, 0.5, seed), 0.0) == 3;
  EXPECT_GT(three, 0);
  // A Pioneer's 16 sonars of 25 deg: its front and rear pairs (+-10 deg, 180 +- 10 deg) overlap by
  // 5 deg, and two sensors look straight to each side.
  std::vector<BeamAxis> pioneer;
  for (const double t : {90, 50, 30, 10, -10, -30, -50, -90, -90, -130, -150, -170, 170, 150, 130, 90})
    pioneer.push_back({geom::deg2rad(t), geom::deg2rad(25)});
  EXPECT_EQ(maxBeamOverlap(pioneer, margin), 2);
  pioneer.erase(pioneer.begin() + 15);  // one side sensor left: the front pair still overlaps
  EXPECT_EQ(maxBeamOverlap(pioneer, margin), 2);
  // 8 beams of 30 deg, 45 deg apart: none overlap; 48 of 30 deg, 7.5 deg apart: four.
  EXPECT_EQ(maxBeamOverlap(evenRing(8, 30), margin), 1);
  EXPECT_EQ(maxBeamOverlap(evenRing(48, 30), margin), 4);
  // Across +-pi: two beams either side of straight behind.
  EXPECT_EQ(maxBeamOverlap({{geom::deg2rad(175), geom::deg2rad(30)}, {geom::deg2rad(-175), geom::deg2rad(30)}}, margin), 2);
  // Nothing usable: 0; unusable beams are left out.
  EXPECT_EQ(maxBeamOverlap({}, margin), 0);
  EXPECT_EQ(maxBeamOverlap({{std::nan(""), 0.5}, {0.0, -1.0}, {0.0, 7.0}, {0.0, std::nan("")}}, margin), 0);
  EXPECT_EQ(maxBeamOverlap({{0.0, 0.5}, {std::nan(""), 0.5}}, margin), 1);
}
