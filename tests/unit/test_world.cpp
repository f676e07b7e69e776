// The simulated world: path following, movers, odometry drift, ray casting.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <string>

#include "sim/drivers.hpp"
#include "sim/path_follower.hpp"
#include "sim/world_geometry.hpp"

using namespace lasonic;
using namespace lasonic::sim;
using geom::kPi;
using geom::Vec2;

namespace {

Scenario parse(const std::string& yaml) { return parseScenario(Config::fromString(yaml, "test.yaml")); }

void expectPose(const PathFollower::State& s, double x, double y, double theta) {
  EXPECT_NEAR(s.pose.x, x, 1e-9);
  EXPECT_NEAR(s.pose.y, y, 1e-9);
  EXPECT_NEAR(geom::angleDiff(s.pose.theta, theta), 0.0, 1e-9);
}

}  // namespace

TEST(PathFollower, DrivesLegsAndTurnsOnTheSpot) {
  // 2 m east, then 2 m north, at 0.5 m/s, turning at 1 rad/s.
  const PathFollower f({{0, 0}, {2, 0}, {2, 2}}, PathMode::Once, 0.5, 1.0);
  expectPose(f.at(0), 0, 0, 0);  // starts at the first waypoint facing the second
  expectPose(f.at(2), 1, 0, 0);
  EXPECT_DOUBLE_EQ(f.at(2).v, 0.5);
  EXPECT_DOUBLE_EQ(f.at(2).omega, 0.0);
  // Turn of pi/2 from t = 4 to 4 + pi/2, on the spot.
  const PathFollower::State turning = f.at(4 + kPi / 4);
  expectPose(turning, 2, 0, kPi / 4);
  EXPECT_DOUBLE_EQ(turning.v, 0.0);
  EXPECT_DOUBLE_EQ(turning.omega, 1.0);
  expectPose(f.at(4 + kPi / 2 + 2), 2, 1, kPi / 2);
  EXPECT_NEAR(f.cycleDuration(), 8 + kPi / 2, 1e-12);
  // After a `once` path the robot stands still at its end.
  const PathFollower::State end = f.at(100);
  expectPose(end, 2, 2, kPi / 2);
  EXPECT_EQ(end.v, 0.0);
  EXPECT_EQ(end.omega, 0.0);
}

TEST(PathFollower, TurnsTheShortWay) {
  // East, then south-east: a right turn of pi/4.
  const PathFollower f({{0, 0}, {1, 0}, {2, -1}}, PathMode::Once, 1.0, 0.5);
  const PathFollower::State s = f.at(1 + 0.5 * (kPi / 4) / 0.5);
  EXPECT_NEAR(s.pose.theta, -kPi / 8, 1e-9);
  EXPECT_DOUBLE_EQ(s.omega, -0.5);
}

TEST(PathFollower, PingPongComesBack) {
  // A mover: instant turns.
  const PathFollower f({{0, 0}, {1, 0}}, PathMode::PingPong, 1.0);
  EXPECT_NEAR(f.at(0.5).pose.x, 0.5, 1e-12);
  EXPECT_NEAR(f.at(1.5).pose.x, 0.5, 1e-12);
  EXPECT_NEAR(f.at(1.5).pose.theta, kPi, 1e-12);
  EXPECT_NEAR(f.at(1.9).pose.x, 0.1, 1e-12);
  EXPECT_NEAR(f.at(2.5).pose.x, 0.5, 1e-12);
  EXPECT_NEAR(f.at(2.5).pose.theta, 0, 1e-12);
  EXPECT_NEAR(f.cycleDuration(), 2.0, 1e-12);
}

TEST(PathFollower, PingPongRobotTurnsAroundAtTheEnds) {
  const PathFollower f({{0, 0}, {1, 0}}, PathMode::PingPong, 1.0, 1.0);
  // Arrives at t = 1, turns pi in pi seconds, drives back, turns pi again.
  expectPose(f.at(1 + kPi / 2), 1, 0, kPi / 2);
  expectPose(f.at(1 + kPi + 0.5), 0.5, 0, kPi);
  EXPECT_NEAR(f.cycleDuration(), 2 + 2 * kPi, 1e-12);
  expectPose(f.at(f.cycleDuration() + 0.5), 0.5, 0, 0);
}

TEST(PathFollower, LoopClosesThePath) {
  const PathFollower f({{0, 0}, {1, 0}, {1, 1}}, PathMode::Loop, 1.0);
  EXPECT_NEAR(f.cycleDuration(), 2 + std::sqrt(2.0), 1e-12);
  expectPose(f.at(2 + std::sqrt(0.5)), 0.5, 0.5, -3 * kPi / 4);  // on the closing leg
  expectPose(f.at(f.cycleDuration() + 0.25), 0.25, 0, 0);
  // A path that already ends at its start gets no extra leg.
  const PathFollower closed({{0, 0}, {1, 0}, {1, 1}, {0, 0}}, PathMode::Loop, 1.0);
  EXPECT_NEAR(closed.cycleDuration(), f.cycleDuration(), 1e-12);
}

TEST(PathFollower, StartDelay) {
  const PathFollower f({{0, 0}, {2, 0}}, PathMode::Once, 1.0, 1.0, 3.0);
  expectPose(f.at(2.9), 0, 0, 0);
  EXPECT_EQ(f.at(2.9).v, 0.0);
  expectPose(f.at(4), 1, 0, 0);
}

namespace {

const char* kWorld = R"(
name: w
duration_s: 10
seed: 3
obstacles:
  - {shape: segment, material: wall, from: [5, -5], to: [5, 5]}
movers:
  - {radius: 0.25, speed: 1.0, path: [[2, -1], [2, 1]], mode: pingpong, avoid_robot: false}
robot: {path: [[0, 0], [4, 0], [4, 3]], speed: 0.5, turn_rate: 1.0, mode: once}
)";

}  // namespace

TEST(WorldCore, StatesFollowTheScenario) {
  WorldCore w(parse(kWorld), OdometryConfig{});
  EXPECT_EQ(w.periodUs(), 20'000);
  const int64_t t0 = w.startUtime();
  EXPECT_GT(t0, 0);
  const sim_state_t s0 = w.stateAt(t0);
  EXPECT_EQ(s0.utime, t0);
  EXPECT_EQ(s0.robot_pose.x, 0.0);
  ASSERT_EQ(s0.nmovers, 1);
  EXPECT_NEAR(s0.movers[0].y, -1.0, 1e-12);
  const sim_state_t s1 = w.stateAt(t0 + 2'000'000);
  EXPECT_NEAR(s1.robot_pose.x, 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(s1.v, 0.5);
  EXPECT_NEAR(s1.movers[0].y, 1.0, 1e-9);
  EXPECT_EQ(s1.seq, 1);
  EXPECT_NEAR(w.stateAt(t0 + 3'000'000).movers[0].y, 0.0, 1e-9);  // on its way back
  EXPECT_THROW(w.stateAt(t0), std::invalid_argument);
  EXPECT_FALSE(w.finished(t0 + 10'000'000));
  EXPECT_TRUE(w.finished(t0 + 10'000'001));
}

namespace {

// The closest each mover's body came to the robot's over a run sampled at 50 Hz [m, < 0:
// overlapping], and the states.
std::vector<double> closestGaps(const Scenario& s, std::vector<sim_state_t>* states = nullptr) {
  WorldCore w(s, OdometryConfig{});
  std::vector<double> gap(s.movers.size(), 1e9);
  for (int64_t u = w.startUtime(); !w.finished(u); u += w.periodUs()) {
    const sim_state_t st = w.stateAt(u);
    for (size_t i = 0; i < gap.size(); ++i)
      gap[i] = std::min(gap[i], std::hypot(st.movers[i].x - st.robot_pose.x, st.movers[i].y - st.robot_pose.y) -
                                    s.robot.radius - st.movers[i].radius);
    if (states) states->push_back(st);
  }
  return gap;
}

// A person walks across the robot's path just as it drives by (crossing), another walks
// head-on at it down its lane, a third stands near its path's end in front of a wall.
const char* kPeople = R"(
name: people
duration_s: 20
seed: 1
obstacles:
  - {shape: segment, material: wall, from: [7.0, -3], to: [7.0, 3]}
movers:
  - {radius: 0.25, speed: 1.0, path: [[2.5, -3], [2.5, 3]], mode: once, start_delay_s: 2.5}
  - {radius: 0.25, speed: 0.5, path: [[6.0, 0.0], [0.0, 0.0]], mode: once, start_delay_s: 4}
  - {radius: 0.25, speed: 0.5, path: [[6.7, 0.3], [6.7, 0.31]], mode: once}
robot: {path: [[0, 0], [6.3, 0]], speed: 0.5, mode: once}
)";

}  // namespace

TEST(WorldCore, PeopleKeepClearOfTheRobot) {
  Scenario s = parse(kPeople);
  ASSERT_TRUE(s.movers[0].avoid_robot);
  EXPECT_DOUBLE_EQ(s.movers[0].keep_clear_m, 0.10);
  std::vector<sim_state_t> states;
  const std::vector<double> gap = closestGaps(s, &states);
  // Crossing and head-on: they wait or step back, never nearer than the gap they keep (a step
  // of the world, 2 cm at these speeds, is the slack).
  EXPECT_GT(gap[0], 0.10 - 0.02);
  EXPECT_GT(gap[1], 0.10 - 0.02);
  // The third stands 0.05 m in front of a wall, where the robot's path ends 0.5 m from it:
  // it cannot step back through the wall, so it steps aside, and keeps clear too.
  EXPECT_GT(gap[2], 0.10 - 0.02);
  for (const sim_state_t& st : states) EXPECT_LE(st.movers[2].x + st.movers[2].radius, 7.0 + 0.005);
  // And they got where they were going: the crossing person reached the far end.
  EXPECT_NEAR(states.back().movers[0].y, 3.0, 1e-6);

  // Walking their paths regardless (the simulator before), the first two walk into the robot.
  for (MoverSpec& m : s.movers) m.avoid_robot = false;
  const std::vector<double> through = closestGaps(s);
  EXPECT_LT(through[0], 0.0);
  EXPECT_LT(through[1], 0.0);
}

namespace {

// The deepest any mover's body reached into a static obstacle over the states (0: never), and
// how many states had a body in a wall or had crossed one since the state before.
struct WallOverlap {
  double deepest = 0;
  int states = 0;
};
WallOverlap wallOverlap(const Scenario& s, const std::vector<sim_state_t>& states) {
  WallOverlap o;
  for (size_t k = 0; k < states.size(); ++k) {
    bool in = false;
    for (const mover_state_t& m : states[k].movers) {
      const Vec2 p(m.x, m.y);
      const Vec2 prev = k > 0 ? Vec2(states[k - 1].movers[m.id].x, states[k - 1].movers[m.id].y) : p;
      for (const Primitive& w : s.statics) {
        const double depth = m.radius - clearance(w, p);
        o.deepest = std::max(o.deepest, depth);
        in = in || depth > 1e-9 || (clearance(w, geom::Segment{prev, p}) == 0 && clearance(w, prev) > 0);
      }
    }
    o.states += in;
  }
  return o;
}

// A dead-end corridor 1.4 m wide, a person walking to and fro near its end, and the robot
// driving in until it stands 0.45 m from the end wall: the person cannot pass the robot (0.35 m
// each side of it, 0.5 m across), nor stand between it and the wall while keeping clear.
const char* kDeadEnd = R"(
name: dead_end
duration_s: 30
seed: 38
obstacles:
  - {shape: polyline, material: wall, points: [[0,0],[6,0],[6,1.4],[0,1.4]]}
movers:
  - {shape: circle, radius: 0.25, material: person, speed: 0.6, path: [[5.6,0.7],[4,0.7]], mode: pingpong}
robot: {radius: 0.35, path: [[0.5,0.7],[5.2,0.7]], speed: 0.3}
)";

}  // namespace

// Stepping back from the robot offsets the person from its path, and its path walks on: the
// body must still never enter or cross a wall (it had reached x = 6.29, beyond the end wall at
// x = 6, in a third of the states).
TEST(WorldCore, APersonSteppingAsideNeverWalksIntoAWall) {
  const Scenario s = parse(kDeadEnd);
  std::vector<sim_state_t> states;
  closestGaps(s, &states);
  const WallOverlap o = wallOverlap(s, states);
  EXPECT_EQ(o.states, 0);
  EXPECT_LE(o.deepest, 1e-9);
  double furthest = 0;
  for (const sim_state_t& st : states) furthest = std::max(furthest, st.movers[0].x);
  EXPECT_LE(furthest, 6.0 - 0.25 + 1e-9);
  // Until the robot comes near, the person walks its path exactly.
  const PathFollower f(s.movers[0].path, s.movers[0].mode, s.movers[0].speed);
  for (size_t k = 0; k < 250; ++k) {  // 5 s: the robot is still 2 m away
    const geom::Pose2 p = f.at(static_cast<double>(k * 20000) * 1e-6).pose;  // (as the world counts)
    ASSERT_EQ(states[k].movers[0].x, p.x) << k;
    ASSERT_EQ(states[k].movers[0].y, p.y) << k;
  }

  // The people of kPeople (one steps aside in front of a wall) keep out of the wall too.
  std::vector<sim_state_t> people;
  const Scenario p = parse(kPeople);
  closestGaps(p, &people);
  EXPECT_EQ(wallOverlap(p, people).states, 0);
}

TEST(WorldCore, APersonFarFromTheRobotKeepsExactlyItsPath) {
  // Bit for bit the path follower's positions: a scene whose people never come near the robot
  // gives the same log as before people kept clear.
  const Scenario s = parse(kWorld);  // (its mover passes 0.5 m from the robot's centre)
  Scenario far = s;
  far.movers[0].path = {{2, 2}, {2, 4}};
  far.movers[0].avoid_robot = true;
  WorldCore w(far, OdometryConfig{});
  const PathFollower f(far.movers[0].path, far.movers[0].mode, far.movers[0].speed,
                       std::numeric_limits<double>::infinity(), far.movers[0].start_delay_s);
  for (int64_t u = w.startUtime(); !w.finished(u); u += w.periodUs()) {
    const sim_state_t st = w.stateAt(u);
    const geom::Pose2 p = f.at(static_cast<double>(u - w.startUtime()) * 1e-6).pose;
    ASSERT_EQ(st.movers[0].x, p.x);
    ASSERT_EQ(st.movers[0].y, p.y);
  }
}

namespace {

// A person walking at 1 m/s along y = 0.2 towards a robot that drives 0.5 m and then stands,
// 0.2 m off the person's line: the person's path runs through the robot.
const char* kStandingRobot = R"(
name: standing_robot
duration_s: 12
movers:
  - {radius: 0.25, speed: 1.0, path: [[4, 0.2], [-3, 0.2]], mode: once}
robot: {radius: 0.35, path: [[0, 0], [0.5, 0]], speed: 0.5, mode: once}
)";

}  // namespace

// A person whom a standing robot blocks waits kPatienceS (2 s) at the distance they keep, then
// walks round the robot and on to the end of their path: nobody waits for ever.
TEST(WorldCore, ABlockedPersonWaitsTwoSecondsThenWalksRoundTheRobot) {
  const Scenario s = parse(kStandingRobot);
  std::vector<sim_state_t> states;
  const std::vector<double> gap = closestGaps(s, &states);
  EXPECT_GT(gap[0], 0.10 - 0.02);
  // Blocked from about 2.8 s: still there at 4 s, after 2 s of waiting.
  ASSERT_GT(states.size(), 200u);
  EXPECT_NEAR(states[150].movers[0].x, 1.18, 0.01);
  EXPECT_NEAR(states[200].movers[0].x, 1.18, 0.01);
  EXPECT_NEAR(states.back().movers[0].x, -3.0, 1e-6);
  EXPECT_NEAR(states.back().movers[0].y, 0.2, 1e-6);
}

// The same person on the robot's very line (y = 0): straight back is exactly against their walk,
// so they step to their right and walk round, as off the line (before, they were pushed back
// along their path for ever).
TEST(WorldCore, APersonBlockedHeadOnOnTheRobotsLineWalksRoundIt) {
  std::string yaml = kStandingRobot;
  for (size_t at; (at = yaml.find("0.2]")) != std::string::npos;) yaml.replace(at, 4, "0.0]");
  const Scenario s = parse(yaml);
  ASSERT_DOUBLE_EQ(s.movers[0].path[0].y(), 0.0);
  std::vector<sim_state_t> states;
  const std::vector<double> gap = closestGaps(s, &states);
  EXPECT_GT(gap[0], 0.10 - 0.02);
  ASSERT_GT(states.size(), 200u);
  EXPECT_NEAR(states[200].movers[0].x, 1.2, 0.01);  // waited in front of it first (0.7 m from its centre)
  double rightmost = 0;  // walking towards -x, their right is +y
  for (const sim_state_t& st : states) rightmost = std::max(rightmost, static_cast<double>(st.movers[0].y));
  EXPECT_GT(rightmost, 0.3);
  EXPECT_NEAR(states.back().movers[0].x, -3.0, 1e-6);
  EXPECT_NEAR(states.back().movers[0].y, 0.0, 1e-6);
}

// Once clear of the robot, a person walks back to their path at walking speed: the offset from
// the path shrinks by at most speed x dt per step of the world, it does not jump back.
TEST(WorldCore, APersonWalksBackToTheirPathAtWalkingSpeed) {
  const Scenario s = parse(kStandingRobot);
  std::vector<sim_state_t> states;
  closestGaps(s, &states);
  const double step = s.movers[0].speed * 0.02;
  double widest = 0;
  for (size_t k = 1; k < states.size(); ++k) {
    const double before = std::abs(states[k - 1].movers[0].y - 0.2), after = std::abs(states[k].movers[0].y - 0.2);
    widest = std::max(widest, after);
    EXPECT_LE(before - after, step + 1e-9) << k;
  }
  EXPECT_GT(widest, 0.3);  // (it did step aside)
}

// A person standing left of the robot's path, with a pillar right behind them, cannot step
// straight back: they step aside to the side they are on (left), never across the robot's path.
TEST(WorldCore, APersonStepsAsideToTheSideTheyAreOn) {
  const Scenario s = parse(R"(
name: pillar
duration_s: 16
obstacles:
  - {shape: circle, material: metal, center: [7.02, 0.18], radius: 0.05}
movers:
  - {radius: 0.25, speed: 0.5, path: [[6.7, 0.1], [6.7, 0.11]], mode: once}
robot: {radius: 0.35, path: [[0, 0], [6.3, 0]], speed: 0.5, mode: once}
)");
  std::vector<sim_state_t> states;
  const std::vector<double> gap = closestGaps(s, &states);
  EXPECT_GT(gap[0], 0.10 - 0.02);
  double lowest = std::numeric_limits<double>::infinity();
  for (const sim_state_t& st : states) lowest = std::min(lowest, static_cast<double>(st.movers[0].y));
  EXPECT_GE(lowest, 0.1 - 1e-9);
  EXPECT_GT(states.back().movers[0].y, 0.3);
}

TEST(WorldCore, KeepClearKeysFromYaml) {
  const Scenario s = parse(R"(
name: k
duration_s: 1
movers:
  - {radius: 0.25, speed: 1.0, path: [[2, -1], [2, 1]], avoid_robot: false, keep_clear_m: 0.3}
robot: {path: [[0, 0], [1, 0]]}
)");
  EXPECT_FALSE(s.movers[0].avoid_robot);
  EXPECT_DOUBLE_EQ(s.movers[0].keep_clear_m, 0.3);
  EXPECT_THROW(parse(R"(
name: k
duration_s: 1
movers:
  - {radius: 0.25, speed: 1.0, path: [[2, -1], [2, 1]], keep_clear_m: -0.1}
robot: {path: [[0, 0], [1, 0]]}
)"), ConfigError);
}

namespace {

// Odometry at the end of a drive along the scenario's path, sampled at 50 Hz.
odometry_t drive(const Scenario& s, const OdometryConfig& c, sim_state_t* truth = nullptr) {
  WorldCore w(s, c);
  sim_state_t st = w.stateAt(w.startUtime());
  for (int64_t u = w.startUtime() + w.periodUs(); !w.finished(u); u += w.periodUs()) st = w.stateAt(u);
  if (truth) *truth = st;
  return w.odometry();
}

}  // namespace

TEST(WorldCore, OdometryStartsAtTheTruthAndDrifts) {
  const Scenario s = parse(kWorld);
  {
    WorldCore w(s, OdometryConfig{});
    w.stateAt(w.startUtime());
    EXPECT_EQ(w.odometry().pose.x, 0.0);
    EXPECT_EQ(w.odometry().pose.y, 0.0);
    EXPECT_EQ(w.odometry().pose.theta, 0.0);
    EXPECT_EQ(w.odometry().utime, w.startUtime());
  }
  sim_state_t truth;
  const odometry_t a = drive(s, OdometryConfig{}, &truth);
  const odometry_t b = drive(s, OdometryConfig{});
  // Same seed, same numbers.
  EXPECT_EQ(a.pose.x, b.pose.x);
  EXPECT_EQ(a.pose.y, b.pose.y);
  EXPECT_EQ(a.pose.theta, b.pose.theta);
  // It drifts, by about what the noise model says (4 m driven, 1 cm/sqrt(m): a few cm).
  const double err = std::hypot(a.pose.x - truth.robot_pose.x, a.pose.y - truth.robot_pose.y);
  EXPECT_GT(err, 1e-4);
  EXPECT_LT(err, 0.3);
  // Another seed, other numbers.
  Scenario other = s;
  other.seed = 4;
  EXPECT_NE(drive(other, OdometryConfig{}).pose.x, a.pose.x);
  // Without noise, odometry is the truth.
  const odometry_t exact = drive(s, OdometryConfig{50, 0, 0, 0});
  EXPECT_NEAR(exact.pose.x, truth.robot_pose.x, 1e-9);
  EXPECT_NEAR(exact.pose.y, truth.robot_pose.y, 1e-9);
  EXPECT_NEAR(exact.pose.theta, truth.robot_pose.theta, 1e-9);
}

TEST(WorldCore, OdometryConfigFromYaml) {
  const OdometryConfig c = odometryConfig(Config::fromString("rate_hz: 20\ndrift_noise: 0.01\n"));
  EXPECT_EQ(c.rate_hz, 20);
  EXPECT_EQ(c.drift_noise, 0.01);
  EXPECT_EQ(c.trans_noise, OdometryConfig{}.trans_noise);
  EXPECT_THROW(odometryConfig(Config::fromString("rate: 20\n")), ConfigError);
  // An error of a metre per square-root metre is no odometry (1e300 put ODOMETRY at 3e298 m).
  for (const char* key : {"trans_noise", "rot_noise", "drift_noise"}) {
    EXPECT_THROW(odometryConfig(Config::fromString(std::string(key) + ": 1e300\n")), ConfigError) << key;
    EXPECT_EQ(odometryConfig(Config::fromString(std::string(key) + ": 1\n")).rate_hz, 50) << key;
  }
}

// The world's end in int64 microseconds: a duration beyond a day is refused, not overflowed.
TEST(WorldCore, RefusesADurationBeyondADay) {
  Scenario s = parse(kWorld);
  s.duration_s = 1e300;
  EXPECT_THROW(WorldCore(s, OdometryConfig{}), std::invalid_argument);
  s.duration_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(WorldCore(s, OdometryConfig{}), std::invalid_argument);
  s.duration_s = 86'400;
  EXPECT_NO_THROW(WorldCore(s, OdometryConfig{}));
}

// A base that reports odometry at 10 Hz while the truth runs at 50 Hz: every fifth state
// publishes it, from the first on.
TEST(WorldCore, OdometryPublishedAtItsOwnRate) {
  const Scenario s = parse(kWorld);
  OdometryConfig c;
  c.publish_hz = 10;
  const WorldCore w(s, c);
  std::vector<int64_t> due;
  for (int64_t t = w.startUtime(); t < w.startUtime() + 500'000; t += w.periodUs())
    if (w.odometryDue(t)) due.push_back(t - w.startUtime());
  EXPECT_EQ(due, (std::vector<int64_t>{0, 100'000, 200'000, 300'000, 400'000}));
  const WorldCore every(s, OdometryConfig{});
  EXPECT_TRUE(every.odometryDue(every.startUtime() + every.periodUs()));
  EXPECT_EQ(odometryConfig(Config::fromString("publish_hz: 10\n")).publish_hz, 10);
  try {
    odometryConfig(Config::fromString("rate_hz: 20\npublish_hz: 50\n"));
    ADD_FAILURE() << "publish_hz above rate_hz accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("publish_hz: must be <= rate_hz (20)"), std::string::npos) << e.what();
  }
}

// ODOMETRY published with every state (publish_hz equal to rate_hz) is allowed: only a rate
// above the state rate is impossible.
TEST(WorldCore, OdometryMayBePublishedWithEveryState) {
  EXPECT_EQ(odometryConfig(Config::fromString("rate_hz: 20\npublish_hz: 20\n")).publish_hz, 20);
}

// Systematic odometry errors (UMBmark's) grow with what was driven and turned: without noise the
// odometry reads exactly the biased motion.
TEST(WorldCore, SystematicOdometryErrors) {
  const Scenario straight = parse(R"(
name: s
duration_s: 10
seed: 3
robot: {path: [[0, 0], [4, 0]], speed: 0.5, mode: once}
)");
  OdometryConfig exact{50, 0, 0, 0};
  OdometryConfig c = exact;
  c.scale_error = 0.02;  // wheels 2 % larger than the odometry assumes
  odometry_t o = drive(straight, c);
  EXPECT_NEAR(o.pose.x, 4.08, 1e-9);
  EXPECT_NEAR(o.pose.y, 0.0, 1e-12);
  EXPECT_NEAR(o.pose.theta, 0.0, 1e-12);
  c = exact;
  c.curvature_error = 0.01;  // [rad/m] unequal wheels: the odometry curves left by 0.04 rad in 4 m
  o = drive(straight, c);
  EXPECT_NEAR(o.pose.theta, 0.04, 1e-9);
  EXPECT_NEAR(o.pose.y, (1 - std::cos(0.04)) / 0.01, 1e-3);  // an arc of radius 100 m
  c = exact;
  c.turn_scale_error = 0.05;  // wheel base 5 % off: every turn reads 5 % too far
  sim_state_t truth;
  o = drive(parse(kWorld), c, &truth);
  EXPECT_NEAR(truth.robot_pose.theta, geom::kPi / 2, 1e-9);
  EXPECT_NEAR(o.pose.theta, 1.05 * geom::kPi / 2, 1e-9);
}

TEST(WorldCore, SystematicOdometryErrorsFromYaml) {
  const OdometryConfig c =
      odometryConfig(Config::fromString("scale_error: 0.005\nturn_scale_error: -0.01\ncurvature_error: 0.004\n"));
  EXPECT_EQ(c.scale_error, 0.005);
  EXPECT_EQ(c.turn_scale_error, -0.01);
  EXPECT_EQ(c.curvature_error, 0.004);
  EXPECT_EQ(OdometryConfig{}.curvature_error, 0.0);
  try {
    odometryConfig(Config::fromString("scale_error: 2\n"));
    FAIL() << "scale_error 2 was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("scale_error"), std::string::npos) << e.what();
  }
}

TEST(DeriveSeed, StreamsDiffer) {
  EXPECT_EQ(deriveSeed(7, "laser"), deriveSeed(7, "laser"));
  EXPECT_NE(deriveSeed(7, "laser"), deriveSeed(7, "sonar"));
  EXPECT_NE(deriveSeed(7, "laser"), deriveSeed(8, "laser"));
}

TEST(WorldGeometry, CastRayFindsTheNearestSurface) {
  const Scenario s = parse(R"(
name: g
obstacles:
  - {shape: segment, material: wall, from: [3, -1], to: [3, 1]}
  - {shape: segment, material: glass, from: [2, -1], to: [2, 1]}
  - {shape: circle, material: plastic, center: [0, 3], radius: 0.5}
movers:
  - {path: [[-2, 0], [-3, 0]]}
robot: {path: [[0, 0], [1, 0]]}
)");
  WorldGeometry world(s);
  const geom::Ray east{{0, 0}, {1, 0}};
  auto h = world.castRay(east, 10);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->range, 2.0, 1e-12);  // the glass
  EXPECT_EQ(h->obstacle, 1);
  EXPECT_NEAR(h->normal.x(), -1.0, 1e-12);  // facing the ray's origin
  h = world.castRay(east, 10, [](const Material& m) { return m.laser == LaserBehaviour::Transparent; });
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->range, 3.0, 1e-12);
  EXPECT_EQ(h->primitive->material->name, "wall");
  EXPECT_FALSE(world.castRay(east, 1.5));  // beyond max_range

  // The same segment seen from the other side: the normal flips towards the origin.
  h = world.castRay({{4, 0}, {-1, 0}}, 10);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->normal.x(), 1.0, 1e-12);

  h = world.castRay({{0, 0}, {0, 1}}, 10);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->range, 2.5, 1e-12);
  EXPECT_NEAR(h->normal.y(), -1.0, 1e-12);
  EXPECT_NEAR(h->point.y(), 2.5, 1e-12);

  // Movers appear where setMovers puts them.
  const geom::Ray west{{0, 0}, {-1, 0}};
  EXPECT_FALSE(world.castRay(west, 10));
  world.setMovers({{0, Vec2(-2, 0), 0.25}});
  h = world.castRay(west, 10);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->range, 1.75, 1e-12);
  EXPECT_EQ(h->obstacle, -2);
  EXPECT_EQ(h->primitive->material->name, "person");
  world.setMovers({{0, Vec2(-4, 0), 0.25}});
  EXPECT_NEAR(world.castRay(west, 10)->range, 3.75, 1e-12);
  EXPECT_EQ(world.primitives().size(), s.statics.size() + 1);
}
