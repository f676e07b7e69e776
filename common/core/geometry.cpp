#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic::geom {

Vec2 Pose2::transform(const Vec2& l) const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {x + c * l.x() - s * l.y(), y + s * l.x() + c * l.y()};
}

Vec2 Pose2::inverseTransform(const Vec2& p) const {
  const double c = std::cos(theta), s = std::sin(theta);
  const double dx = p.x() - x, dy = p.y() - y;
  return {c * dx + s * dy, -s * dx + c * dy};
}

Pose2 Pose2::compose(const Pose2& o) const {
  const Vec2 p = transform(o.position());
  return {p.x(), p.y(), normalizeAngle(theta + o.theta)};
}

Pose2 Pose2::inverse() const {
  const double c = std::cos(theta), s = std::sin(theta);
  return {-(c * x + s * y), -(-s * x + c * y), normalizeAngle(-theta)};
}

Pose2 interpolate(const Pose2& a, const Pose2& b, double s) {
  return {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y),
          normalizeAngle(a.theta + s * angleDiff(b.theta, a.theta))};
}

static double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

std::optional<double> intersect(const Ray& ray, const Segment& s) {
  const Vec2 e = s.b - s.a;
  const double denom = cross(ray.dir, e);
  if (std::abs(denom) < 1e-15) return std::nullopt;  // parallel: a grazing ray sees no surface
  const Vec2 w = s.a - ray.origin;
  const double t = cross(w, e) / denom;   // along the ray
  const double u = cross(w, ray.dir) / denom;  // along the segment
  if (t < 0.0 || u < 0.0 || u > 1.0) return std::nullopt;
  return t;
}

std::optional<double> intersect(const Ray& ray, const Circle& c) {
  const Vec2 oc = ray.origin - c.center;
  const double b = oc.dot(ray.dir);
  const double cc = oc.squaredNorm() - c.radius * c.radius;
  const double disc = b * b - cc;
  if (disc < 0.0) return std::nullopt;
  const double sq = std::sqrt(disc);
  const double t0 = -b - sq;
  if (t0 >= 0.0) return t0;
  const double t1 = -b + sq;
  if (t1 >= 0.0) return 0.0;  // origin inside the disc
  return std::nullopt;
}

Vec2 closestPoint(const Segment& s, const Vec2& p) {
  const Vec2 e = s.b - s.a;
  const double l2 = e.squaredNorm();
  if (l2 <= 0.0) return s.a;
  const double u = std::clamp((p - s.a).dot(e) / l2, 0.0, 1.0);
  return s.a + u * e;
}

double distance(const Segment& s, const Vec2& p) { return (closestPoint(s, p) - p).norm(); }

Vec2 normal(const Segment& s) {
  const Vec2 e = (s.b - s.a).normalized();
  return {-e.y(), e.x()};
}

double incidenceAngle(const Vec2& d, const Vec2& n) {
  const double c = std::min(1.0, std::abs(d.normalized().dot(n.normalized())));
  return std::acos(c);
}

bool Sector::contains(const Vec2& p) const {
  const Vec2 d = p - apex;
  const double r = d.norm();
  if (r > radius) return false;
  if (r == 0.0) return true;
  return std::abs(angleDiff(std::atan2(d.y(), d.x()), heading)) <= 0.5 * opening + 1e-12;
}

SectorEdges::SectorEdges(const Sector& sec)
    : left(unitVector(sec.heading + 0.5 * sec.opening)),
      right(unitVector(sec.heading - 0.5 * sec.opening)),
      axis(unitVector(sec.heading)) {}

std::optional<Segment> clipToWedge(const Sector& sec, const Segment& s) { return clipToWedge(sec, SectorEdges(sec), s); }

std::optional<Segment> clipToWedge(const Sector& sec, const SectorEdges& edges, const Segment& s) {
  // The wedge (opening < pi) is the intersection of two half-planes through the apex.
  const Vec2& left = edges.left;
  const Vec2& right = edges.right;
  // Inward normals: for the left edge, the inside is clockwise of it; for the right, counter-clockwise.
  const Vec2 n_left(left.y(), -left.x());
  const Vec2 n_right(-right.y(), right.x());
  double u0 = 0.0, u1 = 1.0;
  const Vec2 e = s.b - s.a;
  for (const Vec2& n : {n_left, n_right}) {
    const double f0 = n.dot(s.a - sec.apex);  // signed distance at u = 0 (>= 0 inside)
    const double fe = n.dot(e);                // derivative along u
    if (std::abs(fe) < 1e-15) {
      if (f0 < -1e-12) return std::nullopt;
      continue;
    }
    const double u = -f0 / fe;
    if (fe > 0) u0 = std::max(u0, u); else u1 = std::min(u1, u);
    if (u0 > u1) return std::nullopt;
  }
  Segment c{s.a + u0 * e, s.a + u1 * e};
  // The two half-planes also admit the mirrored wedge behind the apex; reject it.
  const Vec2 mid = 0.5 * (c.a + c.b) - sec.apex;
  if (mid.squaredNorm() > 1e-24 && mid.dot(edges.axis) < 0.0) return std::nullopt;
  return c;
}

std::optional<double> nearestInSector(const Sector& sec, const Segment& s) {
  return nearestInSector(sec, SectorEdges(sec), s);
}

std::optional<double> nearestInSector(const Sector& sec, const SectorEdges& edges, const Segment& s) {
  const auto c = clipToWedge(sec, edges, s);
  if (!c) return std::nullopt;
  const double d = distance(*c, sec.apex);
  if (d > sec.radius) return std::nullopt;
  return d;
}

std::optional<double> nearestInSector(const Sector& sec, const Circle& c) {
  const Vec2 d = c.center - sec.apex;
  const double dist = d.norm();
  if (dist <= c.radius) return 0.0;  // apex inside the disc
  // If the centre's bearing is inside the wedge, the nearest boundary point is straight towards it.
  if (std::abs(angleDiff(std::atan2(d.y(), d.x()), sec.heading)) <= 0.5 * sec.opening) {
    const double r = dist - c.radius;
    return r <= sec.radius ? std::optional<double>(r) : std::nullopt;
  }
  // Otherwise the nearest point inside the sector lies on one of the two edges.
  std::optional<double> best;
  for (double side : {-1.0, 1.0}) {
    const Ray edge{sec.apex, unitVector(sec.heading + side * 0.5 * sec.opening)};
    if (auto t = intersect(edge, c); t && *t <= sec.radius) {
      if (!best || *t < *best) best = *t;
    }
  }
  return best;
}

std::optional<Vec2> nearestPointInSector(const Sector& sec, const Segment& s) {
  const auto c = clipToWedge(sec, s);
  if (!c) return std::nullopt;
  const Vec2 p = closestPoint(*c, sec.apex);
  if ((p - sec.apex).norm() > sec.radius) return std::nullopt;
  return p;
}

std::optional<Vec2> nearestPointInSector(const Sector& sec, const Circle& c) {
  const Vec2 d = c.center - sec.apex;
  const double dist = d.norm();
  if (dist <= c.radius) return sec.apex;  // apex inside the disc
  if (std::abs(angleDiff(std::atan2(d.y(), d.x()), sec.heading)) <= 0.5 * sec.opening) {
    if (dist - c.radius > sec.radius) return std::nullopt;
    return Vec2(sec.apex + d * ((dist - c.radius) / dist));
  }
  std::optional<Vec2> best;
  double best_t = 0;
  for (double side : {-1.0, 1.0}) {
    const Ray edge{sec.apex, unitVector(sec.heading + side * 0.5 * sec.opening)};
    if (auto t = intersect(edge, c); t && *t <= sec.radius && (!best || *t < best_t)) {
      best_t = *t;
      best = Vec2(edge.origin + *t * edge.dir);
    }
  }
  return best;
}

}  // namespace lasonic::geom
