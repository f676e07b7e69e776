#include "sim/world_geometry.hpp"

#include <algorithm>

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

std::optional<Hit> WorldGeometry::castRay(const geom::Ray& ray, double max_range,
                                          const std::function<bool(const Material&)>& passes) const {
  // Brute force: scenario worlds hold a few hundred primitives at most.
  const Primitive* best = nullptr;
  double best_t = max_range;
  for (const Primitive& p : prims_) {
    if (passes && passes(*p.material)) continue;
    const std::optional<double> t =
        p.kind == Primitive::Kind::Segment ? geom::intersect(ray, p.segment) : geom::intersect(ray, p.circle);
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
    const std::optional<double> t =
        p.kind == Primitive::Kind::Segment ? geom::intersect(ray, p.segment) : geom::intersect(ray, p.circle);
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
