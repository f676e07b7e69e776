// The simulated laser scanner: materials, noise, thin objects, per-reading timing, geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/drivers.hpp"
#include "sim_state_fixture.hpp"

using namespace lasonic;
using namespace lasonic::sim;
using geom::deg2rad;

namespace {

Scenario parse(const std::string& yaml) { return parseScenario(Config::fromString(yaml, "test.yaml")); }

// A scenario whose only obstacles are `obstacles` (YAML list items); the robot's path is unused
// because the tests feed SIM_STATE by hand.
Scenario world(const std::string& obstacles) {
  return parse("name: t\nobstacles:\n" + obstacles + "robot: {path: [[0,0],[1,0]]}\n");
}

using lasonic::testing::state;

// One scan (and its LASER_TRUTH) by a robot standing at `pose`.
LaserDriverCore::Output scanAndTruthFrom(LaserDriverCore& laser, const geom::Pose2& pose, int64_t t0 = 1'000'000) {
  EXPECT_TRUE(laser.onSimState(state(t0, pose.x, pose.y, pose.theta)).empty());
  auto scans = laser.onSimState(state(t0 + 200'000, pose.x, pose.y, pose.theta));
  EXPECT_EQ(scans.size(), 1u);
  return scans.at(0);
}
laser_scan_t scanFrom(LaserDriverCore& laser, const geom::Pose2& pose, int64_t t0 = 1'000'000) {
  return scanAndTruthFrom(laser, pose, t0).scan;
}

// Index of the reading nearest to a sensor-frame angle.
size_t indexOf(const laser_scan_t& s, double angle) {
  double a = std::fmod(angle - s.angle_min, 2 * geom::kPi);  // [0, 2 pi): the scan starts at angle_min
  if (a < 0) a += 2 * geom::kPi;
  return static_cast<size_t>(std::lround(a / s.angle_increment)) % static_cast<size_t>(s.nranges);
}

// Copies: gtest takes its arguments by reference, and LCM's class constants have no definition.
constexpr int8_t kOk = laser_scan_t::FLAG_OK;
constexpr int8_t kNoReturn = laser_scan_t::FLAG_NO_RETURN;

// The ideal profile (one ray per reading, materials as reflect / transparent / absorb), noise-free.
LaserConfig noiseless() {
  LaserConfig c;
  c.profile = SensorProfile::Ideal;
  c.noise_std = 0;
  return c;
}

// The error a `laser:` section (YAML lines under it) gives, or "no error".
std::string configMessage(const std::string& yaml) {
  try {
    laserConfig(Config::fromString("laser:\n" + yaml, "cfg.yaml").section("laser"));
  } catch (const ConfigError& e) {
    return std::string(e.what());
  }
  return std::string("no error");
}

// The physical profile, noise-free.
LaserConfig physical() {
  LaserConfig c;
  c.noise_std = 0;
  return c;
}

}  // namespace

TEST(Laser, MobotDefaults) {
  LaserDriverCore laser(world(""), LaserConfig{}, 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  EXPECT_EQ(s.nranges, 720);
  EXPECT_NEAR(s.angle_increment, deg2rad(0.5), 1e-12);
  EXPECT_NEAR(s.angle_min, -geom::kPi, 1e-12);
  // Nothing within range: no return anywhere.
  for (int8_t f : s.flags) EXPECT_EQ(f, kNoReturn);
}

TEST(Laser, WallAtKnownDistanceWithinNoise) {
  // A wall 3 m ahead, 20 m long.
  const Scenario sc = world("  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n");
  LaserDriverCore laser(sc, LaserConfig{}, 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int i = 0; i < s.nranges; ++i) {
    const double a = s.angle_min + i * s.angle_increment;
    if (std::abs(a) > deg2rad(60)) continue;
    ASSERT_EQ(s.flags[i], kOk) << i;
    const double err = s.ranges[i] - 3.0 / std::cos(a);
    sum += err;
    sum2 += err * err;
    ++n;
  }
  const double mean = sum / n, std = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.003);   // 241 readings of 1 cm noise: the mean is within 3 mm
  EXPECT_NEAR(std, 0.01, 0.002);
  // Facing away from the wall: nothing.
  EXPECT_EQ(s.flags[indexOf(s, geom::kPi)], kNoReturn);
}

TEST(Laser, IdealGlassAndMeshAreInvisible) {
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"
      "  - {shape: segment, material: glass, from: [1, -1], to: [1, 1]}\n"
      "  - {shape: segment, material: mesh, from: [2, -1], to: [2, 1]}\n");
  LaserDriverCore laser(sc, noiseless(), 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  const size_t ahead = indexOf(s, 0);
  EXPECT_EQ(s.flags[ahead], kOk);
  EXPECT_NEAR(s.ranges[ahead], 3.0, 1e-5);  // straight through glass and mesh to the wall
}

TEST(Laser, IdealBlackCardboardGivesNoReturn) {
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"
      "  - {shape: box, material: black_cardboard, center: [2, 0], size: [0.3, 0.5]}\n");
  LaserDriverCore laser(sc, noiseless(), 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  // The box absorbs the laser and hides the wall behind it.
  EXPECT_EQ(s.flags[indexOf(s, 0)], kNoReturn);
  EXPECT_EQ(s.flags[indexOf(s, deg2rad(10))], kOk);
}

TEST(Laser, IdealThinPipeIsMissedBetweenRays) {
  // A 2 cm pipe spans 0.23 deg at 5 m: with rays 0.5 deg apart, a scan sees it only if a ray
  // happens to fall on it (p = 0.23 / 0.5 = 0.46); at 1 m it spans 1.15 deg and is always seen.
  auto seenFraction = [](double distance) {
    const Scenario sc = world("  - {shape: circle, material: plastic, center: [" + std::to_string(distance) +
                              ", 0], radius: 0.01}\n");
    LaserDriverCore laser(sc, noiseless(), 1);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> heading(-0.1, 0.1);
    int seen = 0;
    const int scans = 400;
    for (int k = 0; k < scans; ++k) {
      // Each scan from a slightly different heading; consecutive scans 1 s apart (a fresh start).
      const int64_t t0 = 1'000'000 + k * 1'000'000;
      const laser_scan_t s = scanFrom(laser, {0, 0, heading(rng)}, t0);
      for (int8_t f : s.flags) seen += f == kOk ? 1 : 0;
    }
    return static_cast<double>(seen) / scans;
  };
  const double far = seenFraction(5.0);
  EXPECT_GT(far, 0.36);
  EXPECT_LT(far, 0.56);  // most scans miss it
  EXPECT_GE(seenFraction(1.0), 1.0);
}

TEST(Laser, ReadingsAreSpreadOverTheScanAndPlacedWithTheirOwnPose) {
  // The robot drives towards a wall 5 m ahead at 1 m/s; the reading straight ahead is taken
  // half-way through the scan, when the robot is 0.1 m further on.
  const Scenario sc = world("  - {shape: segment, material: wall, from: [5, -10], to: [5, 10]}\n");
  LaserDriverCore laser(sc, noiseless(), 1);
  const int64_t t0 = 1'000'000;
  std::vector<laser_scan_t> scans;
  for (int k = 0; k <= 10; ++k) {
    auto out = laser.onSimState(state(t0 + k * 20'000, 0.02 * k, 0, 0));
    // Emitted only once the truth has reached its last reading (at 199.7 ms).
    if (k < 10) {
      EXPECT_TRUE(out.empty()) << k;
    }
    for (auto& o : out) scans.push_back(o.scan);
  }
  ASSERT_EQ(scans.size(), 1u);
  const laser_scan_t& s = scans[0];
  EXPECT_EQ(s.utime, t0);
  ASSERT_EQ(s.offset_us.size(), 720u);
  EXPECT_EQ(s.offset_us[0], 0);
  EXPECT_EQ(s.offset_us[360], 100'000);
  EXPECT_EQ(s.offset_us[719], 199'722);
  for (size_t i = 1; i < s.offset_us.size(); ++i) EXPECT_GE(s.offset_us[i], s.offset_us[i - 1]);
  EXPECT_NEAR(s.ranges[360], 4.9, 1e-5);  // angle 0 at t0 + 100 ms, robot at x = 0.1
  // The next scan starts where this one ended.
  std::vector<laser_scan_t> next;
  for (int k = 11; k <= 20; ++k) {
    auto out = laser.onSimState(state(t0 + k * 20'000, 0.02 * k, 0, 0));
    for (auto& o : out) next.push_back(o.scan);
  }
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].utime, t0 + 200'000);
  EXPECT_EQ(next[0].seq, 1);
}

TEST(Laser, MoversAreInterpolatedPerReading) {
  Scenario sc = parse(
      "name: t\nmovers:\n  - {radius: 0.25, path: [[2, -5], [2, 5]]}\nrobot: {path: [[0,0],[1,0]]}\n");
  LaserDriverCore laser(sc, noiseless(), 1);
  auto withMover = [](int64_t u, double my) {
    sim_state_t st = state(u, 0, 0, 0);
    mover_state_t m;
    m.id = 0;
    m.x = 2;
    m.y = my;
    m.radius = 0.25;
    st.movers = {m};
    st.nmovers = 1;
    return st;
  };
  // The person crosses in front of the robot: at y = -1 at the scan's start, y = +1 at its end,
  // so at the time of the reading straight ahead (half-way) they stand right in front.
  EXPECT_TRUE(laser.onSimState(withMover(1'000'000, -1)).empty());
  const auto scans = laser.onSimState(withMover(1'200'000, 1));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(scans[0].scan.flags[360], kOk);
  EXPECT_NEAR(scans[0].scan.ranges[360], 1.75, 1e-5);
  EXPECT_EQ(scans[0].truth.obstacle[360], -2);  // LASER_TRUTH: mover 0
}

TEST(Laser, A270DegreeScannerWorks) {
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -1], to: [3, 1]}\n"
      "  - {shape: segment, material: wall, from: [-2, -1], to: [-2, 1]}\n");
  const LaserConfig c = laserConfig(Config::fromString("profile: ideal\nfov_deg: 270\nreadings: 541\nnoise_std: 0\n"));
  LaserDriverCore laser(sc, c, 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  EXPECT_EQ(s.nranges, 541);
  EXPECT_NEAR(s.angle_min, deg2rad(-135), 1e-12);
  EXPECT_NEAR(s.angle_increment, deg2rad(0.5), 1e-12);
  EXPECT_NEAR(s.angle_min + 540 * s.angle_increment, deg2rad(135), 1e-12);
  EXPECT_NEAR(s.ranges[270], 3.0, 1e-5);  // straight ahead
  // The wall behind is in the blind 90 deg: never seen.
  for (int i = 0; i < s.nranges; ++i) {
    if (s.flags[i] == kOk) {
      EXPECT_LT(std::abs(s.angle_min + i * s.angle_increment), deg2rad(45));
    }
  }
}

// `sweep: clockwise` (a scanner mounted upside down): the same 270 deg, swept from +135 deg down,
// angle_increment < 0, the readings' times still rising with the index. Standing still, the
// reading at each direction is the counter-clockwise scanner's.
TEST(Laser, AClockwiseScannerSweepsFromTheLeftEdgeDown) {
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -1], to: [3, 2]}\n"
      "  - {shape: segment, material: wall, from: [-1, 1.5], to: [2, 1.5]}\n");
  const std::string keys = "profile: ideal\nfov_deg: 270\nreadings: 541\nnoise_std: 0\n";
  LaserDriverCore ccw_laser(sc, laserConfig(Config::fromString(keys)), 1);
  LaserDriverCore cw_laser(sc, laserConfig(Config::fromString(keys + "sweep: clockwise\n")), 1);
  const laser_scan_t ccw = scanFrom(ccw_laser, {0, 0, 0}), cw = scanFrom(cw_laser, {0, 0, 0});
  ASSERT_EQ(cw.nranges, 541);
  EXPECT_NEAR(cw.angle_min, deg2rad(135), 1e-12);
  EXPECT_NEAR(cw.angle_increment, -deg2rad(0.5), 1e-12);
  EXPECT_EQ(cw.offset_us, ccw.offset_us);  // reading 0 first, whichever way it turns
  int seen = 0;
  for (int i = 0; i < cw.nranges; ++i) {
    const auto j = static_cast<size_t>(cw.nranges - 1 - i);  // the same direction, counter-clockwise
    EXPECT_NEAR(cw.angle_min + i * cw.angle_increment, ccw.angle_min + static_cast<double>(j) * ccw.angle_increment,
                1e-12);
    EXPECT_EQ(cw.flags[static_cast<size_t>(i)], ccw.flags[j]) << i;
    EXPECT_NEAR(cw.ranges[static_cast<size_t>(i)], ccw.ranges[j], 1e-5) << i;
    seen += cw.flags[static_cast<size_t>(i)] == kOk;
  }
  EXPECT_GT(seen, 200);
  EXPECT_NEAR(cw.ranges[270], 3.0, 1e-5);  // straight ahead
  EXPECT_NEAR(cw.ranges[90], 1.5, 1e-5);   // 90 deg to the left: the first readings
  const std::string bad_sweep = configMessage("  sweep: sideways\n");
  EXPECT_NE(bad_sweep.find("cfg.yaml: laser.sweep: must be one of counterclockwise, clockwise"), std::string::npos)
      << bad_sweep;
}

TEST(Laser, MountPoseFromConfig) {
  // Sensor 0.2 m ahead of the robot's centre, looking to the robot's left.
  const Scenario sc = world("  - {shape: segment, material: wall, from: [-5, 3], to: [5, 3]}\n");
  const LaserConfig c =
      laserConfig(Config::fromString("profile: ideal\nnoise_std: 0\nmount: {x: 0.2, y: 0.5, yaw_deg: 90}\n"));
  LaserDriverCore laser(sc, c, 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  EXPECT_NEAR(s.mount.theta, deg2rad(90), 1e-12);
  EXPECT_NEAR(s.ranges[indexOf(s, 0)], 2.5, 1e-5);
}

TEST(Laser, ConfigErrorsNameTheKey) {
  EXPECT_EQ(configMessage("  fov_deg: 400\n"), "cfg.yaml: laser.fov_deg: must be in [1, 360]");
  EXPECT_NE(configMessage("  colour: red\n").find("cfg.yaml: laser.colour: unknown key"), std::string::npos);
  EXPECT_NE(configMessage("  mount: {z: 1}\n").find("laser.mount.z: unknown key"), std::string::npos);
  // On the robot's body: a mount 1e300 m out was accepted (and refused downstream).
  EXPECT_NE(configMessage("  mount: {x: 1e300}\n").find("laser.mount.x: must be in [-5, 5]"), std::string::npos);
  EXPECT_NE(configMessage("  mount: {y: -5.5}\n").find("laser.mount.y: must be in [-5, 5]"), std::string::npos);
  EXPECT_NE(configMessage("  range_max: 0.01\n").find("laser.range_max: range_max (0.01) must be > range_min ("), std::string::npos);
}

TEST(Laser, RefusesBadStatesAndCarriesOn) {
  LaserDriverCore laser(world("  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"), noiseless(), 1);
  EXPECT_TRUE(laser.onSimState(state(1'000'000, 0, 0, 0)).empty());
  EXPECT_THROW(laser.onSimState(state(900'000, 0, 0, 0)), std::invalid_argument);   // backwards
  EXPECT_THROW(laser.onSimState(state(1'000'000, 0, 0, 0)), std::invalid_argument); // repeated
  EXPECT_THROW(laser.onSimState(state(1'100'000, std::nan(""), 0, 0)), std::invalid_argument);
  const auto scans = laser.onSimState(state(1'200'000, 0, 0, 0));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_NEAR(scans[0].scan.ranges[360], 3.0, 1e-5);
}

TEST(Laser, SameSeedSameScan) {
  const Scenario sc = world("  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n");
  LaserDriverCore a(sc, LaserConfig{}, 7), b(sc, LaserConfig{}, 7), c(sc, LaserConfig{}, 8);
  const laser_scan_t sa = scanFrom(a, {0, 0, 0}), sb = scanFrom(b, {0, 0, 0}), scc = scanFrom(c, {0, 0, 0});
  EXPECT_EQ(sa.ranges, sb.ranges);
  EXPECT_NE(sa.ranges, scc.ranges);
}

// ------------------------------------------------------------------ physical profile

TEST(LaserPhysical, GlassReturnsOnlyNearNormalIncidence) {
  // A pane 1.5 m ahead, a wall 3 m ahead behind it. Head-on, the pane's Fresnel reflection comes
  // straight back; a few degrees off normal, the beam passes through to the wall.
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"
      "  - {shape: segment, material: glass, from: [1.5, -3], to: [1.5, 3]}\n");
  LaserDriverCore laser(sc, physical(), 1);
  const auto out = scanAndTruthFrom(laser, {0, 0, 0});
  const laser_scan_t& s = out.scan;
  const size_t ahead = indexOf(s, 0);
  ASSERT_EQ(s.flags[ahead], kOk);
  EXPECT_NEAR(s.ranges[ahead], 1.5, 0.01);
  EXPECT_EQ(out.truth.obstacle[ahead], 1);  // the pane
  for (double deg : {-1.0, 1.0}) {  // within the 2° cone
    const size_t i = indexOf(s, deg2rad(deg));
    EXPECT_NEAR(s.ranges[i], 1.5 / std::cos(deg2rad(deg)), 0.01) << deg;
  }
  for (double deg : {-10.0, -5.0, 5.0, 10.0, 30.0}) {
    const size_t i = indexOf(s, deg2rad(deg));
    ASSERT_EQ(s.flags[i], kOk) << deg;
    EXPECT_NEAR(s.ranges[i], 3.0 / std::cos(deg2rad(deg)), 0.01) << deg;  // through the pane
    EXPECT_EQ(out.truth.obstacle[i], 0) << deg;
  }
  // The ideal profile never sees glass.
  LaserDriverCore ideal(sc, noiseless(), 1);
  EXPECT_NEAR(scanFrom(ideal, {0, 0, 0}).ranges[ahead], 3.0, 1e-5);
}

// A scanner on a host whose clock runs ahead of the odometry's: LASER_SCAN and LASER_TRUTH
// carry that clock's time, the ranges are those of the true reading times (README "Clocks").
TEST(LaserDriver, ClockOffsetStampsTheScanNotTheReadings) {
  const Scenario s = world("  - {shape: segment, material: wall, from: [2,-3], to: [2,3]}\n");
  LaserConfig behind = noiseless();
  behind.clock_offset_s = -0.02;
  LaserDriverCore synced(s, noiseless(), 1), late(s, behind, 1);
  const LaserDriverCore::Output a = scanAndTruthFrom(synced, {0, 0, 0});
  const LaserDriverCore::Output b = scanAndTruthFrom(late, {0, 0, 0});
  EXPECT_EQ(b.scan.utime, a.scan.utime - 20'000);
  EXPECT_EQ(b.truth.utime, b.scan.utime);
  EXPECT_EQ(b.scan.ranges, a.scan.ranges);
  EXPECT_EQ(configMessage("  clock_offset_s: 0.01\n"), "no error");
  EXPECT_NE(configMessage("  clock_offset_s: -4000\n").find("clock_offset_s"), std::string::npos);
}

TEST(LaserPhysical, DarkSurfacesDropOutWithRange) {
  // Black cardboard (remission 3 %) faces the scanner; with a 10 % target detected to 5 m it is
  // seen to 5 * sqrt(0.3) = 2.7 m head-on; white plaster (85 %) far beyond.
  auto seen = [](const std::string& material, double distance) {
    const Scenario sc = world("  - {shape: segment, material: " + material + ", from: [" + std::to_string(distance) +
                              ", -0.5], to: [" + std::to_string(distance) + ", 0.5]}\n");
    LaserDriverCore laser(sc, physical(), 3);
    int ok = 0, n = 0;
    for (int k = 0; k < 20; ++k) {
      const laser_scan_t s = scanFrom(laser, {0, 0, 0}, 1'000'000 + k * 1'000'000);
      for (double deg = -2; deg <= 2; deg += 0.5, ++n) ok += s.flags[indexOf(s, deg2rad(deg))] == kOk;
    }
    return static_cast<double>(ok) / n;
  };
  EXPECT_GT(seen("black_cardboard", 1.0), 0.99);
  EXPECT_GT(seen("black_cardboard", 2.2), 0.9);
  EXPECT_LT(seen("black_cardboard", 3.4), 0.1);
  EXPECT_GT(seen("wall", 3.4), 0.99);
  EXPECT_GT(seen("wall", 12.0), 0.9);
}

TEST(LaserPhysical, ThinPipeHitRateFallsWithRange) {
  // A 2 cm pipe before a wall 1 m behind it. The beam's 0.6° footprint is wider than the 0.5°
  // spacing: the pipe is hit whenever it covers enough of some reading's footprint; far away it
  // covers too little and returns too little power, and what returns mixes with the wall.
  auto hitRate = [](double d) {
    const Scenario sc = world("  - {shape: circle, material: plastic, center: [" + std::to_string(d) +
                              ", 0], radius: 0.01}\n  - {shape: segment, material: wall, from: [" +
                              std::to_string(d + 1) + ", -5], to: [" + std::to_string(d + 1) + ", 5]}\n");
    LaserDriverCore laser(sc, physical(), 5);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> heading(-0.1, 0.1);
    int hits = 0;
    const int scans = 100;
    for (int k = 0; k < scans; ++k) {
      const auto out = scanAndTruthFrom(laser, {0, 0, heading(rng)}, 1'000'000 + k * 1'000'000);
      bool hit = false;
      for (size_t i = 0; i < out.truth.obstacle.size(); ++i)
        hit = hit || (out.truth.obstacle[i] == 0 && out.scan.flags[i] == kOk && std::abs(out.scan.ranges[i] - (d - 0.01)) < 0.05);
      hits += hit;
    }
    return static_cast<double>(hits) / scans;
  };
  const double r1 = hitRate(1.0), r3 = hitRate(3.0), r6 = hitRate(6.0), r9 = hitRate(9.0);
  EXPECT_GT(r1, 0.99);  // 1.15° wide: always covers a footprint
  EXPECT_GE(r1, r3);
  EXPECT_GE(r3, r6);
  EXPECT_GE(r6, r9);
  EXPECT_GT(r1 - r9, 0.5) << r1 << " " << r3 << " " << r6 << " " << r9;
  EXPECT_LT(r9, 0.3);
}

TEST(LaserPhysical, EdgesGiveMixedPixels) {
  // A wall's end 2 m ahead with another wall 0.3 m behind it: the two returns of a footprint
  // that straddles the end overlap (within merge_range) and read in between, nobody's surface
  // in LASER_TRUTH. With the second wall 2 m behind, the returns stay apart and the nearer wins.
  auto scanEdge = [](double behind, int& mixed, int& between) {
    const Scenario sc = world("  - {shape: segment, material: wall, from: [2, -3], to: [2, 0]}\n"
                              "  - {shape: segment, material: wall, from: [" + std::to_string(2 + behind) +
                              ", -5], to: [" + std::to_string(2 + behind) + ", 5]}\n");
    LaserConfig c = physical();
    c.footprint_rays = 11;
    LaserDriverCore laser(sc, c, 1);
    mixed = between = 0;
    for (int k = 0; k < 20; ++k) {
      const auto out = scanAndTruthFrom(laser, {0, 0, deg2rad(0.05 * k)}, 1'000'000 + k * 1'000'000);
      for (size_t i = 0; i < out.truth.obstacle.size(); ++i) {
        if (out.scan.flags[i] != kOk) continue;
        mixed += out.truth.obstacle[i] == -1;
        const double a = out.scan.angle_min + static_cast<double>(i) * out.scan.angle_increment + deg2rad(0.05 * k);
        if (std::abs(a) < deg2rad(5)) between += out.scan.ranges[i] > 2.02 && out.scan.ranges[i] < 1.98 + behind;
      }
    }
  };
  int mixed = 0, between = 0;
  scanEdge(0.3, mixed, between);
  EXPECT_GE(mixed, 10);  // about one per scan
  EXPECT_GE(between, 10);
  scanEdge(2.0, mixed, between);
  EXPECT_EQ(mixed, 0);
  EXPECT_EQ(between, 0);
  // The ideal profile's one ray never mixes.
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [2, -3], to: [2, 0]}\n"
      "  - {shape: segment, material: wall, from: [2.3, -5], to: [2.3, 5]}\n");
  LaserDriverCore ideal(sc, noiseless(), 1);
  const auto out = scanAndTruthFrom(ideal, {0, 0, 0});
  for (size_t i = 0; i < out.truth.obstacle.size(); ++i)
    if (out.scan.flags[i] == kOk) {
      EXPECT_GE(out.truth.obstacle[i], 0);
    }
}

TEST(LaserPhysical, ProfileAndKeysFromConfig) {
  EXPECT_EQ(laserConfig(Config()).profile, SensorProfile::Physical);
  const LaserConfig c = laserConfig(Config::fromString(
      "profile: ideal\nrange_10pct_m: 8\nbeam_divergence_deg: 0.3\nbeam_diameter_m: 0.02\nfootprint_rays: 3\n"
      "merge_range_m: 0.2\n"));
  EXPECT_EQ(c.profile, SensorProfile::Ideal);
  EXPECT_DOUBLE_EQ(c.range_10pct, 8);
  EXPECT_NEAR(c.beam_divergence, deg2rad(0.3), 1e-12);
  EXPECT_DOUBLE_EQ(c.beam_diameter, 0.02);
  EXPECT_EQ(c.footprint_rays, 3);
  EXPECT_DOUBLE_EQ(c.merge_range, 0.2);
  EXPECT_NE(configMessage("  profile: real\n").find("cfg.yaml: laser.profile: must be one of physical, ideal"), std::string::npos);
  EXPECT_NE(configMessage("  range_10pct_m: 0\n").find("laser.range_10pct_m: must be > 0"), std::string::npos);
  EXPECT_NE(configMessage("  footprint_rays: 0\n").find("laser.footprint_rays: must be in [1, 100]"), std::string::npos);
}

TEST(LaserPhysical, MeshStaysTransparentEvenHeadOn) {
  // A transparent material without a specular cone (a mesh) never returns the beam, not even
  // exactly at normal incidence.
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"
      "  - {shape: segment, material: mesh, from: [1, -1], to: [1, 1]}\n");
  LaserConfig c = physical();
  c.footprint_rays = 1;
  c.beam_diameter = 0;
  LaserDriverCore laser(sc, c, 1);
  const auto out = scanAndTruthFrom(laser, {0, 0, 0});
  const size_t ahead = indexOf(out.scan, 0);
  EXPECT_NEAR(out.scan.ranges[ahead], 3.0, 1e-5);
  EXPECT_EQ(out.truth.obstacle[ahead], 0);
}
