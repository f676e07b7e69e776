// The simulated sonar: beam model against hand-built worlds, fault rates, firing schedule,
// determinism and config errors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "sim/drivers.hpp"
#include "sim/sonar_model.hpp"
#include "sim_state_fixture.hpp"

using namespace lasonic;
using namespace lasonic::sim;
using geom::deg2rad;

namespace {

// LCM declares the CAUSE_* constants without defining them: copies that tests may bind to.
constexpr int8_t kDirect = sonar_cause_t::CAUSE_DIRECT;
constexpr int8_t kSpecularLong = sonar_cause_t::CAUSE_SPECULAR_LONG;
constexpr int8_t kNoEcho = sonar_cause_t::CAUSE_NO_ECHO;
constexpr int8_t kCrosstalk = sonar_cause_t::CAUSE_CROSSTALK;
constexpr int8_t kForeign = sonar_cause_t::CAUSE_FOREIGN;

// A scenario around the origin; `body` adds obstacles/movers/sonar keys to the YAML.
Scenario scenario(const std::string& body) {
  return parseScenario(Config::fromString("name: t\nseed: 11\nrobot: {path: [[0,0],[1,0]]}\n" + body, "t.yaml"));
}

// No noise, no misreadings: the beam model alone.
SonarConfig clean(double multipath_prob = 0) {
  SonarConfig c = sonarConfig(Config());
  c.noise_std = c.noise_rel = 0;
  c.crosstalk_prob = c.foreign_prob = 0;
  c.multipath_prob = multipath_prob;
  return c;
}

SonarReading fireOnce(const Scenario& s, const SonarConfig& c, const geom::Pose2& sensor, uint64_t seed = 1) {
  WorldGeometry w(s);
  std::mt19937_64 rng(seed);
  return fireSensor(w, sensor, deg2rad(30), c, rng);
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

using lasonic::testing::state;

std::vector<uint8_t> bytes(const sonar_ring_t& r, const sonar_truth_t& t) {
  std::vector<uint8_t> b(static_cast<size_t>(r.getEncodedSize() + t.getEncodedSize()));
  r.encode(b.data(), 0, r.getEncodedSize());
  t.encode(b.data(), r.getEncodedSize(), t.getEncodedSize());
  return b;
}

// A 4 m x 4 m room of rough walls around the origin.
const char* kRoom = "obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[-2,-2],[2,-2],[2,2],[-2,2]]}\n";

}  // namespace

TEST(SonarModel, GlassFacedHeadOnEchoesAtItsRange) {
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: glass, from: [2,-1], to: [2,1]}\n");
  EXPECT_EQ(s.material("glass").laser, LaserBehaviour::Transparent);  // the laser misses it
  const SonarReading r = fireOnce(s, clean(), {0, 0, 0});
  EXPECT_FALSE(r.no_echo);
  EXPECT_EQ(r.truth.cause, kDirect);
  EXPECT_NEAR(r.range, 2.0, 1e-6);
  EXPECT_NEAR(r.truth.true_range, 2.0, 1e-6);
  EXPECT_EQ(r.truth.obstacle, 0);
  EXPECT_EQ(r.truth.laser_visible, 0);
  EXPECT_EQ(r.truth.nearest_laser_visible, -1);  // nothing the laser sees in the ideal beam
}

TEST(SonarModel, NearestLaserVisibleLooksThroughGlassWithinTheIdealBeam) {
  const Scenario s = scenario(
      "obstacles:\n"
      "  - {shape: segment, material: glass, from: [1,-1], to: [1,1]}\n"
      "  - {shape: segment, material: wall, from: [2,-1], to: [2,1]}\n");
  const SonarReading r = fireOnce(s, clean(), {0, 0, 0});
  EXPECT_EQ(r.truth.cause, kDirect);
  EXPECT_NEAR(r.range, 1.0, 1e-6);
  EXPECT_NEAR(r.truth.nearest_laser_visible, 2.0, 1e-6);
  // The wall beyond the ideal beam's 2.20 m is not counted.
  const SonarReading far = fireOnce(s, clean(), {-0.5, 0, 0});
  EXPECT_EQ(far.truth.nearest_laser_visible, -1);
}

// A wall at 45° through (2,0): the beam's axis mirrors off it towards +y.
std::string wall45(const std::string& material) {
  return "  - {shape: segment, material: " + material + ", from: [0,-2], to: [4,2]}\n";
}

TEST(SonarModel, SmoothMetalAt45DegreesGivesNoDirectEcho) {
  const Scenario s = scenario("obstacles:\n" + wall45("metal"));
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const SonarReading r = fireOnce(s, clean(0.5), {0, 0, 0}, seed);
    EXPECT_EQ(r.truth.cause, kNoEcho);  // the mirrored sound meets nothing
    EXPECT_TRUE(r.no_echo);
  }
}

TEST(SonarModel, SpecularMultipathReadsTooLong) {
  // A rough wall above the mirror point, outside the direct beam, returns the mirrored sound.
  const Scenario s = scenario("obstacles:\n" + wall45("metal") +
                              "  - {shape: segment, material: wall, from: [1.5,1], to: [2.5,1]}\n"
                              "sonar: {}\n");
  SonarConfig c = clean(1.0);
  c.range_max = 5;
  c.group_period_s = 0.05;
  const SonarReading r = fireOnce(s, c, {0, 0, 0});
  EXPECT_EQ(r.truth.cause, kSpecularLong);
  EXPECT_FALSE(r.no_echo);
  EXPECT_GT(r.range, 2.0);       // longer than the true distance along the axis
  EXPECT_NEAR(r.range, 3.0, 0.2);  // d1 + d2 along the axis: 2 + 1
  EXPECT_EQ(r.truth.true_range, -1);
  EXPECT_EQ(r.truth.obstacle, 0);  // the mirror
  // Without multipath the same firing hears nothing.
  EXPECT_EQ(fireOnce(s, clean(0.0), {0, 0, 0}).truth.cause, kNoEcho);
  // One mirror is all this path needs: the single-mirror model gives the same reading.
  c.multipath_bounces = 1;
  const SonarReading one = fireOnce(s, c, {0, 0, 0});
  EXPECT_EQ(one.truth.cause, kSpecularLong);
  EXPECT_EQ(one.range, r.range);
  EXPECT_EQ(one.truth.obstacle, 0);
}

// Two parallel metal walls 1 m apart (y = +-0.5) ending at a rough wall across x = 2.7; the
// sensor between them faces 45°, so every ray meets the metal at 30°..60° (beyond 12°): no
// direct echo, and every ray needs at least two reflections to reach the end wall.
const char* kMetalCorridor =
    "obstacles:\n"
    "  - {shape: segment, material: metal, from: [-1,0.5], to: [2.7,0.5]}\n"
    "  - {shape: segment, material: metal, from: [-1,-0.5], to: [2.7,-0.5]}\n"
    "  - {shape: segment, material: wall, from: [2.7,-0.5], to: [2.7,0.5]}\n";

TEST(SonarModel, MultipathFollowsSeveralSpecularBounces) {
  const Scenario s = scenario(kMetalCorridor);
  SonarConfig c = clean(1.0);
  c.range_max = 5;
  c.group_period_s = 0.05;
  const geom::Pose2 sensor{0, 0, deg2rad(45)};
  c.multipath_bounces = 3;
  const SonarReading r = fireOnce(s, c, sensor);
  EXPECT_EQ(r.truth.cause, kSpecularLong);
  EXPECT_FALSE(r.no_echo);
  // The -15° edge ray (30°) reaches the end wall after two reflections (at x = 0.87, 2.60),
  // meeting it at 30° (a rough wall echoes up to 60°): one-way path 2.7 / cos 30°.
  EXPECT_NEAR(r.range, 2.7 / std::cos(deg2rad(30)), 0.01);
  EXPECT_GT(r.range, 2.0 * 0.5 / std::sin(deg2rad(60)));  // far beyond the nearest wall in the beam
  EXPECT_EQ(r.truth.true_range, -1);
  EXPECT_TRUE(r.truth.obstacle == 0 || r.truth.obstacle == 1);  // a metal wall: the first mirror
  EXPECT_EQ(r.truth.laser_visible, 1);
  // A single mirror (the old model) never reaches the end wall: no echo.
  c.multipath_bounces = 1;
  EXPECT_EQ(fireOnce(s, c, sensor).truth.cause, kNoEcho);
  c.multipath_bounces = 0;
  EXPECT_EQ(fireOnce(s, c, sensor).truth.cause, kNoEcho);
  // Two reflections suffice for the edge ray.
  c.multipath_bounces = 2;
  EXPECT_NEAR(fireOnce(s, c, sensor).range, 2.7 / std::cos(deg2rad(30)), 0.01);
}

TEST(SonarModel, MultipathBeyondRangeMaxIsNoEcho) {
  // Same corridor, default range_max 3 m: the shortest bounced path (3.12 m) is out of range.
  const Scenario s = scenario(kMetalCorridor);
  SonarConfig c = clean(1.0);
  ASSERT_EQ(c.multipath_bounces, 3);  // the default
  ASSERT_DOUBLE_EQ(c.range_max, 3.0);
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const SonarReading r = fireOnce(s, c, {0, 0, deg2rad(45)}, seed);
    EXPECT_EQ(r.truth.cause, kNoEcho);
    EXPECT_TRUE(r.no_echo);
  }
}

TEST(SonarModel, MetalCornerReturnsTheSoundToTheSensor) {
  // Two metal walls meeting at (2,2); the sensor faces the corner obliquely (45.1°: no ray hits
  // the vertex itself). No ray meets either wall within 12°, but the ray nearest the corner
  // comes back after two reflections (a corner reflector), from within the beam: the reading is
  // the distance to the corner, too long against the walls 2.31 m away at the beam's edges.
  const Scenario s = scenario(
      "obstacles:\n"
      "  - {shape: segment, material: metal, from: [2,-3], to: [2,2]}\n"
      "  - {shape: segment, material: metal, from: [-3,2], to: [2,2]}\n");
  SonarConfig c = clean(1.0);
  const geom::Pose2 sensor{0, 0, deg2rad(45.1)};
  const SonarReading r = fireOnce(s, c, sensor);
  EXPECT_EQ(r.truth.cause, kSpecularLong);
  EXPECT_NEAR(r.range, 2.0 * std::sqrt(2.0), 0.01);
  EXPECT_GT(r.range, 2.0 / std::cos(deg2rad(30)) + 0.3);
  // One reflection cannot bring the sound back: the single-mirror model hears nothing.
  c.multipath_bounces = 1;
  EXPECT_EQ(fireOnce(s, c, sensor).truth.cause, kNoEcho);
}

TEST(SonarModel, RoughWallAt45DegreesEchoesFromTheBeamEdge) {
  const Scenario s = scenario("obstacles:\n" + wall45("wall"));
  const SonarReading r = fireOnce(s, clean(), {0, 0, 0});
  EXPECT_EQ(r.truth.cause, kDirect);
  // Nearest point inside the beam: the -15° edge ray, 2 / (cos 15° + sin 15°).
  EXPECT_NEAR(r.range, 2.0 / (std::cos(deg2rad(15)) + std::sin(deg2rad(15))), 1e-6);
  EXPECT_EQ(r.truth.laser_visible, 1);
}

TEST(SonarModel, ThinPipeIsHeardAnywhereInTheBeam) {
  for (double bearing_deg = -14; bearing_deg <= 14; bearing_deg += 0.7) {
    for (double dist : {0.8, 1.7, 2.9}) {
      const double a = deg2rad(bearing_deg);
      const Scenario s = scenario("obstacles:\n  - {shape: circle, material: plastic, center: [" +
                                  std::to_string(dist * std::cos(a)) + "," + std::to_string(dist * std::sin(a)) +
                                  "], radius: 0.02}\n");
      const SonarReading r = fireOnce(s, clean(), {0, 0, 0});
      EXPECT_EQ(r.truth.cause, kDirect) << bearing_deg << "° " << dist << " m";
      EXPECT_NEAR(r.range, dist - 0.02, 0.01);
    }
  }
}

TEST(SonarModel, EchoProbabilityIsDrawnPerObstacleNotPerRay) {
  // A person (echo_prob 0.8) fills the beam: per-ray draws would almost always hear it.
  const Scenario s = scenario(
      "movers:\n  - {radius: 0.4, material: person, speed: 0.5, path: [[1.5,0],[3,0]]}\n");
  WorldGeometry w(s);
  w.setMovers({{0, {1.5, 0}, 0.4}});
  std::mt19937_64 rng(5);
  const int n = 4000;
  int heard = 0;
  for (int i = 0; i < n; ++i) {
    const SonarReading r = fireSensor(w, {0, 0, 0}, deg2rad(30), clean(), rng);
    if (r.truth.cause == kDirect) {
      ++heard;
      EXPECT_EQ(r.truth.obstacle, -2);  // mover 0
    }
  }
  EXPECT_NEAR(static_cast<double>(heard) / n, 0.8, 0.03);
}

TEST(SonarModel, CrosstalkAndForeignRatesMatchConfigAndReadTooShort) {
  const Scenario s = scenario(kRoom);
  // Few rays: the rates do not depend on the beam's sampling, and 20000 firings stay fast under ASan.
  SonarConfig c = sonarConfig(Config::fromString("crosstalk_prob: 0.05\nforeign_prob: 0.03\nrays_per_beam: 5\n"));
  WorldGeometry w(s);
  std::mt19937_64 rng(9);
  const int n = 20000;
  int crosstalk = 0, foreign = 0;
  for (int i = 0; i < n; ++i) {
    const SonarReading r = fireSensor(w, {0, 0, deg2rad(i * 7.0)}, deg2rad(30), c, rng);
    const bool misread = r.truth.cause == kCrosstalk || r.truth.cause == kForeign;
    crosstalk += r.truth.cause == kCrosstalk;
    foreign += r.truth.cause == kForeign;
    if (misread) {
      ASSERT_FALSE(r.no_echo);
      EXPECT_GE(r.range, c.range_min);
      // Too short: below the echo it replaced (plus that echo's noise allowance).
      if (r.truth.true_range > 0) {
        EXPECT_LE(r.range, r.truth.true_range * 1.05 + 0.05);
      }
    }
  }
  EXPECT_NEAR(static_cast<double>(crosstalk) / n, 0.05, 0.01);
  EXPECT_NEAR(static_cast<double>(foreign) / n, 0.03, 0.01);
}

TEST(SonarModel, RangeNoiseHasTheConfiguredSpread) {
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [2,-1], to: [2,1]}\n");
  SonarConfig c = clean();
  c.noise_std = 0.01;
  c.noise_rel = 0.01;  // sd = 0.01 + 0.02 = 0.03 at 2 m
  c.rays_per_beam = 5;  // the axis ray meets the wall at 2 m head-on either way
  WorldGeometry w(s);
  std::mt19937_64 rng(3);
  double sum = 0, sum2 = 0;
  const int n = 5000;
  for (int i = 0; i < n; ++i) {
    const double e = fireSensor(w, {0, 0, 0}, deg2rad(30), c, rng).range - 2.0;
    sum += e;
    sum2 += e * e;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.003);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.03, 0.003);
}

TEST(SonarDriver, FiresGroupsInOrderEveryGroupPeriod) {
  const Scenario s = scenario(kRoom);
  const SonarConfig c = sonarConfig(Config::fromString("group_jitter_s: 0"));
  SonarDriverCore core(s, c, s.seed);
  std::vector<SonarDriverCore::Output> all;
  const int64_t t0 = 1'000'000;
  // Sent once the listening window has closed: 2 * 3.0 m / 343 m/s after the firing, with the
  // first state at or after that.
  const auto window_us = std::llround(2 * 3.0 / 343.0 * 1e6);
  EXPECT_DOUBLE_EQ(c.sendDelay(), 2 * 3.0 / 343.0);
  for (int64_t t = t0; t <= t0 + 1'000'000; t += 20'000)
    for (auto& o : core.onSimState(state(t))) {
      EXPECT_GE(t - o.ring.utime, window_us);         // not before its echoes could be in
      EXPECT_LT(t - o.ring.utime, window_us + 20'000);  // and with the first state after that
      all.push_back(o);
    }
  ASSERT_EQ(all.size(), 33u);  // firings at t0 + k*30 ms, k = 0..32 (k = 33 is due after t0 + 1 s)
  const auto ring = ringSensors(24, 0.35, deg2rad(30), 6);
  for (size_t k = 0; k < all.size(); ++k) {
    const sonar_ring_t& r = all[k].ring;
    const sonar_truth_t& t = all[k].truth;
    EXPECT_EQ(r.utime, t0 + static_cast<int64_t>(k) * 30'000);
    EXPECT_EQ(r.seq, static_cast<int32_t>(k));
    EXPECT_EQ(r.group, static_cast<int16_t>(k % 6));
    EXPECT_EQ(r.num_sensors, 24);
    EXPECT_FLOAT_EQ(r.range_max, 3.0f);
    ASSERT_EQ(r.nreadings, 4);
    EXPECT_EQ(t.utime, r.utime);
    EXPECT_EQ(t.seq, r.seq);
    EXPECT_EQ(t.group, r.group);
    ASSERT_EQ(t.nreadings, 4);
    for (int i = 0; i < 4; ++i) {
      const int id = static_cast<int>(k % 6) + 6 * i;  // 4 sensors 90° apart
      EXPECT_EQ(r.sensor_id[i], id);
      EXPECT_EQ(t.causes[i].sensor_id, id);
      EXPECT_NEAR(r.mount[i].theta, ring[id].mount.theta, 1e-9);
      EXPECT_NEAR(std::hypot(r.mount[i].x, r.mount[i].y), 0.35, 1e-9);
      EXPECT_FLOAT_EQ(r.beam_width[i], static_cast<float>(deg2rad(30)));
    }
  }
  // The group period leaves time for an echo from range_max to come back.
  EXPECT_GE(c.group_period_s, timeOfFlight(c.range_max));
}

TEST(SonarDriver, FiresWithTheTruthInterpolatedToTheFiringTime) {
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [3,-2], to: [3,2]}\n");
  SonarConfig c = sonarConfig(Config::fromString("ring: {groups: 1}\nnoise_std: 0\nnoise_rel: 0\n"
                                                 "crosstalk_prob: 0\nforeign_prob: 0\ngroup_jitter_s: 0\n"
                                                 "send_delay_s: 0\n"));
  SonarDriverCore core(s, c, 1);
  core.onSimState(state(1'000'000, 0.0));
  const auto out = core.onSimState(state(1'100'000, 1.0));  // 10 m/s, to make the point
  ASSERT_EQ(out.size(), 3u);                                  // at 30, 60, 90 ms
  for (size_t k = 0; k < out.size(); ++k) {
    const double x = 0.3 * static_cast<double>(k + 1);
    ASSERT_EQ(out[k].ring.sensor_id[0], 0);  // facing +x, mounted 0.35 m ahead of the centre
    // (A strong echo crosses the physical model's threshold less than a millimetre late.)
    EXPECT_NEAR(out[k].ring.range[0], 3.0 - x - 0.35, 1e-3);
  }
}

// A sonar on a host whose clock runs ahead of the odometry's: the messages carry that clock's
// time, the readings are those of the true firing time (README "Clocks").
TEST(SonarDriver, ClockOffsetStampsTheMessagesNotTheFiring) {
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [3,-2], to: [3,2]}\n");
  const std::string keys = "ring: {groups: 1}\nnoise_std: 0\nnoise_rel: 0\ncrosstalk_prob: 0\nforeign_prob: 0\n"
                           "group_jitter_s: 0\n";
  SonarDriverCore synced(s, sonarConfig(Config::fromString(keys)), 1);
  SonarDriverCore ahead(s, sonarConfig(Config::fromString(keys + "clock_offset_s: 0.05\n")), 1);
  for (SonarDriverCore* core : {&synced, &ahead}) core->onSimState(state(1'000'000, 0.0));
  const auto a = synced.onSimState(state(1'100'000, 1.0));
  const auto b = ahead.onSimState(state(1'100'000, 1.0));
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), a.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(b[k].ring.utime, a[k].ring.utime + 50'000);
    EXPECT_EQ(b[k].truth.utime, b[k].ring.utime);  // the truth still joins its reading
    EXPECT_EQ(b[k].ring.range[0], a[k].ring.range[0]);
  }
  EXPECT_EQ(ahead.geometry(1'000'000).utime, 1'050'000);
  EXPECT_THROW(sonarConfig(Config::fromString("clock_offset_s: 7200\n")), ConfigError);
}

// A driver sends a group once its listening window has closed: later than the firing, with the
// same readings and the firing's time in the message (README "Sensor models").
TEST(SonarDriver, SendsAGroupAfterItsListeningWindow) {
  const Scenario s = scenario("obstacles:\n  - {shape: segment, material: wall, from: [3,-2], to: [3,2]}\n");
  const std::string keys = "ring: {groups: 1}\nnoise_std: 0\nnoise_rel: 0\ncrosstalk_prob: 0\nforeign_prob: 0\n"
                           "group_jitter_s: 0\n";
  SonarDriverCore at_firing(s, sonarConfig(Config::fromString(keys + "send_delay_s: 0\n")), 1);
  SonarDriverCore after(s, sonarConfig(Config::fromString(keys + "send_delay_s: 0.025\n")), 1);
  std::vector<std::pair<int64_t, SonarDriverCore::Output>> a, b;  // (state time it came with, output)
  for (int64_t t = 1'000'000; t <= 1'200'000; t += 10'000) {
    for (auto& o : at_firing.onSimState(state(t, 1e-6 * static_cast<double>(t - 1'000'000)))) a.emplace_back(t, o);
    for (auto& o : after.onSimState(state(t, 1e-6 * static_cast<double>(t - 1'000'000)))) b.emplace_back(t, o);
  }
  ASSERT_EQ(a.size(), 7u);  // fired at 1.00, 1.03, ..., 1.18 s
  ASSERT_EQ(b.size(), 6u);  // the one fired at 1.18 s is due at 1.205 s
  for (size_t k = 0; k < b.size(); ++k) {
    EXPECT_EQ(a[k].first, a[k].second.ring.utime);  // with the state that fired it
    EXPECT_EQ(b[k].second.ring.utime, a[k].second.ring.utime);  // stamped with the firing
    EXPECT_EQ(b[k].second.truth.utime, b[k].second.ring.utime);
    EXPECT_EQ(b[k].first, (b[k].second.ring.utime + 25'000 + 9'999) / 10'000 * 10'000);  // first state >= due
    EXPECT_EQ(b[k].second.ring.range[0], a[k].second.ring.range[0]);  // read at the firing
  }
  // The default is the listening window of the ring's range_max; a bad value names the key.
  EXPECT_DOUBLE_EQ(sonarConfig(Config::fromString("range_max: 5")).sendDelay(), 10.0 / 343.0);
  EXPECT_THROW(sonarConfig(Config::fromString("send_delay_s: -1\n")), ConfigError);
}

TEST(SonarDriver, SameSeedGivesIdenticalReadings) {
  const Scenario s = scenario(std::string(kRoom) +
                              "  - {shape: segment, material: metal, from: [0.5,1], to: [1.5,0.2]}\n"
                              "movers:\n  - {radius: 0.25, material: person, speed: 0.5, path: [[-1,1],[1,1]]}\n");
  const SonarConfig c = sonarConfig(Config::fromString("crosstalk_prob: 0.1\nforeign_prob: 0.1\n"));
  auto run = [&](uint64_t seed) {
    SonarDriverCore core(s, c, seed);
    std::vector<uint8_t> all;
    for (int64_t k = 0; k < 100; ++k) {
      sim_state_t st = state(1'000'000 + k * 20'000, 0.01 * static_cast<double>(k), 0, 0.02 * static_cast<double>(k));
      st.movers.push_back({0, -1 + 0.01 * static_cast<double>(k), 1, 0.25});
      st.nmovers = 1;
      for (auto& o : core.onSimState(st)) {
        const auto b = bytes(o.ring, o.truth);
        all.insert(all.end(), b.begin(), b.end());
      }
    }
    return all;
  };
  const auto a = run(7);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, run(7));
  EXPECT_NE(a, run(8));
}

TEST(SonarDriver, IrregularPioneerRingWorks) {
  // Pioneer 2/3: 8 front and 8 rear transducers; front i and rear i fire together.
  const Config cfg = Config::fromString(R"(
sonar:
  range_max: 2.5
  sensors:
    - {x: 0.069, y: 0.136, theta_deg: 90, beam_deg: 25, group: 0}
    - {x: 0.114, y: 0.119, theta_deg: 50, beam_deg: 25, group: 1}
    - {x: 0.148, y: 0.078, theta_deg: 30, beam_deg: 25, group: 2}
    - {x: 0.166, y: 0.027, theta_deg: 10, beam_deg: 25, group: 3}
    - {x: 0.166, y: -0.027, theta_deg: -10, beam_deg: 25, group: 4}
    - {x: 0.148, y: -0.078, theta_deg: -30, beam_deg: 25, group: 5}
    - {x: 0.114, y: -0.119, theta_deg: -50, beam_deg: 25, group: 6}
    - {x: 0.069, y: -0.136, theta_deg: -90, beam_deg: 25, group: 7}
    - {x: -0.157, y: -0.136, theta_deg: -90, beam_deg: 25, group: 0}
    - {x: -0.203, y: -0.119, theta_deg: -130, beam_deg: 25, group: 1}
    - {x: -0.237, y: -0.078, theta_deg: -150, beam_deg: 25, group: 2}
    - {x: -0.255, y: -0.027, theta_deg: -170, beam_deg: 25, group: 3}
    - {x: -0.255, y: 0.027, theta_deg: 170, beam_deg: 25, group: 4}
    - {x: -0.237, y: 0.078, theta_deg: 150, beam_deg: 25, group: 5}
    - {x: -0.203, y: 0.119, theta_deg: 130, beam_deg: 25, group: 6}
    - {x: -0.157, y: 0.136, theta_deg: 90, beam_deg: 25, group: 7}
)");
  const SonarConfig c = sonarConfig(cfg.section("sonar"));
  ASSERT_EQ(c.sensors.size(), 16u);
  const Scenario s = scenario(kRoom);
  SonarDriverCore core(s, c, 1);
  const sonar_geometry_t g = core.geometry(5);
  EXPECT_EQ(g.num_sensors, 16);
  EXPECT_EQ(g.num_groups, 8);
  EXPECT_NEAR(g.mount[1].theta, deg2rad(50), 1e-9);
  EXPECT_EQ(g.group_of[9], 1);
  EXPECT_FLOAT_EQ(g.range_max, 2.5f);
  int firings = 0;
  for (int64_t t = 1'000'000; t < 1'500'000; t += 20'000)
    for (const auto& o : core.onSimState(state(t))) {
      ASSERT_EQ(o.ring.nreadings, 2);
      EXPECT_EQ(o.ring.num_sensors, 16);
      EXPECT_EQ(o.ring.sensor_id[0], o.ring.group);
      EXPECT_EQ(o.ring.sensor_id[1], o.ring.group + 8);
      EXPECT_FLOAT_EQ(o.ring.beam_width[0], static_cast<float>(deg2rad(25)));
      ++firings;
    }
  EXPECT_GT(firings, 10);
}

TEST(SonarDriver, ScenarioOverridesLayerOverTheFileConfig) {
  const SonarConfig file = sonarConfig(Config::fromString("ring: {count: 16, groups: 4}\nnoise_std: 0.05\n"));
  const Scenario s = scenario("sonar: {noise_std: 0.02, crosstalk_prob: 0.1}\n");
  const SonarConfig c = sonarConfig(s.sonar, file);
  EXPECT_EQ(c.sensors.size(), 16u);
  EXPECT_DOUBLE_EQ(c.noise_std, 0.02);
  EXPECT_DOUBLE_EQ(c.crosstalk_prob, 0.1);
  EXPECT_EQ(firingGroups(c.sensors)[1], (std::vector<int>{1, 5, 9, 13}));
}

TEST(SonarDriver, RefusesBadSimStates) {
  const Scenario s = scenario(kRoom);
  SonarDriverCore core(s, sonarConfig(Config::fromString("group_jitter_s: 0\nsend_delay_s: 0")), 1);
  core.onSimState(state(2'000'000));
  EXPECT_THROW(core.onSimState(state(1'000'000)), std::invalid_argument);  // backwards
  EXPECT_THROW(core.onSimState(state(2'000'000)), std::invalid_argument);  // repeated
  EXPECT_THROW(core.onSimState(state(2'100'000, std::nan(""))), std::invalid_argument);
  sim_state_t ghost = state(2'100'000);
  ghost.movers.push_back({3, 0, 0, 0.2});
  ghost.nmovers = 1;
  EXPECT_THROW(core.onSimState(ghost), std::invalid_argument);  // no mover 3 in the scenario
  // Still working, and nothing was skipped: firings resume at 2.03 s.
  const auto out = core.onSimState(state(2'100'000));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].ring.utime, 2'030'000);
  EXPECT_EQ(out[0].ring.seq, 1);
}

TEST(SonarConfigErrors, NameTheKey) {
  auto err = [](const std::string& yaml) {
    return errorOf([&] { sonarConfig(Config::fromString(yaml, "c.yaml").section("sonar")); });
  };
  EXPECT_NE(err("sonar: {rangemax: 2}").find("sonar.rangemax: unknown key"), std::string::npos);
  EXPECT_NE(err("sonar: {range_max: -1}").find("sonar.range_max: must be > 0"), std::string::npos);
  EXPECT_NE(err("sonar: {multipath_bounces: 11}").find("sonar.multipath_bounces: must be in [0, 10]"),
            std::string::npos);
  EXPECT_EQ(err("sonar: {multipath_bounces: 0}"), "");
  EXPECT_EQ(sonarConfig(Config::fromString("multipath_bounces: 5")).multipath_bounces, 5);
  EXPECT_NE(err("sonar: {crosstalk_prob: 1.5}").find("sonar.crosstalk_prob: must be in [0, 1]"), std::string::npos);
  EXPECT_NE(err("sonar: {ring: {count: 0}}").find("sonar.ring.count"), std::string::npos);
  EXPECT_NE(err("sonar: {ring: {count: 4, groups: 6}}").find("sonar.ring.groups"), std::string::npos);
  EXPECT_NE(err("sonar: {ring: {beams: 4}}").find("sonar.ring.beams: unknown key"), std::string::npos);
  EXPECT_NE(err("sonar: {sensors: [{x: 0, y: 0, theta_deg: 0, group: 0, beam: 30}]}").find("sonar.sensors[0].beam: unknown key"),
            std::string::npos);
  EXPECT_NE(err("sonar: {sensors: [{x: 0, y: 0, theta_deg: 0}]}").find("sonar.sensors[0].group: is required"),
            std::string::npos);
  EXPECT_NE(err("sonar: {sensors: [{x: 0, y: 0, theta_deg: 0, group: 1}]}").find("firing group 0 has no sensor"),
            std::string::npos);
  EXPECT_NE(err("sonar: {sensors: []}").find("sonar.sensors: needs at least one sensor"), std::string::npos);
  EXPECT_NE(err("sonar: {ring: {}, sensors: []}").find("sonar.sensors: give either ring or sensors"), std::string::npos);
  EXPECT_NE(err("sonar: {range_max: 6}").find("sonar.range_max: group_period_s ("), std::string::npos);
  EXPECT_NE(err("sonar: {range_min: 3}").find("sonar.range_min: range_min (3) must be < range_max ("), std::string::npos);
  EXPECT_EQ(err("sonar: {range_max: 5, group_period_s: 0.04}"), "");
  // Physical bounds: transducers on the robot's body, a ring one SONAR_RING can carry, a group
  // period whose microseconds cannot overflow (1e13 s fired the ring 502 times in 2 s).
  EXPECT_NE(err("sonar: {ring: {radius: 1e300}}").find("sonar.ring.radius: must be in [0, 5]"), std::string::npos);
  EXPECT_NE(err("sonar: {sensors: [{x: 1e300, y: 0, theta_deg: 0, group: 0}]}").find("sonar.sensors[0].x: must be in [-5, 5]"),
            std::string::npos);
  EXPECT_NE(err("sonar: {sensors: [{x: 0, y: -6, theta_deg: 0, group: 0}]}").find("sonar.sensors[0].y: must be in [-5, 5]"),
            std::string::npos);
  EXPECT_NE(err("sonar: {group_period_s: 1e13}").find("sonar.group_period_s: must be in (0, 60]"), std::string::npos);
  std::string many = "sonar: {sensors: [";
  for (int i = 0; i < 1025; ++i) many += std::string(i ? ", " : "") + "{x: 0, y: 0, theta_deg: 0, group: 0}";
  EXPECT_NE(err(many + "]}").find("sonar.sensors: has 1025 sensors: at most 1024"), std::string::npos);
  // A scenario's override is named by its own path.
  const std::string e = errorOf([] { sonarConfig(scenario("sonar: {noise_std: -1}\n").sonar); });
  EXPECT_NE(e.find("t.yaml: sonar.noise_std: must be >= 0"), std::string::npos) << e;
}
