// What the laser saw (eval/laser_seen.hpp) and the scores that use it: "laser-invisible" decided
// per scan from LASER_TRUTH, and the material rule when a log has no LASER_TRUTH.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "eval/evaluate.hpp"
#include "eval/laser_seen.hpp"
#include "eval/observability.hpp"
#include "sim/world_geometry.hpp"
#include "sim_state_fixture.hpp"

using namespace lasonic;
using namespace lasonic::eval;
using geom::Vec2;

namespace {
constexpr int64_t kNever = std::numeric_limits<int64_t>::max();
constexpr int kBox = 1;  // obstacle index of the black box

// A 6 x 4 m plaster room (obstacle 0) and a black cardboard box (obstacle 1) whose front face
// x = 2.8, y in [1.8, 2.2] lies 1.3 m ahead of the robot, which stands at (1.5, 2) facing +x.
sim::Scenario boxRoom() {
  return sim::parseScenario(Config::fromString(R"(
name: t
duration_s: 10
seed: 1
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[6,0],[6,4],[0,4]]}
  - {shape: box, material: black_cardboard, center: [3.0, 2.0], size: [0.4, 0.4]}
robot: {radius: 0.35, path: [[1.5,2],[2,2]], speed: 0.1}
)"));
}

using lasonic::testing::state;

// The robot standing at (1.5, 2) facing +x for 3 s.
std::vector<sim_state_t> standing() { return {state(0, 1.5, 2, 0), state(3'000'000, 1.5, 2, 0)}; }

constexpr int kReadings = 720;
constexpr int64_t kScanUs = 200'000;
int32_t offsetUs(int i) { return static_cast<int32_t>(int64_t{i} * kScanUs / kReadings); }
int64_t doneAt(int64_t utime) { return utime + offsetUs(kReadings - 1); }

// A full-circle scan (0.5 deg apart, reading i at utime + offsetUs(i)) by the standing robot: each
// reading the true range of the first static surface its ray meets; the black box returns only
// when box_returns and within box_deg of the robot's heading (else no return, as black cardboard
// beyond its range or at oblique incidence), its truth the obstacle.
void addScan(RunLog& log, const sim::Scenario& sc, int64_t utime, int32_t seq, bool box_returns,
             double box_deg = 90) {
  const sim::WorldGeometry world(sc);
  laser_scan_t s{};
  s.utime = utime;
  s.seq = seq;
  s.angle_min = -geom::kPi;
  s.angle_increment = 2 * geom::kPi / kReadings;
  s.range_min = 0.05f;
  s.range_max = 15.0f;
  laser_truth_t t{};
  t.utime = utime;
  t.seq = seq;
  for (int i = 0; i < kReadings; ++i) {
    const double a = s.angle_min + i * s.angle_increment;
    const auto hit = world.castRay({{1.5, 2.0}, geom::unitVector(a)}, 15.0);
    const bool ok = hit && (hit->obstacle != kBox || (box_returns && std::abs(a) <= geom::deg2rad(box_deg) + 1e-9));
    s.ranges.push_back(ok ? static_cast<float>(hit->range) : 0.0f);
    s.flags.push_back(ok ? int8_t{laser_scan_t::FLAG_OK} : int8_t{laser_scan_t::FLAG_NO_RETURN});
    s.offset_us.push_back(offsetUs(i));
    t.obstacle.push_back(ok ? hit->obstacle : -1);
  }
  s.nranges = t.nranges = kReadings;
  log.laser_scans.push_back(s);
  log.laser_truths.push_back(t);
}

// Scan A (box seen, done at 299'722 us) and scan B (box dark, done at 699'722 us).
constexpr int64_t kScanA = 100'000, kScanB = 500'000;
RunLog twoScans(const sim::Scenario& sc) {
  RunLog log;
  log.sim_states = standing();
  addScan(log, sc, kScanA, 0, true);
  addScan(log, sc, kScanB, 1, false);
  return log;
}

// Sensor 0 (mount 0.35 m ahead, facing +x: at (1.85, 2)) hears the box's front face head-on at
// (2.8, 2), 0.95 m: SONAR_RING, SONAR_TRUTH (DIRECT, material: not laser-visible, no
// laser-reflecting surface within 2.2 m of the beam) and, when cls >= 0, SONAR_COMPLEMENT with
// the Radar Map of the scan done at rm_utime.
void addBoxEcho(RunLog& log, int64_t utime, int cls = -1, float hyp = 0, int64_t rm_utime = 0, float range = 0.95f) {
  sonar_ring_t r{};
  r.utime = utime;
  r.num_sensors = 1;
  r.range_max = 3.0f;
  r.nreadings = 1;
  r.sensor_id = {0};
  r.range = {range};
  r.no_echo = {0};
  pose2d_t mount{};
  mount.x = 0.35;
  r.mount = {mount};
  r.beam_width = {static_cast<float>(geom::deg2rad(30.0))};
  log.sonar_rings.push_back(r);
  sonar_truth_t t{};
  t.utime = utime;
  sonar_cause_t c{};
  c.cause = sonar_cause_t::CAUSE_DIRECT;
  c.obstacle = kBox;
  c.laser_visible = 0;
  c.true_range = 0.95f;
  c.nearest_laser_visible = -1.0f;
  c.hit_x = 2.8;
  c.hit_y = 2.0;
  c.reflector = sonar_cause_t::REFLECTOR_PLANE;
  t.causes = {c};
  t.nreadings = 1;
  log.sonar_truths.push_back(t);
  if (cls < 0) return;
  complement_t cm{};
  cm.utime = utime;
  cm.radar_map_utime = rm_utime;
  cm.tolerance = 0.1f;
  cm.beam_width = static_cast<float>(geom::deg2rad(30.0));
  cm.range_limit = 2.2f;
  complement_reading_t rd{};
  rd.sensor_id = 0;
  rd.cls = static_cast<int8_t>(cls);
  rd.range = range;
  rd.hypothetical_range = hyp;
  cm.readings = {rd};
  cm.nreadings = 1;
  log.complements.push_back(cm);
}

RunLog withoutLaserTruth(RunLog log) {
  log.laser_truths.clear();
  return log;
}
}  // namespace

TEST(LaserSeen, SeesTheBoxInOneScanAndNotInTheOther) {
  const auto sc = boxRoom();
  const RunLog log = twoScans(sc);
  const LaserSeen seen(log);
  ASSERT_TRUE(seen.available());
  EXPECT_EQ(seen.scans(), 2u);
  EXPECT_EQ(seen.scansWithoutTruth(), 0);
  // The newest scan completed (last reading taken) at or before a time.
  EXPECT_EQ(seen.newestAt(doneAt(kScanA) - 1), -1);
  EXPECT_EQ(seen.newestAt(doneAt(kScanA)), 0);
  EXPECT_EQ(seen.newestAt(doneAt(kScanB) - 1), 0);
  EXPECT_EQ(seen.newestAt(doneAt(kScanB)), 1);
  EXPECT_EQ(seen.completedAt(doneAt(kScanA)), 0);
  EXPECT_EQ(seen.completedAt(doneAt(kScanA) + 1), -1);
  // Scan A returned from the box's front face; reading 360 (bearing 0) hit it at (2.8, 2).
  EXPECT_TRUE(seen.saw(0, kBox, {2.8, 2.0}, 0.10));
  EXPECT_TRUE(seen.saw(0, kBox, {2.71, 2.0}, 0.10));
  EXPECT_FALSE(seen.saw(0, kBox, {2.69, 2.0}, 0.10));  // 0.11 m from the face
  EXPECT_TRUE(seen.saw(0, kBox, {2.62, 2.0}, 0.20));   // a radius of two cells
  EXPECT_FALSE(seen.saw(0, kBox, {3.2, 2.0}, 0.10));   // the back face: hidden
  EXPECT_FALSE(seen.saw(0, 0, {2.8, 2.0}, 0.10));      // not the wall's return
  EXPECT_TRUE(seen.saw(0, 0, {0.0, 2.0}, 0.10));       // the wall behind the robot
  // Scan B: nothing from the box.
  EXPECT_FALSE(seen.saw(1, kBox, {2.8, 2.0}, 0.10));
  EXPECT_TRUE(seen.sawBy(600'000, kBox, {2.8, 2.0}, 0.10));
  EXPECT_FALSE(seen.sawBy(800'000, kBox, {2.8, 2.0}, 0.10));
  EXPECT_FALSE(seen.sawBy(200'000, 0, {0.0, 2.0}, 0.10));  // before the first scan: nothing
  EXPECT_FALSE(seen.saw(-1, kBox, {2.8, 2.0}, 0.10));
  EXPECT_FALSE(seen.saw(7, kBox, {2.8, 2.0}, 0.10));
  EXPECT_FALSE(seen.saw(0, kBox, {std::nan(""), 2.0}, 0.10));
}

// A reading whose time offset the pipeline rejects (outside [0, 1 s]) was not seen: the scan is
// completed when its Radar Map is (at its latest good reading), and that reading is no point.
TEST(LaserSeen, AReadingWithARejectedTimeOffsetIsNotSeen) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  log.laser_scans[0].offset_us[360] = 30'000'000;  // the reading that hit the box's front face
  const LaserSeen seen(log);
  ASSERT_EQ(seen.scans(), 2u);
  EXPECT_EQ(seen.completionTime(0), doneAt(kScanA));
  EXPECT_EQ(seen.completedAt(doneAt(kScanA)), 0);
  EXPECT_TRUE(seen.saw(0, kBox, {2.8, 2.05}, 0.10));   // its neighbours
  EXPECT_FALSE(seen.saw(0, kBox, {2.8, 2.0}, 0.01));  // not the rejected reading itself
}

TEST(LaserSeen, PlacesEachReadingWithThePoseAtItsOwnTimeAndTheMount) {
  // The robot drives +x at 1 m/s; the scanner sits 0.1 m ahead of its centre, turned by 90 deg.
  RunLog log;
  log.sim_states = {state(0, 0, 0, 0), state(1'000'000, 1, 0, 0)};
  laser_scan_t s{};
  s.utime = 0;
  s.mount.x = 0.1;
  s.mount.theta = geom::kPi / 2;
  s.angle_min = 0;
  s.angle_increment = 0.5;
  s.range_min = 0.05f;
  s.range_max = 15.0f;
  s.ranges = {1, 1, 1, 1, 1};
  s.flags = {laser_scan_t::FLAG_OK, laser_scan_t::FLAG_OK, laser_scan_t::FLAG_OK, laser_scan_t::FLAG_OK,
             laser_scan_t::FLAG_NO_RETURN};
  s.offset_us = {0, 250'000, 500'000, 750'000, 1'000'000};
  s.nranges = 5;
  laser_truth_t t{};
  t.obstacle = {0, 0, 0, -1, -1};  // reading 3: a mixed pixel; reading 4: no return
  t.nranges = 5;
  log.laser_scans = {s};
  log.laser_truths = {t};
  const LaserSeen seen(log);
  ASSERT_TRUE(seen.available());
  EXPECT_EQ(seen.points(), 3u);
  EXPECT_EQ(seen.completionTime(0), 1'000'000);
  for (int i = 0; i < 3; ++i) {
    const double x = 0.25 * i;  // the robot at the reading's time
    const Vec2 p = Vec2(x + 0.1, 0) + geom::unitVector(geom::kPi / 2 + 0.5 * i);
    EXPECT_TRUE(seen.saw(0, 0, p, 0.01)) << i;
    // Placed with the pose at the scan's start instead: wrong by the distance driven.
    if (i > 0) {
      EXPECT_FALSE(seen.saw(0, 0, p - Vec2(x, 0), 0.01)) << i;
    }
  }
  // The mixed pixel is no obstacle's return.
  EXPECT_FALSE(seen.saw(0, 0, Vec2(0.85, 0) + geom::unitVector(geom::kPi / 2 + 1.5), 0.01));
}

TEST(LaserSeen, ComparesAMoverInItsOwnFrame) {
  // A person (mover 0, obstacle -2) walks +y at 1 m/s past x = 3; one reading at bearing 0 hits
  // its near side at (2.75, 2) at time 0.
  RunLog log;
  for (int64_t t = 0; t <= 1'000'000; t += 500'000) {
    sim_state_t st = state(t, 1.5, 2, 0);
    mover_state_t m{};
    m.id = 0;
    m.x = 3.0;
    m.y = 2.0 + 1e-6 * static_cast<double>(t);
    m.radius = 0.25;
    st.movers = {m};
    st.nmovers = 1;
    log.sim_states.push_back(st);
  }
  laser_scan_t s{};
  s.angle_min = 0;
  s.angle_increment = 0.01;
  s.ranges = {1.25f};
  s.flags = {laser_scan_t::FLAG_OK};
  s.offset_us = {0};
  s.nranges = 1;
  laser_truth_t t{};
  t.obstacle = {-2};
  t.nranges = 1;
  log.laser_scans = {s};
  log.laser_truths = {t};
  const LaserSeen seen(log);
  EXPECT_TRUE(seen.saw(0, -2, {2.75, 2.0}, 0.10, 0));
  // Half a second later that part of the person is 0.5 m further on.
  EXPECT_TRUE(seen.saw(0, -2, {2.75, 2.5}, 0.10, 500'000));
  EXPECT_FALSE(seen.saw(0, -2, {2.75, 2.0}, 0.10, 500'000));
  EXPECT_FALSE(seen.saw(0, -3, {2.75, 2.0}, 0.10, 0));  // another mover
  // The scan's picture keeps the person where the laser saw it.
  const geom::Sector ahead{{1.5, 2.0}, 0.0, geom::deg2rad(30), 2.2};
  ASSERT_TRUE(seen.nearestInSector(0, ahead).has_value());
  EXPECT_NEAR(*seen.nearestInSector(0, ahead), 1.25, 1e-6);
  EXPECT_FALSE(seen.nearestInSector(0, geom::Sector{{1.5, 2.0}, geom::kPi, geom::deg2rad(30), 2.2}).has_value());
}

TEST(LaserSeen, WithoutMatchingTruthNothingIsIndexedAndTheKeySaysSo) {
  const auto sc = boxRoom();
  const RunLog full = twoScans(sc);
  Metrics m;
  evalLaserTruth(LaserSeen(full), m);
  EXPECT_EQ(m.number("sensors.laser_truth"), 1.0);
  EXPECT_EQ(m.number("sensors.laser_scans_without_truth"), 0.0);

  const RunLog none = withoutLaserTruth(full);
  const LaserSeen a(none);
  EXPECT_FALSE(a.available());
  EXPECT_EQ(a.scansWithoutTruth(), 2);
  Metrics ma;
  evalLaserTruth(a, ma);
  EXPECT_EQ(ma.number("sensors.laser_truth"), 0.0);

  // A truth of another length than its scan, or of another seq, does not match.
  RunLog bad = full;
  bad.laser_truths[0].obstacle.pop_back();
  bad.laser_truths[1].seq = 9;
  EXPECT_FALSE(LaserSeen(bad).available());
  bad.laser_truths[1].seq = 1;
  const LaserSeen b(bad);
  EXPECT_TRUE(b.available());
  EXPECT_EQ(b.scans(), 1u);
  EXPECT_EQ(b.scansWithoutTruth(), 1);
  Metrics mb;
  evalLaserTruth(b, mb);
  EXPECT_EQ(mb.number("sensors.laser_scans_without_truth"), 1.0);

  // No SIM_STATE: nowhere to place the readings.
  RunLog no_truth_track = full;
  no_truth_track.sim_states.clear();
  EXPECT_FALSE(LaserSeen(no_truth_track).available());
}

TEST(EvalComplement, InvisibleMeansTheComparedScanDidNotSeeTheEcho) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  // Before any scan: unverifiable. After scan A (box seen): redundant, the RM holds the box.
  // After scan B (box dark): complementary, the RM has nothing in the beam.
  addBoxEcho(log, 200'000, complement_reading_t::CLASS_UNVERIFIABLE, 2.2f, 0);
  addBoxEcho(log, 400'000, complement_reading_t::CLASS_REDUNDANT, 0.95f, doneAt(kScanA));
  addBoxEcho(log, 800'000, complement_reading_t::CLASS_COMPLEMENTARY, 2.2f, doneAt(kScanB));
  Metrics m;
  evalComplement(log, EvalOptions{}, m);
  EXPECT_EQ(m.number("complement.samples.invisible"), 1.0);
  EXPECT_DOUBLE_EQ(m.number("complement.invisible_recall"), 1.0);
  // The seen echo is redundant and was dropped; the dark one carried information.
  EXPECT_EQ(m.number("complement.samples.redundant"), 1.0);
  EXPECT_DOUBLE_EQ(m.number("complement.redundant_drop"), 1.0);
  EXPECT_EQ(m.number("complement.samples.informative"), 1.0);
  EXPECT_DOUBLE_EQ(m.number("complement.informative_recall"), 1.0);
  EXPECT_DOUBLE_EQ(m.number("complement.precision"), 1.0);

  // Had the complement kept the seen echo, that is a failed drop, not a found invisible echo.
  RunLog kept = log;
  kept.complements[1].readings[0].cls = complement_reading_t::CLASS_COMPLEMENTARY;
  Metrics k;
  evalComplement(kept, EvalOptions{}, k);
  EXPECT_DOUBLE_EQ(k.number("complement.redundant_drop"), 0.0);
  EXPECT_DOUBLE_EQ(k.number("complement.invisible_recall"), 1.0);

  // The material rule (no LASER_TRUTH): black cardboard is laser-invisible in every firing,
  // including the one before the first scan.
  Metrics f;
  evalComplement(withoutLaserTruth(log), EvalOptions{}, f);
  EXPECT_EQ(f.number("complement.samples.invisible"), 3.0);
  EXPECT_NEAR(f.number("complement.invisible_recall"), 1.0 / 3.0, 1e-12);
  EXPECT_EQ(f.number("complement.samples.redundant"), 0.0);
  EXPECT_FALSE(f.has("complement.redundant_drop"));
  EXPECT_EQ(f.number("complement.samples.informative"), 3.0);
}

TEST(SectorTruthTable, TheBoxIsObservableWhenTheNewestScanSawIt) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  sim::WorldGeometry world(sc);
  const auto truth = trueSectorDistances(world, {1.5, 2, 0}, 0.35, 48, 3.0);
  for (const int64_t t : {int64_t{400'000}, int64_t{800'000}}) {
    sector_map_t sm{};
    sm.utime = t;
    sm.robot_radius = 0.35f;
    sm.max_range = 3.0f;
    sm.nsectors = 48;
    sm.laser_age_s = sm.sonar_age_s = 0.1f;
    for (int k = 0; k < 48; ++k) {
      sm.distance.push_back(static_cast<float>(truth[static_cast<size_t>(k)]));
      sm.laser_distance.push_back(-1);
      sm.sonar_distance.push_back(-1);
      sm.source.push_back(int8_t{sector_map_t::SOURCE_SONAR});
    }
    log.sector_maps.push_back(sm);
  }
  // Sectors 23 and 24 (bearings -7.5..7.5 deg) have their truth on the box's front face.
  const auto table = sectorTruthTable(log, sc, EvalOptions{});
  ASSERT_EQ(table.maps.size(), 2u);
  for (const int k : {23, 24}) {
    EXPECT_EQ(table.materials[static_cast<size_t>(table.mapSamples(0)[k].material)], "black_cardboard");
    EXPECT_TRUE(table.mapSamples(0)[k].observable) << k;   // after scan A
    EXPECT_FALSE(table.mapSamples(1)[k].observable) << k;  // after scan B
  }
  EXPECT_TRUE(table.mapSamples(0)[0].observable);  // the wall behind the robot: seen by both
  EXPECT_TRUE(table.mapSamples(1)[0].observable);
  // The material rule: black cardboard is never observable without an echo; with one before
  // map B that located the face, it is (in both modes).
  const auto fallback = sectorTruthTable(withoutLaserTruth(log), sc, EvalOptions{});
  EXPECT_FALSE(fallback.mapSamples(0)[24].observable);
  EXPECT_FALSE(fallback.mapSamples(1)[24].observable);
  addBoxEcho(log, 600'000);
  EXPECT_TRUE(sectorTruthTable(log, sc, EvalOptions{}).mapSamples(1)[24].observable);
  EXPECT_TRUE(sectorTruthTable(withoutLaserTruth(log), sc, EvalOptions{}).mapSamples(1)[24].observable);
}

namespace {
// An AGM of 60 x 60 cells of 0.1 m from the origin (odometry = truth), one occupied cell on the
// box's front face.
grid_map_t agmAt(int64_t utime) {
  grid_map_t g{};
  g.utime = utime;
  g.robot_pose.x = 1.5;
  g.robot_pose.y = 2;
  g.cell_size = 0.1f;
  g.width = g.height = 60;
  g.gp_threshold = 2;
  g.g.assign(3600, 0);
  g.h.assign(3600, 0);
  g.gp.assign(3600, 0);
  g.gp[static_cast<size_t>(20 * 60 + 27)] = 5;  // cell centre (2.75, 2.05)
  return g;
}
}  // namespace

TEST(EvalAgmOperational, CountsOnlyBoundaryTheNewestScanDidNotSee) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  // Before the first scan, after scan A (box seen), after scan B (box dark).
  log.agm_operational = {agmAt(200'000), agmAt(400'000), agmAt(800'000)};
  Metrics m;
  evalAgmOperational(log, sc, EvalOptions{}, m);
  const double n = m.number("agm_operational.samples.boundary");
  EXPECT_GT(n, 0.0);
  const double recall = m.number("agm_operational.recall");
  EXPECT_GT(recall, 0.5);  // the one cell covers most of the 0.4 m face
  EXPECT_LT(recall, 1.0);
  // Only the map after scan B counts.
  RunLog only_b = log;
  only_b.agm_operational = {agmAt(800'000)};
  Metrics b;
  evalAgmOperational(only_b, sc, EvalOptions{}, b);
  EXPECT_EQ(b.number("agm_operational.samples.boundary"), n);
  // The material rule counts the box's face in all three maps.
  Metrics f;
  evalAgmOperational(withoutLaserTruth(log), sc, EvalOptions{}, f);
  EXPECT_EQ(f.number("agm_operational.samples.boundary"), 3 * n);
  EXPECT_DOUBLE_EQ(f.number("agm_operational.recall"), recall);
}

TEST(LocatedTimes, OnlyTheSonarAloneLocatesAndOnlyWhatItCouldHear) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  addBoxEcho(log, 200'000);  // before any scan
  addBoxEcho(log, 400'000);  // the laser saw the face (scan A)
  addBoxEcho(log, 800'000);  // it did not (scan B)
  const auto pts = staticBoundary(sc);
  const LaserSeen seen(log);
  const auto per_scan = locatedTimes(log, sc, pts, 0.3, &seen, 0.10, 2.2);
  const auto material = locatedTimes(withoutLaserTruth(log), sc, laserInvisibleBoundary(sc), 0.3, nullptr, 0.10, 2.2);
  // The surface the echo answered from: the front face (one side of the box).
  const auto on_front = [&](const BoundaryPoint& b) {
    const sim::Primitive& p = sc.statics[static_cast<size_t>(b.surface)];
    return b.obstacle == kBox && std::abs(p.segment.a.x() - 2.8) < 1e-9 && std::abs(p.segment.b.x() - 2.8) < 1e-9;
  };
  int front = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    // Nothing but the front face: not the walls, not the box's back or sides (their front
    // corners included: an echo locates the surface that answered), which the transducer at
    // (1.85, 2) cannot hear past the front face anyway.
    if (!on_front(pts[i])) {
      EXPECT_EQ(per_scan[i], kNever) << pts[i].p.transpose();
      continue;
    }
    ++front;
    EXPECT_EQ(per_scan[i], 800'000) << pts[i].p.transpose();
  }
  EXPECT_EQ(front, 10);  // 0.4 m at most 5 cm apart
  // The material rule: located by the first echo, before any scan; still only the front face.
  const auto invisible = laserInvisibleBoundary(sc);
  for (size_t i = 0; i < invisible.size(); ++i)
    EXPECT_EQ(material[i], on_front(invisible[i]) ? 200'000 : kNever) << invisible[i].p.transpose();
  // Beyond the hypothetical scan's limit an echo locates nothing (the complement cannot keep it).
  for (const int64_t t : locatedTimes(log, sc, pts, 0.3, &seen, 0.10, 0.9)) EXPECT_EQ(t, kNever);
}

TEST(EvalAgmTactical, LocatedBoundaryCountsWhileTheLaserDoesNotSeeIt) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  addScan(log, sc, 900'000, 2, true);  // scan C: the box seen again (done at 1'099'722 us)
  addBoxEcho(log, 800'000);            // located by the sonar alone, after scan B
  log.agm_tactical = {agmAt(850'000)};
  Metrics one;
  evalAgmTactical(log, sc, EvalOptions{}, one);
  const double n = one.number("agm_tactical.samples.located_boundary");
  EXPECT_EQ(n, 10.0);  // the front face's 10 points, above
  EXPECT_GT(one.number("agm_tactical.invisible_recall"), 0.5);
  // After scan C the laser sees the face again: the Radar Map's, not the tactical AGM's.
  log.agm_tactical.push_back(agmAt(1'200'000));
  Metrics two;
  evalAgmTactical(log, sc, EvalOptions{}, two);
  EXPECT_EQ(two.number("agm_tactical.samples.located_boundary"), n);
  // The material rule keeps counting it.
  Metrics f;
  evalAgmTactical(withoutLaserTruth(log), sc, EvalOptions{}, f);
  EXPECT_EQ(f.number("agm_tactical.samples.located_boundary"), 2 * n);
}

TEST(LocatedTimes, AnEchoTheLaserSawLocatesNothingNearby) {
  // Scan D sees only the middle of the box's face (within 2 deg of the heading: |y - 2| <= 4.5 cm),
  // so the face's ends are not seen; but the echo's own hit point (2.8, 2) was: the echo is
  // redundant and is no evidence of anything only the sonar knows.
  const auto sc = boxRoom();
  RunLog log;
  log.sim_states = standing();
  addScan(log, sc, kScanA, 0, true, 2.0);
  addBoxEcho(log, 400'000);
  const LaserSeen seen(log);
  ASSERT_TRUE(seen.saw(0, kBox, {2.8, 2.0}, 0.10));
  ASSERT_FALSE(seen.saw(0, kBox, {2.8, 2.2}, 0.10));
  for (const int64_t t : locatedTimes(log, sc, staticBoundary(sc), 0.3, &seen, 0.10, 2.2)) EXPECT_EQ(t, kNever);
  // Had it not been seen (no LASER_TRUTH: the material rule), the face is located.
  int located = 0;
  for (const int64_t t : locatedTimes(withoutLaserTruth(log), sc, laserInvisibleBoundary(sc), 0.3, nullptr, 0.10, 2.2))
    located += t == 400'000;
  EXPECT_EQ(located, 10);
}

TEST(LocatedTimes, NotTheBackOfABin) {
  // A black bin (r = 0.2 m) 1.15 m ahead of the transducer at (1.85, 2): its echo at (2.8, 2)
  // comes from the near side. Points within 0.3 m of it reach 97 deg round the circle from the
  // front, but the transducer sees only 80 deg: the rest is hidden behind the bin itself.
  const auto sc = sim::parseScenario(Config::fromString(R"(
name: t
duration_s: 10
seed: 1
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[6,0],[6,4],[0,4]]}
  - {shape: circle, material: black_cardboard, center: [3.0, 2.0], radius: 0.2}
robot: {radius: 0.35, path: [[1.5,2],[2,2]], speed: 0.1}
)"));
  RunLog log;
  log.sim_states = standing();
  addBoxEcho(log, 400'000);
  const auto pts = laserInvisibleBoundary(sc);
  const auto located = locatedTimes(log, sc, pts, 0.3, nullptr, 0.10, 2.2);
  const Vec2 centre(3.0, 2.0), sensor(1.85, 2.0);
  int near_hidden = 0, seen_side = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec2& p = pts[i].p;
    // Angle round the circle from the point facing the transducer; the tangent is at 80 deg (a
    // ray grazing the bin within 3 cm of the point still counts as reaching it: left open).
    const Vec2 u = (p - centre).normalized(), v = (sensor - centre).normalized();
    const double phi = geom::rad2deg(std::acos(std::clamp(u.dot(v), -1.0, 1.0)));
    const bool near = (p - Vec2(2.8, 2.0)).norm() <= 0.3;
    if (!near) {
      EXPECT_EQ(located[i], kNever) << p.transpose();
    } else if (phi < 75) {
      EXPECT_EQ(located[i], 400'000) << p.transpose();
      ++seen_side;
    } else if (phi > 88) {
      EXPECT_EQ(located[i], kNever) << p.transpose();
      ++near_hidden;
    }
  }
  EXPECT_GT(near_hidden, 0);  // there is something to leave out
  EXPECT_GT(seen_side, 4);
}

TEST(EvalTacticalBreakdown, SaysWhyLocatedPointsAreMissed) {
  const auto sc = boxRoom();
  // The one occupied cell (2.75, 2.05) covers the face's points from y = 1.9 up; the two below
  // (y = 1.80, 1.85) are missed, with that cell on the same face 0.21-0.26 m away.
  auto breakdown = [&](const RunLog& log) {
    Metrics m;
    EvalOptions o;
    o.breakdown = true;
    evalTacticalBreakdown(log, sc, LaserSeen(log), o, m);
    return m;
  };
  RunLog never = twoScans(sc);
  addBoxEcho(never, 800'000);  // located, but no SONAR_COMPLEMENT ever classified it
  never.agm_tactical = {agmAt(850'000)};
  const Metrics a = breakdown(never);
  EXPECT_EQ(a.number("agm_tactical.breakdown.missed.samples"), 2.0);
  EXPECT_DOUBLE_EQ(a.number("agm_tactical.breakdown.missed.no_complementary_echo_other"), 1.0);
  EXPECT_DOUBLE_EQ(a.number("agm_tactical.breakdown.recall_by_material.black_cardboard"), 0.8);
  EXPECT_EQ(a.number("agm_tactical.breakdown.samples_by_material.black_cardboard"), 10.0);

  RunLog heard = twoScans(sc);
  addBoxEcho(heard, 800'000, complement_reading_t::CLASS_COMPLEMENTARY);
  heard.agm_tactical = {agmAt(850'000)};
  const Metrics b = breakdown(heard);
  EXPECT_DOUBLE_EQ(b.number("agm_tactical.breakdown.missed.gap_along_surface"), 1.0);
  // With a CURRENT_SENSOR_MAP holding no sonar line: the two points without a cell are `no_cell`,
  // the eight with one were lost in the line generation: one cell is a run shorter than min_cells.
  line_map_t csm{};
  csm.utime = 850'000;
  csm.robot_pose = heard.agm_tactical[0].robot_pose;
  heard.current_sensor_maps = {csm};
  const Metrics l = breakdown(heard);
  EXPECT_EQ(l.number("lines.breakdown.uncovered.samples"), 10.0);
  EXPECT_DOUBLE_EQ(l.number("lines.breakdown.uncovered.no_cell"), 0.2);
  EXPECT_DOUBLE_EQ(l.number("lines.breakdown.uncovered.short_run"), 0.8);
  heard.current_sensor_maps.clear();

  // The same cell below G_T: the eight points near it are below threshold, the two beyond it
  // were located only 50 ms before the map.
  grid_map_t below = agmAt(850'000);
  below.gp[static_cast<size_t>(20 * 60 + 27)] = 1;
  heard.agm_tactical = {below};
  const Metrics c = breakdown(heard);
  EXPECT_EQ(c.number("agm_tactical.breakdown.missed.samples"), 10.0);
  EXPECT_DOUBLE_EQ(c.number("agm_tactical.breakdown.missed.below_threshold"), 0.8);
  EXPECT_DOUBLE_EQ(c.number("agm_tactical.breakdown.missed.located_within_1s"), 0.2);

  // Off by default.
  EXPECT_FALSE(evaluate(heard, sc).has("agm_tactical.breakdown.missed.samples"));
}

// --tactical-samples: one CSV row per breakdown sample, agreeing with the breakdown's shares.
TEST(EvalTacticalBreakdown, SamplesCsvRowPerPointAgreeingWithTheShares) {
  const auto sc = boxRoom();
  RunLog heard = twoScans(sc);
  addBoxEcho(heard, 800'000, complement_reading_t::CLASS_COMPLEMENTARY);
  heard.agm_tactical = {agmAt(850'000)};
  line_map_t csm{};  // no sonar line: every point uncovered
  csm.utime = 850'000;
  csm.robot_pose = heard.agm_tactical[0].robot_pose;
  heard.current_sensor_maps = {csm};
  std::ostringstream csv;
  writeTacticalSampleHeader(csv);
  EvalOptions o;
  o.breakdown = true;
  o.tactical_samples_csv = &csv;
  Metrics m;
  evalTacticalBreakdown(heard, sc, LaserSeen(heard), o, m);
  std::istringstream in(csv.str());
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,x,y,obstacle,material,in_map,agm_cause,line_covered,line_cause");
  int rows = 0, in_map = 0, gap = 0, no_cell = 0, short_run = 0;
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_NE(line.find(",black_cardboard,"), std::string::npos) << line;
    in_map += line.find(",black_cardboard,1,,0,") != std::string::npos;
    gap += line.find(",0,gap_along_surface,0,no_cell") != std::string::npos;
    no_cell += line.size() >= 8 && line.compare(line.size() - 8, 8, ",no_cell") == 0;
    short_run += line.size() >= 10 && line.compare(line.size() - 10, 10, ",short_run") == 0;
  }
  // As the shares say: ten points, eight in the map (their cell a run too short for a line), two
  // missed beside it (a gap along the face).
  EXPECT_EQ(rows, 10);
  EXPECT_EQ(rows, static_cast<int>(m.number("lines.breakdown.uncovered.samples")));
  EXPECT_EQ(in_map, 8);
  EXPECT_EQ(gap, 2);
  EXPECT_DOUBLE_EQ(m.number("agm_tactical.breakdown.missed.gap_along_surface"), 1.0);
  EXPECT_DOUBLE_EQ(no_cell / 10.0, m.number("lines.breakdown.uncovered.no_cell"));
  EXPECT_DOUBLE_EQ(short_run / 10.0, m.number("lines.breakdown.uncovered.short_run"));
  // The time is from the log's first SIM_STATE, as the sector samples'.
  std::istringstream again(csv.str());
  std::getline(again, line);
  std::getline(again, line);
  const double t = std::stod(line.substr(0, line.find(',')));
  EXPECT_NEAR(t, static_cast<double>(850'000 - heard.sim_states.front().utime) * 1e-6, 1e-9);
}

TEST(EvalTacticalBreakdown, RedoesTheLineGenerationWithTheRunsConfig) {
  const auto sc = boxRoom();
  RunLog log = twoScans(sc);
  addBoxEcho(log, 800'000, complement_reading_t::CLASS_COMPLEMENTARY);
  grid_map_t two_cells = agmAt(850'000);
  two_cells.gp[static_cast<size_t>(21 * 60 + 27)] = 5;  // a second cell (2.75, 2.15)
  log.agm_tactical = {two_cells};
  line_map_t csm{};  // no sonar line published
  csm.utime = 850'000;
  csm.robot_pose = log.agm_tactical[0].robot_pose;
  log.current_sensor_maps = {csm};
  auto breakdown = [&](const std::string& yaml) {
    Metrics m;
    EvalOptions o = evalOptions(Config::fromString(yaml));
    o.breakdown = true;
    evalTacticalBreakdown(log, sc, LaserSeen(log), o, m);
    return m;
  };
  // The code's line generation (min_cells 3): a run of two cells makes no line.
  const Metrics paper = breakdown("pilot: {}\n");
  EXPECT_GT(paper.number("lines.breakdown.uncovered.short_run"), 0.5);
  // A run made with min_cells 2 had a line there: the points it misses are not "short_run".
  const Metrics two = breakdown("navigator: {lines: {min_cells: 2}}\n");
  EXPECT_FALSE(two.has("lines.breakdown.uncovered.short_run"));
  EXPECT_GT(two.number("lines.breakdown.uncovered.samples"), 0.0);
  // A bad key is named.
  EXPECT_THROW(evalOptions(Config::fromString("navigator: {lines: {min_cels: 2}}\n")), ConfigError);
}
