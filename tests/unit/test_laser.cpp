// The simulated laser scanner: materials, noise, thin objects, per-reading timing, geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/drivers.hpp"

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

sim_state_t state(int64_t utime, double x, double y, double theta) {
  sim_state_t st;
  st.utime = utime;
  st.robot_pose.x = x;
  st.robot_pose.y = y;
  st.robot_pose.theta = theta;
  st.nmovers = 0;
  return st;
}

// One scan by a robot standing at `pose`.
laser_scan_t scanFrom(LaserDriverCore& laser, const geom::Pose2& pose, int64_t t0 = 1'000'000) {
  EXPECT_TRUE(laser.onSimState(state(t0, pose.x, pose.y, pose.theta)).empty());
  auto scans = laser.onSimState(state(t0 + 200'000, pose.x, pose.y, pose.theta));
  EXPECT_EQ(scans.size(), 1u);
  return scans.at(0);
}

// Index of the reading nearest to a sensor-frame angle.
size_t indexOf(const laser_scan_t& s, double angle) {
  return static_cast<size_t>(std::lround(geom::normalizeAngle(angle - s.angle_min) / s.angle_increment)) %
         static_cast<size_t>(s.nranges);
}

// Copies: gtest takes its arguments by reference, and LCM's class constants have no definition.
constexpr int8_t kOk = laser_scan_t::FLAG_OK;
constexpr int8_t kNoReturn = laser_scan_t::FLAG_NO_RETURN;

LaserConfig noiseless() {
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

TEST(Laser, GlassAndMeshAreInvisible) {
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

TEST(Laser, BlackCardboardGivesNoReturn) {
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"
      "  - {shape: box, material: black_cardboard, center: [2, 0], size: [0.3, 0.5]}\n");
  LaserDriverCore laser(sc, noiseless(), 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  // The box absorbs the laser and hides the wall behind it.
  EXPECT_EQ(s.flags[indexOf(s, 0)], kNoReturn);
  EXPECT_EQ(s.flags[indexOf(s, deg2rad(10))], kOk);
}

TEST(Laser, ThinPipeIsMissedBetweenRays) {
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
    scans.insert(scans.end(), out.begin(), out.end());
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
    next.insert(next.end(), out.begin(), out.end());
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
  EXPECT_EQ(scans[0].flags[360], kOk);
  EXPECT_NEAR(scans[0].ranges[360], 1.75, 1e-5);
}

TEST(Laser, A270DegreeScannerWorks) {
  const Scenario sc = world(
      "  - {shape: segment, material: wall, from: [3, -1], to: [3, 1]}\n"
      "  - {shape: segment, material: wall, from: [-2, -1], to: [-2, 1]}\n");
  const LaserConfig c = laserConfig(Config::fromString("fov_deg: 270\nreadings: 541\nnoise_std: 0\n"));
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

TEST(Laser, MountPoseFromConfig) {
  // Sensor 0.2 m ahead of the robot's centre, looking to the robot's left.
  const Scenario sc = world("  - {shape: segment, material: wall, from: [-5, 3], to: [5, 3]}\n");
  const LaserConfig c =
      laserConfig(Config::fromString("noise_std: 0\nmount: {x: 0.2, y: 0.5, yaw_deg: 90}\n"));
  LaserDriverCore laser(sc, c, 1);
  const laser_scan_t s = scanFrom(laser, {0, 0, 0});
  EXPECT_NEAR(s.mount.theta, deg2rad(90), 1e-12);
  EXPECT_NEAR(s.ranges[indexOf(s, 0)], 2.5, 1e-5);
}

TEST(Laser, ConfigErrorsNameTheKey) {
  auto message = [](const std::string& yaml) {
    try {
      laserConfig(Config::fromString("laser:\n" + yaml, "cfg.yaml").section("laser"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("  fov_deg: 400\n"), "cfg.yaml: laser.fov_deg: must be in [1, 360]");
  EXPECT_NE(message("  colour: red\n").find("cfg.yaml: laser.colour: unknown key"), std::string::npos);
  EXPECT_NE(message("  mount: {z: 1}\n").find("laser.mount.z: unknown key"), std::string::npos);
  EXPECT_NE(message("  range_max: 0.01\n").find("laser.range_max: range_max must be > range_min"), std::string::npos);
}

TEST(Laser, RefusesBadStatesAndCarriesOn) {
  LaserDriverCore laser(world("  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n"), noiseless(), 1);
  EXPECT_TRUE(laser.onSimState(state(1'000'000, 0, 0, 0)).empty());
  EXPECT_THROW(laser.onSimState(state(900'000, 0, 0, 0)), std::invalid_argument);   // backwards
  EXPECT_THROW(laser.onSimState(state(1'000'000, 0, 0, 0)), std::invalid_argument); // repeated
  EXPECT_THROW(laser.onSimState(state(1'100'000, std::nan(""), 0, 0)), std::invalid_argument);
  const auto scans = laser.onSimState(state(1'200'000, 0, 0, 0));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_NEAR(scans[0].ranges[360], 3.0, 1e-5);
}

TEST(Laser, SameSeedSameScan) {
  const Scenario sc = world("  - {shape: segment, material: wall, from: [3, -10], to: [3, 10]}\n");
  LaserDriverCore a(sc, LaserConfig{}, 7), b(sc, LaserConfig{}, 7), c(sc, LaserConfig{}, 8);
  const laser_scan_t sa = scanFrom(a, {0, 0, 0}), sb = scanFrom(b, {0, 0, 0}), scc = scanFrom(c, {0, 0, 0});
  EXPECT_EQ(sa.ranges, sb.ranges);
  EXPECT_NE(sa.ranges, scc.ranges);
}
