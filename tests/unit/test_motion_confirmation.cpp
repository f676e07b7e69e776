// MotionConfirmation: echoes of one transducer that the robot's own motion spread beyond the
// AGM's neighbourhood confirm each other; a standing robot's, a single echo, two transducers'
// or a stale pair do not; one ring cycle is the sensor's own previous firing, whatever the ring.
#include <gtest/gtest.h>

#include <vector>

#include "operational/agm.hpp"
#include "operational/motion_confirmation.hpp"
#include "stages/pilot_stage.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

// The operational AGM as shipped (100 x 100 cells of 0.1 m, t = 1, G_T = 2, h_max 18).
AgmParams operational() { return PilotConfig::operationalAgmDefaults(); }

MotionConfirmationParams on() {
  MotionConfirmationParams p;
  p.enabled = true;
  p.tolerance_m = 0.10;
  return p;
}

// An echo of sensor `id` fired at `t_s` from `sensor` (axis +y), placed at `point`.
PlacedEcho echo(int id, double t_s, const Vec2& sensor, const Vec2& point) {
  PlacedEcho e;
  e.point = point;
  e.sensor = geom::Pose2{sensor.x(), sensor.y(), M_PI / 2};
  e.range = (point - sensor).norm();
  e.sensor_id = id;
  e.utime = static_cast<int64_t>(t_s * 1e6);
  return e;
}

// A wall at y = 1.05 beside a robot driving along +x: the transducer facing it fires every
// 0.18 s (one ring cycle) and hears the foot of its perpendicular, which moves with it. At
// `speed` the feet lie speed * 0.18 m apart. Returns the AGM's confirmed cells after `n` echoes.
int confirmedCells(double speed, bool enabled, int n = 4, int* added = nullptr) {
  AccumulativeGridMap agm(operational());
  MotionConfirmationParams p = on();
  p.enabled = enabled;
  MotionConfirmation mc(p);
  int extra = 0;
  for (int k = 0; k < n; ++k) {
    const double x = 0.03 + speed * 0.18 * k;
    std::vector<Vec2> hits = {Vec2(x, 1.05)};
    extra += mc.apply({echo(3, 0.18 * k, Vec2(x, 0.35), Vec2(x, 1.05))}, agm, hits);
    agm.update(hits);
  }
  if (added) *added = extra;
  int confirmed = 0;
  for (int iy = 0; iy < 100; ++iy)
    for (int ix = 0; ix < 100; ++ix) confirmed += agm.gp(ix, iy) >= 2 ? 1 : 0;
  return confirmed;
}

}  // namespace

TEST(MotionConfirmation, AWallBesideAFastRobotIsConfirmedOnlyWithIt) {
  // 1.2 m/s: feet 0.216 m apart, two cells: the paper's AGM never confirms the wall.
  EXPECT_EQ(confirmedCells(1.2, false), 0);
  int added = 0;
  EXPECT_GE(confirmedCells(1.2, true, 4, &added), 3);
  EXPECT_EQ(added, 3);  // every echo but the first
}

TEST(MotionConfirmation, ASlowRobotsEchoesAreNeighboursAndCountOnce) {
  // 0.3 m/s: feet 0.054 m apart, in one neighbourhood: confirmed anyway, nothing added.
  int added = -1;
  EXPECT_GT(confirmedCells(0.3, true, 4, &added), 0);
  EXPECT_EQ(added, 0);
  EXPECT_EQ(confirmedCells(0.3, true), confirmedCells(0.3, false));
}

TEST(MotionConfirmation, NeedsTheSameSensorMovingAsFarAsItsEchoes) {
  AccumulativeGridMap agm(operational());
  MotionConfirmation mc(on());
  std::vector<Vec2> hits;
  // A standing transducer whose two echoes lie 0.3 m apart (a person stepping, crosstalk): no.
  EXPECT_EQ(mc.apply({echo(1, 0.00, Vec2(0, 0), Vec2(0.0, 1.0))}, agm, hits), 0);
  EXPECT_EQ(mc.apply({echo(1, 0.18, Vec2(0, 0), Vec2(0.3, 1.0))}, agm, hits), 0);
  // Another sensor's echo, however near its neighbour's: no.
  EXPECT_EQ(mc.apply({echo(2, 0.20, Vec2(0.3, 0), Vec2(0.3, 1.0))}, agm, hits), 0);
  // The same sensor moved 0.2 m and its echo 0.25 m: within the tolerance, yes.
  EXPECT_EQ(mc.apply({echo(2, 0.38, Vec2(0.5, 0), Vec2(0.55, 1.0))}, agm, hits), 1);
  // ... moved 0.2 m, echo 0.5 m away: no (not the same surface's foot).
  EXPECT_EQ(mc.apply({echo(2, 0.56, Vec2(0.7, 0), Vec2(1.05, 1.0))}, agm, hits), 0);
  // ... moved 0.2 m, echo 0.2 m on, but after a cycle twice the one before (0.34 s after
  // 0.18 s: a firing skipped or lost): no.
  EXPECT_EQ(mc.apply({echo(2, 0.90, Vec2(0.9, 0), Vec2(1.25, 1.0))}, agm, hits), 0);
  // A single echo of a new sensor, or one without a sensor id: nothing.
  EXPECT_EQ(mc.apply({echo(7, 1.00, Vec2(0, 0), Vec2(0.0, 1.0)), echo(-1, 1.0, Vec2(0, 0), Vec2(0, 1))}, agm, hits), 0);
  EXPECT_EQ(hits.size(), 1u);
}

TEST(MotionConfirmation, AnOlderEchoDoesNotReplaceItsSensorsLatest) {
  AccumulativeGridMap agm(operational());
  MotionConfirmation mc(on());
  std::vector<Vec2> hits;
  EXPECT_EQ(mc.apply({echo(4, 0.36, Vec2(0.4, 0), Vec2(0.4, 1.0))}, agm, hits), 0);
  // An echo that waited for later arcs comes late, older than the sensor's latest.
  EXPECT_EQ(mc.apply({echo(4, 0.18, Vec2(0.2, 0), Vec2(0.2, 1.0))}, agm, hits), 0);
  // The next one pairs with the latest (0.36 s), not with the late one.
  EXPECT_EQ(mc.apply({echo(4, 0.54, Vec2(0.6, 0), Vec2(0.62, 1.0))}, agm, hits), 1);
}

TEST(MotionConfirmation, DisabledAddsNothing) {
  int added = -1;
  EXPECT_EQ(confirmedCells(1.2, false, 6, &added), 0);
  EXPECT_EQ(added, 0);
}

TEST(MotionConfirmation, EverNewSensorIdsDoNotGrowWithoutBound) {
  AccumulativeGridMap agm(operational());
  MotionConfirmation mc(on());
  std::vector<Vec2> hits;
  // Malformed messages with a new id each: nothing confirmed, and the stage goes on working.
  for (int id = 0; id < 5000; ++id) EXPECT_EQ(mc.apply({echo(id, 0.001 * id, Vec2(0, 0), Vec2(0, 1))}, agm, hits), 0);
  EXPECT_TRUE(hits.empty());
  EXPECT_LE(mc.sensors(), MotionConfirmation::kMaxSensors);
  EXPECT_EQ(mc.apply({echo(9, 5.00, Vec2(0.0, 0), Vec2(0.0, 1.0))}, agm, hits), 0);
  EXPECT_EQ(mc.apply({echo(9, 5.18, Vec2(0.2, 0), Vec2(0.22, 1.0))}, agm, hits), 1);
}

// One ring cycle comes from the firings: a ring slower than MOBOT-IV's (the Pioneer's 8 groups of
// 40 ms, each up to 8 ms late: 0.32-0.384 s; here a ring of 0.5-0.6 s) pairs its echoes as well,
// with no time to configure.
TEST(MotionConfirmation, ASlowerRingPairsItsEchoesToo) {
  AccumulativeGridMap agm(operational());
  MotionConfirmation mc(on());
  std::vector<Vec2> hits;
  const double times[] = {0.0, 0.5, 1.1, 1.6, 2.2};  // cycles 0.5, 0.6, 0.5, 0.6 s
  int added = 0;
  for (const double t : times) {
    const double x = 0.4 * t;  // a transducer at 0.4 m/s: its feet 0.2-0.24 m apart, two cells
    added += mc.apply({echo(5, t, Vec2(x, 0), Vec2(x, 1.0))}, agm, hits);
  }
  EXPECT_EQ(added, 4);
}

// A firing that placed no echo (nothing heard, or the laser explained it) breaks the pair: the
// echo before it is two cycles old.
TEST(MotionConfirmation, AFiringWithoutAnEchoBreaksThePair) {
  AccumulativeGridMap agm(operational());
  MotionConfirmation mc(on());
  std::vector<Vec2> hits;
  EXPECT_EQ(mc.apply({echo(6, 0.00, Vec2(0.0, 0), Vec2(0.0, 1.0))}, agm, hits), 0);
  mc.fired(6, 0);  // the same firing again (the caller reports every reading): no change
  EXPECT_EQ(mc.apply({echo(6, 0.18, Vec2(0.22, 0), Vec2(0.22, 1.0))}, agm, hits), 1);
  mc.fired(6, static_cast<int64_t>(0.18e6));
  mc.fired(6, static_cast<int64_t>(0.36e6));  // no echo placed at this firing
  EXPECT_EQ(mc.apply({echo(6, 0.54, Vec2(0.44, 0), Vec2(0.44, 1.0))}, agm, hits), 0);
  // ... and the next regular firing pairs again.
  EXPECT_EQ(mc.apply({echo(6, 0.72, Vec2(0.66, 0), Vec2(0.66, 1.0))}, agm, hits), 1);
  // A sonar that stopped for 2 s: its next echo pairs with nothing, the one after does.
  EXPECT_EQ(mc.apply({echo(6, 2.72, Vec2(0.88, 0), Vec2(0.88, 1.0))}, agm, hits), 0);
  EXPECT_EQ(mc.apply({echo(6, 2.90, Vec2(1.10, 0), Vec2(1.10, 1.0))}, agm, hits), 1);
}
