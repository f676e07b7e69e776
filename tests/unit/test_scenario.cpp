// Scenario files: the format of README "Scenario format", and errors that name the offending key path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "sim/drivers.hpp"
#include "sim/scenario.hpp"
#include "sim/world_geometry.hpp"
#include "scratch_dir.hpp"

using namespace lasonic;
using namespace lasonic::sim;

namespace {

const char* kGood = R"(
name: fig7_lab
duration_s: 60
seed: 7
materials:
  frosted_glass: {laser: transparent, sonar_echo_angle_deg: 10, sonar_echo_prob: 0.9}
  metal: {sonar_echo_angle_deg: 15}
obstacles:
  - {shape: polyline, material: metal, closed: true, points: [[0,0],[6,0],[6,4],[0,4]]}
  - {shape: segment,  material: frosted_glass, from: [2,4], to: [3,4]}
  - {shape: circle,   material: plastic, center: [3,2], radius: 0.02}
  - {shape: box,      material: black_cardboard, center: [4,1], size: [0.5,0.3], yaw_deg: 20}
movers:
  - {shape: circle, radius: 0.25, material: person, speed: 0.8, path: [[1,1],[5,1]], mode: pingpong}
robot:
  radius: 0.35
  path: [[1,2],[5,2],[5,3]]
  speed: 0.3
  mode: once
laser: {noise_std: 0.02}
sonar: {}
odometry: {trans_noise: 0.0}
)";

Scenario parse(const std::string& yaml) { return parseScenario(Config::fromString(yaml, "test.yaml")); }

// The minimal valid scenario plus `extra` top-level text.
std::string minimal(const std::string& extra = "", const std::string& robot = "{path: [[0,0],[1,0]]}") {
  return "name: t\nrobot: " + robot + "\n" + extra;
}

// Parsing must fail with a message containing `expected` (file name and key path).
void expectError(const std::string& yaml, const std::string& expected) {
  try {
    parse(yaml);
    ADD_FAILURE() << "no error, expected: " << expected;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << expected;
  }
}

}  // namespace

TEST(Scenario, LoadsTheDesignExample) {
  const Scenario s = parse(kGood);
  EXPECT_EQ(s.name, "fig7_lab");
  EXPECT_DOUBLE_EQ(s.duration_s, 60);
  EXPECT_EQ(s.seed, 7u);
  ASSERT_EQ(s.obstacles.size(), 4u);
  // Closed polyline: 4 edges, the top one cut in two by the glass door drawn on it (a pane in
  // the wall); segment: 1; circle: 1; box: 4 edges.
  ASSERT_EQ(s.statics.size(), 11u);
  EXPECT_EQ(s.statics[2].segment.b, geom::Vec2(3, 4));  // the top wall, from (6, 4) to the door
  EXPECT_EQ(s.statics[3].segment.a, geom::Vec2(2, 4));  // and on from the door
  EXPECT_EQ(s.statics[4].segment.b, geom::Vec2(0, 0));  // closing edge back to the start
  EXPECT_EQ(s.statics[6].kind, Primitive::Kind::Circle);
  EXPECT_EQ(s.statics[10].obstacle, 3);
  // The box is rotated by yaw_deg about its centre.
  const geom::Vec2 corner = s.statics[7].segment.a;
  EXPECT_NEAR((corner - geom::Vec2(4, 1)).norm(), std::hypot(0.25, 0.15), 1e-12);
  EXPECT_NEAR(std::atan2(s.statics[7].segment.b.y() - corner.y(), s.statics[7].segment.b.x() - corner.x()),
              geom::deg2rad(20), 1e-12);

  EXPECT_EQ(s.material("frosted_glass").laser, LaserBehaviour::Transparent);
  EXPECT_NEAR(s.material("frosted_glass").sonar_echo_prob, 0.9, 1e-12);
  // An override changes only the keys it gives.
  EXPECT_NEAR(s.material("metal").sonar_echo_angle, geom::deg2rad(15), 1e-12);
  EXPECT_EQ(s.material("metal").laser, LaserBehaviour::Reflect);
  EXPECT_EQ(s.statics[0].material, &s.material("metal"));

  EXPECT_FALSE(s.laserVisible(1));  // frosted glass
  EXPECT_TRUE(s.laserVisible(2));   // plastic pipe
  EXPECT_FALSE(s.laserVisible(3));  // black cardboard
  EXPECT_TRUE(s.laserVisible(-2));  // mover 0: a person

  ASSERT_EQ(s.movers.size(), 1u);
  EXPECT_EQ(s.movers[0].mode, PathMode::PingPong);
  EXPECT_DOUBLE_EQ(s.movers[0].speed, 0.8);
  EXPECT_EQ(s.robot.path.size(), 3u);
  EXPECT_EQ(s.robot.mode, PathMode::Once);
  EXPECT_DOUBLE_EQ(laserConfig(s.laser).noise_std, 0.02);
  EXPECT_DOUBLE_EQ(odometryConfig(s.odometry).trans_noise, 0.0);
}

TEST(Scenario, BuiltinMaterials) {
  const auto m = builtinMaterials();
  for (const char* n : {"wall", "metal", "glass", "mesh", "black_cardboard", "plastic", "person"})
    EXPECT_TRUE(m.count(n)) << n;
  EXPECT_EQ(m.at("glass").laser, LaserBehaviour::Transparent);
  EXPECT_EQ(m.at("mesh").laser, LaserBehaviour::Transparent);
  EXPECT_EQ(m.at("black_cardboard").laser, LaserBehaviour::Absorb);
  EXPECT_NEAR(m.at("metal").sonar_echo_angle, geom::deg2rad(12), 1e-12);
  EXPECT_NEAR(m.at("person").sonar_echo_prob, 0.8, 1e-12);
}

TEST(Scenario, PhysicalMaterialParameters) {
  const auto m = builtinMaterials();
  // Every built-in material has physical parameters too.
  EXPECT_NEAR(m.at("wall").sonar_roughness, 0.2e-3, 1e-12);
  EXPECT_GT(m.at("mesh").sonar_transmit, 0.5);
  EXPECT_EQ(m.at("metal").sonar_transmit, 0.0);
  EXPECT_GT(m.at("person").sonar_fluct_db, 0.0);
  EXPECT_NEAR(m.at("black_cardboard").laser_remission, 0.03, 1e-12);
  EXPECT_GT(m.at("glass").laser_specular, 0.0);
  // A new material with only the ideal keys gets physical ones derived from them (rough above
  // 30°), and keeps its echo probability in the physical profile; one with only physical keys
  // gets an ideal echo angle.
  const Scenario s = parse(minimal(
      "materials:\n"
      "  felt: {laser: absorb, sonar_echo_angle_deg: 80, sonar_echo_prob: 0.7}\n"
      "  tile: {laser: reflect, sonar_echo_angle_deg: 9}\n"
      "  brick: {laser: reflect, sonar_roughness_mm: 3, sonar_lobe_deg: 30, sonar_diffuse: 1, laser_remission: 0.3}\n"
      "  wall: {sonar_roughness_mm: 0.5, laser_remission: 0.7}\n"));
  EXPECT_GT(s.material("felt").sonar_roughness, 1e-3);
  EXPECT_NEAR(s.material("felt").sonar_hear_prob, 0.7, 1e-12);
  EXPECT_NEAR(s.material("felt").laser_remission, 0.03, 1e-12);  // `absorb`: matte black
  EXPECT_LT(s.material("tile").sonar_roughness, 0.2e-3);
  EXPECT_DOUBLE_EQ(s.material("tile").sonar_hear_prob, 1.0);
  EXPECT_NEAR(s.material("brick").sonar_echo_angle, geom::deg2rad(90), 1e-12);
  EXPECT_NEAR(s.material("brick").sonar_lobe, geom::deg2rad(30), 1e-12);
  EXPECT_NEAR(s.material("brick").laser_remission, 0.3, 1e-12);
  // Overriding a built-in changes only the keys given: the ideal wall is untouched.
  EXPECT_NEAR(s.material("wall").sonar_roughness, 0.5e-3, 1e-12);
  EXPECT_NEAR(s.material("wall").sonar_echo_angle, geom::deg2rad(60), 1e-12);
  EXPECT_NEAR(s.material("wall").sonar_lobe, geom::deg2rad(5), 1e-12);
}

// An override of a built-in acts in the physical default as in the ideal profile: a changed
// `laser` brings that behaviour's remission, ideal sonar keys given alone their physical twins.
// (The physical profile ignored them: a wall made `absorb` still returned 0.64 of the laser's
// beams, glass made `reflect` none, and `wall: {sonar_echo_prob: 0}` was heard as before.)
TEST(Scenario, OverridingABuiltinActsInThePhysicalProfile) {
  const Scenario s = parse(minimal(
      "materials:\n"
      "  wall: {laser: absorb, sonar_echo_prob: 0}\n"
      "  glass: {laser: reflect}\n"
      "  metal: {laser: reflect, sonar_echo_angle_deg: 80}\n"
      "  plastic: {sonar_echo_angle_deg: 80, sonar_roughness_mm: 0.02}\n"
      "  person: {laser: absorb, laser_remission: 0.2}\n"));
  EXPECT_NEAR(s.material("wall").laser_remission, 0.03, 1e-12);  // as black cardboard
  EXPECT_DOUBLE_EQ(s.material("wall").sonar_hear_prob, 0.0);
  EXPECT_NEAR(s.material("wall").sonar_roughness, 0.2e-3, 1e-12);  // the echo angle was not given
  EXPECT_NEAR(s.material("glass").laser_remission, 0.5, 1e-12);
  EXPECT_NEAR(s.material("glass").sonar_roughness, 0.001e-3, 1e-12);  // no sonar key given
  // `laser: reflect` on metal changes nothing; its new echo angle makes it rough (above 30°).
  EXPECT_NEAR(s.material("metal").laser_remission, 0.40, 1e-12);
  EXPECT_NEAR(s.material("metal").sonar_roughness, 3e-3, 1e-12);
  EXPECT_NEAR(s.material("metal").sonar_lobe, geom::deg2rad(40), 1e-12);
  // Physical keys in the override are taken as they are: only the roughness changes.
  EXPECT_NEAR(s.material("plastic").sonar_roughness, 0.02e-3, 1e-12);
  EXPECT_NEAR(s.material("plastic").sonar_lobe, geom::deg2rad(1), 1e-12);
  EXPECT_NEAR(s.material("plastic").sonar_echo_angle, geom::deg2rad(80), 1e-12);
  EXPECT_NEAR(s.material("person").laser_remission, 0.2, 1e-12);
}

TEST(Scenario, FramesAndEmitters) {
  const Scenario s = parse(minimal(
      "obstacles:\n"
      "  - {shape: segment, material: glass, from: [0,0], to: [1,0], frame: {material: wall, width: 0.05, depth: 0.1}}\n"
      "  - {shape: circle, material: plastic, center: [3,3], radius: 0.1}\n"
      "emitters:\n  - {position: [1, 2], period_s: 0.05, phase_s: 0.01, level_db: 40, heading_deg: 90}\n"));
  // The scenario's own obstacles keep their indices; the two jambs follow.
  ASSERT_EQ(s.obstacles.size(), 4u);
  EXPECT_EQ(s.obstacles[1].shape, "circle");
  EXPECT_EQ(s.obstacles[2].frame_of, 0);
  EXPECT_EQ(s.obstacles[3].frame_of, 0);
  EXPECT_EQ(s.obstacles[2].material, "wall");
  // The pane is shortened by the jambs' width.
  EXPECT_NEAR(s.obstacles[0].points[0].x(), 0.05, 1e-12);
  EXPECT_NEAR(s.obstacles[0].points[1].x(), 0.95, 1e-12);
  // Jamb at the start: 0.05 along x, 0.1 across, from x = 0 to 0.05.
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (const geom::Vec2& p : s.obstacles[2].points) {
    xmin = std::min(xmin, p.x());
    xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  EXPECT_NEAR(xmin, 0.0, 1e-12);
  EXPECT_NEAR(xmax, 0.05, 1e-12);
  EXPECT_NEAR(ymax - ymin, 0.1, 1e-12);
  // Statics: pane 1 + circle 1 + 2 boxes of 4 edges; jamb edges carry the jamb's index.
  EXPECT_EQ(s.statics.size(), 10u);
  EXPECT_EQ(s.statics.back().obstacle, 3);
  EXPECT_EQ(s.statics.back().material->name, "wall");
  EXPECT_TRUE(s.laserVisible(2));  // a plaster jamb
  ASSERT_EQ(s.emitters.size(), 1u);
  EXPECT_DOUBLE_EQ(s.emitters[0].period_s, 0.05);
  EXPECT_DOUBLE_EQ(s.emitters[0].phase_s, 0.01);
  EXPECT_DOUBLE_EQ(*s.emitters[0].level_db, 40);
  EXPECT_NEAR(*s.emitters[0].heading, geom::kPi / 2, 1e-12);
  // A copy keeps everything.
  const Scenario copy = s;
  EXPECT_EQ(copy.emitters.size(), 1u);
  EXPECT_EQ(copy.statics.back().material, &copy.material("wall"));
}

TEST(Scenario, CopiesOwnTheirMaterials) {
  Scenario copy;
  {
    const Scenario original = parse(kGood);
    copy = original;
  }
  // The original is gone: the copy's primitives must point into the copy.
  EXPECT_EQ(copy.statics[0].material, &copy.material("metal"));
  EXPECT_EQ(copy.statics[0].material->name, "metal");
}

TEST(Scenario, ErrorsNameTheKeyPath) {
  expectError(minimal("obstacles:\n  - {shape: circle, material: wall, center: [1,1], radius: 1}\n"
                      "  - {shape: circle, material: wall, center: [1,1], radius: 0}\n"),
              "test.yaml: obstacles[1].radius: must be > 0");
  expectError(minimal("colour: red\n"), "test.yaml: colour: unknown key");
  expectError(minimal("obstacles:\n  - {shape: segment, material: wall, from: [0,0], to: [1,0], colour: red}\n"),
              "obstacles[0].colour: unknown key");
  expectError(minimal("obstacles:\n  - {shape: segment, material: unobtainium, from: [0,0], to: [1,0]}\n"),
              "obstacles[0].material: unknown material \"unobtainium\"");
  expectError(minimal("obstacles:\n  - {shape: segment, material: wall, from: [1,1], to: [1,1]}\n"),
              "obstacles[0].to: equals from (zero-length segment)");
  expectError(minimal("obstacles:\n  - {shape: polyline, material: wall, points: [[0,0]]}\n"),
              "obstacles[0].points: needs at least 2 points");
  expectError(minimal("obstacles:\n  - {shape: polyline, material: wall, points: [[0,0],[1,0],[1,0]]}\n"),
              "obstacles[0].points[2]: repeats the previous point");
  expectError(minimal("obstacles:\n  - {shape: box, material: wall, center: [0,0], size: [1,0]}\n"),
              "obstacles[0].size: both sides must be > 0");
  expectError(minimal("obstacles:\n  - {shape: blob, material: wall}\n"),
              "obstacles[0].shape: must be segment, polyline, circle or box");
  expectError(minimal("", "{path: [[0,0]]}"), "robot.path: needs at least 2 points");
  expectError(minimal("", "{path: [[0,0],[1,0]], speed: 0}"), "robot.speed: must be in (0, 5]");
  expectError(minimal("", "{path: [[0,0],[1,0]], mode: sometimes}"), "robot.mode: must be once, loop or pingpong");
  expectError(minimal("duration_s: 0\n"), "duration_s: must be in (0, 86400]");
  expectError(minimal("movers:\n  - {path: [[0,0],[1,0]], speed: 1, mode: twice}\n"),
              "movers[0].mode: must be once, loop or pingpong");
  expectError(minimal("movers:\n  - {path: [[0,0],[1,0]], speed: -1}\n"), "movers[0].speed: must be in (0, 10]");
  expectError(minimal("materials:\n  foam: {laser: soak, sonar_echo_angle_deg: 10}\n"),
              "materials.foam.laser: must be reflect, transparent or absorb");
  expectError(minimal("materials:\n  foam: {laser: absorb}\n"), "materials.foam.sonar_echo_angle_deg: is required");
  expectError(minimal("materials:\n  foam: {laser: absorb, sonar_roughness_mm: -1}\n"),
              "materials.foam.sonar_roughness_mm: must be in [0, 1000]");
  expectError(minimal("materials:\n  wall: {sonar_reflect_db: 3}\n"), "materials.wall.sonar_reflect_db: must be in [-100, 0]");
  expectError(minimal("materials:\n  wall: {sonar_transmit: 1}\n"), "materials.wall.sonar_transmit: must be < 1");
  expectError(minimal("materials:\n  wall: {laser_remission: 1.5}\n"), "materials.wall.laser_remission: must be in [0, 1]");
  expectError(minimal("materials:\n  wall: {laser_shine: 1}\n"), "materials.wall.laser_shine: unknown key");
  expectError(minimal("obstacles:\n  - {shape: segment, material: glass, from: [0,0], to: [1,0], frame: {material: wood, width: 0.05}}\n"),
              "obstacles[0].frame.material: unknown material \"wood\"");
  expectError(minimal("obstacles:\n  - {shape: segment, material: glass, from: [0,0], to: [1,0], frame: {material: wall, width: 0.5}}\n"),
              "obstacles[0].frame.width: leaves nothing of the segment");
  expectError(minimal("obstacles:\n  - {shape: segment, material: glass, from: [0,0], to: [1,0], frame: {material: wall}}\n"),
              "obstacles[0].frame.width: is required");
  expectError(minimal("obstacles:\n  - {shape: box, material: glass, center: [0,0], size: [1,1], frame: {material: wall, width: 0.1}}\n"),
              "obstacles[0].frame: unknown key");
  expectError(minimal("obstacles:\n  - {shape: polyline, closed: true, material: glass, points: [[0,0],[1,0],[1,1]], frame: {material: wall, width: 0.1}}\n"),
              "obstacles[0].frame: only segments and open polylines can have a frame");
  expectError(minimal("emitters:\n  - {position: [1, 2]}\n"), "emitters[0].period_s: is required");
  expectError(minimal("emitters:\n  - {position: [1, 2], period_s: 0}\n"), "emitters[0].period_s: must be >= 0.001");
  expectError(minimal("emitters:\n  - {position: [1, 2], period_s: 0.1, colour: red}\n"), "emitters[0].colour: unknown key");
  expectError("name: t\n", "robot: is required");
}

// A seed is an integer in [0, 2^63 - 1], as --seed: a number beyond it (2^64 - 1 is an integer
// too), a negative or a fractional one is refused with that range, not as "not an integer".
TEST(Scenario, SeedMessagesSayTheRange) {
  for (const char* seed : {"18446744073709551615", "9223372036854775808", "-5", "7.0", "1e3"})
    expectError(minimal(std::string("seed: ") + seed + "\n"),
                std::string("test.yaml: seed: must be an integer in [0, 9223372036854775807] (got ") + seed + ")");
  EXPECT_EQ(parse(minimal("seed: 9223372036854775807\n")).seed, 9223372036854775807u);
  EXPECT_EQ(parse(minimal("seed: 0\n")).seed, 0u);
  expectError(minimal("seed: [1]\n"), "test.yaml: seed: must be an integer");
}

// A mover is a circle: a box's keys are not "unknown", the shape is what is wrong.
TEST(Scenario, AMoverIsACircleBeforeItsKeysAreChecked) {
  expectError(minimal("movers:\n  - {shape: box, size: [0.5, 0.5], path: [[1,1],[5,1]]}\n"),
              "test.yaml: movers[0].shape: movers must be circles (got \"box\")");
  expectError(minimal("movers:\n  - {shape: circle, size: [0.5, 0.5], path: [[1,1],[5,1]]}\n"),
              "test.yaml: movers[0].size: unknown key");
}

// A degenerate shape is an error: a closed polyline must enclose an area. One that crosses
// itself (a figure of eight, zero signed area) does.
TEST(Scenario, AClosedPolylineMustEncloseAnArea) {
  expectError(minimal("obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[1,1],[2,1],[3,1]]}\n"),
              "test.yaml: obstacles[0].points: a closed polyline must enclose an area (its points are collinear)");
  expectError(minimal("obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[0,0],[1,1],[3,3],[2,2]]}\n"),
              "obstacles[0].points: a closed polyline must enclose an area");
  EXPECT_EQ(parse(minimal("obstacles:\n  - {shape: polyline, material: metal, closed: true, "
                          "points: [[4,3.5],[5,4.5],[5,3.5],[4,4.5]]}\n")).statics.size(), 4u);
  // An open polyline along a line is a wall; a repeated point is still an error.
  EXPECT_EQ(parse(minimal("obstacles:\n  - {shape: polyline, material: wall, points: [[1,1],[2,1],[3,1]]}\n")).statics.size(), 2u);
  expectError(minimal("obstacles:\n  - {shape: polyline, material: wall, points: [[1,1],[2,1],[2,1]]}\n"),
              "obstacles[0].points[2]: repeats the previous point");
}

// The robot follows its path blind, through an obstacle if the path runs through one: where its
// disc first overlaps each obstacle is found (and lasonic-sim warns of it).
TEST(Scenario, WhereTheRobotsPathOverlapsAnObstacle) {
  const Scenario s = parse(R"(
name: t
duration_s: 30
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[8,0],[8,4],[0,4]]}
  - {shape: circle, material: plastic, center: [2.5,2.39], radius: 0.05}
  - {shape: box, material: metal, center: [5,2], size: [0.5,0.5]}
  - {shape: segment, material: glass, from: [6.5,1], to: [6.5,3]}
  - {shape: circle, material: plastic, center: [2.5,1.55], radius: 0.05}
robot: {radius: 0.35, path: [[1,2],[7.5,2]], speed: 0.3}
)");
  const std::vector<RobotOverlap> o = robotOverlaps(s);
  ASSERT_EQ(o.size(), 3u);
  // Each at the first sample (2 cm apart) past where the disc reaches it: the pipe 0.34 m from
  // the path (1 cm into the disc) once the centre is within 0.40 m of the pipe's, the box's face
  // at 4.75 - 0.35, the pane at 6.5 - 0.35; the pipe 0.40 m from the path is clear.
  EXPECT_EQ(o[0].obstacle, 1);
  EXPECT_NEAR(o[0].at.x(), 2.5 - std::sqrt(0.40 * 0.40 - 0.39 * 0.39) + 0.01, 0.011);
  EXPECT_EQ(o[1].obstacle, 2);
  EXPECT_NEAR(o[1].at.x(), 4.4 + 0.01, 0.011);
  EXPECT_NEAR(o[1].t, (o[1].at.x() - 1) / 0.3, 1e-9);
  EXPECT_EQ(o[2].obstacle, 3);
  EXPECT_NEAR(o[2].at.x(), 6.15 + 0.01, 0.011);
  EXPECT_EQ(describeRobotOverlap(s, o[1]).rfind("robot.path: the robot (radius 0.35) overlaps obstacles[2] at (4.", 0), 0u);

  // Starting inside a box (solid), never touching its sides at first: found where it starts.
  const Scenario in = parse(R"(
name: t
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[7,0],[7,5],[0,5]]}
  - {shape: box, material: wall, center: [2,2], size: [1.4,1.4]}
robot: {radius: 0.35, path: [[2,2],[6,2]], speed: 0.3}
)");
  const std::vector<RobotOverlap> o2 = robotOverlaps(in);
  ASSERT_EQ(o2.size(), 1u);
  EXPECT_EQ(o2[0].obstacle, 1);
  EXPECT_EQ(o2[0].t, 0.0);
  EXPECT_EQ(describeRobotOverlap(in, o2[0]),
            "robot.path: the robot (radius 0.35) overlaps obstacles[1] at (2.00, 2.00) (t \u2248 0.0 s, where it starts)");

  // A thin pane across the path is found whatever the sampling, and a path that passes close
  // (touching is not overlapping) gives nothing.
  EXPECT_EQ(robotOverlaps(s, 1.0).size(), 3u);
  const std::vector<RobotOverlap> good = robotOverlaps(parse(kGood));  // (its path runs through the pipe)
  ASSERT_EQ(good.size(), 1u);
  EXPECT_EQ(good[0].obstacle, 2);
  EXPECT_TRUE(robotOverlaps(parse(minimal("obstacles:\n  - {shape: segment, material: wall, from: [0,0.35], to: [1,0.35]}\n"))).empty());
  // A jamb is named by the obstacle it frames.
  const Scenario door = parse(minimal("obstacles:\n  - {shape: segment, material: glass, from: [0.5,-1], to: [0.5,0.3], "
                                      "frame: {material: wall, width: 0.1}}\n"));
  const std::vector<RobotOverlap> o3 = robotOverlaps(door);
  ASSERT_EQ(o3.size(), 2u);
  EXPECT_NE(describeRobotOverlap(door, o3[0]).find("obstacles[0] at"), std::string::npos);
  EXPECT_NE(describeRobotOverlap(door, o3[1]).find("obstacles[2] (a jamb of obstacles[0]'s frame)"), std::string::npos);
}

// A mover's disc along its own path, after its start delay: a person drawn walking through a
// pane is found where the disc first reaches it; one walking beside a wall is not.
TEST(Scenario, WhereAMoversPathOverlapsAnObstacle) {
  const Scenario s = parse(R"(
name: t
duration_s: 30
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[8,0],[8,6],[0,6]]}
  - {shape: segment, material: glass, from: [3,3.4], to: [5.5,3.4]}
  - {shape: box, material: metal, center: [6.5,1.0], size: [0.6,0.6]}
movers:
  - {radius: 0.25, speed: 0.5, path: [[4,0.5],[4,4.5]], start_delay_s: 2}
  - {radius: 0.25, speed: 0.8, path: [[1,5.5],[7,5.5]]}
  - {radius: 0.2, speed: 1.0, path: [[6.5,3],[6.5,2]], mode: once}
robot: {radius: 0.35, path: [[1,2],[2,2]], speed: 0.3}
)");
  const std::vector<MoverOverlap> o = moverOverlaps(s);
  ASSERT_EQ(o.size(), 1u);
  // The first mover meets the pane once its centre is within 0.25 m of it, 2.65 m along its
  // path, 2 s + 5.3 s after the start (sampled every 2 cm); the second walks with its centre
  // 0.5 m from the top wall (clear), the third stops 0.5 m short of the box.
  EXPECT_EQ(o[0].mover, 0);
  EXPECT_EQ(o[0].where.obstacle, 1);
  EXPECT_NEAR(o[0].where.at.y(), 3.15 + 0.01, 0.011);
  EXPECT_NEAR(o[0].where.t, 2 + (o[0].where.at.y() - 0.5) / 0.5, 1e-9);
  EXPECT_EQ(describeMoverOverlap(s, o[0]).rfind(
                "movers[0].path: the mover (radius 0.25) overlaps obstacles[1] at (4.00, 3.1", 0),
            0u)
      << describeMoverOverlap(s, o[0]);
  EXPECT_NE(describeMoverOverlap(s, o[0]).find("later if it waits for the robot"), std::string::npos);
  Scenario blind = s;  // a mover that walks its path regardless is there on time
  blind.movers[0].avoid_robot = false;
  EXPECT_EQ(describeMoverOverlap(blind, o[0]).find("later"), std::string::npos) << describeMoverOverlap(blind, o[0]);

  // Past where the run ends, nothing; a mover standing in a box from the start is found there.
  Scenario short_run = s;
  short_run.duration_s = 6;
  EXPECT_TRUE(moverOverlaps(short_run).empty());
  const Scenario in = parse(R"(
name: t
obstacles:
  - {shape: polyline, material: wall, closed: true, points: [[0,0],[8,0],[8,6],[0,6]]}
  - {shape: box, material: wall, center: [2,2], size: [1.4,1.4]}
movers:
  - {radius: 0.25, path: [[2,2],[6,2]]}
robot: {radius: 0.35, path: [[1,5],[2,5]], speed: 0.3}
)");
  const std::vector<MoverOverlap> o2 = moverOverlaps(in);
  ASSERT_EQ(o2.size(), 1u);
  EXPECT_EQ(describeMoverOverlap(in, o2[0]),
            "movers[0].path: the mover (radius 0.25) overlaps obstacles[1] at (2.00, 2.00) (t \u2248 0.0 s, where it starts)");
}

// The override sections are read by the simulator's own readers when the scenario is loaded, so
// every tool (lasonic-eval, lasonic-render, lasonic-sim-world, either driver) refuses a scenario
// that lasonic-sim would refuse.
TEST(Scenario, SensorOverridesAreCheckedWhenLoaded) {
  expectError(minimal("laser: {colour: red}\n"), "test.yaml: laser.colour: unknown key");
  expectError(minimal("laser: {readings: 0}\n"), "test.yaml: laser.readings: must be in [2, 100000]");
  expectError(minimal("sonar: {zzz_typo: 1}\n"), "test.yaml: sonar.zzz_typo: unknown key");
  expectError(minimal("sonar: {ring: {count: 0}}\n"), "test.yaml: sonar.ring.count: must be in [1, 1000]");
  expectError(minimal("odometry: {trans_noise: -1}\n"), "test.yaml: odometry.trans_noise: must be in [0, 1]");
  expectError(minimal("odometry: {rate: 20}\n"), "test.yaml: odometry.rate: unknown key");
  // What depends on the configuration beneath is checked with it: 6 m needs a longer
  // group_period_s than the default, which a --config file may give.
  const Scenario s = parse(minimal("sonar: {range_max: 6}\nodometry: {publish_hz: 100}\n"));
  EXPECT_THROW(sonarConfig(s.sonar), ConfigError);
  EXPECT_EQ(sonarConfig(s.sonar, sonarConfig(Config::fromString("group_period_s: 0.05"))).range_max, 6);
  EXPECT_THROW(odometryConfig(s.odometry), ConfigError);
  EXPECT_EQ(odometryConfig(s.odometry, odometryConfig(Config::fromString("rate_hz: 200"))).publish_hz, 100);
}

// Physical bounds (README "Scenario format"): a value beyond them was accepted and made the
// simulation's state non-finite (a mover of radius 1e300 aborted lasonic-sim), hung it (an
// emitter pinging every 1e-300 s) or overflowed its microsecond clock (duration_s: 1e300).
TEST(Scenario, PhysicalBounds) {
  expectError(minimal("", "{path: [[0,0],[1,0]], radius: 1e300}"), "robot.radius: must be in (0, 5]");
  expectError(minimal("", "{path: [[0,0],[1,0]], speed: 100}"), "robot.speed: must be in (0, 5]");
  expectError(minimal("movers:\n  - {path: [[0,0],[1,0]], radius: 1e300}\n"), "movers[0].radius: must be in (0, 5]");
  expectError(minimal("movers:\n  - {path: [[0,0],[1,0]], speed: 1e300}\n"), "movers[0].speed: must be in (0, 10]");
  expectError(minimal("duration_s: 1e300\n"), "duration_s: must be in (0, 86400]");
  expectError(minimal("emitters:\n  - {position: [1, 2], period_s: 1e-300}\n"), "emitters[0].period_s: must be >= 0.001");
  expectError(minimal("emitters:\n  - {position: [1e300, 2], period_s: 0.1}\n"),
              "emitters[0].position: must lie within 1000 km of the origin");
  expectError(minimal("", "{path: [[0,0],[1e300,0]]}"), "robot.path[1]: must lie within 1000 km of the origin");
  expectError(minimal("obstacles:\n  - {shape: box, material: wall, center: [0,0], size: [1e300,1]}\n"),
              "obstacles[0].size: both sides must be <= 1e6 m");
  expectError(minimal("obstacles:\n  - {shape: circle, material: wall, center: [0,0], radius: 1e300}\n"),
              "obstacles[0].radius: must be <= 1e6 m");
  expectError(minimal("obstacles:\n  - {shape: polyline, material: wall, points: [[0,0],[0,-1e300]]}\n"),
              "obstacles[0].points[1]: must lie within 1000 km of the origin");
  expectError(minimal("obstacles:\n  - {shape: segment, material: glass, from: [0,0], to: [1,0], frame: {material: wall, width: 0.1, depth: 1e300}}\n"),
              "obstacles[0].frame.depth: must be <= 1e6 m");
  // The largest values accepted still simulate: every state finite.
  Scenario s = parse(minimal("duration_s: 2\nmovers:\n  - {path: [[0,0.5],[1,0.5]], radius: 5, speed: 10}\n",
                             "{path: [[0,0],[1,0]], radius: 5, speed: 5}"));
  WorldCore world(s, OdometryConfig{});
  for (int64_t u = world.startUtime(); !world.finished(u); u += world.periodUs()) {
    const sim_state_t st = world.stateAt(u);
    ASSERT_TRUE(std::isfinite(st.robot_pose.x) && std::isfinite(st.movers[0].x) && std::isfinite(st.movers[0].y));
  }
}

// The name names a run's files.
TEST(Scenario, NameIsAFileName) {
  expectError("name: ''\nrobot: {path: [[0,0],[1,0]]}\n", "name: must not be empty");
  expectError("name: a/b\nrobot: {path: [[0,0],[1,0]]}\n", "name: must not contain '/'");
}

TEST(Scenario, FileErrorsNameTheFile) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string path = scratch.file("lasonic_test_bad_scenario.yaml");
  {
    std::ofstream f(path);
    f << minimal("obstacles:\n  - {shape: circle, material: wall, center: [1,1], radius: -2}\n");
  }
  try {
    loadScenario(path);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": obstacles[0].radius: must be > 0");
  }
  EXPECT_THROW(loadScenario("/nonexistent/scenario.yaml"), ConfigError);
}

// Every shipped scenario loads, its sensor overrides are valid, and it is physically
// consistent: the robot keeps robot.radius + 0.15 m from static obstacles, and nobody walks
// through a wall, the robot or another person.
class ShippedScenario : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedScenario, LoadsAndKeepsClear) {
  const std::string path = std::string(LASONIC_SOURCE_DIR) + "/deploy/scenarios/" + GetParam() + ".yaml";
  const Scenario s = loadScenario(path);
  const std::string param = GetParam();
  EXPECT_EQ(s.name, param.substr(param.rfind('/') + 1));
  EXPECT_NO_THROW(laserConfig(s.laser));
  EXPECT_NO_THROW(odometryConfig(s.odometry));
  EXPECT_NO_THROW(sonarConfig(s.sonar));
  // Both profiles can be chosen per scenario.
  EXPECT_EQ(sonarConfig(Config::fromString("profile: ideal"), sonarConfig(s.sonar)).profile, SensorProfile::Ideal);

  WorldCore world(s, OdometryConfig{});
  auto clearance = [&](const geom::Vec2& p) {
    double d = 1e9;
    for (const Primitive& prim : s.statics)
      d = std::min(d, prim.kind == Primitive::Kind::Segment ? geom::distance(prim.segment, p)
                                                              : (p - prim.circle.center).norm() - prim.circle.radius);
    return d;
  };
  for (int64_t u = world.startUtime(); !world.finished(u); u += 50'000) {
    const sim_state_t st = world.stateAt(u);
    const double t = static_cast<double>(u - world.startUtime()) * 1e-6;
    const geom::Vec2 robot(st.robot_pose.x, st.robot_pose.y);
    ASSERT_GE(clearance(robot), s.robot.radius + 0.15 - 1e-9) << "robot at t=" << t;
    for (const mover_state_t& m : st.movers) {
      const geom::Vec2 mp(m.x, m.y);
      ASSERT_GE(clearance(mp), m.radius) << "mover " << m.id << " in a wall at t=" << t;
      ASSERT_GE((mp - robot).norm(), m.radius + s.robot.radius) << "mover " << m.id << " hits the robot at t=" << t;
      for (const mover_state_t& o : st.movers) {
        if (o.id > m.id) {
          ASSERT_GE((mp - geom::Vec2(o.x, o.y)).norm(), m.radius + o.radius) << m.id << " meets " << o.id << " at t=" << t;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Deploy, ShippedScenario,
                         ::testing::Values("fig4_room", "fig7_lab", "corridor_people", "office_glass"));
// The scene suite (README "Results"): the same checks.
INSTANTIATE_TEST_SUITE_P(Suite, ShippedScenario,
                         ::testing::Values("suite/glass_corridor", "suite/glass_door_edge", "suite/mesh_railings",
                                           "suite/black_boxes", "suite/thin_pipes", "suite/metal_angled",
                                           "suite/people_crossing", "suite/narrow_passage", "suite/laser_clutter",
                                           "suite/pioneer_lab", "suite/pioneer_office"));
// Holdout scenes (README "Scene suite"): the same checks.
INSTANTIATE_TEST_SUITE_P(Holdout, ShippedScenario,
                         ::testing::Values("holdout/glass_lobby", "holdout/warehouse_aisle", "holdout/corridor_fast",
                                           "holdout/glass_showroom", "holdout/pioneer_corridor",
                                           "holdout/pioneer_workshop", "holdout/cafe_tables",
                                           "holdout/glass_balustrade", "holdout/waiting_robot",
                                           "holdout/turning_in_place", "holdout/slow_corridor",
                                           "holdout/pioneer_sick180", "holdout/mesh_partition",
                                           "holdout/glass_office_row", "holdout/window_wall",
                                           "holdout/reception_240", "holdout/pioneer_stockroom"));
// (holdout/angled_glass_doors is left out: its black box stands between two legs of the loop
// 1.4 m apart, closer than this test's 0.15 m margin to one of them; the robot's disc clears it,
// which lasonic-sim checks.)
// Scenes outside the suite (README "Simulator"): the same checks; in people_in_the_way the
// people's paths cross the robot's, and they keep clear of it.
INSTANTIATE_TEST_SUITE_P(Experiments, ShippedScenario,
                         ::testing::Values("experiments/people_in_the_way", "experiments/creeping_mesh_corridor",
                                           "experiments/creeping_glass_corridor", "experiments/angled_mesh_room",
                                           "experiments/shop_front_arcade", "experiments/glass_meeting_rooms",
                                           "experiments/long_glass_hall", "experiments/glass_loop",
                                           "experiments/office_glass_hour", "experiments/custom_materials_pingpong"));

// A pane drawn on a wall's line (as the format's own example draws a glass door) is a pane in the
// wall: the wall is cut there. Other obstacles drawn on each other (a box's side on a wall) are
// found, and a point of the shared stretch counts as the obstacle the laser sees best; a pane
// meeting a wall end-on or two segments meeting end to end share no surface.
TEST(Scenario, PanesCutWallsAndCoincidentObstacles) {
  const Scenario s = parse(minimal(
      "obstacles:\n"
      "  - {shape: polyline, material: metal, closed: true, points: [[0,0],[6,0],[6,4],[0,4]]}\n"
      "  - {shape: segment, material: glass, from: [2,4], to: [3,4]}\n"
      "  - {shape: segment, material: glass, from: [6,1], to: [6.5,1]}\n"
      "  - {shape: box, material: black_cardboard, center: [0.25,2], size: [0.5,0.4]}\n"
      "  - {shape: segment, material: wall, from: [8,0], to: [9,0]}\n"
      "  - {shape: segment, material: glass, from: [9,0], to: [10,0]}\n"
      "  - {shape: segment, material: mesh, from: [-1,0], to: [1,0]}\n"));
  // The metal room: 4 sides, the top one cut by the door into two, the bottom one shortened by
  // the mesh drawn over its first metre (and beyond the room).
  double top = 0, bottom = 0;
  int pieces = 0;
  for (const Primitive& p : s.statics) {
    if (p.obstacle != 0) continue;
    ++pieces;
    EXPECT_FALSE(std::abs(p.segment.a.y() - 4) < 1e-9 && std::abs(p.segment.b.y() - 4) < 1e-9 &&
                 std::max(p.segment.a.x(), p.segment.b.x()) > 2 + 1e-9 && std::min(p.segment.a.x(), p.segment.b.x()) < 3 - 1e-9)
        << "the wall still runs through the door";
    if (std::abs(p.segment.a.y() - 4) < 1e-9 && std::abs(p.segment.b.y() - 4) < 1e-9) top += p.segment.length();
    if (std::abs(p.segment.a.y()) < 1e-9 && std::abs(p.segment.b.y()) < 1e-9) bottom += p.segment.length();
  }
  EXPECT_EQ(pieces, 5);
  EXPECT_NEAR(top, 5.0, 1e-9);
  EXPECT_NEAR(bottom, 5.0, 1e-9);
  ASSERT_EQ(s.coincident.size(), 7u);
  EXPECT_EQ(s.coincident[0], (std::vector<int>{3}));  // the box's side on x = 0; no pane any more
  EXPECT_TRUE(s.coincident[1].empty());
  EXPECT_TRUE(s.coincident[2].empty());  // meets the wall end-on
  EXPECT_TRUE(s.coincident[4].empty());  // two segments meeting end to end
  EXPECT_TRUE(s.coincident[5].empty());
  EXPECT_EQ(s.canonicalObstacle(1, {2.5, 4.0}), 1);   // the door is the door's
  EXPECT_EQ(s.canonicalObstacle(3, {0.0, 2.1}), 0);   // the box's side on the wall: the wall
  EXPECT_EQ(s.canonicalObstacle(0, {0.0, 2.1}), 0);
  EXPECT_EQ(s.canonicalObstacle(3, {0.5, 2.1}), 3);   // its free side
  EXPECT_EQ(s.canonicalObstacle(-2, {2.5, 4.0}), -2);  // movers as they are
  int asked = 0;
  EXPECT_TRUE(s.eitherSeen(3, {0.0, 2.1}, [&](int o) { ++asked; return o == 0; }));
  EXPECT_EQ(asked, 2);
  EXPECT_FALSE(s.eitherSeen(2, {6.2, 1.0}, [&](int o) { return o == 0; }));
}

// Two walls drawn over the same stretch (a room's outline and a wall piece drawn again beside a
// door, as angled_glass_doors does): a point there counts as the lower-indexed one, and was seen
// when the laser returned from either — also when the echo named the one it counts as and the
// laser the other (that case called 159 wall echoes of angled_glass_doors' seed 1 laser-invisible).
TEST(Scenario, TwoWallsDrawnOnEachOtherAreSeenAsEither) {
  const Scenario s = parse(minimal(
      "obstacles:\n"
      "  - {shape: polyline, material: wall, points: [[0,0],[6,0]]}\n"
      "  - {shape: segment, material: wall, from: [1,0], to: [3,0]}\n"));
  EXPECT_EQ(s.canonicalObstacle(1, {2.0, 0.0}), 0);
  EXPECT_EQ(s.canonicalObstacle(0, {2.0, 0.0}), 0);
  EXPECT_EQ(s.partnersAt(0, {2.0, 0.0}), (std::vector<int>{1}));
  EXPECT_TRUE(s.partnersAt(0, {5.0, 0.0}).empty());
  EXPECT_TRUE(s.eitherSeen(0, {2.0, 0.0}, [](int o) { return o == 1; }));
  EXPECT_TRUE(s.eitherSeen(1, {2.0, 0.0}, [](int o) { return o == 0; }));
  EXPECT_FALSE(s.eitherSeen(0, {5.0, 0.0}, [](int o) { return o == 1; }));  // beyond the shared stretch
}

namespace {
// The stretches [x0, x1] of obstacle `o`'s statics along y = 0 (a wall drawn along the x axis).
std::vector<std::pair<double, double>> piecesAlongX(const Scenario& s, int o) {
  std::vector<std::pair<double, double>> out;
  for (const Primitive& p : s.statics)
    if (p.obstacle == o) out.emplace_back(std::min(p.segment.a.x(), p.segment.b.x()), std::max(p.segment.a.x(), p.segment.b.x()));
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace

// A pane that overlaps a wall by less than 5 cm (drawn up to its end, a little too long) is no
// door in it: the wall stays whole.
TEST(Scenario, APaneOverlappingAWallByLessThanFiveCentimetresDoesNotCutIt) {
  const Scenario s = parse(minimal(
      "obstacles:\n"
      "  - {shape: segment, material: wall, from: [0,0], to: [2,0]}\n"
      "  - {shape: segment, material: glass, from: [1.98,0], to: [3,0]}\n"));
  const auto wall = piecesAlongX(s, 0);
  ASSERT_EQ(wall.size(), 1u);
  EXPECT_NEAR(wall[0].second, 2.0, 1e-9);
}

// Two panes drawn over one stretch of a wall, one inside the other: the wall is cut where either
// lies, and does not come back behind the larger one where the smaller ends.
TEST(Scenario, APaneInsideAnotherCutsTheWallOnlyWhereEitherLies) {
  const Scenario s = parse(minimal(
      "obstacles:\n"
      "  - {shape: segment, material: wall, from: [0,0], to: [4,0]}\n"
      "  - {shape: segment, material: glass, from: [1,0], to: [3,0]}\n"
      "  - {shape: segment, material: mesh, from: [1.5,0], to: [2,0]}\n"));
  const auto wall = piecesAlongX(s, 0);
  ASSERT_EQ(wall.size(), 2u);
  EXPECT_NEAR(wall[0].first, 0.0, 1e-9);
  EXPECT_NEAR(wall[0].second, 1.0, 1e-9);
  EXPECT_NEAR(wall[1].first, 3.0, 1e-9);
  EXPECT_NEAR(wall[1].second, 4.0, 1e-9);
}
