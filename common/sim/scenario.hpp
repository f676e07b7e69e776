#pragma once
// Scenario files (README "Scenario format"): the static world, moving obstacles, the
// robot's path and per-scenario sensor overrides. Loading errors name the key path, e.g.
// "obstacles[3].radius: must be > 0".
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"

namespace lasonic::sim {

// Physical bounds of what the simulator accepts (README "Scenario format"). Each lies far beyond
// any real robot, person or building, and keeps the simulation's arithmetic sound: ray casting
// in metres, schedules in int64 microseconds.
namespace bounds {
// [m] No mobile robot of this kind (MOBOT-IV: 0.35 m, a Pioneer: 0.27 m) reaches more than 5 m
// from its centre, so nothing mounted on it (a laser, a sonar) is further out; nor is a person,
// trolley or forklift moving about a building wider than that.
inline constexpr double kMaxBodyRadius = 5.0;
// [m/s] A mobile robot indoors drives at most a few metres a second (as --robot-speed).
inline constexpr double kMaxRobotSpeed = 5.0;
// [m/s] No person runs faster than a sprinter, nor does anything else that moves among people.
inline constexpr double kMaxMoverSpeed = 10.0;
// [s] A day of simulated time: no battery-powered robot drives longer in one run.
inline constexpr double kMaxDurationS = 86'400.0;
// [m] 1000 km from the origin: far beyond any building, and where doubles still resolve
// 1e-10 m (the drivers refuse a SIM_STATE beyond it, as a pose of 1e30 m turns ray casting into NaN).
inline constexpr double kMaxCoordinate = 1e6;
// [s] An ultrasound source cannot ping again before its own burst has rung down: about 1 ms for
// a 49 kHz transducer.
inline constexpr double kMinEmitterPeriodS = 1e-3;
}  // namespace bounds

enum class LaserBehaviour { Reflect, Transparent, Absorb };

// How a surface material looks to each sensor. Two sensor profiles read it (README "Sensor
// models"): the ideal profile (the method's idealised sensors) uses `laser`, sonar_echo_angle and
// sonar_echo_prob; the physical profile (the default) uses the physical parameters below.
struct Material {
  std::string name;
  LaserBehaviour laser = LaserBehaviour::Reflect;
  // --- ideal profile
  double sonar_echo_angle = 0;  // [rad] largest incidence angle that still echoes straight back
  double sonar_echo_prob = 1;   // probability that a surface within that angle echoes
  // --- physical profile, sonar
  double sonar_reflect_db = 0;  // [dB] <= 0: power lost in the reflection (absorbed by the material)
  double sonar_roughness = 0;   // [m] rms surface height: coherent (mirror) share exp(-(2 k h)^2)
  double sonar_lobe = 0;        // [rad] rms facet slope: width of the incoherent specular lobe
  double sonar_diffuse = 0;     // share of the incoherent power scattered diffusely (Lambert)
  double sonar_transmit = 0;    // share of the power that passes through (a mesh); 0: opaque
  double sonar_fluct_db = 0;    // [dB] std-dev of a slowly varying echo level (a person's posture)
  double sonar_fluct_s = 1;     // [s] correlation time of that variation
  double sonar_aspect_db = 0;   // [dB] a mover is this much weaker seen from the side than head-on
  // Per-reading echo probability in the physical profile: 1, except for a material described
  // only by the ideal keys, whose sonar_echo_prob carries over.
  double sonar_hear_prob = 1;
  // --- physical profile, laser
  double laser_remission = 0;   // diffuse reflectance at the scanner's wavelength (0..1)
  double laser_specular = 0;    // [rad] a transparent surface returns the beam within this of normal incidence
};

// Built-in materials (README "Scenario format"): wall, metal, glass, mesh, black_cardboard,
// plastic, person; each with its ideal and physical parameters.
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
  // A frame (door jambs): obstacles appended after the scenario's own, one box at each end of
  // this segment / open polyline, whose ends were shortened by its width. -1: not a frame;
  // else the index of the framed obstacle.
  int frame_of = -1;
  // This obstacle's own frame (segment / open polyline): material, width along the ends, depth
  // across; empty material: none.
  std::string frame_material;
  double frame_width = 0, frame_depth = 0;
};

// A foreign ultrasound source (another robot's sonar, a motion detector): pings every period_s
// from a fixed position; the physical sonar hears its direct sound (README "Sensor models").
struct EmitterSpec {
  geom::Vec2 position{geom::Vec2::Zero()};
  double period_s = 0.1;
  double phase_s = 0;                 // first ping at sim time phase_s
  std::optional<double> level_db;     // margin of its sound at 1 m on our axis at full gain; default: like our own transducer
  std::optional<double> heading;      // [rad] points like our transducer; unset: omnidirectional
};

struct MoverSpec {
  int id = 0;
  double radius = 0.25;
  std::string material = "person";
  double speed = 0.5;     // [m/s]
  std::vector<geom::Vec2> path;
  PathMode mode = PathMode::PingPong;
  double start_delay_s = 0;
  // People keep out of a robot's way: the mover waits rather than step within keep_clear_m of
  // the robot's body, and steps back when the robot comes closer (WorldCore). false: it walks
  // its path regardless, through the robot if the paths cross.
  bool avoid_robot = true;
  double keep_clear_m = 0.10;  // [m] a hand's width: people stop short of touching
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
  std::vector<EmitterSpec> emitters;
  RobotSpec robot;
  Config laser;     // overrides of the laser driver's config keys
  Config sonar;     // overrides of the sonar driver's config keys
  Config odometry;  // overrides of the odometry (drift) config keys

  // Static obstacles drawn on top of each other: per obstacle, the others with a straight side
  // lying on one of its own (within kCoincidentM, overlapping by 5 cm or more), e.g. a glass
  // pane drawn on a wall's line. Neither sensor can tell such surfaces apart (the laser returns
  // from the wall, an echo from either), so the evaluation counts a shared stretch once, as the
  // obstacle the laser sees best (canonicalObstacle; README "Evaluation").
  static constexpr double kCoincidentM = 0.01;
  std::vector<std::vector<int>> coincident;

  const Material& material(const std::string& name) const;
  // True for static obstacles whose material reflects the laser.
  bool laserVisible(int obstacle) const;
  // The obstacle a point of `obstacle`'s surface is counted as: the coincident obstacle whose
  // surface passes within kCoincidentM of p and that the laser sees best (reflect, then absorb,
  // then transparent; then the lower index), else `obstacle` itself (movers too).
  int canonicalObstacle(int obstacle, const geom::Vec2& p) const;
  // The coincident obstacles of `obstacle` whose surface passes within kCoincidentM of p.
  std::vector<int> partnersAt(int obstacle, const geom::Vec2& p) const;
  // Calls seen(o) for `obstacle` and, where its surface at p is drawn on others', for each of
  // them: whether a sensor that tells obstacles apart saw the point as any of them (the laser
  // returns from the wall behind a pane, or from the pane near its normal; of two walls drawn on
  // each other, from either).
  template <typename Seen>
  bool eitherSeen(int obstacle, const geom::Vec2& p, const Seen& seen) const {
    if (seen(obstacle)) return true;
    for (const int o : partnersAt(obstacle, p))
      if (seen(o)) return true;
    return false;
  }
};

// A transparent obstacle drawn on an opaque one's line (a glass door or a mesh panel drawn on the
// wall it sits in, as the format's example draws one) replaces it there: the opaque side is cut
// where the pane lies, so the laser passes through the door and the sonar meets the pane, as in
// a real doorway. (Drawn exactly on each other, the ray casts decided by rounding which surface
// was met: the laser returned from the wall on most rays and lost it on some.)
void cutPanesIntoWalls(Scenario& s);
// Fills Scenario::coincident from its statics.
void findCoincidentObstacles(Scenario& s);

// Throws ConfigError naming the file and key path.
Scenario loadScenario(const std::string& file);
Scenario parseScenario(const Config& root);
// Whether the movers a log's SIM_STATE names (their ids) are this scenario's, as they are in a
// log simulated from it: empty if so, else why not ("its SIM_STATE has 3 movers, the scenario 0").
std::string simStateMoversMismatch(const Scenario& scenario, const std::vector<int>& mover_ids);
// Distance from p to the robot's path as the simulator drives it: the waypoints' legs, and the
// leg back to the first waypoint when the path loops. The simulated robot stays on these legs
// (it turns on the spot at waypoints), so a true pose far from them was not simulated from this
// scenario. Infinity when the scenario has no path.
double distanceToRobotPath(const Scenario& scenario, const geom::Vec2& p);
// How far off its path a log's robot may be before lasonic-eval and lasonic-render call the log
// another scenario's [m].
inline constexpr double kRobotOffPathM = 1.0;

}  // namespace lasonic::sim
