// EchoPlacer with arc votes: an echo whose arc crosses no voted cell waits (arc_wait_cycles) for
// later arcs, and then joins only a cell the grid already holds.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/config.hpp"
#include "operational/echo_placer.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

AgmParams tactical() {
  AgmParams p;
  p.size = 100;
  p.cell_size = 0.1;
  p.t = 1;
  p.g_threshold = 5;
  p.h_max = 2000;
  p.g_max = 100;
  p.arc_vote_tau = 100;
  return p;
}

EchoPlacementConfig waiting(int cycles, double min_votes = 1.5) {
  EchoPlacementConfig c;
  c.bearing = AgmBearing::Axis;
  c.placement = AgmPlacement::ArcVotes;
  c.arc_require_votes = true;
  c.arc_wait_cycles = cycles;
  c.arc_min_votes = min_votes;  // 1.5: two arcs, some cycles old (votes fade with arc_vote_tau)
  return c;
}

// One echo from a transducer at `from` aimed at `target`, at the target's range.
std::vector<GroupReading> echoAt(int id, const Vec2& from, const Vec2& target) {
  GroupReading r;
  r.sensor_id = id;
  r.echo = true;
  const Vec2 d = target - from;
  r.e.range = d.norm();
  r.e.sensor = geom::Pose2{from.x(), from.y(), std::atan2(d.y(), d.x())};
  r.e.beam_width = geom::deg2rad(30);
  r.axis_end = target;
  return {r};
}

const Vec2 kTarget{1.55, 0.05};  // a cell centre

// The first three echoes of a surface point from three poses, each in its own update cycle, then
// an empty cycle; returns the points each cycle placed.
std::vector<std::vector<Vec2>> threeArcs(EchoPlacer& placer, AccumulativeGridMap& agm) {
  std::vector<std::vector<Vec2>> placed;
  const std::vector<std::vector<GroupReading>> groups = {
      echoAt(0, {0, 0}, kTarget), echoAt(1, {0.3, 0.9}, kTarget), echoAt(2, {0.3, -0.9}, kTarget), {}};
  for (const auto& g : groups) {
    placed.push_back(placer.place(g, agm));
    agm.update(placed.back());
  }
  return placed;
}

}  // namespace

TEST(EchoPlacer, WithoutWaitingTheFirstTwoEchoesOfASurfaceAreLost) {
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  EchoPlacer placer(waiting(0));
  const auto placed = threeArcs(placer, agm);
  EXPECT_TRUE(placed[0].empty());
  EXPECT_TRUE(placed[1].empty());
  ASSERT_EQ(placed[2].size(), 1u);  // two earlier arcs cross the third's at the target
  EXPECT_LT((placed[2][0] - kTarget).norm(), 0.1);
  EXPECT_TRUE(placed[3].empty());
}

TEST(EchoPlacer, WaitingEchoesJoinTheCellLaterArcsConfirm) {
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  EchoPlacer placer(waiting(100));
  const auto placed = threeArcs(placer, agm);
  EXPECT_TRUE(placed[0].empty());
  EXPECT_TRUE(placed[1].empty());
  ASSERT_EQ(placed[2].size(), 1u);
  // The next cycle: the first two echoes, each crossed by two arcs besides its own, join the
  // cell the third one started.
  ASSERT_EQ(placed[3].size(), 2u);
  for (const Vec2& p : placed[3]) EXPECT_LT((p - kTarget).norm(), 0.1);
  int ix = 0, iy = 0;
  ASSERT_TRUE(agm.cellAt(kTarget, ix, iy));
  EXPECT_EQ(agm.g(ix, iy), 3);
}

TEST(EchoPlacer, LastPlacedNamesEachPlacedEchoWithItsTransducer) {
  // What the tactical level's laser join needs: every echo the last place() put in, waiting ones
  // included, with the transducer that heard it and its range; none for an echo still waiting.
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  EchoPlacer placer(waiting(100));
  placer.place(echoAt(0, {0, 0}, kTarget), agm);
  EXPECT_TRUE(placer.lastPlaced().empty());  // waiting for a second arc
  placer.place(echoAt(1, {0.3, 0.9}, kTarget), agm);
  const auto third = placer.place(echoAt(2, {0.3, -0.9}, kTarget), agm);
  ASSERT_EQ(third.size(), 1u);
  ASSERT_EQ(placer.lastPlaced().size(), 1u);
  const PlacedEcho& e = placer.lastPlaced().front();
  EXPECT_EQ(e.point, third.front());
  EXPECT_NEAR(e.sensor.x, 0.3, 1e-12);
  EXPECT_NEAR(e.sensor.y, -0.9, 1e-12);
  EXPECT_NEAR(e.range, (kTarget - Vec2(0.3, -0.9)).norm(), 1e-12);
  EXPECT_NEAR(e.beam_width, geom::deg2rad(30), 1e-12);
  agm.update(third);
  // The next cycle places the two that waited, from their own transducers.
  const auto later = placer.place({}, agm);
  ASSERT_EQ(later.size(), 2u);
  ASSERT_EQ(placer.lastPlaced().size(), 2u);
  EXPECT_NEAR(placer.lastPlaced()[0].sensor.y, 0.0, 1e-12);
  EXPECT_NEAR(placer.lastPlaced()[1].sensor.y, 0.9, 1e-12);
}

TEST(EchoPlacer, AWaitingEchoNeverStartsACellOfItsOwn) {
  // Later arcs cross the waiting echo's arc at the target, but no echo was placed there: the
  // waiting echo stays out until the grid holds that cell, and is dropped after arc_wait_cycles.
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  EchoPlacer placer(waiting(5));
  auto crossAt = [&](const Vec2& target) {
    for (const Vec2& from : {Vec2{0.3, 0.9}, Vec2{0.3, -0.9}}) {
      const Vec2 d = target - from;
      const double b = std::atan2(d.y(), d.x());
      agm.addArcVotes(from, d.norm(), b - 0.3, b + 0.3);
    }
  };
  EXPECT_TRUE(placer.place(echoAt(0, {0, 0}, kTarget), agm).empty());
  agm.update({});
  crossAt(kTarget);
  EXPECT_TRUE(placer.place({}, agm).empty());  // votes enough, but the cell holds nothing
  agm.update({});
  agm.update({kTarget});  // now the grid holds it
  const auto placed = placer.place({}, agm);
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_LT((placed[0] - kTarget).norm(), 0.1);
  // Another waiting echo whose wait runs out before its cell is confirmed: dropped (with a wait
  // of 20 cycles it would be placed, as above).
  for (const int wait : {5, 20}) {
    EchoPlacer p(waiting(wait));
    const Vec2 other{1.55, wait == 5 ? 1.05 : -0.95};  // a fresh spot each time
    EXPECT_TRUE(p.place(echoAt(0, {0, 0.2}, other), agm).empty());
    for (int i = 0; i < 7; ++i) agm.update({});
    agm.update({other});
    crossAt(other);
    EXPECT_EQ(p.place({}, agm).size(), wait == 5 ? 0u : 1u) << "wait " << wait;
  }
}

TEST(EchoPlacer, AnArcWeighsItsVoteWeight) {
  // The same echo from the same pose, placed with vote weights 1, 0.5 and 0: its arc's cells hold
  // that many votes (read in the next cycle, faded by one cycle of arc_vote_tau).
  for (const double w : {1.0, 0.5, 0.0}) {
    AccumulativeGridMap agm(tactical());
    agm.centreOn({0.05, 0.05});
    EchoPlacer placer(waiting(100));
    placer.setVoteWeight(w);
    placer.place(echoAt(0, {0, 0}, kTarget), agm);
    agm.update({});
    int ix = 0, iy = 0;
    ASSERT_TRUE(agm.cellAt(kTarget, ix, iy));
    EXPECT_NEAR(agm.arcVotes(ix, iy), w * std::exp(-1.0 / 100), 1e-6) << "weight " << w;
  }
  // Two arcs heard standing (weight 0) fix nothing: the echo still waits, as after one arc.
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  EchoPlacer placer(waiting(100));
  placer.setVoteWeight(0);
  const auto placed = threeArcs(placer, agm);
  for (const auto& cycle : placed) EXPECT_TRUE(cycle.empty());
}

TEST(EchoPlacer, WaitCyclesKey) {
  const auto c = echoPlacementConfig(Config::fromString("arc_wait_cycles: 12"));
  EXPECT_EQ(c.arc_wait_cycles, 12);
  EXPECT_EQ(echoPlacementConfig(Config::fromString("{}")).arc_wait_cycles, 0);  // the pilot: none
  EXPECT_THROW(echoPlacementConfig(Config::fromString("arc_wait_cycles: -1")), ConfigError);
}

namespace {
EchoPlacementConfig onTheAxis(bool fill, double spread = 0, int min_agree = 1) {
  EchoPlacementConfig c;  // each echo at its own end point: the spread alone is tested
  c.bearing = AgmBearing::Axis;
  c.placement = AgmPlacement::Estimate;
  c.arc_wait_cycles = 100;
  c.surface_fill = fill;
  c.surface_spread_m = spread;
  c.surface_min_agree = min_agree;
  c.surface_max_gap_m = 0.5;  // the feet below are 0.3 m apart
  return c;
}
int gAt(const AccumulativeGridMap& agm, const Vec2& p) {
  int ix = 0, iy = 0;
  return agm.cellAt(p, ix, iy) ? agm.g(ix, iy) : -1;
}
// A wall at y = 1.55 heard face-on from three poses 0.3 m apart (cell centres, so no rounding).
void driveAlongWall(EchoPlacer& placer, AccumulativeGridMap& agm) {
  for (double x : {0.05, 0.35, 0.65}) agm.update(placer.place(echoAt(0, {x, 0.05}, {x, 1.55}), agm));
}
}  // namespace

TEST(EchoPlacer, SurfaceFillJoinsTheFeetOfOnePlane) {
  for (const bool fill : {false, true}) {
    AccumulativeGridMap agm(tactical());
    EchoPlacer placer(onTheAxis(fill, 0.1));
    driveAlongWall(placer, agm);
    for (double x : {0.05, 0.35, 0.65}) EXPECT_EQ(gAt(agm, {x, 1.55}), 1) << "the echo's own cell x " << x;
    // Between the feet: one hit each with the fill, none without (the paper: one cell per echo).
    for (double x : {0.15, 0.25, 0.45, 0.55}) EXPECT_EQ(gAt(agm, {x, 1.55}), fill ? 1 : 0) << "x " << x;
    // Beyond the last foot, up to surface_spread_m (0.1 m), away from the earlier ones.
    EXPECT_EQ(gAt(agm, {0.75, 1.55}), fill ? 1 : 0);
    EXPECT_EQ(gAt(agm, {0.85, 1.55}), 0);
    EXPECT_EQ(gAt(agm, {-0.05, 1.55}), 0);  // not beyond the first: it had no earlier foot
    EXPECT_EQ(gAt(agm, {0.15, 1.45}), 0);   // nor off the line
  }
}

TEST(EchoPlacer, SurfaceFillWaitsForEnoughAgreeingFeet) {
  AccumulativeGridMap agm(tactical());
  EchoPlacementConfig c = onTheAxis(true, 0, 2);
  c.surface_max_gap_m = 0.7;  // both earlier feet count for the third (0.3 and 0.6 m away)
  EchoPlacer placer(c);
  driveAlongWall(placer, agm);
  EXPECT_EQ(gAt(agm, {0.15, 1.55}), 0);  // the second foot had one earlier foot only
  EXPECT_EQ(gAt(agm, {0.45, 1.55}), 1);  // the third had two
}

TEST(EchoPlacer, FeetThatDoNotMoveWithTheSensorAreNoPlane) {
  // Two poles at one range, heard from poses 0.05 m apart: nearly parallel bearings, both points
  // on one line across them, but the second foot moved 0.2 m while the sensor moved 0.05 m: the
  // arcs are not tangent to one line, so nothing is filled between the poles.
  AccumulativeGridMap agm(tactical());
  EchoPlacer placer(onTheAxis(true, 0.2));
  agm.update(placer.place(echoAt(0, {0.05, 0.05}, {0.05, 1.55}), agm));
  agm.update(placer.place(echoAt(0, {0.10, 0.05}, {0.25, 1.55}), agm));
  EXPECT_EQ(gAt(agm, {0.15, 1.55}), 0);
  EXPECT_EQ(gAt(agm, {0.35, 1.55}), 0);
}

TEST(EchoPlacer, SurfaceKeys) {
  const auto c = echoPlacementConfig(Config::fromString(
      "{surface_fill: true, surface_spread_m: 0.15, surface_min_agree: 2, surface_max_gap_m: 0.3, "
      "surface_max_angle_deg: 5}"));
  EXPECT_TRUE(c.surface_fill);
  EXPECT_DOUBLE_EQ(c.surface_spread_m, 0.15);
  EXPECT_EQ(c.surface_min_agree, 2);
  EXPECT_DOUBLE_EQ(c.surface_max_gap_m, 0.3);
  EXPECT_NEAR(c.surface_max_angle, geom::deg2rad(5), 1e-12);
  EXPECT_FALSE(echoPlacementConfig(Config::fromString("{}")).surface_fill);  // the paper: one cell per echo
  EXPECT_THROW(echoPlacementConfig(Config::fromString("surface_spread_m: -1")), ConfigError);
  EXPECT_THROW(echoPlacementConfig(Config::fromString("surface_min_agree: 0")), ConfigError);
}

// The wait's boundaries (no other test pinned them down): the echo's own arc never confirms it,
// and it is still placed at exactly arc_wait_cycles.
TEST(EchoPlacer, AWaitingEchoIsNotConfirmedByItsOwnArc) {
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  const Vec2 target{1.55, 0.05};
  EchoPlacer placer(waiting(100, 0.5));
  EXPECT_TRUE(placer.place(echoAt(0, {0, 0}, target), agm).empty());
  agm.update({target});  // the grid holds the cell; only the echo's own arc voted there
  EXPECT_TRUE(placer.place({}, agm).empty());
}

TEST(EchoPlacer, AWaitingEchoIsPlacedExactlyArcWaitCyclesLater) {
  AccumulativeGridMap agm(tactical());
  agm.centreOn({0.05, 0.05});
  const Vec2 target{1.55, 0.05};
  const int wait = 4;
  EchoPlacer placer(waiting(wait, 1.5));
  EXPECT_TRUE(placer.place(echoAt(0, {0, 0}, target), agm).empty());  // waits from cycle c0
  for (int i = 0; i < wait - 1; ++i) agm.update({});
  agm.update({target});
  for (const Vec2& from : {Vec2{0.3, 0.9}, Vec2{0.3, -0.9}}) {
    const Vec2 d = target - from;
    const double b = std::atan2(d.y(), d.x());
    agm.addArcVotes(from, d.norm(), b - 0.3, b + 0.3);
  }
  EXPECT_EQ(placer.place({}, agm).size(), 1u);  // cycle c0 + wait: still waiting, now placed
}
