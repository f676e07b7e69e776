#include "sim/world_geometry.hpp"

#include <algorithm>
#include <cstdio>

#include "sim/path_follower.hpp"

namespace lasonic::sim {

namespace {

double cross(const geom::Vec2& a, const geom::Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Distance between two segments: 0 where they cross, else the nearest of an end to the other.
double distance(const geom::Segment& s, const geom::Segment& w) {
  const geom::Vec2 ds = s.b - s.a, dw = w.b - w.a;
  const double o1 = cross(ds, w.a - s.a), o2 = cross(ds, w.b - s.a);
  const double o3 = cross(dw, s.a - w.a), o4 = cross(dw, s.b - w.a);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 0.0;
  return std::min({geom::distance(s, w.a), geom::distance(s, w.b), geom::distance(w, s.a), geom::distance(w, s.b)});
}

}  // namespace

double clearance(const Primitive& p, const geom::Vec2& q) {
  if (p.kind == Primitive::Kind::Segment) return geom::distance(p.segment, q);
  return (q - p.circle.center).norm() - p.circle.radius;
}

double clearance(const Primitive& p, const geom::Segment& s) {
  if (p.kind == Primitive::Kind::Segment) return distance(p.segment, s);
  return geom::distance(s, p.circle.center) - p.circle.radius;
}

namespace {

// Whether q lies inside the polygon (even-odd rule).
bool inside(const std::vector<geom::Vec2>& poly, const geom::Vec2& q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const geom::Vec2 &a = poly[i], &b = poly[j];
    if ((a.y() > q.y()) != (b.y() > q.y()) && q.x() < a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      in = !in;
  }
  return in;
}

// Where a disc of radius r carried by `f` from t = 0 to `end` first overlaps each static obstacle
// (robotOverlaps' rule), sampled every step_m at `speed`.
std::vector<RobotOverlap> discOverlaps(const Scenario& s, const PathFollower& f, double radius, double speed,
                                       double end, double step_m) {
  // At most 200 000 samples of an absurdly long path.
  const double dt = std::max(step_m / speed, end / 200'000);
  std::vector<bool> met(s.obstacles.size(), false);
  std::vector<RobotOverlap> out;
  const double r = radius - 1e-9;  // (touching is not overlapping)
  geom::Vec2 prev = f.at(0).pose.position();
  for (double t = 0;; t = std::min(t + dt, end)) {
    const geom::Vec2 q = f.at(t).pose.position();
    const geom::Segment way{prev, q};
    for (const Primitive& p : s.statics) {
      if (met[p.obstacle] || !(clearance(p, way) < r)) continue;
      met[p.obstacle] = true;
      out.push_back({p.obstacle, q, t});
    }
    for (size_t i = 0; i < s.obstacles.size(); ++i)
      if (!met[i] && s.obstacles[i].shape == "box" && inside(s.obstacles[i].points, q)) {
        met[i] = true;
        out.push_back({static_cast<int>(i), q, t});
      }
    if (t >= end) break;
    prev = q;
  }
  return out;
}

// "obstacles[3]", or "obstacles[5] (a jamb of obstacles[3]'s frame)".
std::string obstacleName(const Scenario& s, int obstacle) {
  const ObstacleSpec& spec = s.obstacles.at(static_cast<size_t>(obstacle));
  std::string what = "obstacles[" + std::to_string(obstacle) + "]";
  if (spec.frame_of >= 0) what += " (a jamb of obstacles[" + std::to_string(spec.frame_of) + "]'s frame)";
  return what;
}

}  // namespace

std::vector<RobotOverlap> robotOverlaps(const Scenario& s, double step_m) {
  const PathFollower robot(s.robot.path, s.robot.mode, s.robot.speed, s.robot.turn_rate);
  // One cycle of a repeating path is all of it.
  return discOverlaps(s, robot, s.robot.radius, s.robot.speed, std::min(s.duration_s, robot.cycleDuration()), step_m);
}

std::vector<MoverOverlap> moverOverlaps(const Scenario& s, double step_m) {
  std::vector<MoverOverlap> out;
  for (size_t i = 0; i < s.movers.size(); ++i) {
    const MoverSpec& m = s.movers[i];
    // As the world moves it (WorldCore): turning on the spot, after its start delay.
    const PathFollower f(m.path, m.mode, m.speed, std::numeric_limits<double>::infinity(), m.start_delay_s);
    const double end = std::min(s.duration_s, m.start_delay_s + f.cycleDuration());
    for (const RobotOverlap& o : discOverlaps(s, f, m.radius, m.speed, end, step_m))
      out.push_back({static_cast<int>(i), o});
  }
  return out;
}

std::string describeMoverOverlap(const Scenario& s, const MoverOverlap& o) {
  const MoverSpec& m = s.movers.at(static_cast<size_t>(o.mover));
  char buf[320];
  std::snprintf(buf, sizeof buf, "the mover (radius %.2f) overlaps %s at (%.2f, %.2f) (t \u2248 %.1f s%s)", m.radius,
                obstacleName(s, o.where.obstacle).c_str(), o.where.at.x(), o.where.at.y(), o.where.t,
                o.where.t <= m.start_delay_s ? ", where it starts"
                : m.avoid_robot              ? ", later if it waits for the robot"
                                             : "");
  return "movers[" + std::to_string(o.mover) + "].path: " + std::string(buf);
}

std::string describeRobotOverlap(const Scenario& s, const RobotOverlap& o) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "the robot (radius %.2f) overlaps %s at (%.2f, %.2f) (t \u2248 %.1f s%s)",
                s.robot.radius, obstacleName(s, o.obstacle).c_str(), o.at.x(), o.at.y(), o.t,
                o.t == 0 ? ", where it starts" : "");
  return "robot.path: " + std::string(buf);
}

WorldGeometry::WorldGeometry(const Scenario& scenario)
    : scenario_(&scenario), n_static_(scenario.statics.size()), prims_(scenario.statics) {}

void WorldGeometry::setMovers(const std::vector<MoverPose>& movers) {
  prims_.resize(n_static_);
  for (const MoverPose& m : movers) {
    Primitive p;
    p.kind = Primitive::Kind::Circle;
    p.circle = {m.position, m.radius};
    p.obstacle = -m.id - 2;
    p.material = &scenario_->material(scenario_->movers.at(static_cast<size_t>(m.id)).material);
    prims_.push_back(p);
  }
}

std::optional<double> rangeAlong(const geom::Ray& ray, const Primitive& p) {
  if (p.kind != Primitive::Kind::Segment) return geom::intersect(ray, p.circle);
  if (const std::optional<double> t = geom::intersect(ray, p.segment)) return t;
  // Only a start on the segment's line (within kOnSurfaceM) can have missed by rounding: then
  // geom::intersect's test again with the start moved back by kOnSurfaceM.
  const geom::Vec2 e = p.segment.b - p.segment.a, w = p.segment.a - ray.origin;
  const double off = w.x() * e.y() - w.y() * e.x();  // the start's distance from the line x |e|
  if (off * off > kOnSurfaceM * kOnSurfaceM * e.squaredNorm()) return std::nullopt;
  const std::optional<double> t = geom::intersect({ray.origin - kOnSurfaceM * ray.dir, ray.dir}, p.segment);
  if (!t) return std::nullopt;
  return std::max(0.0, *t - kOnSurfaceM);
}

std::optional<Hit> WorldGeometry::castRay(const geom::Ray& ray, double max_range,
                                          const std::function<bool(const Material&)>& passes) const {
  // Brute force: scenario worlds hold a few hundred primitives at most.
  const Primitive* best = nullptr;
  double best_t = max_range;
  for (const Primitive& p : prims_) {
    if (passes && passes(*p.material)) continue;
    const std::optional<double> t = rangeAlong(ray, p);
    if (t && *t <= best_t) {
      best_t = *t;
      best = &p;
    }
  }
  if (!best) return std::nullopt;
  return makeHit(ray, best_t, *best);
}

std::optional<Hit> WorldGeometry::castRayAmong(const geom::Ray& ray, double max_range,
                                               const std::vector<uint32_t>& statics) const {
  const Primitive* best = nullptr;
  double best_t = max_range;
  auto test = [&](const Primitive& p) {
    const std::optional<double> t = rangeAlong(ray, p);
    if (t && *t <= best_t) {
      best_t = *t;
      best = &p;
    }
  };
  for (uint32_t i : statics) test(prims_[i]);
  for (size_t i = n_static_; i < prims_.size(); ++i) test(prims_[i]);
  if (!best) return std::nullopt;
  return makeHit(ray, best_t, *best);
}

Hit WorldGeometry::makeHit(const geom::Ray& ray, double t, const Primitive& p) const {
  Hit h;
  h.range = t;
  h.point = ray.origin + t * ray.dir;
  h.primitive = &p;
  h.obstacle = p.obstacle;
  if (p.kind == Primitive::Kind::Segment) {
    h.normal = geom::normal(p.segment);
  } else {
    const geom::Vec2 radial = h.point - p.circle.center;
    // A ray starting inside a disc hits at range 0; its surface then faces the ray head-on.
    h.normal = radial.norm() > 1e-12 ? geom::Vec2(radial.normalized()) : geom::Vec2(-ray.dir);
  }
  if (h.normal.dot(ray.dir) > 0) h.normal = -h.normal;
  return h;
}

}  // namespace lasonic::sim
