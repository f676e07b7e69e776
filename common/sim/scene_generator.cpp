#include "sim/scene_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <sstream>

#include "core/geometry.hpp"

namespace lasonic::sim {
namespace {

using geom::Vec2;

// --- The ranges drawn from, and why -----------------------------------------------------------
// Rooms of offices, labs and workshop bays.
constexpr double kRoomMinW = 7, kRoomMaxW = 13, kRoomMinH = 5, kRoomMaxH = 9;
constexpr int kMinObstacles = 4, kMaxObstacles = 9;
// Between two obstacles at least the robot's diameter (0.7 m) plus a margin: a gap is a gap the
// robot could drive through, not a crack between two things that touch.
constexpr double kObstacleSpacing = 0.9;
// A glass or mesh partition ends this far from a room wall at least (room to pass behind it is
// not needed; it must not merge with the wall).
constexpr double kPartitionWallGap = 0.2;
// The robot passes furniture with its radius plus 0.25 m, as a cautious planner does, and keeps
// 0.7 m from the room's walls.
constexpr double kPathClearance = 0.25, kPathWallGap = 0.7;
constexpr double kMinLeg = 1.5;  // [m] a leg shorter than this is a wiggle, not a drive
constexpr int kMinLegs = 4, kMaxLegs = 7;
// Indoor robot speeds: a cautious 0.2 m/s to a brisk 0.6 m/s.
const std::vector<double> kRobotSpeeds{0.2, 0.3, 0.4, 0.5, 0.6};
constexpr double kTurnRate = 1.0;     // [rad/s] the scenario's default turn on the spot
constexpr double kMaxDuration = 90;   // [s] the suite's longest scenes are 60-70 s
// People: a person is a 0.25 m disc walking 0.6 (strolling) to 1.4 m/s (brisk), to and fro
// along a line of 2.5 m or more. The simulator has no collision avoidance, so a person's line
// keeps the person's radius plus 0.2 m from furniture and both radii plus 0.15 m from the
// robot's path.
constexpr double kPersonRadius = 0.25, kPersonMinSpeed = 0.6, kPersonMaxSpeed = 1.4;
constexpr double kPersonMinWalk = 2.5, kPersonFurnitureGap = 0.2, kPersonRobotGap = 0.15;
constexpr double kPersonMaxDelay = 10;  // [s] when a person starts walking
// One scene in four is the Pioneer-type robot (README "Another robot").
constexpr double kPioneerShare = 0.25;
constexpr double kMobotRadius = 0.35, kPioneerRadius = 0.27;

// Uniform draws from the raw 64-bit stream (the standard's distributions differ between
// library implementations; mt19937_64's output does not). Every draw is a statement of its own
// or an init-declarator, which C++ sequences in order; never two draws as arguments of one call,
// whose order the compiler chooses (GCC right to left, Clang left to right). Where a point's
// coordinates are drawn, y comes first: the order the published scenes were generated in.
class Draw {
 public:
  explicit Draw(uint64_t index) : rng_(0x6c61736f6e6963ULL ^ index) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * 0x1.0p-53);
  }
  int integer(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(rng_() % static_cast<uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform(0, 1) < p; }
  template <class T>
  const T& pick(const std::vector<T>& v) {
    return v[static_cast<size_t>(rng_() % v.size())];
  }

 private:
  std::mt19937_64 rng_;
};

// Points from a to b at most `step` apart, both ends included.
std::vector<Vec2> along(const Vec2& a, const Vec2& b, double step) {
  std::vector<Vec2> out;
  const int n = std::max(1, static_cast<int>((b - a).norm() / step));
  for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (static_cast<double>(i) / n));
  return out;
}

// An obstacle's outline for the clearance checks: segments and at most one disc.
struct Outline {
  std::vector<geom::Segment> segments;
  std::vector<geom::Circle> circles;
  double distance(const Vec2& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : segments) d = std::min(d, geom::distance(s, p));
    for (const auto& c : circles) d = std::min(d, (p - c.center).norm() - c.radius);
    return d;
  }
  std::vector<Vec2> samples(double step) const {
    std::vector<Vec2> out;
    for (const auto& s : segments)
      for (const Vec2& q : along(s.a, s.b, step)) out.push_back(q);
    for (const auto& c : circles)
      for (int i = 0; i < 16; ++i) out.push_back(c.center + c.radius * geom::unitVector(i * geom::kPi / 8));
    return out;
  }
};

double nearest(const std::vector<Outline>& outlines, const Vec2& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& o : outlines) d = std::min(d, o.distance(p));
  return d;
}

std::string fmt(double v, int decimals = 2) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}
std::string pt(const Vec2& p) { return "[" + fmt(p.x()) + ", " + fmt(p.y()) + "]"; }

struct Placed {
  std::string line;  // the obstacle's scenario entry
  std::string material;
  Outline outline;
};

// One obstacle drawn inside a W x H room, or nothing when it does not fit.
std::optional<Placed> drawObstacle(Draw& d, double W, double H) {
  // Glass three times: the laser-invisible surface buildings have most of.
  static const std::vector<std::string> kMaterials{"glass", "glass", "glass", "mesh", "black_cardboard",
                                                   "plastic", "wall", "metal"};
  Placed p;
  p.material = d.pick(kMaterials);
  const bool pipe_material = p.material == "plastic" || p.material == "metal";
  if (pipe_material && d.chance(0.6)) {
    // A pipe, pole or table leg: 2-10 cm across.
    static const std::vector<double> kRadii{0.01, 0.015, 0.025, 0.05};
    const double c_y = d.uniform(0.5, H - 0.5), c_x = d.uniform(0.5, W - 0.5);
    const Vec2 c(c_x, c_y);
    const double r = d.pick(kRadii);
    p.line = "{shape: circle, material: " + p.material + ", center: " + pt(c) + ", radius: " + fmt(r, 3) + "}";
    p.outline.circles.push_back({c, r});
    return p;
  }
  if (p.material != "glass" && p.material != "mesh") {
    // A box: a cabinet, a crate, a bin, a black cardboard box; at any angle.
    const double c_y = d.uniform(0.6, H - 0.6), c_x = d.uniform(0.6, W - 0.6);
    const Vec2 c(c_x, c_y);
    const double size_y = d.uniform(0.3, 0.8), size_x = d.uniform(0.3, 1.2);
    const Vec2 size(size_x, size_y);
    const double yaw_deg = d.uniform(0, 90);
    // The corners as the scenario loader makes them (README "Scenario format": box).
    const double cy = std::cos(geom::deg2rad(yaw_deg)), sy = std::sin(geom::deg2rad(yaw_deg));
    std::vector<Vec2> w;
    for (const Vec2& k : {Vec2(-0.5, -0.5), Vec2(0.5, -0.5), Vec2(0.5, 0.5), Vec2(-0.5, 0.5)}) {
      const Vec2 q(k.x() * size.x(), k.y() * size.y());
      w.emplace_back(c.x() + q.x() * cy - q.y() * sy, c.y() + q.x() * sy + q.y() * cy);
    }
    for (size_t i = 0; i < 4; ++i) p.outline.segments.push_back({w[i], w[(i + 1) % 4]});
    p.line = "{shape: box, material: " + p.material + ", center: " + pt(c) + ", size: " + pt(size) +
             ", yaw_deg: " + fmt(yaw_deg, 1) + "}";
    return p;
  }
  // A glass pane or partition, a mesh screen or railing: 1-4 m, along the building's axes or at
  // any angle.
  const double length = d.uniform(1.0, 4.0);
  const int orientation = d.integer(0, 2);
  const double angle = orientation == 0 ? 0.0 : orientation == 1 ? geom::kPi / 2 : d.uniform(0, geom::kPi);
  const double a_y = d.uniform(0.3, H - 0.3), a_x = d.uniform(0.3, W - 0.3);
  const Vec2 a(a_x, a_y);
  const Vec2 b = a + length * geom::unitVector(angle);
  const double g = kPartitionWallGap;
  if (!(b.x() > g && b.x() < W - g && b.y() > g && b.y() < H - g)) return std::nullopt;
  p.outline.segments.push_back({a, b});
  // Three panes in ten stand in a frame (door jambs the laser sees, 5 cm wide, 10 cm deep).
  const bool framed = p.material == "glass" && d.chance(0.3);
  if (framed) {
    const Vec2 across = 0.05 * geom::unitVector(angle + geom::kPi / 2);
    for (const Vec2& end : {a, b}) p.outline.segments.push_back({end - across, end + across});
  }
  p.line = "{shape: segment, material: " + p.material + ", from: " + pt(a) + ", to: " + pt(b) +
           (framed ? ", frame: {material: wall, width: 0.05, depth: 0.1}" : "") + "}";
  return p;
}

}  // namespace

std::optional<GeneratedScene> generateScene(uint64_t index) {
  Draw d(index);
  GeneratedScene scene;
  char name[32];
  std::snprintf(name, sizeof(name), "random_%03llu", static_cast<unsigned long long>(index));
  scene.name = name;
  const double W = d.uniform(kRoomMinW, kRoomMaxW), H = d.uniform(kRoomMinH, kRoomMaxH);
  const std::string room_material = d.chance(2.0 / 3.0) ? "wall" : "metal";
  std::vector<Placed> placed;
  const int wanted = d.integer(kMinObstacles, kMaxObstacles);
  for (int tries = 0; static_cast<int>(placed.size()) < wanted && tries < 500; ++tries) {
    std::optional<Placed> p = drawObstacle(d, W, H);
    if (!p) continue;
    bool apart = true;
    for (const Vec2& q : p->outline.samples(0.05))
      for (const Placed& o : placed)
        if (o.outline.distance(q) < kObstacleSpacing) apart = false;
    if (apart) placed.push_back(std::move(*p));
  }
  std::vector<Outline> outlines;
  for (const Placed& p : placed) outlines.push_back(p.outline);

  scene.pioneer = d.chance(kPioneerShare);
  const double radius = scene.pioneer ? kPioneerRadius : kMobotRadius;
  const double clearance = radius + kPathClearance;
  auto inside = [&](const Vec2& q, double gap) {
    return q.x() > gap && q.x() < W - gap && q.y() > gap && q.y() < H - gap;
  };
  auto legClear = [&](const Vec2& a, const Vec2& b) {
    for (const Vec2& q : along(a, b, 0.1))
      if (!inside(q, kPathWallGap) || nearest(outlines, q) < clearance) return false;
    return true;
  };
  const double lo = kPathWallGap + 0.1;
  std::vector<Vec2> path;
  for (int attempt = 0; attempt < 2000 && path.empty(); ++attempt) {
    const double w0_y = d.uniform(lo, H - lo), w0_x = d.uniform(lo, W - lo);
    std::vector<Vec2> wp{Vec2(w0_x, w0_y)};
    if (nearest(outlines, wp[0]) < clearance) continue;
    const int legs = d.integer(kMinLegs, kMaxLegs);
    bool ok = true;
    for (int i = 0; i < legs && ok; ++i) {
      // The longest of three clear legs: a robot drives to places across the room, it does not
      // wiggle in a corner.
      std::optional<Vec2> next;
      int clear = 0;
      for (int t = 0; t < 100 && clear < 3; ++t) {
        const double n_y = d.uniform(lo, H - lo), n_x = d.uniform(lo, W - lo);
        const Vec2 n(n_x, n_y);
        if ((n - wp.back()).norm() > kMinLeg && legClear(wp.back(), n)) {
          ++clear;
          if (!next || (n - wp.back()).norm() > (*next - wp.back()).norm()) next = n;
        }
      }
      ok = next.has_value();
      if (ok) wp.push_back(*next);
    }
    if (ok) path = wp;
  }
  if (path.empty()) return std::nullopt;
  const double speed = d.pick(kRobotSpeeds);
  double length = 0, turns = 0;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    length += (path[i + 1] - path[i]).norm();
    if (i + 2 < path.size()) {
      const Vec2 u = path[i + 1] - path[i], v = path[i + 2] - path[i + 1];
      turns += std::abs(std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v)));
    }
  }
  // The path driven once, the turns on the spot, 2 s to stand at the end; at most kMaxDuration.
  const double duration = std::min(kMaxDuration, std::ceil(length / speed + turns / kTurnRate + 2.0));

  std::vector<Vec2> robot_samples;
  for (size_t i = 0; i + 1 < path.size(); ++i)
    for (const Vec2& q : along(path[i], path[i + 1], 0.1)) robot_samples.push_back(q);
  std::vector<std::string> movers;
  const double u = d.uniform(0, 1);
  const int people = u < 0.4 ? 0 : u < 0.8 ? 1 : 2;
  for (int k = 0; k < people; ++k) {
    for (int t = 0; t < 400; ++t) {
      const double a_y = d.uniform(0.5, H - 0.5), a_x = d.uniform(0.5, W - 0.5);
      const Vec2 a(a_x, a_y);
      const double b_y = d.uniform(0.5, H - 0.5), b_x = d.uniform(0.5, W - 0.5);
      const Vec2 b(b_x, b_y);
      if ((b - a).norm() < kPersonMinWalk) continue;
      bool ok = true;
      for (const Vec2& q : along(a, b, 0.1)) {
        if (nearest(outlines, q) < kPersonRadius + kPersonFurnitureGap) ok = false;
        for (const Vec2& r : robot_samples)
          if ((q - r).norm() < kPersonRadius + radius + kPersonRobotGap) ok = false;
        if (!ok) break;
      }
      if (!ok) continue;
      const double delay = d.uniform(0, kPersonMaxDelay), walk = d.uniform(kPersonMinSpeed, kPersonMaxSpeed);
      char line[256];
      std::snprintf(line, sizeof(line),
                    "{shape: circle, radius: %.2f, material: person, speed: %.2f, path: [%s, %s], "
                    "mode: pingpong, start_delay_s: %.1f}",
                    kPersonRadius, walk, pt(a).c_str(), pt(b).c_str(), delay);
      movers.push_back(line);
      break;
    }
  }
  scene.movers = static_cast<int>(movers.size());

  std::set<std::string> materials;
  for (const Placed& p : placed) materials.insert(p.material);
  const std::vector<std::string> obstacle_materials(materials.begin(), materials.end());
  if (!movers.empty()) materials.insert("person");
  scene.materials.assign(materials.begin(), materials.end());

  std::ostringstream y;
  y << "# Random scene " << index << " (lasonic-scenegen; README \"Random scenes\"): a " << fmt(W) << " x "
    << fmt(H) << " m room with " << (room_material == "wall" ? "plaster" : "metal") << " walls, "
    << placed.size() << " obstacles (";
  for (size_t i = 0; i < obstacle_materials.size(); ++i) y << (i ? ", " : "") << obstacle_materials[i];
  y << "), " << movers.size() << (movers.size() == 1 ? " person" : " people") << "; "
    << (scene.pioneer ? "the Pioneer-type robot" : "MOBOT-IV") << " at " << fmt(speed) << " m/s.\n";
  y << "name: " << scene.name << "\n";
  y << "duration_s: " << duration << "\n";
  y << "seed: " << index << "\n";
  y << "obstacles:\n";
  y << "  - {shape: polyline, material: " << room_material << ", closed: true, points: [[0, 0], "
    << pt(Vec2(W, 0)) << ", " << pt(Vec2(W, H)) << ", " << pt(Vec2(0, H)) << "]}\n";
  for (const Placed& p : placed) y << "  - " << p.line << "\n";
  if (!movers.empty()) {
    y << "movers:\n";
    for (const std::string& m : movers) y << "  - " << m << "\n";
  }
  y << "robot:\n  radius: " << fmt(radius) << "\n  path: [";
  for (size_t i = 0; i < path.size(); ++i) y << (i ? ", " : "") << pt(path[i]);
  y << "]\n  speed: " << fmt(speed) << "\n  mode: once\n";
  if (scene.pioneer) {
    // The sensors of the suite's Pioneer scenes (README "Another robot"): a 270 deg laser at the
    // front, 16 sonars of 25 deg in a front and a rear array of 8.
    y << "laser:\n  fov_deg: 270\n  readings: 811\n  scan_rate_hz: 15\n  mount: {x: 0.10, y: 0.0, yaw_deg: 0}\n";
    y << "sonar:\n  sensors:\n";
    struct S {
      double x, y, theta;
    };
    static const S kFront[8] = {{0.069, 0.136, 90},   {0.114, 0.119, 50},   {0.148, 0.078, 30},
                                {0.166, 0.027, 10},   {0.166, -0.027, -10}, {0.148, -0.078, -30},
                                {0.114, -0.119, -50}, {0.069, -0.136, -90}};
    static const S kRear[8] = {{-0.157, -0.136, -90}, {-0.203, -0.119, -130}, {-0.237, -0.078, -150},
                               {-0.255, -0.027, -170}, {-0.255, 0.027, 170},   {-0.237, 0.078, 150},
                               {-0.203, 0.119, 130},   {-0.157, 0.136, 90}};
    for (const S* array : {kFront, kRear})
      for (int g = 0; g < 8; ++g) {
        char line[128];
        std::snprintf(line, sizeof(line), "    - {x: %.3f, y: %.3f, theta_deg: %.0f, beam_deg: 25, group: %d}\n",
                      array[g].x, array[g].y, array[g].theta, g);
        y << line;
      }
    y << "  group_period_s: 0.04\n";
  }
  scene.yaml = y.str();
  return scene;
}

}  // namespace lasonic::sim
