#pragma once
// 2-D geometry for the whole pipeline: poses, and the ray / segment / circle / beam-sector
// queries that the sensor models, the hypothetical scan and the evaluation share.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace lasonic::geom {

using Vec2 = Eigen::Vector2d;

constexpr double kPi = 3.14159265358979323846;
inline double deg2rad(double d) { return d * kPi / 180.0; }
inline double rad2deg(double r) { return r * 180.0 / kPi; }
// A beam's full opening as a message carries it: finite and in (0, pi) rad; anything else is a
// malformed field (a sonar beam is never a half-plane), for every stage that reads one.
inline bool plausibleBeamWidth(double w) { return std::isfinite(w) && w > 0.0 && w < kPi; }

// Wraps to (-pi, pi].
inline double normalizeAngle(double a) {
  if (!std::isfinite(a)) return a;
  // fmod(a, 2pi) is a itself when |a| < 2pi (exactly: the quotient is 0); the common case.
  if (!(std::abs(a) < 2.0 * kPi)) a = std::fmod(a, 2.0 * kPi);
  if (a <= -kPi) a += 2.0 * kPi;
  if (a > kPi) a -= 2.0 * kPi;
  return a;
}
// Signed smallest difference a - b, in (-pi, pi].
inline double angleDiff(double a, double b) { return normalizeAngle(a - b); }

// Rigid 2-D transform / pose: a frame at (x, y) rotated by theta.
struct Pose2 {
  double x = 0, y = 0, theta = 0;

  Vec2 position() const { return {x, y}; }
  // Local point -> parent frame.
  Vec2 transform(const Vec2& local) const;
  // Parent point -> local frame.
  Vec2 inverseTransform(const Vec2& parent) const;
  // this ∘ other: other is expressed in this frame.
  Pose2 compose(const Pose2& other) const;
  Pose2 inverse() const;
};

// Linear in position, shortest-arc in heading; s in [0,1].
Pose2 interpolate(const Pose2& a, const Pose2& b, double s);

inline Vec2 unitVector(double angle) { return {std::cos(angle), std::sin(angle)}; }

struct Segment {
  Vec2 a, b;
  double length() const { return (b - a).norm(); }
};

// The principal axes of a 2-D scatter from its central second moments (sums or means, weighted
// or not: any common scale). A line through the centroid along `angle` is the total-least-squares
// fit (it minimises the sum of squared orthogonal distances, which is `minor`); `major` is the
// spread along it. The one formula every line fit here shares (Radar Map lines, movers' faces,
// tactical lines, pass-through's remembered lines).
struct PrincipalAxes {
  double angle = 0;  // of the major axis, in (-pi/2, pi/2]
  double major = 0, minor = 0;  // eigenvalues, major >= minor >= 0
};
inline PrincipalAxes principalAxes(double sxx, double syy, double sxy) {
  const double half = 0.5 * (sxx - syy);
  const double disc = std::sqrt(half * half + sxy * sxy);
  const double mean = 0.5 * (sxx + syy);
  return {0.5 * std::atan2(2.0 * sxy, sxx - syy), mean + disc, std::max(0.0, mean - disc)};
}

// Pose2::transform for many points: the pose's cos and sin taken once (the same values, bit for
// bit: the same expression on the same numbers).
class PoseTransform {
 public:
  explicit PoseTransform(const Pose2& p)
      : x_(p.x), y_(p.y), theta_(p.theta), c_(std::cos(p.theta)), s_(std::sin(p.theta)) {}
  Vec2 operator()(const Vec2& l) const { return {x_ + c_ * l.x() - s_ * l.y(), y_ + s_ * l.x() + c_ * l.y()}; }
  Segment operator()(const Segment& s) const { return {(*this)(s.a), (*this)(s.b)}; }
  // Pose2::compose.
  Pose2 operator()(const Pose2& o) const {
    const Vec2 p = (*this)(o.position());
    return {p.x(), p.y(), normalizeAngle(theta_ + o.theta)};
  }

 private:
  double x_, y_, theta_, c_, s_;
};

struct Circle {
  Vec2 center;
  double radius = 0;
};

// A ray from origin along a unit direction.
struct Ray {
  Vec2 origin;
  Vec2 dir;  // unit length
};

// Ray casts: distance along the ray to the first intersection (>= 0), if any.
std::optional<double> intersect(const Ray& ray, const Segment& s);
std::optional<double> intersect(const Ray& ray, const Circle& c);

Vec2 closestPoint(const Segment& s, const Vec2& p);
double distance(const Segment& s, const Vec2& p);
// Unit normal of a segment (left of a->b).
Vec2 normal(const Segment& s);
// Incidence angle in [0, pi/2] between a ray direction and a surface with the given normal
// (0 = perpendicular hit).
double incidenceAngle(const Vec2& ray_dir, const Vec2& surface_normal);

// A circular sector (an ideal sonar beam): apex, axis heading, full opening angle (< pi) and radius.
struct Sector {
  Vec2 apex;
  double heading = 0;
  double opening = 0;   // full angle [rad], 0 < opening < pi
  double radius = 0;

  bool contains(const Vec2& p) const;
};

// Distance from the apex to the nearest point of the segment that lies inside the sector
// (the ideal sonar's reading of that segment), if the segment enters the sector.
std::optional<double> nearestInSector(const Sector& sec, const Segment& s);
// Same for a circle's boundary (a solid disc: the nearest boundary point inside the sector).
std::optional<double> nearestInSector(const Sector& sec, const Circle& c);
// The nearest point itself (same rules; the evaluation needs to know which surface point
// defines a sector's truth).
std::optional<Vec2> nearestPointInSector(const Sector& sec, const Segment& s);
std::optional<Vec2> nearestPointInSector(const Sector& sec, const Circle& c);

// Clip a segment to the infinite wedge of the sector (ignoring the radius). Empty if outside.
std::optional<Segment> clipToWedge(const Sector& sec, const Segment& s);

// A sector's edge and axis directions, for testing many segments against one sector: the very
// values clipToWedge would compute (three sin/cos pairs) on every call.
struct SectorEdges {
  explicit SectorEdges(const Sector& sec);
  Vec2 left, right, axis;
};
std::optional<Segment> clipToWedge(const Sector& sec, const SectorEdges& e, const Segment& s);
std::optional<double> nearestInSector(const Sector& sec, const SectorEdges& e, const Segment& s);

}  // namespace lasonic::geom
