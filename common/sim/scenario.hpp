#pragma once
// Scenario files (DESIGN.md "Scenario file format"): the static world, moving obstacles, the
// robot's path and per-scenario sensor overrides. Loading errors name the key path, e.g.
// "obstacles[3].radius: must be > 0".
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"

namespace lasonic::sim {

enum class LaserBehaviour { Reflect, Transparent, Absorb };

struct Material {
  std::string name;
  LaserBehaviour laser = LaserBehaviour::Reflect;
  double sonar_echo_angle = 0;  // [rad] largest incidence angle that still echoes straight back
  double sonar_echo_prob = 1;   // probability that a surface within that angle echoes
};

// Built-in materials (DESIGN.md): wall, metal, glass, mesh, black_cardboard, plastic, person.
std::map<std::string, Material> builtinMaterials();

enum class PathMode { Once, Loop, PingPong };

// One geometric primitive of the world. Polylines and boxes are expanded into segments at load
// time; every primitive remembers which scenario entry it came from.
struct Primitive {
  enum class Kind { Segment, Circle } kind = Kind::Segment;
  geom::Segment segment{geom::Vec2::Zero(), geom::Vec2::Zero()};  // Kind::Segment
  geom::Circle circle{geom::Vec2::Zero(), 0.0};                    // Kind::Circle
  int obstacle = -1;      // index in Scenario::obstacles, or -(mover id)-2 for a mover
  const Material* material = nullptr;  // points into Scenario::materials (stable: std::map)
};

struct ObstacleSpec {
  std::string shape;      // polyline | segment | circle | box
  std::string material;
  std::vector<geom::Vec2> points;  // polyline points / segment ends / box corners
  bool closed = false;
  geom::Circle circle{geom::Vec2::Zero(), 0.0};  // circle
};

struct MoverSpec {
  int id = 0;
  double radius = 0.25;
  std::string material = "person";
  double speed = 0.5;     // [m/s]
  std::vector<geom::Vec2> path;
  PathMode mode = PathMode::PingPong;
  double start_delay_s = 0;
};

struct RobotSpec {
  double radius = 0.35;
  std::vector<geom::Vec2> path;
  double speed = 0.3;     // [m/s]
  PathMode mode = PathMode::Once;
  double turn_rate = 1.0; // [rad/s] the robot turns on the spot at waypoints
};

struct Scenario {
  Scenario() = default;
  // Copies re-point every Primitive::material into the copy's own materials map.
  Scenario(const Scenario& other);
  Scenario& operator=(const Scenario& other);
  Scenario(Scenario&&) = default;  // std::map keeps its nodes when moved
  Scenario& operator=(Scenario&&) = default;

  std::string name;
  std::string file;
  double duration_s = 60;
  uint64_t seed = 1;
  std::map<std::string, Material> materials;
  std::vector<ObstacleSpec> obstacles;
  std::vector<Primitive> statics;  // expanded static geometry
  std::vector<MoverSpec> movers;
  RobotSpec robot;
  Config laser;     // overrides of the laser driver's config keys
  Config sonar;     // overrides of the sonar driver's config keys
  Config odometry;  // overrides of the odometry (drift) config keys

  const Material& material(const std::string& name) const;
  // True for static obstacles whose material reflects the laser.
  bool laserVisible(int obstacle) const;
};

// Throws ConfigError naming the file and key path.
Scenario loadScenario(const std::string& file);
Scenario parseScenario(const Config& root);

}  // namespace lasonic::sim
