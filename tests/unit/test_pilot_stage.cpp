// PilotStage on memq://: message flow, published values, output rates and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>

#include <lasonic/grid_map_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "stages/pilot_stage.hpp"

using namespace lasonic;

namespace {

constexpr double kPi = geom::kPi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Copies: gtest takes its arguments by reference, which the generated static consts cannot bind.
constexpr int8_t kNone = sector_map_t::SOURCE_NONE, kLaser = sector_map_t::SOURCE_LASER,
                 kSonar = sector_map_t::SOURCE_SONAR, kCopied = sector_map_t::SOURCE_SONAR_COPIED;
constexpr int8_t kNoReturn = laser_scan_t::FLAG_NO_RETURN;

// A scan of n readings over period_us, none of which returned.
laser_scan_t noReturnScan(int64_t utime, double angle_min, double angle_increment, int n, int period_us) {
  laser_scan_t s{};
  s.utime = utime;
  s.angle_min = angle_min;
  s.angle_increment = angle_increment;
  s.range_min = 0.05f;
  s.range_max = 15.0f;
  for (int i = 0; i < n; ++i) {
    s.ranges.push_back(0.0f);
    s.flags.push_back(kNoReturn);
    s.offset_us.push_back(i * period_us / n);
  }
  return s;
}

// The fixture's pilot puts a cell's obstacle at its point nearest the robot (the paper's cell
// geometry), so the expected distances below are exact cell boundaries.
PilotConfig nearestPointPilot() {
  PilotConfig c;
  c.sector_map.sonar_cell_point = CellPoint::Nearest;
  return c;
}

// Handles every message waiting on a memq:// node.
void drainAll(Node& node) {
  while (node.spinOnce(0) > 0) {
  }
}

// The robot stands at (1, 2) facing `theta` from `from` to `to` [us]: one ODOMETRY every 20 ms.
void standStill(Node& node, int64_t from, int64_t to, double theta = 0.0) {
  for (int64_t t = from; t <= to; t += 20'000) {
    odometry_t o{};
    o.utime = t;
    o.pose = {1.0, 2.0, theta};
    node.publish(channels::ODOMETRY, o);
  }
}

struct PilotFixture : ::testing::Test {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotStage stage;
  std::vector<sector_map_t> maps;
  std::vector<grid_map_t> grids;

  explicit PilotFixture(const PilotConfig& config = nearestPointPilot()) : stage(node, config) {
    node.subscribe<sector_map_t>(channels::SECTOR_MAP, [this](const sector_map_t& m) { maps.push_back(m); });
    node.subscribe<grid_map_t>(channels::AGM_OPERATIONAL, [this](const grid_map_t& m) { grids.push_back(m); });
  }
  void drain() { drainAll(node); }
  // The robot stands at (1, 2) facing +x, from 0 to 2 s.
  void odometry(double theta = 0.0) {
    standStill(node, 0, 2'000'000, theta);
    drain();
  }
  // 360 deg scan of 720 readings over 0.2 s with one return: 1.0 m to the robot's left.
  void laserScan(int64_t utime) {
    laser_scan_t s = noReturnScan(utime, -kPi, 2 * kPi / 720, 720, 200'000);
    s.ranges[540] = 1.0f;  // angle -pi + 540 * 0.5 deg = +90 deg
    s.flags[540] = laser_scan_t::FLAG_OK;
    node.publish(channels::LASER_SCAN, s);
    drain();
  }
  static complement_reading_t reading(int8_t cls, double x, double y) {
    complement_reading_t r{};
    r.cls = cls;
    r.range = 1.0f;
    r.hypothetical_range = 2.2f;
    r.end_x = x;
    r.end_y = y;
    r.beam_width = 0.5236f;  // 30 deg
    return r;
  }
  // One firing group with one complementary echo 1 m ahead (global (2.05, 2.05)).
  void complement(int64_t utime, std::vector<complement_reading_t> extra = {}) {
    complement_t c{};
    c.utime = utime;
    c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, 2.05, 2.05));
    c.readings.push_back(reading(complement_reading_t::CLASS_FALSE, 0.0, 5.0));  // never accumulated
    for (auto& r : extra) c.readings.push_back(r);
    node.publish(channels::SONAR_COMPLEMENT, c);
    drain();
  }
};

}  // namespace

// A 2 Hz scanner (a scan every 0.5 s, its readings over the 0.5 s): the laser is stale after two
// of its own scan periods, timed from its scans, not after the 0.4 s that are two of a 5 Hz one.
// The dark continuation's gaps are in the LaserScan's order: a clockwise scan's reversed.
TEST(PilotStage, NoReturnMaskFollowsTheLaserScansOrder) {
  laser_scan_t m;
  m.nranges = 4;
  m.ranges = {0.f, 1.f, 1.f, 1.f};
  m.flags = {laser_scan_t::FLAG_NO_RETURN, laser_scan_t::FLAG_OK, laser_scan_t::FLAG_OK, laser_scan_t::FLAG_OK};
  m.offset_us = {0, 100, 200, 300};
  m.angle_increment = 0.1;
  std::vector<uint8_t> mask;
  noReturnMask(m, mask);
  EXPECT_EQ(mask, (std::vector<uint8_t>{1, 0, 0, 0}));
  m.angle_increment = -0.1;  // reading 0 is the LaserScan's last
  noReturnMask(m, mask);
  EXPECT_EQ(mask, (std::vector<uint8_t>{0, 0, 0, 1}));
}

TEST(PilotStage, TheLaserIsStaleAfterTwoOfItsOwnScanPeriods) {
  const auto staleAfter = [](const PilotConfig& cfg, int64_t age_us) {
    Node node{"t", "memq://", Node::Options{false, false}};
    PilotStage stage(node, cfg);
    std::vector<sector_map_t> maps;
    node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&](const sector_map_t& m) { maps.push_back(m); });
    standStill(node, 0, 6'000'000);
    drainAll(node);
    for (int64_t t = 0; t <= 3'000'000; t += 500'000) {
      laser_scan_t s = noReturnScan(t, -kPi, 2 * kPi / 720, 720, 500'000);
      s.ranges[540] = 1.0f;
      s.flags[540] = laser_scan_t::FLAG_OK;
      node.publish(channels::LASER_SCAN, s);
      drainAll(node);
    }
    const int64_t newest = 3'000'000 + 719 * 500'000 / 720;  // the last scan's last reading
    complement_t c{};
    c.utime = newest + age_us;
    node.publish(channels::SONAR_COMPLEMENT, c);
    drainAll(node);
    EXPECT_FALSE(maps.empty());
    return maps.empty() || maps.back().laser_stale != 0;
  };
  const PilotConfig shipped = pilotConfig(Config{});
  EXPECT_DOUBLE_EQ(shipped.laser_stale_scans, 2);
  EXPECT_FALSE(staleAfter(shipped, 450'000));   // 0.45 s: within 1.0 s
  EXPECT_TRUE(staleAfter(shipped, 1'050'000));  // beyond it
  PilotConfig seconds = shipped;
  seconds.laser_stale_scans = 0;
  EXPECT_TRUE(staleAfter(seconds, 450'000));    // the 0.4 s of laser_stale_s
}

TEST_F(PilotFixture, LaserThenSonarMapsAndAgmRate) {
  odometry();
  laserScan(100'000);
  ASSERT_EQ(maps.size(), 1u);
  const int left = 36, ahead = 24;
  {
    const sector_map_t& m = maps.back();
    EXPECT_EQ(m.nsectors, 48);
    EXPECT_GE(m.utime, 299'000);  // the scan's last reading
    EXPECT_NEAR(m.laser_distance[left], 0.65, 1e-5);
    EXPECT_EQ(m.source[left], kLaser);
    EXPECT_EQ(m.laser_stale, 0);
    EXPECT_EQ(m.sonar_stale, 1);
    EXPECT_FLOAT_EQ(m.sonar_age_s, -1.0f);
    EXPECT_FLOAT_EQ(m.robot_radius, 0.35f);
    EXPECT_DOUBLE_EQ(m.robot_pose.y, 2.0);
  }
  // Firing groups every 30 ms from 0.3 s to 1.29 s.
  for (int64_t t = 300'000; t < 1'300'000; t += 30'000) complement(t);
  ASSERT_EQ(maps.size(), 35u);  // one per group, after the laser's
  {
    // After two groups the echo's cell reaches G_T = 2: sonar 1 m ahead, nearest cell point
    // (2.0, 2.0): 1.0 m from the centre, 0.65 m from the boundary; copied into 23 and 25.
    const sector_map_t& m = maps[2];
    EXPECT_NEAR(m.distance[ahead], 0.65, 1e-5);
    EXPECT_EQ(m.source[ahead], kSonar);
    EXPECT_EQ(m.source[ahead - 1], kCopied);
    EXPECT_EQ(m.source[ahead + 1], kCopied);
    EXPECT_EQ(m.sonar_stale, 0);
    EXPECT_EQ(maps[1].source[ahead], kNone);  // one hit: below G_T
  }
  {
    // The laser has not been heard for ~1 s: stale, its value held.
    const sector_map_t& m = maps.back();
    EXPECT_EQ(m.laser_stale, 1);
    EXPECT_GT(m.laser_age_s, 0.5f);
    EXPECT_NEAR(m.distance[left], 0.65, 1e-5);
  }
  // AGM_OPERATIONAL at 2 Hz of message time: at 0.30 s and 0.81 s.
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].utime, 300'000);
  EXPECT_EQ(grids[1].utime, 810'000);
  const grid_map_t& g = grids[1];
  EXPECT_EQ(g.width, 100);
  EXPECT_EQ(g.ncells, 10000);
  EXPECT_FLOAT_EQ(g.cell_size, 0.1f);
  EXPECT_EQ(g.gp_threshold, 2);
  // Window re-centred on the robot's cell (10, 20): origin cell (-40, -30).
  EXPECT_NEAR(g.origin_x, -4.0, 1e-9);
  EXPECT_NEAR(g.origin_y, -3.0, 1e-9);
  const size_t echo = 50 * 100 + 60;  // global cell (20, 20)
  EXPECT_EQ(g.g[echo], 18);           // hit by the 18 groups 0.30 .. 0.81 s
  EXPECT_EQ(g.h[echo], 0);
  EXPECT_EQ(g.gp[echo], 18);
  int occupied = 0;
  for (auto v : g.g) occupied += v > 0;
  EXPECT_EQ(occupied, 1);
  EXPECT_EQ(node.counter("agm.cycles"), 34);
  EXPECT_EQ(node.counter("agm.recentred"), 1);
  EXPECT_EQ(node.counter("laser.lost"), 0);  // stale, but one scan has no pace to have missed
  EXPECT_EQ(node.errors(), 0);
}

// Without a recent Radar Map the complement verifies nothing; its echoes within the range limit
// go in as complementary ones (stale_radar_map: echoes), so an obstacle that comes near while the
// laser is lost is in the sector map; the paper's pilot leaves them out. Beyond the limit, or in
// a group with a fresh map (an echo beyond the limit), they stay out.
struct StaleRadarMapRun {
  std::vector<sector_map_t> maps;
  int64_t unverified = 0;
};
StaleRadarMapRun staleRadarMapRun(const PilotConfig& cfg, bool stale, float range) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotStage stage(node, cfg);
  StaleRadarMapRun run;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&](const sector_map_t& m) { run.maps.push_back(m); });
  standStill(node, 0, 2'000'000);
  drainAll(node);
  for (int64_t t = 300'000; t < 600'000; t += 30'000) {
    complement_t c{};
    c.utime = t;
    c.radar_map_stale = stale ? 1 : 0;
    c.range_limit = 2.2f;
    c.tolerance = 0.1f;
    complement_reading_t r{};
    r.cls = complement_reading_t::CLASS_UNVERIFIABLE;
    r.range = range;  // from the front transducer at (1.35, 2.0) facing +x
    r.hypothetical_range = 2.2f;
    r.sensor_pose = {1.35, 2.0, 0.0};
    r.end_x = 1.35 + range;
    r.end_y = 2.0;
    r.beam_width = 0.5236f;
    c.readings.push_back(r);
    c.nreadings = 1;
    node.publish(channels::SONAR_COMPLEMENT, c);
    drainAll(node);
  }
  run.unverified = node.counter("agm.unverified_echoes");
  return run;
}

TEST(PilotStage, WithoutARecentRadarMapTheSonarsEchoesAreTheMap) {
  const int ahead = 24;
  PilotConfig cfg = nearestPointPilot();
  const StaleRadarMapRun lost = staleRadarMapRun(cfg, true, 0.8f);
  ASSERT_FALSE(lost.maps.empty());
  EXPECT_EQ(lost.unverified, 10);
  EXPECT_EQ(lost.maps.back().source[ahead], kSonar);
  EXPECT_NEAR(lost.maps.back().sonar_distance[ahead], 0.8, 0.11);  // (its cell's nearest point)
  EXPECT_EQ(staleRadarMapRun(cfg, true, 2.5f).unverified, 0);   // beyond the 2.2 m limit
  EXPECT_EQ(staleRadarMapRun(cfg, false, 2.5f).unverified, 0);  // a fresh map's echo beyond it
  cfg.stale_radar_map_echoes = false;                           // the paper
  const StaleRadarMapRun paper = staleRadarMapRun(cfg, true, 0.8f);
  EXPECT_EQ(paper.unverified, 0);
  EXPECT_EQ(paper.maps.back().source[ahead], kNone);
}

// A sensor that was delivering and goes stale is an outage, an error once per outage; one that
// never delivered is not (start-up in any order); back, it can be lost again.
TEST_F(PilotFixture, ASensorOutageIsReportedOncePerOutage) {
  odometry();  // poses from 0 to 2 s
  for (int64_t t = 300'000; t < 500'000; t += 30'000) complement(t);  // sonar only: no laser yet
  EXPECT_EQ(node.counter("laser.lost"), 0);
  laserScan(300'000);  // 5 Hz: its last readings at 0.5 and 0.7 s
  laserScan(500'000);
  for (int64_t t = 720'000; t < 1'200'000; t += 30'000) complement(t);
  EXPECT_EQ(maps.back().laser_stale, 1);
  EXPECT_EQ(node.counter("laser.lost"), 1);
  EXPECT_EQ(node.counter("sonar.lost"), 0);
  laserScan(1'100'000);  // back (its last reading at 1.3 s): fresh, not reported again
  EXPECT_EQ(maps.back().laser_stale, 0);
  complement(1'320'000);
  EXPECT_EQ(node.counter("laser.lost"), 1);
  // Now the sonar stops (its last group at 1.32 s) while the laser goes on: stale after 0.36 s.
  laserScan(1'400'000);
  EXPECT_EQ(maps.back().sonar_stale, 0);
  EXPECT_EQ(node.counter("sonar.lost"), 0);
  laserScan(1'600'000);
  EXPECT_EQ(maps.back().sonar_stale, 1);
  EXPECT_EQ(node.counter("sonar.lost"), 1);
  EXPECT_EQ(node.counter("laser.lost"), 1);
  EXPECT_EQ(node.errors(), 2);
}

// AGM_OPERATIONAL goes out again as soon as 1/agm_publish_hz (0.5 s) of message time has passed
// since the last one: a group fired exactly 0.5 s later publishes, one fired 10 ms earlier does
// not.
TEST_F(PilotFixture, TheAgmIsPublishedAgainExactlyOnePeriodLater) {
  odometry();
  complement(300'000);
  complement(790'000);
  ASSERT_EQ(grids.size(), 1u);
  complement(800'000);
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[1].utime, 800'000);
}

TEST_F(PilotFixture, BadInputIsReportedAndTheStageGoesOn) {
  odometry_t bad{};
  bad.utime = 1;
  bad.pose = {kNaN, 2.0, 0.0};
  node.publish(channels::ODOMETRY, bad);
  drain();
  EXPECT_EQ(node.counter("rejected.odometry_nan"), 1);

  odometry();
  complement(300'000, {reading(complement_reading_t::CLASS_COMPLEMENTARY, kNaN, 1.0),
                       reading(9, 1.0, 1.0)});
  EXPECT_EQ(node.counter("rejected.complement_nan"), 1);
  EXPECT_EQ(node.counter("rejected.complement_class"), 1);
  EXPECT_EQ(node.counter("agm.hits"), 1);
  complement(200'000);  // time went backwards: dropped
  EXPECT_EQ(node.counter("rejected.complement_backwards"), 1);
  complement(330'000);
  EXPECT_EQ(node.counter("agm.cycles"), 2);
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps.back().source[24], kSonar);
  EXPECT_EQ(node.errors(), 4);

  odometry_t back{};
  back.utime = 1'500'000;  // older than the newest (2 s), by less than a restarted clock (1 s)
  back.pose = {1.0, 2.0, 0.0};
  node.publish(channels::ODOMETRY, back);
  drain();
  EXPECT_EQ(node.counter("rejected.odometry_backwards"), 1);
}

// A reading whose time offset is rejected says nothing: the sector map is the scan's, at its
// latest good reading, not half a minute later where no pose is (which would also have moved the
// pilot's clock on).
TEST_F(PilotFixture, ARejectedLaserTimeOffsetDoesNotMoveTheMapsTime) {
  odometry();
  laser_scan_t s = noReturnScan(100'000, -kPi, 2 * kPi / 720, 720, 200'000);
  s.ranges[540] = 1.0f;
  s.flags[540] = laser_scan_t::FLAG_OK;
  s.offset_us[200] = 30'000'000;
  node.publish(channels::LASER_SCAN, s);
  drain();
  EXPECT_EQ(node.counter("rejected.laser_offset"), 1);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps.back().utime, 100'000 + 719 * 200'000 / 720);
  EXPECT_EQ(maps.back().source[36], kLaser);
}

TEST_F(PilotFixture, NegativeComplementRangesAreSkipped) {
  odometry();
  // A complementary reading with a finite but negative range: skipped, not accumulated.
  complement_reading_t negative = reading(complement_reading_t::CLASS_COMPLEMENTARY, 1.0, 3.0);
  negative.range = -0.5f;
  complement(300'000, {negative});
  EXPECT_EQ(node.counter("rejected.complement_range"), 1);
  EXPECT_EQ(node.counter("agm.hits"), 1);  // the fixture's own echo only
  EXPECT_EQ(node.errors(), 1);
  complement(330'000);  // still working
  EXPECT_EQ(node.counter("agm.cycles"), 2);
  EXPECT_EQ(node.counter("rejected.complement_range"), 1);
}

TEST_F(PilotFixture, NoOdometryNoSectorMap) {
  complement(300'000);
  EXPECT_TRUE(maps.empty());
  EXPECT_EQ(node.counter("sector_map.no_odometry"), 1);
  EXPECT_TRUE(grids.empty());  // no grid with a made-up robot pose either
  EXPECT_EQ(node.counter("agm.no_odometry"), 1);
  EXPECT_EQ(node.counter("agm.cycles"), 1);  // the AGM itself still runs (hits are global)
}

TEST_F(PilotFixture, AnOdometryOutageIsReportedOnceAndTheMapsComeBack) {
  odometry();  // poses from 0 to 2 s
  complement(300'000);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(node.counter("odometry.lost"), 0);
  // The odometry driver dies at 2 s; the sonar goes on.
  for (int64_t t = 2'600'000; t <= 3'000'000; t += 100'000) complement(t);
  EXPECT_EQ(maps.size(), 1u);  // no map with a made-up pose
  EXPECT_GE(node.counter("sector_map.no_odometry"), 5);
  EXPECT_EQ(node.counter("odometry.lost"), 1);  // once per outage, an error
  EXPECT_EQ(node.errors(), 1);
  // It comes back.
  standStill(node, 3'020'000, 4'000'000);
  drain();
  complement(3'500'000);
  EXPECT_GT(maps.size(), 1u);  // (also on ODOMETRY, every map_max_interval_s)
  EXPECT_EQ(node.counter("odometry.lost"), 1);
}

// Odometry that stopped exactly kLostUs (0.5 s, the sector map's staleness limit) before a map
// is not yet an outage; a microsecond later it is, and it is reported once.
TEST(OdometryOutage, IsReportedOnlyOnceOdometryIsSilentForLongerThanKLostUs) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PoseHistory poses;
  poses.add(1'000'000, geom::Pose2{1.0, 2.0, 0.0});
  OdometryOutage outage;
  outage.missing(node, poses, 1'000'000 + OdometryOutage::kLostUs, "SECTOR_MAP");
  EXPECT_EQ(node.counter("odometry.lost"), 0);
  outage.missing(node, poses, 1'000'001 + OdometryOutage::kLostUs, "SECTOR_MAP");
  EXPECT_EQ(node.counter("odometry.lost"), 1);
  outage.missing(node, poses, 2'000'000 + OdometryOutage::kLostUs, "SECTOR_MAP");
  EXPECT_EQ(node.counter("odometry.lost"), 1);
}

TEST_F(PilotFixture, RotationDoesNotRotateTheGrid) {
  odometry(kPi / 2);  // facing +y: the echo at (2.05, 2.05) is now to the right
  complement(300'000);
  complement(330'000);
  const sector_map_t& m = maps.back();
  EXPECT_EQ(m.source[12], kSonar);  // bearing ~ -87 deg
  EXPECT_NEAR(m.distance[12], 0.65, 1e-5);
}

TEST(PilotConfig, ErrorsNameTheKeyPath) {
  const auto expectError = [](const std::string& yaml, const std::string& path) {
    try {
      pilotConfig(Config::fromString(yaml).section("pilot"));
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expectError("pilot: {colour: red}", "pilot.colour");
  expectError("pilot: {agm: {t: -1}}", "pilot.agm.t");
  expectError("pilot: {max_range: 6.0}", "pilot.max_range");  // beyond the AGM window
  expectError("pilot: {agm_publish_hz: 0}", "pilot.agm_publish_hz");
  expectError("pilot: {agm_publish_hz: 1e-14}", "pilot.agm_publish_hz");  // its period would overflow
  expectError("pilot: {map_max_interval_s: 1e13}", "pilot.map_max_interval_s");
  // Thresholds never reached, cells and memories that could not be meant: exit 2, not an empty map.
  expectError("pilot: {agm: {g_threshold: 101}}", "pilot.agm.g_threshold");  // g_max 100
  expectError("pilot: {gp_threshold: 1000}", "pilot.gp_threshold");          // (2t+1)^2 g_max = 900
  expectError("pilot: {max_range: 1e-300}", "pilot.max_range");
  expectError("pilot: {agm: {cell_size: 1e9}}", "pilot.agm.cell_size");
  expectError("pilot: {agm: {h_max: 1e9}}", "pilot.agm.h_max");
  expectError("pilot: {sonar_stale_s: 1e13}", "pilot.sonar_stale_s");
  expectError("pilot: {predict_movers: maybe}", "pilot.predict_movers");
  expectError("pilot: {mover_prediction: {horizon_s: -1}}", "pilot.mover_prediction.horizon_s");
  expectError("pilot: {mover_prediction: {horizon_scans: -1}}", "pilot.mover_prediction.horizon_scans");
  expectError("pilot: {laser_stale_scans: .nan}", "pilot.laser_stale_scans");
  expectError("pilot: {mover_prediction: {min_speed: 3, max_speed: 2}}",
              "pilot.mover_prediction.max_speed: (2) must be greater than min_speed (3)");
  expectError("pilot: {mover_prediction: {speed: 2}}", "pilot.mover_prediction.speed");
  const PilotConfig m = pilotConfig(
      Config::fromString("pilot: {predict_movers: false, mover_prediction: {min_speed: 0.5, horizon_s: 0.2}}").section("pilot"));
  EXPECT_FALSE(m.predict_movers);
  EXPECT_DOUBLE_EQ(m.mover_prediction.min_speed, 0.5);
  EXPECT_DOUBLE_EQ(m.mover_prediction.horizon_s, 0.2);
  const PilotConfig c =
      pilotConfig(Config::fromString("pilot: {agm: {g_threshold: 3}, max_range: 2.5}").section("pilot"));
  EXPECT_EQ(c.sector_map.gp_threshold, 3);  // defaults to G_T
  EXPECT_DOUBLE_EQ(c.sector_map.max_range, 2.5);
}

namespace {
// The ConfigError pilotConfig throws for `yaml` (the whole file), or "" if it accepts it.
std::string pilotConfigError(const std::string& yaml) {
  try {
    pilotConfig(Config::fromString(yaml).section("pilot"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// A mover prediction whose speed window is empty (max_speed equal to min_speed) can never call
// anything a mover: an error, as for a max_speed below min_speed.
TEST(PilotConfig, AnEmptyMoverSpeedWindowIsAnError) {
  EXPECT_NE(pilotConfigError("pilot: {mover_prediction: {min_speed: 0.5, max_speed: 0.5}}")
                .find("pilot.mover_prediction.max_speed: (0.5) must be greater than min_speed (0.5)"),
            std::string::npos);
  EXPECT_EQ(pilotConfigError("pilot: {mover_prediction: {min_speed: 0.5, max_speed: 0.6}}"), "");
}

TEST(PilotConfig, AnEmptyRoundClusterRadiusWindowIsAnError) {
  EXPECT_NE(pilotConfigError("pilot: {laser_memory_heard_through: {min_radius_m: 0.6, max_radius_m: 0.5}}")
                .find("pilot.laser_memory_heard_through.max_radius_m: (0.5) must not be less than min_radius_m (0.6)"),
            std::string::npos);
  EXPECT_NE(pilotConfigError("pilot: {laser_memory_heard_through: {clear_after: -1}}")
                .find("pilot.laser_memory_heard_through.clear_after"),
            std::string::npos);
  EXPECT_NE(pilotConfigError("pilot: {laser_memory_heard_through: {radius: 0.3}}").find("radius"), std::string::npos);
  EXPECT_EQ(pilotConfigError("pilot: {laser_memory_heard_through: {min_radius_m: 0.5, max_radius_m: 0.5}}"), "");
}

// The sector map reaches robot_radius + max_range from the robot's centre: the AGM window must
// hold all of it, the robot's own radius included, wherever re-centring lets the robot be.
TEST(PilotConfig, TheAgmWindowMustHoldTheRobotRadiusPlusMaxRange) {
  const PilotConfig d = pilotConfig(Config{});
  const double view = d.agm.guaranteedView();
  const double radius = d.sector_map.robot_radius;
  ASSERT_GT(radius, 0.1);
  const std::string within = "pilot: {max_range: " + std::to_string(view - radius) + "}";
  const std::string beyond = "pilot: {max_range: " + std::to_string(view - radius / 2) + "}";
  EXPECT_EQ(pilotConfigError(within), "");
  EXPECT_NE(pilotConfigError(beyond).find("pilot.max_range: robot_radius + max_range"), std::string::npos);
}

// A sector-map threshold of 0 would take every empty cell of the AGM for an obstacle: Gp must be
// at least 1, as G_T.
TEST(PilotConfig, AGpThresholdOfZeroIsAnError) {
  EXPECT_NE(pilotConfigError("pilot: {gp_threshold: 0}").find("pilot.gp_threshold"), std::string::npos);
  EXPECT_EQ(pilotConfigError("pilot: {gp_threshold: 1}"), "");
}

TEST(PilotConfig, BearingAndCellPointOptions) {
  const PilotConfig d = pilotConfig(Config::fromString("pilot: {}").section("pilot"));
  EXPECT_EQ(d.placement.bearing, AgmBearing::Neighbours);
  EXPECT_EQ(d.placement.placement, AgmPlacement::Evidence);
  EXPECT_EQ(d.placement.evidence_min_g, 2);
  EXPECT_EQ(d.sector_map.copy_rule, CopyRule::UnlessLaserConfirmed);
  EXPECT_EQ(d.sector_map.laser_explains_radius, 0.10);
  EXPECT_EQ(d.sector_map.sonar_cell_point, CellPoint::Centre);
  EXPECT_TRUE(d.remembered);
  const PilotConfig c = pilotConfig(
      Config::fromString("pilot: {agm_bearing: axis, agm_placement: estimate, evidence_min_g: 3, sonar_cell_point: nearest, "
                         "copy_rule: paper, copy_confirm_tolerance: 0.2, laser_explains_radius: 0.15, remembered: false, "
                         "neighbour_bearing: {beam_deg: 25, similar: 0.05, max_age_s: 0.3}}")
          .section("pilot"));
  EXPECT_EQ(c.placement.bearing, AgmBearing::Axis);
  EXPECT_EQ(c.placement.placement, AgmPlacement::Estimate);
  EXPECT_EQ(c.placement.evidence_min_g, 3);
  EXPECT_EQ(c.sector_map.copy_rule, CopyRule::Paper);
  EXPECT_DOUBLE_EQ(c.sector_map.copy_confirm_tolerance, 0.2);
  EXPECT_DOUBLE_EQ(c.sector_map.laser_explains_radius, 0.15);
  EXPECT_EQ(c.sector_map.sonar_cell_point, CellPoint::Nearest);
  EXPECT_FALSE(c.remembered);
  EXPECT_NEAR(c.placement.params.beam_width, geom::deg2rad(25.0), 1e-12);
  EXPECT_DOUBLE_EQ(c.placement.params.similar, 0.05);
  EXPECT_DOUBLE_EQ(c.placement.params.max_age_s, 0.3);
  for (const char* bad : {"pilot: {agm_bearing: cone}", "pilot: {agm_placement: arc}", "pilot: {evidence_min_g: 0}",
                          "pilot: {copy_rule: never}", "pilot: {laser_explains_radius: -0.1}", "pilot: {sonar_cell_point: far}",
                          "pilot: {neighbour_bearing: {beam: 30}}", "pilot: {neighbour_bearing: {similar: -1}}"}) {
    EXPECT_THROW(pilotConfig(Config::fromString(bad).section("pilot")), ConfigError) << bad;
  }
}

namespace {
// Two adjacent sensors of a ring at the origin (axes 5 and 20 deg): sensor 1 reads 0.6 m at
// 0.30 s, sensor 0 reads 1.0 m at 0.33 s (its left neighbour reads shorter: beam edge).
std::vector<grid_map_t> runTwoSensors(AgmBearing b) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotConfig cfg;
  cfg.placement.bearing = b;
  cfg.agm_publish_hz = 1000;  // a grid after every cycle
  PilotStage stage{node, cfg};
  std::vector<grid_map_t> grids;
  node.subscribe<grid_map_t>(channels::AGM_OPERATIONAL, [&](const grid_map_t& m) { grids.push_back(m); });
  for (int64_t t = 0; t <= 1'000'000; t += 20'000) {
    odometry_t o{};
    o.utime = t;
    node.publish(channels::ODOMETRY, o);
  }
  const auto group = [&](int64_t utime, int id, double deg, double range) {
    const double a = geom::deg2rad(deg);
    complement_reading_t r{};
    r.sensor_id = static_cast<int16_t>(id);
    r.cls = complement_reading_t::CLASS_COMPLEMENTARY;
    r.range = static_cast<float>(range);
    r.hypothetical_range = 2.2f;
    r.sensor_pose = {0.35 * std::cos(a), 0.35 * std::sin(a), a};
    r.end_x = r.sensor_pose.x + r.range * std::cos(a);
    r.end_y = r.sensor_pose.y + r.range * std::sin(a);
    complement_t c{};
    c.utime = utime;
    c.readings.push_back(r);
    c.nreadings = 1;
    node.publish(channels::SONAR_COMPLEMENT, c);
  };
  group(300'000, 1, 20.0, 0.6);
  group(330'000, 0, 5.0, 1.0);
  drainAll(node);
  return grids;
}
int occupiedCell(const grid_map_t& g, int skip = -1) {
  for (int i = 0; i < g.ncells; ++i)
    if (g.g[static_cast<size_t>(i)] > 0 && i != skip) return i;
  return -1;
}
}  // namespace

TEST(PilotStageBearing, AxisIsThePapersEndPointNeighboursUseTheBeamEdge) {
  const auto axis = runTwoSensors(AgmBearing::Axis);
  const auto nb = runTwoSensors(AgmBearing::Neighbours);
  ASSERT_EQ(axis.size(), 2u);
  ASSERT_EQ(nb.size(), 2u);
  // The first reading has no neighbour: the same cell either way.
  const int first = occupiedCell(axis[0]);
  EXPECT_EQ(occupiedCell(nb[0]), first);
  const auto cellOf = [](const grid_map_t& g, double x, double y) {
    return static_cast<int>(std::floor((y - g.origin_y) / g.cell_size)) * g.width +
           static_cast<int>(std::floor((x - g.origin_x) / g.cell_size));
  };
  // Axis: sensor 0's echo at its end point, 1.35 m along 5 deg; neighbours: at its beam edge
  // (20 deg), 1.0 m from the sensor.
  const double a = geom::deg2rad(5.0), e = geom::deg2rad(20.0);
  EXPECT_EQ(occupiedCell(axis[1], first), cellOf(axis[1], 1.35 * std::cos(a), 1.35 * std::sin(a)));
  EXPECT_EQ(occupiedCell(nb[1], first), cellOf(nb[1], 0.35 * std::cos(a) + std::cos(e), 0.35 * std::sin(a) + std::sin(e)));
  EXPECT_NE(occupiedCell(nb[1], first), occupiedCell(axis[1], first));
}

TEST_F(PilotFixture, OdometryMakesMapsWhenNoSensorDoesSoADeadSonarIsFlagged) {
  odometry();  // 0 .. 2 s: no sensor yet, so no map (nothing to age)
  EXPECT_TRUE(maps.empty());
  laserScan(100'000);
  complement(330'000);
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_FALSE(maps.back().sonar_stale);
  // The sonar falls silent; odometry goes on to 3 s: a map at least every 0.1 s of odometry.
  standStill(node, 2'020'000, 3'000'000);
  drain();
  ASSERT_GE(maps.size(), 10u);
  EXPECT_EQ(node.counter("sector_map.on_odometry"), static_cast<int64_t>(maps.size()) - 2);
  for (size_t i = 3; i < maps.size(); ++i) EXPECT_LE(maps[i].utime - maps[i - 1].utime, 100'000 + 20'000);
  EXPECT_TRUE(maps.back().sonar_stale);
  EXPECT_TRUE(maps.back().laser_stale);
}

// When no sensor makes a map, the ODOMETRY that comes map_max_interval_s (0.1 s) of message time
// after the last map makes one: the interval is a bound a consumer may rely on, not one odometry
// tick more.
TEST_F(PilotFixture, OdometryMakesAMapExactlyMapMaxIntervalAfterTheLast) {
  standStill(node, 0, 300'000);
  drain();
  complement(300'000);
  ASSERT_EQ(maps.size(), 1u);
  standStill(node, 320'000, 380'000);
  drain();
  EXPECT_EQ(maps.size(), 1u);
  standStill(node, 400'000, 400'000);
  drain();
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps.back().utime, 400'000);
  EXPECT_EQ(node.counter("sector_map.on_odometry"), 1);
}

// A scan none of whose readings has odometry says nothing about the room: the sector map keeps
// the previous scan's returns (ageing), rather than taking it for a scan of an empty room.
TEST_F(PilotFixture, AScanWithoutOdometryKeepsThePreviousScansReturns) {
  const int left = 36;
  odometry();  // poses from 0 to 2 s
  laserScan(100'000);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_NEAR(maps.back().laser_distance[left], 0.65, 1e-5);
  laserScan(2'500'000);  // every reading after the last pose
  EXPECT_EQ(node.counter("rejected.laser_no_odometry"), 1);
  standStill(node, 2'020'000, 3'000'000);
  drain();
  complement(2'900'000);
  EXPECT_NEAR(maps.back().laser_distance[left], 0.65, 1e-5);
}

TEST_F(PilotFixture, AClockThatJumpsBackRestartsTheStage) {
  odometry();
  complement(330'000);
  complement(1'900'000);
  EXPECT_EQ(node.counter("agm.cycles"), 2);
  // The sources restarted: a complement 1.5 s older than the newest on its channel.
  complement(400'000);
  EXPECT_EQ(node.counter("time_resets"), 1);
  EXPECT_EQ(node.counter("rejected.complement_backwards"), 0);
  EXPECT_EQ(node.counter("agm.cycles"), 3);  // used, on a fresh grid
  // A small step back is a late message, not a restart.
  complement(300'000);
  EXPECT_EQ(node.counter("rejected.complement_backwards"), 1);
  // Absurd times are dropped and counted.
  complement(-5);
  complement(std::numeric_limits<int64_t>::max());
  EXPECT_EQ(node.counter("rejected.time"), 2);
  EXPECT_EQ(node.counter("time_resets"), 1);
}

// A 270 deg scanner sees something 1 m to the robot's left (returns at +90 deg +- half_width
// readings of 0.5 deg); the robot then turns to face -y, so it lies straight behind, in the
// scanner's blind wedge, and the next scan (at second_scan_us, the robot standing since 0.6 s)
// has no return. Returns the last SECTOR_MAP and the remembered returns counted.
namespace {
// The robot at (1, 2) facing +x until 0.5 s, turning to face -y by 0.6 s: its odometry at t.
odometry_t turningAway(int64_t t) {
  odometry_t o{};
  o.utime = t;
  o.pose = {1.0, 2.0, t <= 500'000 ? 0.0 : (t >= 600'000 ? -kPi / 2 : -kPi / 2 * static_cast<double>(t - 500'000) / 1e5)};
  return o;
}

std::pair<sector_map_t, int64_t> mapAfterTurningAway(double memory_s, int half_width, bool predict_movers = true,
                                                     int64_t second_scan_us = 1'000'000) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotConfig cfg;
  cfg.laser_memory_s = memory_s;
  cfg.predict_movers = predict_movers;
  PilotStage stage{node, cfg};
  std::vector<sector_map_t> maps;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&maps](const sector_map_t& m) { maps.push_back(m); });
  const auto drain = [&node] { drainAll(node); };
  // At (1, 2) facing +x until 0.5 s, facing -y from 0.6 s; published up to `until` (ahead of each
  // scan: the pose history holds only the last few seconds; the last map's laser must be fresh).
  int64_t next_odometry = 0;
  const auto odometry = [&](int64_t until) {
    for (; next_odometry <= until; next_odometry += 20'000) {
      odometry_t o = turningAway(next_odometry);
      node.publish(channels::ODOMETRY, o);
      drain();
    }
  };
  const auto scan = [&](int64_t utime, bool something_left) {
    laser_scan_t s = noReturnScan(utime, -0.75 * kPi, geom::deg2rad(0.5), 541, 100'000);  // 270 deg
    if (something_left)
      for (int i = 450 - half_width; i <= 450 + half_width; ++i) {  // a straight face 1 m to the left
        s.ranges[static_cast<size_t>(i)] = static_cast<float>(1.0 / std::cos(geom::deg2rad(0.5 * (i - 450))));
        s.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
      }
    node.publish(channels::LASER_SCAN, s);
    drain();
  };
  odometry(2'000'000);
  scan(100'000, true);
  if (second_scan_us > 2'000'000) odometry(second_scan_us + 200'000);
  scan(second_scan_us, false);
  EXPECT_GE(maps.size(), 2u);  // (and one at least every map_max_interval_s of odometry between)
  return {maps.empty() ? sector_map_t{} : maps.back(), node.counter("laser.remembered_returns")};
}
}  // namespace

// A wall (1.7 m of it) left behind a 270 deg scanner stays in the sector map as a laser value;
// without the memory (the paper: the newest scan only) nothing is known there.
TEST(PilotLaserMemory, AWallLeftBehindA270DegreeScannerStaysInTheSectorMap) {
  const int behind = 0, ahead = 24;  // [-180, -172.5) deg; [0, 7.5) deg
  {
    const auto [m, remembered] = mapAfterTurningAway(3.0, 80);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_NEAR(m.laser_distance[behind], 1.0 - 0.35, 0.01) << "the wall behind, 1 m from the centre";
    EXPECT_EQ(m.source[behind], kLaser);
    EXPECT_GT(remembered, 0);
    EXPECT_EQ(m.source[ahead], kNone);  // ahead (now -y) the newest scan saw nothing
  }
  {
    const auto [m, remembered] = mapAfterTurningAway(0.0, 80);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_EQ(m.source[behind], kNone);
    EXPECT_FLOAT_EQ(m.laser_distance[behind], -1.0f);
    EXPECT_EQ(remembered, 0);
  }
}

// A robot that waits (or creeps) does not leave the wall behind beyond the sector map's reach:
// the shipped memory keeps it while the robot stands, 20 s after the scanner last saw it; the
// former 3 s (a robot driving past at 0.3-0.6 m/s) had forgotten it.
TEST(PilotLaserMemory, AWaitingRobotKeepsTheWallBehindItForLaserMemoryS) {
  const int behind = 0;
  ASSERT_GE(PilotConfig{}.laser_memory_s, 20.0);
  {
    const auto [m, remembered] = mapAfterTurningAway(PilotConfig{}.laser_memory_s, 80, true, 20'100'000);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_NEAR(m.laser_distance[behind], 1.0 - 0.35, 0.01);
    EXPECT_GT(remembered, 0);
  }
  {
    const auto [m, remembered] = mapAfterTurningAway(3.0, 80, true, 20'100'000);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_EQ(m.source[behind], kNone);
    EXPECT_EQ(remembered, 0);
  }
}

// What the memory keeps is returns: the dark continuation's points (the face goes on 0.10 m past
// each end, into the empty readings) are the newest scan's alone. Without the mover prediction
// every return is kept, so exactly the face's 161.
TEST(PilotLaserMemory, TheDarkContinuationIsNotRemembered) {
  ASSERT_GT(PilotConfig{}.dark_continuation.length, 0.0);
  for (const bool predict : {true, false}) {
    const auto [m, remembered] = mapAfterTurningAway(3.0, 80, predict);
    EXPECT_EQ(remembered, 161) << "predict_movers " << predict;
  }
}

// Something person-sized (0.17 m of returns) seen in one scan only may be a person walking: it
// is not remembered (MoverPrediction::still).
TEST(PilotLaserMemory, APersonSizedClusterSeenOnceIsNotRemembered) {
  const auto [m, remembered] = mapAfterTurningAway(3.0, 10);
  ASSERT_EQ(m.nsectors, 48);
  EXPECT_EQ(m.source[0], kNone);
  EXPECT_EQ(remembered, 0);
}

// A person stands 1.25 m to the left of a robot at (1, 2) with a 270 deg scanner (two scans see
// them: a still person-sized cluster); the robot turns to face -y, so they are straight behind,
// where the scanner does not look; they walk off. From 1.0 s a rear transducer at (1, 2.3) facing
// +y hears nothing within 2 m, `silent_groups` firing groups in a row. The last SECTOR_MAP's laser
// distance straight behind (-1: none), after a scan at 1.4 s.
namespace {
float behindAfterSilence(int silent_groups, int clear_after) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotConfig cfg;
  cfg.laser_memory_heard_through.clear_after = clear_after;
  PilotStage stage{node, cfg};
  std::vector<sector_map_t> maps;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&maps](const sector_map_t& m) { maps.push_back(m); });
  for (int64_t t = 0; t <= 2'000'000; t += 20'000) {
    odometry_t o = turningAway(t);
    node.publish(channels::ODOMETRY, o);
  }
  drainAll(node);
  const auto scan = [&](int64_t utime, bool person) {
    laser_scan_t s = noReturnScan(utime, -0.75 * kPi, geom::deg2rad(0.5), 541, 100'000);
    const double d = 1.25, r = 0.25;  // the person's centre and radius
    for (int i = 0; person && i < 541; ++i) {
      const double a = geom::deg2rad(0.5 * (i - 450));  // from +90 deg (the left)
      const double disc = r * r - d * d * std::sin(a) * std::sin(a);
      if (disc < 0 || std::cos(a) <= 0) continue;
      s.ranges[static_cast<size_t>(i)] = static_cast<float>(d * std::cos(a) - std::sqrt(disc));
      s.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
    }
    node.publish(channels::LASER_SCAN, s);
    drainAll(node);
  };
  scan(100'000, true);
  scan(300'000, true);
  scan(1'000'000, false);
  for (int k = 0; k < silent_groups; ++k) {
    complement_t c{};
    c.utime = 1'110'000 + 30'000 * k;
    c.group = static_cast<int16_t>(k % 6);
    c.tolerance = 0.1f;
    complement_reading_t rear = PilotFixture::reading(complement_reading_t::CLASS_REDUNDANT, 1.0, 4.3);
    rear.range = rear.hypothetical_range = 2.0f;
    rear.sensor_pose = {1.0, 2.3, kPi / 2};
    c.readings.push_back(rear);
    node.publish(channels::SONAR_COMPLEMENT, c);
    drainAll(node);
  }
  scan(1'400'000, false);
  EXPECT_GT(node.counter("laser.remembered_returns"), 0);
  return maps.empty() || maps.back().nsectors != 48 ? -2.0f : maps.back().laser_distance[0];
}
}  // namespace

TEST(PilotLaserMemory, APersonBehindTheScannerIsForgottenOnceSoundWentThroughThemThreeTimes) {
  ASSERT_EQ(PilotConfig{}.laser_memory_heard_through.clear_after, 3);
  EXPECT_NEAR(behindAfterSilence(0, 3), 1.0 - 0.35, 0.02);  // kept: nothing heard there yet
  EXPECT_NEAR(behindAfterSilence(2, 3), 1.0 - 0.35, 0.02);
  EXPECT_FLOAT_EQ(behindAfterSilence(3, 3), -1.0f);         // gone
  EXPECT_NEAR(behindAfterSilence(3, 0), 1.0 - 0.35, 0.02);  // off: kept for laser_memory_s
}

// takeOutMovers: the runs with a velocity leave `points` for `moving` (with their velocity and
// times), a run of velocity zero stays, and what stays keeps its order.
TEST(PilotStage, TakeOutMoversKeepsTheOthersInOrder) {
  std::vector<TimedPoint> scan;
  std::vector<geom::Vec2> points;
  for (int k = 0; k < 10; ++k) {
    scan.push_back({geom::Vec2(k, -k), 1000 + k});
    points.push_back(scan.back().p);
  }
  const std::vector<MoverPrediction::MovingRun> runs = {
      {2, 3, geom::Vec2(1, 0)}, {5, 5, geom::Vec2(0, 0)}, {8, 9, geom::Vec2(0, -1)}};
  std::vector<SectorMap::MovingPoint> moving;
  takeOutMovers(scan, runs, points, moving);
  const std::vector<int> stays = {0, 1, 4, 5, 6, 7}, moves = {2, 3, 8, 9};
  ASSERT_EQ(points.size(), stays.size());
  for (size_t i = 0; i < stays.size(); ++i) EXPECT_EQ(points[i], scan[static_cast<size_t>(stays[i])].p) << i;
  ASSERT_EQ(moving.size(), moves.size());
  for (size_t i = 0; i < moves.size(); ++i) {
    const TimedPoint& t = scan[static_cast<size_t>(moves[i])];
    EXPECT_EQ(moving[i].p, t.p) << i;
    EXPECT_EQ(moving[i].utime, t.utime) << i;
    EXPECT_EQ(moving[i].v, i < 2 ? geom::Vec2(1, 0) : geom::Vec2(0, -1)) << i;
  }
  // No run with a velocity: nothing moves.
  std::vector<geom::Vec2> all, before;
  for (const TimedPoint& t : scan) all.push_back(t.p);
  before = all;
  std::vector<SectorMap::MovingPoint> none;
  takeOutMovers(scan, {{5, 5, geom::Vec2(0, 0)}}, all, none);
  EXPECT_EQ(all, before);
  EXPECT_TRUE(none.empty());
}

// The valid returns in scan order, with their times, whatever the reused vectors held before;
// the newest reading's time counts whether or not it returned.
TEST(PilotStage, ValidReturnsKeepsTheValidInOrderWithTheirTimes) {
  std::vector<complement::ScanPoint> placed;
  std::vector<complement::LaserReading> readings;
  for (int k = 0; k < 9; ++k) {
    complement::ScanPoint p;
    p.p = geom::Vec2(k, 2 * k);
    p.valid = k % 3 != 1;
    placed.push_back(p);
    complement::LaserReading r;
    r.utime = k == 4 ? 9000 : 1000 + k;  // (reading 4, invalid, is the newest)
    readings.push_back(r);
  }
  std::vector<geom::Vec2> points(20, geom::Vec2(-1, -1));  // left over from a longer scan
  std::vector<TimedPoint> timed(3);
  int64_t newest = 500;
  validReturns(placed, readings, points, &timed, newest);
  const std::vector<int> valid = {0, 2, 3, 5, 6, 8};
  ASSERT_EQ(points.size(), valid.size());
  ASSERT_EQ(timed.size(), valid.size());
  for (size_t i = 0; i < valid.size(); ++i) {
    const auto k = static_cast<size_t>(valid[i]);
    EXPECT_EQ(points[i], placed[k].p) << i;
    EXPECT_EQ(timed[i].p, placed[k].p) << i;
    EXPECT_EQ(timed[i].utime, readings[k].utime) << i;
  }
  EXPECT_EQ(newest, 9000);
  // Without times: the same points, `timed` untouched.
  std::vector<geom::Vec2> only;
  std::vector<TimedPoint> untouched(2);
  int64_t newest2 = 0;
  validReturns(placed, readings, only, nullptr, newest2);
  EXPECT_EQ(only, points);
  EXPECT_EQ(newest2, 9000);
  EXPECT_EQ(untouched.size(), 2u);
}

// The remembered source takes a tactical cell at its foot on the navigator's line of the same
// cycle (AGM_LINES with AGM_TACTICAL's utime), in either order; a line map of another cycle or
// a bad one leaves the cells at their centres.
struct PilotRememberedFixture : PilotFixture {
  int sectorAhead = 23;  // the cell lies 2.7 deg right of ahead
  PilotRememberedFixture() = default;
  explicit PilotRememberedFixture(const PilotConfig& config) : PilotFixture(config) {}
  // AGM_TACTICAL with occupied cells (ix, iy) of 0.1 m from the origin; by default one, global
  // (2.0..2.1, 1.9..2.0): centre (2.05, 1.95).
  // `frame`: the navigator's frame from the odometry's (scan matching), identity by default.
  // `gp_threshold`: the threshold the map says its cells were published with.
  // `heard`: what the map says made its occupied cells (grid_map_t::HEARD_*).
  void tactical(int64_t utime, const std::vector<std::pair<int, int>>& cells = {{20, 19}},
                const geom::Pose2& frame = {}, int gp_threshold = 5, int8_t heard = grid_map_t::HEARD_UNKNOWN) {
    grid_map_t g{};
    g.utime = utime;
    const geom::Pose2 robot = frame.compose(geom::Pose2{1.0, 2.0, 0.0});
    g.robot_pose = {robot.x, robot.y, robot.theta};
    // The grid's axes are the navigator's; its origin so that cell (20, 19) is centred where the
    // odometry's (2.05, 1.95) lies in that frame (rotated cells: only that one is exact).
    const geom::Vec2 origin = frame.transform(geom::Vec2{2.05, 1.95}) - geom::Vec2{2.05, 1.95};
    g.origin_x = origin.x();
    g.origin_y = origin.y();
    g.cell_size = 0.1f;
    g.width = g.height = 40;
    g.ncells = 1600;
    g.gp_threshold = gp_threshold;
    g.g.assign(1600, 0);
    g.h.assign(1600, 0);
    g.gp.assign(1600, 0);
    g.heard.assign(1600, 0);
    for (const auto& [ix, iy] : cells) {
      g.gp[static_cast<size_t>(iy * 40 + ix)] = 9;
      g.heard[static_cast<size_t>(iy * 40 + ix)] = heard;
    }
    node.publish(channels::AGM_TACTICAL, g);
    drain();
  }
  // AGM_LINES with one sonar line along x = x_line, y 1.5..2.5.
  void lines(int64_t utime, double x_line) {
    line_map_t l{};
    l.utime = utime;
    l.robot_pose = {1.0, 2.0, 0.0};
    line_segment_t s{};
    s.x0 = s.x1 = x_line;
    s.y0 = 1.5;
    s.y1 = 2.5;
    s.npoints = 10;
    s.source = line_segment_t::SOURCE_SONAR;
    l.segments.push_back(s);
    l.nsegments = 1;
    node.publish(channels::AGM_LINES, l);
    drain();
  }
  // An empty firing group: a new sector map.
  float rememberedAhead(int64_t utime) {
    complement_t c{};
    c.utime = utime;
    node.publish(channels::SONAR_COMPLEMENT, c);
    drain();
    return maps.back().remembered_distance[sectorAhead];
  }
};

TEST_F(PilotRememberedFixture, CellsMoveOntoTheLineOfTheirCycle) {
  odometry();
  const double at_centre = std::hypot(1.05, 0.05) - 0.35;  // the cell's centre, from the boundary
  const double on_line = std::hypot(1.12, 0.05) - 0.35;    // its foot on the line at x = 2.12
  tactical(500'000);
  EXPECT_NEAR(rememberedAhead(510'000), at_centre, 1e-5);
  lines(500'000, 2.12);  // the same cycle: the cell moves 0.07 m back onto the line
  EXPECT_NEAR(rememberedAhead(540'000), on_line, 1e-5);
  EXPECT_EQ(node.counter("remembered.line_maps"), 1);

  // Lines first, then the grid of the same cycle: the same.
  lines(1'000'000, 2.12);
  tactical(1'000'000);
  EXPECT_NEAR(rememberedAhead(1'010'000), on_line, 1e-5);

  // The next grid comes without its lines (lost): the cell at its centre, not on the old line.
  tactical(1'500'000);
  EXPECT_NEAR(rememberedAhead(1'510'000), at_centre, 1e-5);
  // A line 0.25 m away (beyond 0.2 m) does not take the cell.
  lines(1'500'000, 2.30);
  EXPECT_NEAR(rememberedAhead(1'540'000), at_centre, 1e-5);
  EXPECT_EQ(node.errors(), 0);
}

// A remembered cell that only echoes the laser could not check made (HEARD_UNCHECKED: beyond the
// scanner's view, or explained only by an earlier scan) is left out, and counted; a cell that
// checked echoes made too, or whose making is not recorded, is used. With remembered_unchecked it
// is used too.
TEST_F(PilotRememberedFixture, CellsOnlyUncheckedEchoesMadeAreLeftOut) {
  odometry();
  const double at_centre = std::hypot(1.05, 0.05) - 0.35;
  tactical(500'000, {{20, 19}}, {}, 5, grid_map_t::HEARD_UNCHECKED);
  EXPECT_LT(rememberedAhead(510'000), 0.0f);  // nothing remembered ahead
  EXPECT_EQ(node.counter("remembered.unchecked_left_out"), 1);
  for (const int8_t heard : {grid_map_t::HEARD_CHECKED, grid_map_t::HEARD_BOTH, grid_map_t::HEARD_UNKNOWN}) {
    tactical(1'000'000 + heard * 100'000, {{20, 19}}, {}, 5, heard);
    EXPECT_NEAR(rememberedAhead(1'010'000 + heard * 100'000), at_centre, 1e-5) << int{heard};
  }
  EXPECT_EQ(node.counter("remembered.unchecked_left_out"), 1);
}

namespace {
PilotConfig rememberingUnchecked() {
  PilotConfig c = nearestPointPilot();
  c.remembered_unchecked = true;
  return c;
}
struct PilotUncheckedFixture : PilotRememberedFixture {
  PilotUncheckedFixture() : PilotRememberedFixture(rememberingUnchecked()) {}
};
}  // namespace

TEST_F(PilotUncheckedFixture, WithRememberedUncheckedEveryCellIsUsed) {
  odometry();
  tactical(500'000, {{20, 19}}, {}, 5, grid_map_t::HEARD_UNCHECKED);
  EXPECT_NEAR(rememberedAhead(510'000), std::hypot(1.05, 0.05) - 0.35, 1e-5);
  EXPECT_EQ(node.counter("remembered.unchecked_left_out"), 0);
}

// An AGM_TACTICAL that says its threshold is 0 still gives only the cells with weight as
// remembered obstacles: an empty cell is no obstacle, whatever threshold the map carries.
TEST_F(PilotRememberedFixture, EmptyCellsAreNeverRememberedWhateverTheMapsThreshold) {
  odometry();
  const double at_centre = std::hypot(1.05, 0.05) - 0.35;
  tactical(500'000, {{20, 19}}, {}, 0);
  EXPECT_NEAR(rememberedAhead(510'000), at_centre, 1e-5);
}

TEST_F(PilotRememberedFixture, CellsComeIntoThePilotsFrameThroughTheMapsRobotPose) {
  // The navigator's frame is the odometry's corrected by scan matching: here 0.3 m and 0.1 rad
  // away. Its robot_pose says where the robot is in it; through that and the pilot's own pose at
  // the same time, a cell the navigator holds at the odometry's (2.05, 1.95) is ahead again.
  odometry();
  const double at_centre = std::hypot(1.05, 0.05) - 0.35;
  tactical(500'000, {{20, 19}}, geom::Pose2{0.3, -0.2, 0.1});
  EXPECT_NEAR(rememberedAhead(510'000), at_centre, 1e-5);
  tactical(1'000'000, {{20, 19}}, geom::Pose2{-0.4, 0.1, -0.05});
  EXPECT_NEAR(rememberedAhead(1'010'000), at_centre, 1e-5);
  // Read as odometry coordinates, the cell would lie 0.3 m away.
  const geom::Vec2 off = geom::Pose2{-0.4, 0.1, -0.05}.transform(geom::Vec2{2.05, 1.95});
  EXPECT_GT((off - geom::Vec2{2.05, 1.95}).norm(), 0.25);
  // A robot_pose that is not finite drops the map (counted), the old one stays.
  grid_map_t bad{};
  bad.utime = 1'500'000;
  bad.robot_pose = {std::numeric_limits<double>::quiet_NaN(), 2.0, 0.0};
  bad.cell_size = 0.1f;
  bad.width = bad.height = 1;
  bad.ncells = 1;
  bad.g.assign(1, 0);
  bad.h.assign(1, 0);
  bad.gp.assign(1, 9);
  node.publish(channels::AGM_TACTICAL, bad);
  drain();
  EXPECT_EQ(node.counter("rejected.tactical_map"), 1);
  EXPECT_NEAR(rememberedAhead(1'510'000), at_centre, 1e-5);
}

TEST_F(PilotRememberedFixture, BadLineMapsAreReportedAndDropped) {
  odometry();
  const double at_centre = std::hypot(1.05, 0.05) - 0.35;
  tactical(500'000);
  line_map_t l{};
  l.utime = 500'000;
  line_segment_t s{};
  s.x0 = kNaN;
  s.y0 = 1.5;
  s.x1 = 2.12;
  s.y1 = 2.5;
  l.segments.push_back(s);
  l.nsegments = 1;
  node.publish(channels::AGM_LINES, l);
  drain();
  EXPECT_EQ(node.counter("rejected.agm_lines"), 1);
  EXPECT_NEAR(rememberedAhead(510'000), at_centre, 1e-5);
  lines(500'000, 2.12);  // the same cycle, now valid: used
  lines(400'000, 2.12);  // older: dropped
  EXPECT_EQ(node.counter("rejected.agm_lines_backwards"), 1);
  EXPECT_NEAR(rememberedAhead(540'000), std::hypot(1.12, 0.05) - 0.35, 1e-5);
  EXPECT_EQ(node.errors(), 2);
}

// Two cells of a pane 0.6 m apart (less than the robot's 0.7 m width), ahead-right and ahead-left
// of the robot: the sector straight ahead, between them, is empty in the grid; the line of their
// cycle fills it.
constexpr int kPaneCellsRow0 = 17, kPaneCellsRow1 = 23;  // centres y = 1.75 and 2.35, x = 2.05
TEST_F(PilotRememberedFixture, TheLineIsRememberedBetweenItsCells) {
  odometry();
  tactical(500'000, {{20, kPaneCellsRow0}, {20, kPaneCellsRow1}});
  EXPECT_FLOAT_EQ(rememberedAhead(510'000), -1.0f);  // no lines yet: the gap stays
  lines(500'000, 2.12);
  // The fill along x = 2.12 between y = 1.75 and 2.35: sector 23 (-7.5..0 deg) holds its points
  // from y = 2.0 down to y = 1.85; the nearest is the one straight ahead, 1.12 m from the centre.
  EXPECT_NEAR(rememberedAhead(540'000), 1.12 - 0.35, 0.01);
  // Lines of another cycle: the cells alone again.
  tactical(1'000'000, {{20, kPaneCellsRow0}, {20, kPaneCellsRow1}});
  EXPECT_FLOAT_EQ(rememberedAhead(1'010'000), -1.0f);
  EXPECT_EQ(node.errors(), 0);
}

struct PilotNoFillFixture : PilotRememberedFixture {
  static PilotConfig noFill() {
    PilotConfig c = nearestPointPilot();
    c.remembered_fill_m = 0;
    return c;
  }
  PilotNoFillFixture() : PilotRememberedFixture(noFill()) {}
};

TEST_F(PilotNoFillFixture, RememberedFillOffKeepsTheCellsAlone) {
  odometry();
  tactical(500'000, {{20, kPaneCellsRow0}, {20, kPaneCellsRow1}});
  lines(500'000, 2.12);
  EXPECT_FLOAT_EQ(rememberedAhead(540'000), -1.0f);
  EXPECT_EQ(node.counter("remembered.line_maps"), 1);  // the lines still move the cells
}

TEST_F(PilotRememberedFixture, AGapTheRobotFitsThroughIsNotFilled) {
  odometry();
  // 0.8 m apart (y = 1.65 and 2.45): wider than the robot (2 x 0.35 m), a passage.
  tactical(500'000, {{20, 16}, {20, 24}});
  lines(500'000, 2.12);
  EXPECT_FLOAT_EQ(rememberedAhead(540'000), -1.0f);
}

TEST(PilotConfig, RememberedOnLinesOffIgnoresTheLines) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotConfig c;
  c.remembered_on_lines_m = 0;
  PilotStage stage{node, c};
  line_map_t l{};
  l.utime = 1;
  node.publish(channels::AGM_LINES, l);
  drainAll(node);
  EXPECT_EQ(node.counter("remembered.line_maps"), 0);
}

// A dark face 1 m ahead (x = 2, the robot at (1, 2) facing +x): the scan sees it from -20 to
// +6 deg; beyond +6 deg nothing comes back (it turns too dark to detect). Returns the SECTOR_MAP
// and the continuation points counted.
namespace {
// With bad_offsets, the empty readings past +6 deg carry a negative time offset (rejected).
std::pair<sector_map_t, int64_t> mapOfADarkFace(double continuation_m, bool bad_offsets = false) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotConfig cfg;
  cfg.dark_continuation.length = continuation_m;
  PilotStage stage{node, cfg};
  std::vector<sector_map_t> maps;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&maps](const sector_map_t& m) { maps.push_back(m); });
  standStill(node, 0, 1'000'000);
  laser_scan_t s = noReturnScan(100'000, -kPi, 2 * kPi / 720, 720, 200'000);
  for (int i = 360 - 40; i <= 360 + 12; ++i) {  // reading 360 is straight ahead
    s.ranges[static_cast<size_t>(i)] = static_cast<float>(1.0 / std::cos(geom::deg2rad(0.5 * (i - 360))));
    s.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
  }
  if (bad_offsets)
    for (int i = 360 + 13; i <= 360 + 40; ++i) s.offset_us[static_cast<size_t>(i)] = -1;
  node.publish(channels::LASER_SCAN, s);
  drainAll(node);
  EXPECT_EQ(maps.size(), 1u);
  EXPECT_EQ(node.errors(), bad_offsets ? 28 : 0);
  return {maps.empty() ? sector_map_t{} : maps.back(), node.counter("laser.dark_continuation")};
}
}  // namespace

// The face goes on past its last return at +6 deg: with the continuation (0.10 m along it, to
// +11.6 deg) sector 25 (7.5-15 deg) holds it as a laser value at its 7.5 deg edge; without it
// (the paper) sector 25 has nothing. Beyond the continuation (sector 26) nothing either way.
TEST(PilotDarkContinuation, ADarkFaceGoesOnPastItsLastReturn) {
  const int seen = 24, dark = 25, beyond = 26;
  {
    const auto [m, points] = mapOfADarkFace(0.10);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_EQ(m.source[seen], kLaser);
    EXPECT_NEAR(m.laser_distance[seen], 1.0 - 0.35, 1e-4);
    EXPECT_EQ(m.source[dark], kLaser);
    EXPECT_NEAR(m.laser_distance[dark], 1.0 / std::cos(geom::deg2rad(7.5)) - 0.35, 0.01);
    EXPECT_EQ(m.source[beyond], kNone);
    EXPECT_GT(points, 10);  // both ends of the face
  }
  {
    const auto [m, points] = mapOfADarkFace(0.0);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_EQ(m.source[seen], kLaser);
    EXPECT_EQ(m.source[dark], kNone);
    EXPECT_FLOAT_EQ(m.laser_distance[dark], -1.0f);
    EXPECT_EQ(points, 0);
  }
  {
    // Readings rejected as malformed are no gap, whatever their flag: the +6 deg end is not
    // continued (the -20 deg end still is).
    const auto [m, points] = mapOfADarkFace(0.10, true);
    ASSERT_EQ(m.nsectors, 48);
    EXPECT_EQ(m.source[seen], kLaser);
    EXPECT_EQ(m.source[dark], kNone);
    EXPECT_GT(points, 0);
    EXPECT_LT(points, mapOfADarkFace(0.10).second);
  }
}

// A 360 deg scanner (720 readings of 0.5 deg) sees a face 1 m to the left of a standing robot;
// the next scan's readings there come back empty (a dark face at its detection limit), or hold a
// return 2 m away. Returns the last SECTOR_MAP's value in the sector to the left.
namespace {
sector_map_t mapAfterTheFaceGoesDark(bool memory_dark, bool farther_return) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotConfig cfg;
  cfg.laser_memory_dark = memory_dark;
  cfg.dark_continuation.length = 0;  // the memory alone
  PilotStage stage{node, cfg};
  std::vector<sector_map_t> maps;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&maps](const sector_map_t& m) { maps.push_back(m); });
  const auto drain = [&node] { drainAll(node); };
  standStill(node, 0, 1'000'000);
  drain();
  const auto scan = [&](int64_t utime, double range) {
    laser_scan_t s = noReturnScan(utime, -kPi, geom::deg2rad(0.5), 720, 200'000);
    if (range > 0)
      for (int i = 540 - 60; i <= 540 + 60; ++i) {  // +90 deg +- 30 deg: a face 1 m (or 2 m) to the left
        s.ranges[static_cast<size_t>(i)] = static_cast<float>(range / std::cos(geom::deg2rad(0.5 * (i - 540))));
        s.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
      }
    node.publish(channels::LASER_SCAN, s);
    drain();
  };
  scan(100'000, 1.0);
  scan(400'000, farther_return ? 2.0 : 0.0);
  EXPECT_EQ(maps.size(), 2u);
  return maps.empty() ? sector_map_t{} : maps.back();
}
}  // namespace

// An empty reading is no free space: the face a scan saw stays (as a laser value, remembered)
// while the next scan reads nothing there; a return in that bearing decides; without
// laser_memory_dark a 360 deg scanner's newest scan alone decides (the paper).
TEST(PilotLaserMemory, AFaceThatGoesDarkStaysUntilAReturnSaysOtherwise) {
  const int left = 36;  // [90, 97.5) deg
  ASSERT_TRUE(PilotConfig{}.laser_memory_dark);
  const sector_map_t dark = mapAfterTheFaceGoesDark(true, false);
  ASSERT_EQ(dark.nsectors, 48);
  EXPECT_EQ(dark.source[left], kLaser);
  EXPECT_NEAR(dark.laser_distance[left], 1.0 - 0.35, 0.01);
  const sector_map_t farther = mapAfterTheFaceGoesDark(true, true);
  ASSERT_EQ(farther.nsectors, 48);
  EXPECT_NEAR(farther.laser_distance[left], 2.0 - 0.35, 0.01);  // the face is gone: 2 m now
  const sector_map_t paper = mapAfterTheFaceGoesDark(false, false);
  ASSERT_EQ(paper.nsectors, 48);
  EXPECT_EQ(paper.source[left], kNone);
}

// A clock that jumps back (a restarted simulator, a looping log) starts the laser memory afresh:
// a face the memory held from before the restart is not reported where the first scan after it
// reads nothing.
TEST(PilotLaserMemory, AClockRestartForgetsWhatTheMemoryHeld) {
  const int left = 36;  // [90, 97.5) deg
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotStage stage{node, PilotConfig{}};
  std::vector<sector_map_t> maps;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&maps](const sector_map_t& m) { maps.push_back(m); });
  const auto scan = [&node](int64_t utime, bool face) {
    laser_scan_t s = noReturnScan(utime, -kPi, geom::deg2rad(0.5), 720, 200'000);
    if (face)
      for (int i = 540 - 60; i <= 540 + 60; ++i) {  // +90 deg +- 30 deg: a face 1 m to the left
        s.ranges[static_cast<size_t>(i)] = static_cast<float>(1.0 / std::cos(geom::deg2rad(0.5 * (i - 540))));
        s.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
      }
    node.publish(channels::LASER_SCAN, s);
    drainAll(node);
  };
  standStill(node, 0, 3'000'000);
  drainAll(node);
  scan(2'000'000, true);
  scan(2'300'000, false);
  ASSERT_FALSE(maps.empty());
  EXPECT_EQ(maps.back().source[left], kLaser);  // the face stays while the scan reads nothing there
  // The sources restart at 0.
  standStill(node, 0, 1'000'000);
  drainAll(node);
  scan(100'000, false);
  EXPECT_EQ(node.counter("time_resets"), 1);
  EXPECT_EQ(maps.back().utime, 100'000 + 719 * 200'000 / 720);
  EXPECT_EQ(maps.back().source[left], kNone);
}

// An echo that an earlier scan's lines explain where the newest scan does not look (class
// seen_before) is left out where the laser's returns the sector map holds report that surface in
// the echo's own sector, at its range; elsewhere it is the only report and goes in.
TEST_F(PilotFixture, ASeenBeforeEchoIsLeftOutOnlyWhereTheLaserHasThatSurface) {
  odometry();
  laserScan(100'000);  // one return, 1 m to the left: global (1, 3)
  const auto seenBefore = [](double theta, double range) {
    complement_reading_t r = reading(complement_reading_t::CLASS_SEEN_BEFORE, 1.0 + range * std::cos(theta),
                                     2.0 + range * std::sin(theta));
    r.range = static_cast<float>(range);
    r.hypothetical_range = static_cast<float>(range);
    r.sensor_pose = {1.0, 2.0, theta};
    return r;
  };
  // Towards the return at its range; towards it but 0.3 m short (the tolerance is 0.1 m); and
  // to the right, where the laser has nothing.
  complement_t c{};
  c.utime = 300'000;
  c.tolerance = 0.1f;
  c.beam_width = 0.5236f;
  c.readings = {seenBefore(kPi / 2, 1.0), seenBefore(kPi / 2, 0.7), seenBefore(-kPi / 2, 1.0)};
  node.publish(channels::SONAR_COMPLEMENT, c);
  drain();
  EXPECT_EQ(node.counter("agm.seen_before_left_out"), 1);
  EXPECT_EQ(node.counter("agm.hits"), 2);
  EXPECT_EQ(node.errors(), 0);
}

// An outside-view echo the newest scan's lines explain (redundant by the hypothesis: the message
// keeps that range) came from the surface the scan saw at the edge of its view: left out where
// the sector map holds a laser return in the echo's own sector, at any range (here 1.0 m for an
// echo of 0.7 m: on its axis it would lie in front of that return); kept where the laser reports
// nothing there, and kept when the hypothesis did not explain it (false: it passed that surface).
// With pilot.outside_view_redundant: echo every one goes in.
namespace {
void publishOutsideViewEchoes(Node& node) {
  const auto outsideView = [](double theta, double range, double hypothesis) {
    complement_reading_t r{};
    r.cls = complement_reading_t::CLASS_OUTSIDE_VIEW;
    r.range = static_cast<float>(range);
    r.hypothetical_range = static_cast<float>(hypothesis);
    r.end_x = 1.0 + range * std::cos(theta);
    r.end_y = 2.0 + range * std::sin(theta);
    r.sensor_pose = {1.0, 2.0, theta};
    r.beam_width = 0.5236f;
    return r;
  };
  complement_t c{};
  c.utime = 300'000;
  c.tolerance = 0.1f;
  c.beam_width = 0.5236f;
  c.readings = {outsideView(kPi / 2, 0.7, 0.75), outsideView(-kPi / 2, 0.7, 0.75), outsideView(kPi / 2, 0.7, 0.5)};
  node.publish(channels::SONAR_COMPLEMENT, c);
}
PilotConfig everyOutsideViewEcho() {
  PilotConfig c = nearestPointPilot();
  c.outside_view_redundant_laser = false;
  return c;
}
struct PilotEveryOutsideViewEcho : PilotFixture {
  PilotEveryOutsideViewEcho() : PilotFixture(everyOutsideViewEcho()) {}
};
}  // namespace

TEST_F(PilotFixture, AnExplainedOutsideViewEchoIsLeftOutWhereTheLaserReportsItsSector) {
  ASSERT_TRUE(PilotConfig{}.outside_view_redundant_laser);
  odometry();
  laserScan(100'000);  // one return, 1 m to the left: global (1, 3)
  publishOutsideViewEchoes(node);
  drain();
  EXPECT_EQ(node.counter("agm.outside_view_redundant_left_out"), 1);
  EXPECT_EQ(node.counter("agm.hits"), 2);
  EXPECT_EQ(node.errors(), 0);
}

TEST_F(PilotEveryOutsideViewEcho, WithEchoEveryOutsideViewEchoGoesIn) {
  odometry();
  laserScan(100'000);
  publishOutsideViewEchoes(node);
  drain();
  EXPECT_EQ(node.counter("agm.outside_view_redundant_left_out"), 0);
  EXPECT_EQ(node.counter("agm.hits"), 3);
}

// The operational AGM's memory is three ring cycles counted from the firings: on a ring of 8
// groups (the Pioneer's) a cell heard once is kept for 24 update cycles, not the 18 of agm.h_max
// (MOBOT-IV's 6 groups); with h_max_ring_cycles 0, agm.h_max on any ring.
namespace {
// G of the AGM after one echo in the first of `groups` x 3 firing groups of 40 ms: the grid
// published after cycle `after` (every cycle is published).
int heardWeightAfter(double ring_cycles, int groups, int after) {
  PilotConfig cfg = nearestPointPilot();
  cfg.h_max_ring_cycles = ring_cycles;
  cfg.hold_unpassed.ring_cycles = 0;  // the paper's forgetting (no sound passes the cell here)
  cfg.agm_publish_hz = 1000;
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotStage stage(node, cfg);
  std::vector<grid_map_t> grids;
  node.subscribe<grid_map_t>(channels::AGM_OPERATIONAL, [&](const grid_map_t& m) { grids.push_back(m); });
  const auto drain = [&] { drainAll(node); };
  standStill(node, 0, 2'000'000);
  drain();
  for (int k = 0; k <= after; ++k) {
    complement_t c{};
    c.utime = 100'000 + 40'000 * k;
    c.group = static_cast<int16_t>(k % groups);
    c.tolerance = 0.1f;
    if (k == 0) c.readings.push_back(PilotFixture::reading(complement_reading_t::CLASS_COMPLEMENTARY, 2.05, 2.05));
    node.publish(channels::SONAR_COMPLEMENT, c);
    drain();
  }
  if (grids.empty() || grids.back().utime != 100'000 + 40'000 * after) return -1;
  int g = 0;
  for (const int16_t v : grids.back().g) g = std::max<int>(g, v);
  return g;
}
}  // namespace

TEST(PilotRingMemory, TheAgmForgetsAfterThreeRingCyclesOfTheRingItHears) {
  ASSERT_EQ(PilotConfig{}.h_max_ring_cycles, 3);
  ASSERT_EQ(PilotConfig{}.agm.h_max, 18);
  EXPECT_EQ(heardWeightAfter(3, 8, 18), 1);  // heard 18 cycles ago: kept on either ring
  EXPECT_EQ(heardWeightAfter(3, 8, 24), 1);  // 24: three of this ring's cycles
  EXPECT_EQ(heardWeightAfter(3, 8, 25), 0);
  EXPECT_EQ(heardWeightAfter(3, 6, 18), 1);  // MOBOT-IV's ring: 18
  EXPECT_EQ(heardWeightAfter(3, 6, 19), 0);
  EXPECT_EQ(heardWeightAfter(0, 8, 19), 0);  // agm.h_max, whatever the ring
}

namespace {
// Forgetting only what the sonar could have heard: one echo at (2.05, 2.05) in the first of
// MOBOT-IV's six firing groups (30 ms), then groups that hear nothing there, or from group
// `pass_from` on a reading whose beam goes through that cell (a transducer at (1.35, 2.05)
// facing +x, echo at 2.0 m: the cell 0.7 m away). G of the AGM published after cycle `after`.
// A pilot whose robot stands at (1, 2) for 3 s, every AGM_OPERATIONAL it publishes kept.
struct StandingPilot {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotStage stage;
  std::vector<grid_map_t> grids;
  static PilotConfig everyGrid(PilotConfig c) {
    c.agm_publish_hz = 1000;
    return c;
  }
  explicit StandingPilot(const PilotConfig& cfg) : stage(node, everyGrid(cfg)) {
    node.subscribe<grid_map_t>(channels::AGM_OPERATIONAL, [this](const grid_map_t& m) { grids.push_back(m); });
    standStill(node, 0, 3'000'000);
    drainAll(node);
  }
};

int keptWeightAfter(int after, int pass_from, double hold_ring_cycles = 4) {
  PilotConfig cfg = nearestPointPilot();
  cfg.hold_unpassed.ring_cycles = hold_ring_cycles;
  StandingPilot pilot(cfg);
  Node& node = pilot.node;
  const std::vector<grid_map_t>& grids = pilot.grids;
  for (int k = 0; k <= after; ++k) {
    complement_t c{};
    c.utime = 100'000 + 30'000 * k;
    c.group = static_cast<int16_t>(k % 6);
    c.tolerance = 0.1f;
    if (k == 0) c.readings.push_back(PilotFixture::reading(complement_reading_t::CLASS_COMPLEMENTARY, 2.05, 2.05));
    if (k >= pass_from) {
      complement_reading_t r = PilotFixture::reading(complement_reading_t::CLASS_REDUNDANT, 3.35, 2.05);
      r.range = r.hypothetical_range = 2.0f;
      r.sensor_pose = {1.35, 2.05, 0.0};
      c.readings.push_back(r);
    }
    node.publish(channels::SONAR_COMPLEMENT, c);
    drainAll(node);
  }
  if (grids.empty() || grids.back().utime != 100'000 + 30'000 * after) return -1;
  int g = 0;
  for (const int16_t v : grids.back().g) g = std::max<int>(g, v);
  return g;
}
}  // namespace

TEST(PilotRingMemory, ACellNoSoundWentThroughIsKeptUntilSoundDoes) {
  ASSERT_EQ(PilotConfig{}.hold_unpassed.ring_cycles, 4);
  // h_max: three ring cycles (18 groups); then four more (24) while no sound goes through it.
  EXPECT_EQ(keptWeightAfter(18, 1000), 1);
  EXPECT_EQ(keptWeightAfter(19, 1000, 0), 0);  // the paper: forgotten after h_max
  EXPECT_EQ(keptWeightAfter(19, 1000), 1);
  EXPECT_EQ(keptWeightAfter(42, 1000), 1);
  EXPECT_EQ(keptWeightAfter(43, 1000), 0);
  // Sound through it after h_max: forgotten then, not later.
  EXPECT_EQ(keptWeightAfter(29, 30), 1);
  EXPECT_EQ(keptWeightAfter(30, 30), 0);
  // ... and sound through it before: forgotten after h_max as the paper's.
  EXPECT_EQ(keptWeightAfter(19, 5), 0);
}

// A person the laser sees walking may have made the cells near them: those go after h_max, as
// the paper's, and are not kept for want of sound through them. The robot stands at (1, 2); a
// person 1 m away walks round it at 1 m/s (a 20 deg arc of returns, 11.5 deg further each 0.2 s
// scan of a 360 deg scanner); one echo at 0.61 s lands on the cell the person stands on then;
// the next scans see them walk on past it. G of that cell at 1.4 s (the echo 0.79 s old: beyond
// h_max's 0.54 s, within the hold's 1.26 s).
namespace {
int echoCellNearAWalkerAfter(double mover_radius_m) {
  PilotConfig cfg = nearestPointPilot();
  cfg.hold_unpassed.mover_radius_m = mover_radius_m;
  StandingPilot pilot(cfg);
  Node& node = pilot.node;
  const std::vector<grid_map_t>& grids = pilot.grids;
  const auto bearing = [](int64_t scan_start) { return geom::deg2rad(-45.0) + 1.0 * static_cast<double>(scan_start) * 1e-6; };
  const int64_t echo_us = 610'000;
  const double b_echo = bearing(600'000);
  const geom::Vec2 echo(1.0 + std::cos(b_echo), 2.0 + std::sin(b_echo));
  int64_t next_scan = 0;
  for (int k = 0; 30'000 * k <= 1'400'000; ++k) {
    const int64_t t = 30'000 * k + 10'000;
    while (next_scan + 200'000 <= t) {  // a scan is published once its last reading is taken
      laser_scan_t sc = noReturnScan(next_scan, -kPi, geom::deg2rad(0.5), 720, 200'000);
      const double b = bearing(next_scan);
      for (int i = 0; i < 720; ++i) {
        const double a = -kPi + geom::deg2rad(0.5) * i;
        if (std::abs(geom::angleDiff(a, b)) <= geom::deg2rad(10.0)) {
          sc.ranges[static_cast<size_t>(i)] = 1.0f;
          sc.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
        }
      }
      node.publish(channels::LASER_SCAN, sc);
      drainAll(node);
      next_scan += 200'000;
    }
    complement_t c{};
    c.utime = t;
    c.group = static_cast<int16_t>(k % 6);
    c.tolerance = 0.1f;
    if (t == echo_us) c.readings.push_back(PilotFixture::reading(complement_reading_t::CLASS_COMPLEMENTARY, echo.x(), echo.y()));
    node.publish(channels::SONAR_COMPLEMENT, c);
    drainAll(node);
  }
  EXPECT_GT(node.counter("laser.moving_returns"), 0);
  if (grids.empty()) return -1;
  const grid_map_t& g = grids.back();
  const auto ix = static_cast<int>(std::floor((echo.x() - g.origin_x) / g.cell_size));
  const auto iy = static_cast<int>(std::floor((echo.y() - g.origin_y) / g.cell_size));
  if (ix < 0 || iy < 0 || ix >= g.width || iy >= g.height) return -1;
  return g.g[static_cast<size_t>(iy * g.width + ix)];
}
}  // namespace

TEST(PilotRingMemory, CellsNearAPersonTheLaserSeesWalkingAreNotKept) {
  ASSERT_GT(PilotConfig{}.hold_unpassed.mover_radius_m, 0.0);
  EXPECT_EQ(echoCellNearAWalkerAfter(PilotConfig{}.hold_unpassed.mover_radius_m), 0);
  EXPECT_EQ(echoCellNearAWalkerAfter(0.0), 1);  // kept: no sound went through it
}

// A robot turning on the spot at 1 rad/s against a 360 deg scanner's sweep (clockwise against
// counter-clockwise), inside a round room 1 m away everywhere: each 0.2 s scan's readings,
// taken at their own headings, cover 360 deg less 11.5 deg in its last reading's frame, a wedge
// at the seam behind the robot. The laser memory keeps the scan before's returns there, so
// every sector keeps its wall.
namespace {
// The last SECTOR_MAP of a robot standing at (1, 2) and turning at -1 rad/s, after four 0.2 s
// scans of a round room 1 m away (every reading returns).
sector_map_t turningInARoundRoom(const PilotConfig& config) {
  Node node{"t", "memq://", Node::Options{false, false}};
  PilotStage stage(node, config);
  std::vector<sector_map_t> maps;
  node.subscribe<sector_map_t>(channels::SECTOR_MAP, [&maps](const sector_map_t& m) { maps.push_back(m); });
  for (int64_t t = 0; t <= 1'000'000; t += 20'000) {
    odometry_t o{};
    o.utime = t;
    o.pose = {1.0, 2.0, -1.0 * static_cast<double>(t) * 1e-6};
    o.omega = -1.0;
    node.publish(channels::ODOMETRY, o);
  }
  drainAll(node);
  for (int64_t scan = 0; scan < 4; ++scan) {
    laser_scan_t s = noReturnScan(scan * 200'000, -kPi, 2 * kPi / 720, 720, 200'000);
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      s.ranges[i] = 1.0f;
      s.flags[i] = laser_scan_t::FLAG_OK;
    }
    node.publish(channels::LASER_SCAN, s);
    drainAll(node);
  }
  return maps.empty() ? sector_map_t{} : maps.back();
}
}  // namespace

TEST(PilotStage, ATurnAgainstTheSweepLeavesNoSectorWithoutItsWall) {
  const sector_map_t m = turningInARoundRoom(PilotConfig{});
  ASSERT_EQ(m.nsectors, 48);
  int walls = 0;
  for (int k = 0; k < m.nsectors; ++k) {
    const auto i = static_cast<size_t>(k);
    EXPECT_EQ(m.source[i], kLaser) << "sector " << k;
    if (m.source[i] == kLaser) walls += std::abs(m.laser_distance[i] - 0.65f) < 0.02f;  // 1 m less the radius
  }
  EXPECT_EQ(walls, m.nsectors);
  // pilot.laser_memory_seam: false: the scan covers every bearing, and the wedge has no wall.
  PilotConfig seamless;
  seamless.laser_memory_seam = false;
  const sector_map_t n = turningInARoundRoom(seamless);
  ASSERT_EQ(n.nsectors, 48);
  int without = 0;
  for (int k = 0; k < n.nsectors; ++k) without += n.source[static_cast<size_t>(k)] != kLaser;
  EXPECT_GE(without, 1);
  EXPECT_LE(without, 2);  // 11.5 deg: at most two sectors of 7.5
}
