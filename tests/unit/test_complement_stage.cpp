// ComplementStage on memq://: outputs, class counters, stale Radar Map policy, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <lasonic/complement_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/line_map_t.hpp>

#include "complement_fixture.hpp"
#include "lcmio/node.hpp"
#include "stages/complement_stage.hpp"

using namespace lasonic;

// The generated CLASS_* are `static const` members without a definition: gtest's EXPECT_EQ
// takes references, so compare against local copies.
constexpr int8_t kComplementary = complement_reading_t::CLASS_COMPLEMENTARY;
constexpr int8_t kRedundant = complement_reading_t::CLASS_REDUNDANT;
constexpr int8_t kUnverifiable = complement_reading_t::CLASS_UNVERIFIABLE;
constexpr int8_t kInvalid = complement_reading_t::CLASS_INVALID;

namespace {

class StageTest : public ::testing::Test {
 protected:
  StageTest() : node("test-complement", "memq://", Node::Options{false, false}), stage(node, complementConfig(Config{})) {
    node.subscribe<line_map_t>(channels::RADAR_MAP, [this](const line_map_t& m) { maps.push_back(m); });
    node.subscribe<hypothetical_scan_t>(channels::SONAR_HYPOTHESIS,
                                        [this](const hypothetical_scan_t& m) { hyps.push_back(m); });
    node.subscribe<complement_t>(channels::SONAR_COMPLEMENT, [this](const complement_t& m) { comps.push_back(m); });
  }
  template <typename T>
  void send(const char* channel, T msg) {
    node.publish(channel, msg);
    while (node.spinOnce(0) > 0) {
    }
  }
  // Odometry every 20 ms over [t0, t1] for the still Fig. 4 robot.
  void odometry(int64_t t0, int64_t t1) {
    for (int64_t t = t0; t <= t1; t += 20'000) send(channels::ODOMETRY, fixture::odometryAt(traj, t));
  }
  void scan(int64_t t0) { send(channels::LASER_SCAN, fixture::simulateScan(fixture::fig4Room(), traj, t0, 100'000)); }
  void ring(int64_t t, std::vector<int> ids, std::vector<double> ranges) {
    send(channels::SONAR_RING, fixture::sonarGroup(t, 0, ids, ranges));
  }
  int8_t cls(size_t i) const { return comps.back().readings.at(i).cls; }

  fixture::Trajectory traj = fixture::still(fixture::fig4RobotPose());
  Node node;
  ComplementStage stage;
  std::vector<line_map_t> maps;
  std::vector<hypothetical_scan_t> hyps;
  std::vector<complement_t> comps;
};

// Fig. 4, sensor 6 faces the glass door (1.5 m), sensor 0 the right wall (1.7 m).
constexpr int kDoor = 6, kWall = 0;

}  // namespace

TEST_F(StageTest, PublishesRadarMapHypothesisAndComplementAndCountsClasses) {
  odometry(0, 200'000);
  scan(0);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps[0].nsegments, 5);
  EXPECT_EQ(maps[0].source_utime, 0);
  ring(150'000, {kDoor, kWall}, {1.5, 1.7});
  ASSERT_EQ(hyps.size(), 1u);
  ASSERT_EQ(comps.size(), 1u);
  EXPECT_EQ(comps[0].radar_map_stale, 0);
  EXPECT_EQ(comps[0].radar_map_utime, maps[0].utime);
  EXPECT_EQ(cls(0), kComplementary);
  EXPECT_EQ(cls(1), kRedundant);
  EXPECT_NEAR(hyps[0].range[0], 2.20f, 1e-6);
  EXPECT_NEAR(hyps[0].range[1], 1.7f, 1e-3);
  EXPECT_EQ(node.counter("class.complementary"), 1);
  EXPECT_EQ(node.counter("class.redundant"), 1);
  EXPECT_EQ(node.errors(), 0);
}

TEST_F(StageTest, BeforeTheFirstScanEverythingIsUnverifiableAndFlagged) {
  odometry(0, 100'000);
  ring(50'000, {kDoor, kWall}, {1.5, 1.7});
  ASSERT_EQ(comps.size(), 1u);
  EXPECT_EQ(comps[0].radar_map_stale, 1);
  EXPECT_EQ(comps[0].radar_map_utime, 0);
  EXPECT_EQ(hyps[0].radar_map_stale, 1);
  EXPECT_EQ(cls(0), kUnverifiable);
  EXPECT_EQ(cls(1), kUnverifiable);
  EXPECT_EQ(node.counter("unverifiable.stale_radar_map"), 2);
  EXPECT_EQ(node.counter("class.complementary"), 0);
}

TEST_F(StageTest, AStaleRadarMapIsFlaggedNotTrusted) {
  odometry(0, 2'000'000);
  scan(0);
  ring(1'900'000, {kDoor}, {1.5});  // RM ends at ~0.1 s; default limit 0.5 s
  EXPECT_EQ(comps.back().radar_map_stale, 1);
  EXPECT_EQ(cls(0), kUnverifiable);
  EXPECT_EQ(node.counter("unverifiable.stale_radar_map"), 1);
}

// A laser that had been scanning and stops is an outage: laser.lost once (an error), however many
// groups go unverifiable; back, it is fresh again, and another stop is another outage.
TEST_F(StageTest, ALaserOutageIsReportedOnce) {
  odometry(0, 5'000'000);
  ring(50'000, {kDoor}, {1.5});  // before the first scan: not an outage
  scan(100'000);                  // its last reading at 0.2 s
  for (int64_t t = 250'000; t < 800'000; t += 30'000) ring(t, {kDoor}, {1.5});
  EXPECT_EQ(comps.back().radar_map_stale, 1);
  EXPECT_EQ(node.counter("laser.lost"), 0);  // one scan: no pace it has missed yet
  scan(800'000);                              // 0.7 s later: fresh
  for (int64_t t = 950'000; t < 2'500'000; t += 30'000) ring(t, {kDoor}, {1.5});
  EXPECT_EQ(comps.back().radar_map_stale, 1);
  EXPECT_EQ(node.counter("laser.lost"), 1);  // silent for more than twice its 0.7 s
  scan(2'500'000);
  ring(2'650'000, {kDoor}, {1.5});
  EXPECT_EQ(comps.back().radar_map_stale, 0);
  ring(4'200'000, {kDoor}, {1.5});  // 1.6 s after it: the 0.7 s pace again, not the outage's gap
  EXPECT_EQ(node.counter("laser.lost"), 2);
  EXPECT_EQ(node.errors(), 2);
}

// The Radar Map's age limit in the laser's own periods: a 1 Hz scanner's map verifies the rings
// up to 2.5 s after it (rm_max_age_scans 2.5), where 0.5 s would leave most of them unverifiable;
// with rm_max_age_scans 0 the configured 0.5 s holds.
TEST(ComplementStageRate, TheRadarMapAgeLimitFollowsASlowScanner) {
  const fixture::Trajectory traj = fixture::still(fixture::fig4RobotPose());
  for (const double scans : {2.5, 0.0}) {
    Node node("test-complement", "memq://", Node::Options{false, false});
    ComplementStage stage(node, complementConfig(Config::fromString("rm_max_age_scans: " + std::to_string(scans))));
    std::vector<complement_t> comps;
    node.subscribe<complement_t>(channels::SONAR_COMPLEMENT, [&](const complement_t& m) { comps.push_back(m); });
    auto send = [&](const char* channel, const auto& msg) {
      node.publish(channel, msg);
      while (node.spinOnce(0) > 0) {
      }
    };
    for (int64_t t = 0; t <= 8'000'000; t += 20'000) send(channels::ODOMETRY, fixture::odometryAt(traj, t));
    for (int64_t t = 0; t <= 4'000'000; t += 1'000'000)  // 1 Hz: timed after the fourth scan
      send(channels::LASER_SCAN, fixture::simulateScan(fixture::fig4Room(), traj, t, 100'000));
    send(channels::SONAR_RING, fixture::sonarGroup(5'000'000, 0, {kDoor}, {1.5}));  // 0.9 s after the map
    ASSERT_FALSE(comps.empty());
    EXPECT_EQ(comps.back().radar_map_stale, scans > 0 ? 0 : 1) << scans;
    send(channels::SONAR_RING, fixture::sonarGroup(7'000'000, 0, {kDoor}, {1.5}));  // 2.9 s after: stale
    EXPECT_EQ(comps.back().radar_map_stale, 1) << scans;
  }
}

TEST_F(StageTest, BadSonarReadingsAreInvalidAndTheStageGoesOn) {
  odometry(0, 200'000);
  scan(0);
  ring(150'000, {kDoor, kWall, 30}, {std::numeric_limits<double>::quiet_NaN(), 1.7, 1.0});
  EXPECT_EQ(cls(0), kInvalid);
  EXPECT_EQ(cls(1), kRedundant);
  EXPECT_EQ(cls(2), kInvalid);
  EXPECT_EQ(node.counter("rejected.sonar_range"), 1);
  EXPECT_EQ(node.counter("rejected.sonar_id"), 1);
  EXPECT_EQ(node.counter("class.invalid"), 2);
  ring(160'000, {kDoor}, {1.5});  // still working
  EXPECT_EQ(cls(0), kComplementary);
}

TEST_F(StageTest, TimestampsGoingBackwardsAreRejected) {
  odometry(0, 300'000);
  send(channels::ODOMETRY, fixture::odometryAt(traj, 100'000));
  EXPECT_EQ(node.counter("rejected.odometry_backwards"), 1);
  scan(100'000);
  scan(50'000);
  EXPECT_EQ(maps.size(), 1u);
  EXPECT_EQ(node.counter("rejected.laser_backwards"), 1);
  ring(200'000, {kDoor}, {1.5});
  ring(200'000, {kDoor}, {1.5});  // the same group again
  ring(150'000, {kDoor}, {1.5});  // an older one
  EXPECT_EQ(comps.size(), 1u);
  EXPECT_EQ(node.counter("rejected.sonar_backwards"), 2);
  ring(210'000, {kDoor}, {1.5});  // the next one is taken
  EXPECT_EQ(comps.size(), 2u);
}

TEST_F(StageTest, OneStrayTimeFarAheadIsDroppedAndForgetsNothing) {
  odometry(0, 200'000);
  scan(0);
  ASSERT_EQ(maps.size(), 1u);
  // One odometry message stamped an hour ahead (a clock stepped on one computer), then the
  // stream goes on: accepted, it would make the next message look like a restarted clock.
  send(channels::ODOMETRY, fixture::odometryAt(traj, 3'600'000'000));
  odometry(220'000, 300'000);
  EXPECT_EQ(node.counter("time_resets"), 0);
  EXPECT_EQ(node.counter("rejected.time_ahead"), 1);
  ring(250'000, {kDoor}, {1.5});  // the Radar Map and the poses are still there
  EXPECT_EQ(cls(0), kComplementary);
  EXPECT_EQ(comps.back().radar_map_stale, 0);
}

TEST_F(StageTest, MissingOdometryMakesTheGroupInvalidAndKeepsTheRadarMap) {
  ring(0, {kDoor}, {1.5});  // no odometry at all yet
  EXPECT_EQ(cls(0), kInvalid);
  EXPECT_EQ(node.counter("rejected.sonar_no_odometry"), 1);
  scan(0);  // no pose for any reading: no Radar Map
  EXPECT_TRUE(maps.empty());
  EXPECT_EQ(node.counter("rejected.laser_no_odometry"), 1);
}

TEST_F(StageTest, AScanWithoutAPoseAtItsLastReadingKeepsThePreviousRadarMap) {
  odometry(0, 300'000);
  scan(0);
  ASSERT_EQ(maps.size(), 1u);
  // Odometry stops at 0.3 s; the poses are held 0.2 s beyond. The next scan's readings are all
  // placed but its last one, a gap, comes 0.6 s later: the map would be seen from nowhere
  // (the odometry origin) and its view and poles placed there.
  laser_scan_t s = fixture::simulateScan(fixture::fig4Room(), traj, 200'000, 100'000);
  s.flags.back() = laser_scan_t::FLAG_NO_RETURN;
  s.offset_us.back() = 700'000;
  send(channels::LASER_SCAN, s);
  EXPECT_EQ(maps.size(), 1u);
  EXPECT_EQ(node.counter("rejected.laser_no_odometry"), 1);
  ring(250'000, {kDoor, kWall}, {1.5, 1.7});  // classified on the first map
  EXPECT_EQ(comps.back().radar_map_utime, maps[0].utime);
  EXPECT_EQ(cls(0), kComplementary);
  EXPECT_EQ(cls(1), kRedundant);
}

TEST_F(StageTest, AScanOfMalformedReadingsOnlyKeepsThePreviousRadarMap) {
  odometry(0, 300'000);
  scan(0);
  ASSERT_EQ(maps.size(), 1u);
  laser_scan_t s = fixture::simulateScan(fixture::fig4Room(), traj, 100'000, 100'000);
  for (auto& f : s.flags) f = 7;  // no such flag
  send(channels::LASER_SCAN, s);
  EXPECT_EQ(maps.size(), 1u);
  EXPECT_EQ(node.counter("rejected.laser_flag"), static_cast<int64_t>(s.flags.size()));
  EXPECT_EQ(node.counter("rejected.laser_scan"), 1);
  ring(150'000, {kWall}, {1.7});  // an empty map would make the wall's echo complementary
  EXPECT_EQ(cls(0), kRedundant);
  // A scan of gaps only is a reading of an empty room, not a broken one: it replaces the map.
  s = fixture::simulateScan(fixture::fig4Room(), traj, 200'000, 100'000);
  for (auto& f : s.flags) f = laser_scan_t::FLAG_NO_RETURN;
  send(channels::LASER_SCAN, s);
  EXPECT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps.back().nsegments, 0);
}

TEST_F(StageTest, SensorsFiredTogetherWithOverlappingBeamsAreReportedOnce) {
  odometry(0, 400'000);
  scan(0);
  ring(150'000, {kDoor, kWall}, {1.5, 1.7});  // 90 deg apart: fine
  EXPECT_EQ(node.counter("ring.overlapping_beams"), 0);
  ring(180'000, {kWall, kWall + 1}, {1.7, 1.7});  // 15 deg apart, 30 deg beams
  ring(210'000, {kWall, kWall + 1}, {1.7, 1.7});  // the same pair again: reported once
  EXPECT_EQ(node.counter("ring.overlapping_beams"), 1);
  ASSERT_EQ(comps.size(), 3u);  // and still classified
}

TEST_F(StageTest, ALateEchoOfTheGroupBeforeIsExplainedByTheFarWall) {
  // A hall whose far wall (x = 6 m from the robot) lies beyond the sonar's range. Sensor 0
  // faces it and pings; 30 ms later sensor 1 (15 deg) hears that ping come back by way of the
  // wall: at half the mirror path less half the 10.3 m sound has gone since, about 0.56 m.
  traj = fixture::still({0, 0, 0});
  fixture::World hall;
  hall.laser_visible = {{{6, -3}, {6, 3}}, {{6, 3}, {-2, 3}}, {{-2, 3}, {-2, -3}}, {{-2, -3}, {6, -3}}};
  odometry(0, 400'000);
  send(channels::LASER_SCAN, fixture::simulateScan(hall, traj, 0, 100'000));
  const auto mounts = fixture::ringMounts();
  const geom::Vec2 e = mounts[0].position(), p = mounts[1].position();
  const double late = 0.5 * (geom::Vec2(12.0 - e.x(), e.y()) - p).norm() - 0.5 * 343.0 * 0.030;
  send(channels::SONAR_RING, fixture::sonarGroup(150'000, 0, {0}, {-1.0}));  // no echo within 3 m
  send(channels::SONAR_RING, fixture::sonarGroup(180'000, 1, {1}, {late + 0.02}));
  ASSERT_EQ(comps.size(), 2u);
  EXPECT_EQ(cls(0), kRedundant);
  EXPECT_NEAR(comps.back().readings[0].hypothetical_range, late, 0.02);  // the Radar Map's line, not the wall itself
  EXPECT_EQ(node.counter("redundant.late_echo"), 1);
  // The same reading 80 ms after the ping (beyond the 65 ms window): complementary.
  send(channels::SONAR_RING, fixture::sonarGroup(260'000, 1, {1}, {late + 0.02}));
  EXPECT_EQ(cls(0), kComplementary);
  EXPECT_EQ(node.counter("redundant.late_echo"), 1);
}

// A laser and a sonar on computers whose clocks run ahead of the odometry's (README "Clocks"):
// reported, named, counted, and the data still used.
TEST_F(StageTest, AClockAheadOfTheOdometryIsReportedAndTheDataStillUsed) {
  odometry(0, 200'000);
  scan(0);  // one clock: nothing to report
  EXPECT_EQ(node.counter("time.laser_ahead_of_odometry"), 0);
  scan(250'000);  // its last reading 150 ms after the newest odometry
  EXPECT_EQ(maps.size(), 2u);
  EXPECT_EQ(node.counter("time.laser_ahead_of_odometry"), 1);
  EXPECT_NE(node.status().lastError().find("LASER_SCAN stamped 150 ms later than the newest ODOMETRY"), std::string::npos)
      << node.status().lastError();
  ring(300'000, {kDoor}, {1.5});
  ASSERT_EQ(comps.size(), 1u);
  EXPECT_EQ(cls(0), kComplementary);
  EXPECT_EQ(node.counter("time.sonar_ahead_of_odometry"), 1);
  EXPECT_NE(node.status().lastError().find("SONAR_RING stamped 100 ms later"), std::string::npos) << node.status().lastError();
  ring(310'000, {kDoor}, {1.5});  // once per 5 s of odometry time
  EXPECT_EQ(node.counter("time.sonar_ahead_of_odometry"), 1);
  EXPECT_EQ(node.counter("time.laser_behind_odometry") + node.counter("time.sonar_behind_odometry"), 0);
}
