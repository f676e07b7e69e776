// The physical sonar model (sim/sonar_physical.hpp): echo strength against the beam edge and
// range, corners, edges, late echoes, blanking, mesh, people, emitters, beam scale, determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "sim/drivers.hpp"
#include "sim/sonar_model.hpp"
#include "sim/sonar_physical.hpp"
#include "sim_state_fixture.hpp"

using namespace lasonic;
using namespace lasonic::sim;
using geom::deg2rad;

namespace {

constexpr int8_t kDirect = sonar_cause_t::CAUSE_DIRECT;
constexpr int8_t kNoEcho = sonar_cause_t::CAUSE_NO_ECHO;
constexpr int8_t kSpecularLong = sonar_cause_t::CAUSE_SPECULAR_LONG;
constexpr int8_t kCrosstalk = sonar_cause_t::CAUSE_CROSSTALK;
constexpr int8_t kForeign = sonar_cause_t::CAUSE_FOREIGN;
constexpr int8_t kLateEcho = sonar_cause_t::CAUSE_LATE_ECHO;
constexpr int8_t kPlane = sonar_cause_t::REFLECTOR_PLANE;
constexpr int8_t kCorner = sonar_cause_t::REFLECTOR_CORNER;
constexpr int8_t kEdge = sonar_cause_t::REFLECTOR_EDGE;
constexpr int8_t kCylinder = sonar_cause_t::REFLECTOR_CYLINDER;

Scenario scenario(const std::string& body) {
  return parseScenario(Config::fromString("name: t\nseed: 11\nrobot: {path: [[0,0],[1,0]]}\n" + body, "t.yaml"));
}

std::string num(double v) { return std::to_string(v); }
std::string pt(double x, double y) { return "[" + num(x) + ", " + num(y) + "]"; }

// The physical profile without noise or random misreadings.
// (Sent at the firing: a driver core's output comes with the state that fires it.)
SonarConfig clean(const std::string& extra = "") {
  return sonarConfig(Config::fromString("noise_std: 0\nnoise_rel: 0\nforeign_prob: 0\nsend_delay_s: 0\n" + extra));
}

// One firing of sensor 0 at `sensor` (a fresh model: no earlier pings).
SonarReading fire(const Scenario& s, const SonarConfig& c, const geom::Pose2& sensor, uint64_t seed = 1) {
  WorldGeometry w(s);
  PhysicalSonar model(s, c, seed);
  std::mt19937_64 rng(seed);
  return model.fireGroup(w, 1'000'000, {0}, {sensor}, {}, rng).at(0);
}

using lasonic::testing::state;

std::string pipeAt(double range, double bearing_deg, const std::string& material = "plastic", double r = 0.01) {
  const double a = deg2rad(bearing_deg), d = range + r;
  return "  - {shape: circle, material: " + material + ", center: " + pt(d * std::cos(a), d * std::sin(a)) +
         ", radius: " + num(r) + "}\n";
}

}  // namespace

TEST(SonarPhysical, ThinPipeRangeFallsTowardTheBeamEdge) {
  // A 2 cm pipe: the farthest it is heard falls off the axis (directivity), and the widest
  // bearing it is heard at falls with range (spreading, absorption): the effective beam is not
  // a 30° sector.
  const SonarConfig c = clean("range_max: 5\n");
  auto heard = [&](double range, double bearing) {
    const SonarReading r = fire(scenario("obstacles:\n" + pipeAt(range, bearing)), c, {0, 0, 0});
    return r.truth.cause == kDirect && std::abs(r.range - range) < 0.03;
  };
  auto farthest = [&](double bearing) {
    double best = 0;
    for (double d = 0.2; d <= 4.95; d += 0.1)
      if (heard(d, bearing)) best = d;
    return best;
  };
  auto widest = [&](double range) {
    double best = -1;
    for (double b = 0; b <= 40; b += 1.0)
      if (heard(range, b)) best = b;
    return best;
  };
  const double f0 = farthest(0), f6 = farthest(6), f9 = farthest(9), f11 = farthest(11);
  EXPECT_GE(f0, 4.0);  // on the axis
  EXPECT_GT(f0, f6);
  EXPECT_GT(f6, f9);
  EXPECT_GT(f9, f11);
  EXPECT_GT(f11, 0.2);
  const double near = widest(0.4), mid = widest(1.5), far = widest(2.8);
  EXPECT_GT(near, 15.0) << "a strong near echo is heard beyond the nominal 15° half-beam (side lobe)";
  EXPECT_GT(near, mid);
  EXPECT_GT(mid, far);
  EXPECT_LT(far, 10.0) << "a weak far echo only near the axis";
}

TEST(SonarPhysical, FlatWallSideLobesAndRange) {
  // A smooth metal wall whose normal is 28.9° off the axis (the second side lobe, -47.6 dB round
  // trip): heard from its foot point at 0.8 m, not at 2.8 m; via the first side lobe (17.2°,
  // -35 dB) still at 2.8 m. Echoes come from the foot of the perpendicular, not the axis.
  const SonarConfig c = clean();
  auto wall = [&](double d, double normal_deg) {
    const double a = deg2rad(normal_deg);
    const geom::Vec2 foot(d * std::cos(a), d * std::sin(a)), along(-std::sin(a), std::cos(a));
    const geom::Vec2 p = foot - 5 * along, q = foot + 5 * along;
    return fire(scenario("obstacles:\n  - {shape: segment, material: metal, from: " + pt(p.x(), p.y()) +
                         ", to: " + pt(q.x(), q.y()) + "}\n"),
                c, {0, 0, 0});
  };
  const SonarReading near = wall(0.8, 28.9);
  EXPECT_EQ(near.truth.cause, kDirect);
  EXPECT_EQ(near.truth.reflector, kPlane);
  EXPECT_NEAR(near.truth.true_range, 0.8, 1e-6);
  EXPECT_NEAR(near.range, 0.8, 0.03);  // weak: it crosses the threshold late
  EXPECT_NEAR(near.truth.hit_x, 0.8 * std::cos(deg2rad(28.9)), 1e-6);
  EXPECT_NEAR(near.truth.hit_y, 0.8 * std::sin(deg2rad(28.9)), 1e-6);
  EXPECT_EQ(wall(2.8, 28.9).truth.cause, kNoEcho);
  EXPECT_EQ(wall(2.8, 10.0).truth.cause, kDirect);   // main lobe
  EXPECT_EQ(wall(2.8, 12.7).truth.cause, kNoEcho);   // its first null
  EXPECT_EQ(wall(2.8, 17.2).truth.cause, kDirect);   // first side lobe
  EXPECT_EQ(wall(2.8, 45.0).truth.cause, kNoEcho);
}

TEST(SonarPhysical, CornerAnswersFromObliqueAnglesAtItsRange) {
  // Two metal walls meeting at (2,2). No wall is met within 40° of normal incidence, yet the
  // corner returns the sound to the transducer from anywhere inside it: a DIRECT echo at the
  // corner's range, from the vertex.
  const std::string walls =
      "obstacles:\n"
      "  - {shape: segment, material: metal, from: [2,-3], to: [2,2]}\n"
      "  - {shape: segment, material: metal, from: [-3,2], to: [2,2]}\n";
  const Scenario s = scenario(walls);
  const SonarConfig c = clean();
  const geom::Vec2 v(2, 2);
  // Positions from which both walls are met 35°-55° off normal (nearer to normal, a wall's own
  // echo would come first through a side lobe).
  for (const geom::Vec2& p : {geom::Vec2(0, 0), geom::Vec2(0.4, 0.1), geom::Vec2(0.1, 0.4), geom::Vec2(1.0, 0.9)}) {
    for (double aim_off : {-6.0, 0.0, 6.0}) {
      const double heading = std::atan2(v.y() - p.y(), v.x() - p.x()) + deg2rad(aim_off);
      const SonarReading r = fire(s, c, {p.x(), p.y(), heading});
      EXPECT_EQ(r.truth.cause, kDirect) << p.transpose() << " " << aim_off;
      EXPECT_EQ(r.truth.reflector, kCorner) << p.transpose() << " " << aim_off;
      EXPECT_NEAR(r.range, (v - p).norm(), 0.02);
      EXPECT_NEAR(r.truth.true_range, (v - p).norm(), 1e-5);
      EXPECT_NEAR(r.truth.hit_x, 2.0, 1e-9);
      EXPECT_NEAR(r.truth.hit_y, 2.0, 1e-9);
    }
  }
  // The same walls 0.3 m short of meeting: no corner, nothing answers from (0,0) facing 45°.
  const Scenario open = scenario(
      "obstacles:\n"
      "  - {shape: segment, material: metal, from: [2,-3], to: [2,1.7]}\n"
      "  - {shape: segment, material: metal, from: [-3,2], to: [1.7,2]}\n");
  EXPECT_EQ(fire(open, c, {0, 0, deg2rad(45)}).truth.cause, kNoEcho);
  // The ideal profile hears the corner only as a too-long multipath reading.
  SonarConfig ideal = c;
  ideal.multipath_prob = 1;
  WorldGeometry w(s);
  std::mt19937_64 rng(1);
  EXPECT_EQ(fireSensor(w, {0, 0, deg2rad(45.1)}, deg2rad(30), ideal, rng).truth.cause, kSpecularLong);
}

TEST(SonarPhysical, PaneEndAnswersWeakly) {
  // A glass pane along x = d from y = 0.3 d upwards: its perpendicular foot (d, 0) is off the
  // pane, so only its end can answer, by weak diffraction: heard at 1 m, not at 2.5 m, and some
  // 40 dB weaker than a plane.
  const SonarConfig c = clean();
  auto paneEnd = [&](double d) {
    return scenario("obstacles:\n  - {shape: segment, material: glass, from: " + pt(d, 0.3 * d) + ", to: " +
                    pt(d, 4 * d) + "}\n");
  };
  const double aim = std::atan2(0.3, 1.0);
  const SonarReading near = fire(paneEnd(1.0), c, {0, 0, aim});
  EXPECT_EQ(near.truth.cause, kDirect);
  EXPECT_EQ(near.truth.reflector, kEdge);
  EXPECT_NEAR(near.range, std::hypot(1.0, 0.3), 0.03);
  EXPECT_NEAR(near.truth.hit_y, 0.3, 1e-9);
  EXPECT_EQ(fire(paneEnd(2.5), c, {0, 0, aim}).truth.cause, kNoEcho);
  // Its margin against a mirror's at the same range.
  const Scenario s = paneEnd(1.0);
  WorldGeometry w(s);
  PhysicalSonar model(s, c, 1);
  double edge_margin = -1;
  for (const Echo& e : model.ownEchoes(w, {0, 0, aim}, 0))
    if (e.reflector == kEdge) edge_margin = e.margin;
  ASSERT_GE(edge_margin, 0);
  EXPECT_LT(edge_margin, model.budget().planeMargin(std::hypot(1.0, 0.3)) - 35);
  // The frame's jambs: a framed pane's ends are boxes with edges and faces of their own.
  const Scenario framed = scenario(
      "obstacles:\n  - {shape: segment, material: glass, from: [1, 0.3], to: [1, 4], frame: {material: wall, width: 0.05}}\n");
  ASSERT_EQ(framed.obstacles.size(), 3u);
  EXPECT_EQ(framed.obstacles[1].frame_of, 0);
  EXPECT_EQ(framed.obstacles[1].material, "wall");
  const SonarReading jamb = fire(framed, c, {0, 0, aim});
  EXPECT_EQ(jamb.truth.cause, kDirect);
  EXPECT_EQ(jamb.truth.obstacle, 1);  // the jamb at the lower end
}

TEST(SonarPhysical, LateEchoesFromAFarWallRepeatAndVanishWithALongGroupPeriod) {
  // A plaster wall 7 m ahead of a standing robot: the echo of a sensor on the 0.35 m ring takes
  // 2 * 6.65 m / 343 m/s = 38.8 ms, after this firing's 17.5 ms window, and arrives in the window
  // of the next group (30 ms later) at the range (13.3 - 343 * 0.03) / 2 = 1.5 m — every ring
  // cycle again. With the groups 65 ms apart
  // (longer than the 62 ms an echo from the 10.7 m hearing range takes) nothing arrives late.
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [7, -20], to: [7, 20]}\n");
  // The robot faces 7.5° off the wall's normal, so that the wall's mirror point lies between
  // the axes of two neighbouring sensors, which fire one group apart.
  auto run = [&](const std::string& extra, std::map<int, int>& per_sensor) {
    const SonarConfig c = clean(extra);
    SonarDriverCore core(s, c, 3);
    int late = 0, firings = 0;
    for (int64_t t = 1'000'000; t <= 3'000'000; t += 20'000)
      for (const auto& o : core.onSimState(state(t, 0, 0, deg2rad(7.5)))) {
        ++firings;
        for (size_t i = 0; i < o.truth.causes.size(); ++i) {
          if (o.truth.causes[i].cause != kLateEcho) continue;
          ++late;
          ++per_sensor[o.truth.causes[i].sensor_id];
          EXPECT_FALSE(o.ring.no_echo[i]);
          EXPECT_GT(o.ring.range[i], 1.45);
          EXPECT_LT(o.ring.range[i], 1.65);
        }
      }
    EXPECT_GT(firings, 20);
    return late;
  };
  std::map<int, int> per_sensor;
  EXPECT_GT(run("group_jitter_s: 0\n", per_sensor), 10);
  int most = 0;
  for (const auto& [id, n] : per_sensor) most = std::max(most, n);
  EXPECT_GE(most, 9) << "the same sensor hears it every ring cycle (11 cycles in 2 s)";
  std::map<int, int> none;
  EXPECT_EQ(run("group_jitter_s: 0\ngroup_period_s: 0.065\n", none), 0);
  // The random crosstalk model has no late echoes either.
  EXPECT_EQ(run("group_jitter_s: 0\ncrosstalk: random\ncrosstalk_prob: 0\n", none), 0);
}

TEST(SonarPhysical, VariedFiringDelaysSpreadTheLateEchoesOverRange) {
  // The wall of the test above, with each group fired 0-8 ms late at random: the late echo of
  // the earlier ping arrives at a different time after each firing, so it reads a different
  // range every ring cycle (343 m/s * 8 ms / 2 = 1.4 m apart at most) instead of one.
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [7, -20], to: [7, 20]}\n");
  SonarDriverCore core(s, clean("group_jitter_s: 0.008\n"), 3);
  std::vector<double> late;
  int64_t last = 0, min_gap = 1'000'000, max_gap = 0;
  for (int64_t t = 1'000'000; t <= 5'000'000; t += 20'000)
    for (const auto& o : core.onSimState(state(t, 0, 0, deg2rad(7.5)))) {
      if (last > 0) {
        min_gap = std::min(min_gap, o.ring.utime - last);
        max_gap = std::max(max_gap, o.ring.utime - last);
      }
      last = o.ring.utime;
      for (size_t i = 0; i < o.truth.causes.size(); ++i)
        if (o.truth.causes[i].cause == kLateEcho) late.push_back(o.ring.range[i]);
    }
  EXPECT_GE(min_gap, 30'000);
  EXPECT_LE(max_gap, 38'000);
  EXPECT_GT(max_gap, 34'000);  // the delays really vary
  ASSERT_GT(late.size(), 5u);
  const auto [lo, hi] = std::minmax_element(late.begin(), late.end());
  EXPECT_GT(*hi - *lo, 0.5) << "late echoes still at one range";
}

TEST(SonarPhysical, ArrivalsOfAnotherPingFollowTheMirrorPath) {
  // Sensor A at the origin facing +x pings; sensor B 0.1 m to its side, facing 10° left,
  // listens. A wall at x = 1.5: the mirror path A -> wall -> B has length |A' - B| with A' the
  // image of A behind the wall.
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [1.5, -5], to: [1.5, 5]}\n");
  const SonarConfig c = clean();
  WorldGeometry w(s);
  PhysicalSonar model(s, c, 1);
  const geom::Pose2 a{0, 0, 0}, b{0, 0.1, deg2rad(10)};
  const double L = (geom::Vec2(3.0, 0) - b.position()).norm();
  const auto same = model.arrivals(w, {1'000'000, 0, a}, b, 1'000'000, 1);
  ASSERT_FALSE(same.empty());
  EXPECT_EQ(same[0].cause, kCrosstalk);
  EXPECT_NEAR(same[0].range, 0.5 * L, 1e-9);
  EXPECT_NEAR(same[0].hit.x(), 1.5, 1e-9);
  // The same ping heard by B 5 ms later reads 343 * 0.005 / 2 = 0.86 m shorter: a late echo.
  const auto later = model.arrivals(w, {1'000'000, 0, a}, b, 1'005'000, 1);
  ASSERT_FALSE(later.empty());
  EXPECT_EQ(later[0].cause, kLateEcho);
  EXPECT_NEAR(later[0].range, 0.5 * (L - 343.0 * 0.005), 1e-9);
  // A listener facing away hears nothing.
  EXPECT_TRUE(model.arrivals(w, {1'000'000, 0, a}, {0, 0.1, geom::kPi}, 1'000'000, 1).empty());
}

TEST(SonarPhysical, ACornerSendsAPingBackToANeighbourParallelToHowItLeft) {
  // A right-angled corner at v = (3, 3). Twice reflected, a ray comes back parallel to how it
  // left, so the path emitter e -> corner -> listener p has length |(2v - e) - p|, and it leaves
  // e towards p's image 2v - p while p hears it from e's image 2v - e: for e = (0.5, 1.5) and
  // p = (1.5, 0.5) both directions are 45 deg, although v itself lies 31 deg from e.
  const Scenario s = scenario("obstacles:\n  - {shape: polyline, material: wall, points: [[3, -1], [3, 3], [-1, 3]]}\n");
  const SonarConfig c = clean();
  WorldGeometry w(s);
  PhysicalSonar model(s, c, 1);
  const geom::Vec2 v(3, 3), e(0.5, 1.5), p(1.5, 0.5);
  const geom::Pose2 listener{p.x(), p.y(), deg2rad(45)};
  auto corner = [&](double emitter_heading_deg) -> std::optional<Echo> {
    for (const Echo& x : model.arrivals(w, {1'000'000, 0, {e.x(), e.y(), deg2rad(emitter_heading_deg)}}, listener,
                                        1'000'000, 1))
      if (x.reflector == kCorner) return x;
    return std::nullopt;
  };
  const auto along = corner(45);  // the emitter's axis on the way the sound leaves
  ASSERT_TRUE(along.has_value()) << "the corner's walls must not block the path from the corner itself";
  EXPECT_EQ(along->cause, kCrosstalk);
  EXPECT_NEAR(along->range, 0.5 * ((2 * v - e) - p).norm(), 1e-9);
  EXPECT_NEAR(along->hit.x(), 3.0, 1e-9);
  // Aimed at the corner point instead, the emitter sends the sound 14 deg off its axis.
  const auto at_vertex = corner(31);
  EXPECT_TRUE(!at_vertex || at_vertex->margin < along->margin - 3.0);
  // The same ping heard 5 ms later by the same listener: a late echo, 0.86 m shorter.
  bool late = false;
  for (const Echo& x : model.arrivals(w, {1'000'000, 0, {e.x(), e.y(), deg2rad(45)}}, listener, 1'005'000, 1))
    late = late || (x.reflector == kCorner && x.cause == kLateEcho &&
                    std::abs(x.range - 0.5 * (((2 * v - e) - p).norm() - 343.0 * 0.005)) < 1e-9);
  EXPECT_TRUE(late);
}

TEST(SonarPhysical, BlankedEchoesAreLostAndTheNextOneIsRead) {
  // A pipe 6 cm from the transducer (inside range_min = 0.10 m), 10° off the axis, and a wall
  // at 1.5 m: the pipe's echo arrives while the receiver is blanked; the wall's is read. The
  // ideal profile clamps the pipe's echo to range_min instead.
  const Scenario s = scenario("obstacles:\n" + pipeAt(0.06, 10) +
                              "  - {shape: segment, material: wall, from: [1.5, -3], to: [1.5, 3]}\n");
  const SonarConfig c = clean();
  const SonarReading r = fire(s, c, {0, 0, 0});
  EXPECT_EQ(r.truth.cause, kDirect);
  EXPECT_NEAR(r.range, 1.5, 0.01);
  EXPECT_EQ(r.truth.obstacle, 1);
  SonarConfig ideal = c;
  ideal.profile = SensorProfile::Ideal;
  WorldGeometry w(s);
  std::mt19937_64 rng(1);
  const SonarReading clamped = fireSensor(w, {0, 0, 0}, deg2rad(30), ideal, rng);
  EXPECT_NEAR(clamped.range, c.range_min, 1e-6);
  EXPECT_EQ(clamped.truth.obstacle, 0);
  // Nothing but the blanked pipe: no echo.
  EXPECT_EQ(fire(scenario("obstacles:\n" + pipeAt(0.06, 10)), c, {0, 0, 0}).truth.cause, kNoEcho);
}

// A transducer flush with a metal box's face (its robot's disc touching the box: 2.55 - 0.2 m
// rounds to just below 2.35 m): the face meets its rays at 0, and the box's far face, behind it,
// is heard by neither profile (before, half the rays started just beyond the near face, inside
// the solid box). 1 mm off the face, the same.
TEST(SonarPhysical, ATransducerFlushWithABoxDoesNotHearThroughIt) {
  for (const double gap : {0.0, 0.001}) {
    const Scenario s = scenario("obstacles:\n  - {shape: box, material: metal, center: [1.0, " + num(2.55 + gap) +
                                "], size: [0.6, 0.4]}\n  - {shape: segment, material: wall, from: [-3, 4], to: [5, 4]}\n");
    const geom::Pose2 sensor{1.0, 2.35, geom::kPi / 2};
    const SonarConfig c = clean();
    const SonarReading r = fire(s, c, sensor);
    EXPECT_FALSE(r.truth.cause == kDirect && r.truth.hit_y > 2.5) << gap << ": heard at y = " << r.truth.hit_y;
    SonarConfig ideal = c;
    ideal.profile = SensorProfile::Ideal;
    WorldGeometry w(s);
    std::mt19937_64 rng(1);
    const SonarReading i = fireSensor(w, sensor, deg2rad(30), ideal, rng);
    EXPECT_FALSE(i.truth.cause == kDirect && i.truth.hit_y > 2.5) << gap << ": heard at y = " << i.truth.hit_y;
    EXPECT_FALSE(!i.no_echo && i.range > 0.3) << gap << ": read " << i.range;
  }
  // The point meets a segment through it at 0; a ray from beside it, as before.
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [0, 0.3], to: [1, 0.3]}\n");
  const Primitive& wall = s.statics.at(0);
  EXPECT_NEAR(rangeAlong({{0.5, 0.3 - 1e-12}, {0, 1}}, wall).value_or(-1), 0.0, 1e-11);
  EXPECT_EQ(rangeAlong({{0.5, 0.3 + 1e-12}, {0, 1}}, wall), std::optional<double>(0.0));
  EXPECT_EQ(rangeAlong({{0.5, 0.3 + 1e-6}, {0, 1}}, wall), std::nullopt);
  EXPECT_NEAR(rangeAlong({{0.5, 0.0}, {0, 1}}, wall).value_or(-1), 0.3, 1e-15);
}

// The listening end of a path as the ping's end above: a transducer flush with a pane hears
// what comes through the pane as one 1 mm behind it does (through a mesh 0.7 dB weaker, through
// glass not at all), from a foreign emitter and from a neighbour's ping off a wall beyond.
TEST(SonarPhysical, ATransducerFlushWithAPaneListensThroughIt) {
  for (const std::string pane : {"mesh", "glass"}) {
    const Scenario s = scenario("obstacles:\n  - {shape: segment, material: " + pane +
                                ", from: [-1, 1], to: [3, 1]}\n  - {shape: segment, material: metal, from: [-3, 3], "
                                "to: [5, 3]}\nemitters:\n  - {position: [1, 2], period_s: 0.01, phase_s: 0.001}\n");
    WorldGeometry w(s);
    PhysicalSonar model(s, clean(), 1);
    const geom::Pose2 flush{1.0, 1.0, geom::kPi / 2}, behind{1.0, 1.0 - 1e-3, geom::kPi / 2};
    auto loudest = [](const std::vector<Echo>& echoes) {
      double m = -1;
      for (const Echo& e : echoes) m = std::max(m, e.margin);
      return m;
    };
    // The emitter 1 m beyond the pane: its pings arrive every 10 ms.
    double from_emitter_flush = -1, from_emitter_behind = -1;
    for (int k = 0; k < 10; ++k) {
      const int64_t utime = WorldCore::kStartUtime + k * 1'000;
      from_emitter_flush = std::max(from_emitter_flush, loudest(model.emitterArrivals(w, flush, utime)));
      from_emitter_behind = std::max(from_emitter_behind, loudest(model.emitterArrivals(w, behind, utime)));
    }
    // A neighbour 0.5 m aside pinging at the same moment, its sound off the metal wall.
    const PhysicalSonar::Ping ping{WorldCore::kStartUtime, 1, {0.5, 0.9, geom::kPi / 2}};
    const double crosstalk_flush = loudest(model.arrivals(w, ping, flush, ping.utime, 0));
    const double crosstalk_behind = loudest(model.arrivals(w, ping, behind, ping.utime, 0));
    if (pane == "mesh") {
      ASSERT_GT(from_emitter_behind, 0);
      ASSERT_GT(crosstalk_behind, 0);
      EXPECT_NEAR(from_emitter_flush, from_emitter_behind, 0.05);
      EXPECT_NEAR(crosstalk_flush, crosstalk_behind, 0.05);
    } else {
      EXPECT_LT(from_emitter_flush, 0);
      EXPECT_LT(from_emitter_behind, 0);
    }
  }
}

TEST(SonarPhysical, MeshLetsSoundThrough) {
  // A wire mesh 1 m ahead and a metal wall 2 m ahead: the wall's echo comes through the mesh
  // (85 % each way, -1.4 dB), which also answers itself (the nearer, the reading). Glass instead
  // of the mesh hides the wall.
  const SonarConfig c = clean();
  auto wallEcho = [&](const std::string& screen) {
    const Scenario s = scenario("obstacles:\n  - {shape: segment, material: " + screen +
                                ", from: [1, -3], to: [1, 3]}\n  - {shape: segment, material: metal, from: [2, -3], to: [2, 3]}\n");
    WorldGeometry w(s);
    PhysicalSonar model(s, c, 1);
    double margin = -1;
    for (const Echo& e : model.ownEchoes(w, {0, 0, 0}, 0))
      if (e.prim->obstacle == 1 && e.reflector == kPlane) margin = std::max(margin, e.margin);
    return margin;
  };
  const Scenario alone = scenario("obstacles:\n  - {shape: segment, material: metal, from: [2, -3], to: [2, 3]}\n");
  WorldGeometry w(alone);
  PhysicalSonar model(alone, c, 1);
  const double free_margin = model.ownEchoes(w, {0, 0, 0}, 0).at(0).margin;
  EXPECT_NEAR(wallEcho("mesh"), free_margin + 20 * std::log10(0.85), 0.01);
  EXPECT_LT(wallEcho("glass"), 0);
  const SonarReading r = fire(scenario("obstacles:\n  - {shape: segment, material: mesh, from: [1, -3], to: [1, 3]}\n"
                                       "  - {shape: segment, material: metal, from: [2, -3], to: [2, 3]}\n"),
                              c, {0, 0, 0});
  EXPECT_EQ(r.truth.obstacle, 0);
  EXPECT_NEAR(r.range, 1.0, 0.03);
}

TEST(SonarPhysical, PersonIsHeardWithACorrelatedRangeDependentProbability) {
  // A person at the edge of detection: their echo level wanders (posture, 4 dB, correlation
  // time 0.5 s), so heard / not heard come in runs; with a correlation time of 1 ms they do not.
  const SonarConfig c = clean();
  auto stats = [&](const std::string& person_keys, double range, double bearing_deg, double& p_heard,
                   double& after_heard, double& after_missed) {
    const double a = deg2rad(bearing_deg), d = range + 0.25;
    Scenario s = scenario("materials:\n  person: {" + person_keys + "}\nmovers:\n  - {radius: 0.25, material: person, speed: 0.5, path: [" +
                          pt(d * std::cos(a), d * std::sin(a)) + ", [9, 9]]}\n");
    WorldGeometry w(s);
    w.setMovers({{0, {d * std::cos(a), d * std::sin(a)}, 0.25}});
    PhysicalSonar model(s, c, 7);
    std::mt19937_64 rng(7);
    int heard = 0, n = 0, hh = 0, h_ = 0, mh = 0, m_ = 0;
    bool prev = false;
    for (int k = 0; k < 3000; ++k) {
      const SonarReading r = model.fireGroup(w, 1'000'000 + k * 180'000, {0}, {{0, 0, 0}}, {{0, 0}}, rng).at(0);
      const bool now = r.truth.cause == kDirect;
      if (k > 0) {
        (prev ? h_ : m_) += 1;
        (prev ? hh : mh) += now;
      }
      heard += now;
      ++n;
      prev = now;
    }
    p_heard = static_cast<double>(heard) / n;
    after_heard = static_cast<double>(hh) / std::max(1, h_);
    after_missed = static_cast<double>(mh) / std::max(1, m_);
  };
  // Find the bearing where a steady person would just be heard at 2.5 m.
  const Scenario probe = scenario("movers:\n  - {radius: 0.25, material: person, speed: 0.5, path: [[2.75, 0], [9, 9]]}\n");
  double edge = 0;
  {
    SonarConfig steady = c;
    for (double b = 0; b < 30; b += 0.25) {
      const double a = deg2rad(b);
      WorldGeometry w(probe);
      w.setMovers({{0, {2.75 * std::cos(a), 2.75 * std::sin(a)}, 0.25}});
      Scenario flat = probe;
      flat.materials["person"].sonar_fluct_db = 0;
      PhysicalSonar model(flat, steady, 1);
      bool any = false;
      for (const Echo& e : model.ownEchoes(w, {0, 0, 0}, 0)) any = any || (e.prim && e.prim->obstacle == -2);
      if (any) edge = b;
    }
  }
  ASSERT_GT(edge, 3.0);
  double p, after_heard, after_missed;
  stats("sonar_fluct_s: 0.5", 2.5, edge, p, after_heard, after_missed);
  EXPECT_GT(p, 0.15);
  EXPECT_LT(p, 0.85);
  EXPECT_GT(after_heard - after_missed, 0.3) << p << " " << after_heard << " " << after_missed;
  stats("sonar_fluct_s: 0.001", 2.5, edge, p, after_heard, after_missed);
  EXPECT_LT(std::abs(after_heard - after_missed), 0.08) << p << " " << after_heard << " " << after_missed;
  // Nearer at the same bearing, the person is heard more often.
  double p_near, p_far, unused1, unused2;
  stats("sonar_fluct_s: 0.5", 1.2, edge, p_near, unused1, unused2);
  stats("sonar_fluct_s: 0.5", 2.5, edge, p_far, unused1, unused2);
  EXPECT_GT(p_near, p_far + 0.2);
}

TEST(SonarPhysical, ForeignEmitterIsHeardAtItsArrivalTime) {
  // An emitter 1.5 m ahead pinging every 50 ms; the sensor fires every 180 ms (one group): the
  // reading is (sent + 1.5 m / 343 m/s - fired) * 343 / 2 whenever that lies in the window and
  // before the wall's echo at 2.5 m.
  const Scenario s = scenario(
      "obstacles:\n  - {shape: segment, material: wall, from: [2.5, -3], to: [2.5, 3]}\n"
      "emitters:\n  - {position: [1.5, 0], period_s: 0.05, phase_s: 0.003}\n");
  ASSERT_EQ(s.emitters.size(), 1u);
  const SonarConfig c = clean();
  WorldGeometry w(s);
  PhysicalSonar model(s, c, 1);
  std::mt19937_64 rng(1);
  int foreign = 0;
  for (int k = 0; k < 40; ++k) {
    const int64_t utime = WorldCore::kStartUtime + k * 180'000;
    const SonarReading r = model.fireGroup(w, utime, {0}, {{0, 0, 0}}, {}, rng).at(0);
    const double t = k * 0.18;
    // The emitter's pings arriving in [t + 2 * 0.1 / 343, t + 2 * 2.5 / 343] (before the wall's echo).
    std::vector<double> expected;
    for (int n = 0; n < 200; ++n) {
      const double range = 0.5 * 343.0 * (0.003 + n * 0.05 + 1.5 / 343.0 - t);
      if (range >= c.range_min && range < 2.5) expected.push_back(range);
    }
    if (expected.empty()) {
      EXPECT_EQ(r.truth.cause, kDirect) << k;
    } else {
      ++foreign;
      EXPECT_EQ(r.truth.cause, kForeign) << k;
      EXPECT_NEAR(r.range, expected.front(), 0.01) << k;
      EXPECT_NEAR(r.truth.true_range, 2.5, 1e-5);  // the wall's echo it replaced
    }
  }
  EXPECT_GT(foreign, 5);
}

// An emitter starts with its first ping at phase_s: a sensor firing before then hears only the
// wall, never a ping from before the emitter started; after it, the pings are heard.
TEST(SonarPhysical, AForeignEmitterIsSilentBeforeItsFirstPing) {
  const Scenario s = scenario(
      "obstacles:\n  - {shape: segment, material: wall, from: [2.5, -3], to: [2.5, 3]}\n"
      "emitters:\n  - {position: [1.5, 0], period_s: 0.05, phase_s: 1.0}\n");
  const SonarConfig c = clean();
  WorldGeometry w(s);
  PhysicalSonar model(s, c, 1);
  std::mt19937_64 rng(1);
  int foreign = 0;
  for (int k = 0; k < 12; ++k) {
    const SonarReading r = model.fireGroup(w, WorldCore::kStartUtime + k * 180'000, {0}, {{0, 0, 0}}, {}, rng).at(0);
    if (k * 0.18 + 2 * 2.5 / 343.0 < 1.0) {
      EXPECT_EQ(r.truth.cause, kDirect) << k;  // (firings up to 0.9 s)
    }
    foreign += r.truth.cause == kForeign ? 1 : 0;
  }
  EXPECT_GT(foreign, 0);
}

TEST(SonarPhysical, BeamScaleWidensTheSimulatedBeamOnly) {
  // The widest bearing a pipe at 1.5 m is heard at scales with beam_scale; SONAR_RING keeps
  // publishing the nominal beam the pipeline assumes.
  auto widest = [](double scale) {
    const SonarConfig c = clean("beam_scale: " + num(scale) + "\nside_lobes: false\n");
    double best = 0;
    for (double b = 0; b <= 30; b += 0.25)
      if (fire(scenario("obstacles:\n" + pipeAt(1.5, b)), c, {0, 0, 0}).truth.cause == kDirect) best = b;
    return best;
  };
  const double w08 = widest(0.8), w10 = widest(1.0), w12 = widest(1.2);
  EXPECT_NEAR(w08 / w10, 0.8, 0.05);
  EXPECT_NEAR(w12 / w10, 1.2, 0.05);
  const Scenario s = scenario("obstacles:\n" + pipeAt(1.5, 0));
  SonarDriverCore core(s, clean("beam_scale: 1.2\n"), 1);
  const auto out = core.onSimState(state(1'000'000));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FLOAT_EQ(out[0].ring.beam_width[0], static_cast<float>(deg2rad(30)));
  EXPECT_FLOAT_EQ(core.geometry(1'000'000).beam_width[0], static_cast<float>(deg2rad(30)));
  // ... unless the driver is calibrated to its transducer: then both say 36°.
  SonarDriverCore calibrated(s, clean("beam_scale: 1.2\nreport_scaled_beam: true\n"), 1);
  const auto cal = calibrated.onSimState(state(1'000'000));
  ASSERT_EQ(cal.size(), 1u);
  EXPECT_FLOAT_EQ(cal[0].ring.beam_width[0], static_cast<float>(deg2rad(30) * 1.2));
  EXPECT_FLOAT_EQ(calibrated.geometry(1'000'000).beam_width[0], static_cast<float>(deg2rad(30) * 1.2));
  // The ideal profile's sector scales too: a pipe at 17° from sensor 0 (mounted at (0.35, 0)) is
  // outside 30° but inside 36°.
  SonarConfig ideal = clean("profile: ideal\n");
  ideal.multipath_prob = 0;
  const double a17 = deg2rad(17);
  const Scenario pipe17 = scenario("obstacles:\n  - {shape: circle, material: plastic, center: " +
                                   pt(0.35 + 1.5 * std::cos(a17), 1.5 * std::sin(a17)) + ", radius: 0.01}\n");
  SonarDriverCore narrow(pipe17, ideal, 1);
  ideal.beam_scale = 1.2;
  SonarDriverCore wide(pipe17, ideal, 1);
  EXPECT_EQ(narrow.onSimState(state(1'000'000)).at(0).truth.causes[0].cause, kNoEcho);
  EXPECT_EQ(wide.onSimState(state(1'000'000)).at(0).truth.causes[0].cause, kDirect);
}

TEST(SonarPhysical, RoughAndSmoothSurfacesAtOneIncidence) {
  // At 45° incidence 2.5 m away, a rough (brick-like) wall scatters enough back to be heard; a
  // painted plaster wall (88 % mirror) only nearer; a metal wall not at all.
  const SonarConfig c = clean();
  auto at45 = [&](const std::string& material, double d) {
    // The wall through (d, 0) at 45°.
    return fire(scenario("materials:\n  brick: {laser: reflect, sonar_roughness_mm: 3, sonar_lobe_deg: 30, sonar_diffuse: 1}\n"
                         "obstacles:\n  - {shape: segment, material: " + material + ", from: " + pt(d - 3, -3) +
                         ", to: " + pt(d + 3, 3) + "}\n"),
                c, {0, 0, 0});
  };
  const SonarReading brick = at45("brick", 2.5);
  EXPECT_EQ(brick.truth.cause, kDirect);
  EXPECT_EQ(brick.truth.reflector, kPlane);
  // Near the axis (a weak echo: its beam is narrow), not at the 15° edge of an ideal sector.
  EXPECT_GT(brick.truth.true_range, 2.5 / (1 + std::tan(deg2rad(10))));
  EXPECT_EQ(at45("wall", 2.5).truth.cause, kNoEcho);
  EXPECT_EQ(at45("wall", 1.0).truth.cause, kDirect);
  EXPECT_EQ(at45("metal", 0.5).truth.cause, kNoEcho);
}

TEST(SonarPhysical, CylindersAnswerFromTheirNearestPoint) {
  const SonarReading r = fire(scenario("obstacles:\n" + pipeAt(1.2, 5, "black_cardboard", 0.2)), clean(), {0, 0, 0});
  EXPECT_EQ(r.truth.cause, kDirect);
  EXPECT_EQ(r.truth.reflector, kCylinder);
  EXPECT_NEAR(r.truth.true_range, 1.2, 1e-6);
  EXPECT_NEAR(std::hypot(r.truth.hit_x, r.truth.hit_y), 1.2, 1e-6);
}

TEST(SonarPhysical, SameSeedSameLogAnotherSeedAnother) {
  // Everything random in the physical model derives from the seed: people's fluctuation,
  // unmodelled foreign sources, noise; late echoes and emitters from the geometry.
  const Scenario s = scenario(
      "obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[-2,-2],[7,-2],[7,2],[-2,2]]}\n"
      "  - {shape: segment, material: mesh, from: [1, -1], to: [1, 1]}\n"
      "movers:\n  - {radius: 0.25, material: person, speed: 0.5, path: [[-1,1],[1,1]]}\n"
      "emitters:\n  - {position: [3, -1.5], period_s: 0.07}\n");
  const SonarConfig c = sonarConfig(Config::fromString("foreign_prob: 0.05\n"));
  auto run = [&](uint64_t seed, std::map<int, int>& causes) {
    SonarDriverCore core(s, c, seed);
    std::vector<uint8_t> all;
    for (int64_t k = 0; k < 150; ++k) {
      sim_state_t st = state(1'000'000 + k * 20'000, 0.01 * static_cast<double>(k), 0, 0.02 * static_cast<double>(k));
      st.movers.push_back({0, -1 + 0.01 * static_cast<double>(k), 1, 0.25});
      st.nmovers = 1;
      for (auto& o : core.onSimState(st)) {
        std::vector<uint8_t> b(static_cast<size_t>(o.ring.getEncodedSize() + o.truth.getEncodedSize()));
        o.ring.encode(b.data(), 0, o.ring.getEncodedSize());
        o.truth.encode(b.data(), o.ring.getEncodedSize(), o.truth.getEncodedSize());
        all.insert(all.end(), b.begin(), b.end());
        for (const auto& cause : o.truth.causes) ++causes[cause.cause];
      }
    }
    return all;
  };
  std::map<int, int> causes, unused;
  const auto a = run(7, causes);
  EXPECT_EQ(a, run(7, unused));
  EXPECT_NE(a, run(8, unused));
  EXPECT_GT(causes[kDirect], 0);
  EXPECT_GT(causes[kForeign], 0);
}

TEST(SonarPhysical, ConfigKeysAndErrors) {
  const SonarConfig d = sonarConfig(Config());
  EXPECT_EQ(d.profile, SensorProfile::Physical);
  EXPECT_EQ(d.crosstalk, CrosstalkModel::Geometric);
  EXPECT_DOUBLE_EQ(d.beam_scale, 1.0);
  const SonarConfig c = sonarConfig(Config::fromString(
      "profile: ideal\nbeam_scale: 0.8\nfrequency_hz: 40000\ntransducer_radius_m: 0.008\npulse_cycles: 8\n"
      "side_lobes: false\nplane_range_m: 6\ntvg_range_m: 0.5\nair_absorption_db_per_m: 1.3\nray_step_deg: 0.25\n"
      "crosstalk: random\n"));
  EXPECT_EQ(c.profile, SensorProfile::Ideal);
  EXPECT_DOUBLE_EQ(c.beam_scale, 0.8);
  EXPECT_DOUBLE_EQ(c.frequency_hz, 40000);
  EXPECT_DOUBLE_EQ(c.transducer_radius, 0.008);
  EXPECT_EQ(c.pulse_cycles, 8);
  EXPECT_FALSE(c.side_lobes);
  EXPECT_DOUBLE_EQ(c.plane_range, 6);
  EXPECT_DOUBLE_EQ(c.tvg_range, 0.5);
  EXPECT_DOUBLE_EQ(c.air_absorption, 1.3);
  EXPECT_NEAR(c.ray_step, deg2rad(0.25), 1e-12);
  EXPECT_EQ(c.crosstalk, CrosstalkModel::Random);
  auto err = [](const std::string& yaml) {
    try {
      sonarConfig(Config::fromString(yaml, "c.yaml").section("sonar"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("sonar: {profile: real}").find("c.yaml: sonar.profile: must be one of physical, ideal"), std::string::npos);
  EXPECT_NE(err("sonar: {beam_scale: 0}").find("sonar.beam_scale: must be in (0, 5]"), std::string::npos);
  EXPECT_NE(err("sonar: {crosstalk: sometimes}").find("sonar.crosstalk: must be one of geometric, random"),
            std::string::npos);
  EXPECT_NE(err("sonar: {plane_range_m: 2}").find("sonar.plane_range_m: plane_range_m"), std::string::npos);
  EXPECT_NE(err("sonar: {side_lobes: maybe}").find("sonar.side_lobes: must be true or false"), std::string::npos);
  EXPECT_NE(err("sonar: {transducer_radius_m: -1}").find("sonar.transducer_radius_m"), std::string::npos);
}

TEST(SonarPhysical, FindsCornersAndEdges) {
  // A closed room: four corners, no edges (from inside); a box: four outside edges; a free
  // segment: two ends; a T (a wall ending on another): two corners.
  auto count = [](const std::string& obstacles, size_t corners, size_t edges) {
    const Scenario s = scenario("obstacles:\n" + obstacles);
    const Reflectors r = findReflectors(s.statics, deg2rad(5));
    EXPECT_EQ(r.corners.size(), corners) << obstacles;
    EXPECT_EQ(r.edges.size(), edges) << obstacles;
    return r;
  };
  const Reflectors room =
      count("  - {shape: polyline, material: wall, closed: true, points: [[0,0],[4,0],[4,3],[0,3]]}\n", 4, 4);
  for (const CornerReflector& c : room.corners) {
    EXPECT_TRUE(insideWedge(c.start, c.opening, c.vertex, {2, 1.5}));  // seen from inside the room
    EXPECT_NEAR(c.opening, geom::kPi / 2, 1e-9);
    if (c.vertex.norm() < 1e-9) {
      EXPECT_FALSE(insideWedge(c.start, c.opening, c.vertex, {-1, -1}));  // behind the corner at the origin
    }
  }
  for (const EdgeReflector& e : room.edges) EXPECT_FALSE(insideWedge(e.start, e.opening, e.point, {2, 1.5}));
  count("  - {shape: box, material: wall, center: [1, 1], size: [0.5, 0.3]}\n", 4, 4);
  count("  - {shape: segment, material: glass, from: [0, 0], to: [1, 0]}\n", 0, 2);
  count("  - {shape: segment, material: wall, from: [0, 0], to: [4, 0]}\n"
        "  - {shape: segment, material: wall, from: [2, 0], to: [2, 2]}\n",
        2, 3);
  // A pane in line with its wall (a closed door) makes no corner and no edge where they meet.
  count("  - {shape: segment, material: wall, from: [0, 0], to: [2, 0]}\n"
        "  - {shape: segment, material: glass, from: [2, 0], to: [3, 0]}\n",
        0, 2);
}

// Only a right angle (within the tolerance) is a corner reflector, which sends sound back
// parallel to how it came: two walls meeting at 45 deg make none, only the edge of their
// outside (and the two free ends).
TEST(SonarPhysical, AnAcuteJunctionIsNoCornerReflector) {
  const Scenario s = scenario("obstacles:\n  - {shape: polyline, material: wall, points: [[1,1],[0,0],[1,0]]}\n");
  const Reflectors r = findReflectors(s.statics, deg2rad(5));
  EXPECT_TRUE(r.corners.empty());
  EXPECT_EQ(r.edges.size(), 3u);
}

// Where two materials meet at an outside edge, the edge answers with the stronger reflector's
// level: a wall ending on a mesh screen is the wall's edge.
TEST(SonarPhysical, AnEdgeBetweenTwoMaterialsIsTheStrongerOnes) {
  const Scenario s = scenario("obstacles:\n"
                              "  - {shape: segment, material: mesh, from: [2, 0], to: [2, 2]}\n"
                              "  - {shape: segment, material: wall, from: [0, 0], to: [2, 0]}\n");
  const Reflectors r = findReflectors(s.statics, deg2rad(5));
  const EdgeReflector* joint = nullptr;
  for (const EdgeReflector& e : r.edges)
    if ((e.point - geom::Vec2(2, 0)).norm() < 1e-9) joint = &e;
  ASSERT_NE(joint, nullptr);
  EXPECT_EQ(joint->a->material->name, "wall");
  ASSERT_NE(joint->b, nullptr);
  EXPECT_EQ(joint->b->material->name, "mesh");
}

TEST(SonarPhysical, EffectiveBeamDependsOnTheReflectorAndItsRange) {
  // The widest bearing off the axis at which a reflector is still heard (the README's effective
  // beam table, printed here): a near wall through the side lobes, far beyond the method's
  // assumed 15° half-beam; weak reflectors only near the axis, narrower with range.
  const SonarConfig c = clean();
  struct Kind {
    const char* name;
    std::function<std::string(double range, double bearing_deg)> world;
    int8_t reflector;
  };
  auto rotated = [](double range, double bearing_deg, double x, double y) {
    const double a = deg2rad(bearing_deg);
    return geom::Vec2(range * (x * std::cos(a) - y * std::sin(a)), range * (x * std::sin(a) + y * std::cos(a)));
  };
  auto wall = [&](const std::string& material) {
    return [=](double r, double b) {
      const geom::Vec2 p = rotated(r, b, 1, -6 / r), q = rotated(r, b, 1, 6 / r);
      return "  - {shape: segment, material: " + material + ", from: " + pt(p.x(), p.y()) + ", to: " + pt(q.x(), q.y()) + "}\n";
    };
  };
  const std::vector<Kind> kinds = {
      {"metal wall (plane)", wall("metal"), kPlane},
      {"plaster wall (plane)", wall("wall"), kPlane},
      {"metal corner", [&](double r, double b) {
         const geom::Vec2 v = rotated(r, b, 1, 0), p = v + rotated(1, b + 135, 1, 0) * 2, q = v + rotated(1, b - 135, 1, 0) * 2;
         return "  - {shape: polyline, material: metal, points: [" + pt(p.x(), p.y()) + ", " + pt(v.x(), v.y()) + ", " +
                pt(q.x(), q.y()) + "]}\n";
       }, kCorner},
      {"bin r 0.2 m (black cardboard)", [&](double r, double b) { return pipeAt(r, b, "black_cardboard", 0.2); }, kCylinder},
      {"pipe r 1 cm (plastic)", [&](double r, double b) { return pipeAt(r, b); }, kCylinder},
      {"pane end (glass edge)", [&](double r, double b) {
         const geom::Vec2 e = rotated(r, b, 1, 0), f = e + rotated(1, b + 90, 1, 0) * 3;
         return "  - {shape: segment, material: glass, from: " + pt(e.x(), e.y()) + ", to: " + pt(f.x(), f.y()) + "}\n";
       }, kEdge},
  };
  const std::vector<double> ranges = {0.5, 1.0, 2.0, 2.9};
  std::map<std::string, std::vector<double>> widest;
  std::string table = "effective half-beam [deg] at range";
  for (double r : ranges) table += " | " + num(r).substr(0, 3) + " m";
  table += "\n";
  for (const Kind& k : kinds) {
    table += k.name;
    for (double r : ranges) {
      double best = -1;
      for (double b = 0; b <= 45; b += 0.5) {
        const SonarReading s = fire(scenario("obstacles:\n" + k.world(r, b)), c, {0, 0, 0});
        if (s.truth.cause == kDirect && s.truth.reflector == k.reflector && std::abs(s.truth.true_range - r) < 0.02) best = b;
      }
      widest[k.name].push_back(best);
      table += " | " + (best < 0 ? std::string("-") : num(best).substr(0, 4));
    }
    table += "\n";
  }
  std::cout << table;
  // Strong near reflectors are heard beyond the nominal 15° (side lobes), weak ones not.
  EXPECT_GT(widest["metal wall (plane)"][0], 25.0);
  EXPECT_GT(widest["metal corner"][0], 25.0);
  EXPECT_LT(widest["pipe r 1 cm (plastic)"][3], 10.0);
  EXPECT_LT(widest["pane end (glass edge)"][0], 10.0);
  EXPECT_LT(widest["pane end (glass edge)"][3], 0.0);  // not heard at all at 2.9 m
  for (const auto& [name, w] : widest)
    for (size_t i = 1; i < w.size(); ++i) EXPECT_LE(w[i], w[i - 1]) << name << " at " << ranges[i] << " m";
}
