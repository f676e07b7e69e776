#include "operational/laser_shadow.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic {
namespace {
constexpr double kMaxSteps = 1e4;  // points per edge: 500 m at 5 cm
}  // namespace

void laserShadow(const std::vector<geom::Vec2>& points, const std::vector<uint8_t>& valid, const geom::Vec2& origin,
                 bool full_circle, const LaserShadowParams& p, std::vector<geom::Vec2>& out) {
  if (!(p.spacing > 0) || !(p.reach > 0) || !origin.allFinite()) return;
  const size_t n = std::min(points.size(), valid.size());
  const auto ok = [&](size_t i) { return valid[i] != 0 && points[i].allFinite(); };
  const double reach2 = p.reach * p.reach;
  // Interior points of a..b, at most `spacing` apart, within the reach.
  const auto along = [&](const geom::Vec2& a, const geom::Vec2& b) {
    const double len = (b - a).norm();
    if (!(len > p.spacing)) return;
    const double steps = std::ceil(len / p.spacing);
    if (steps > kMaxSteps) return;  // (not from a real scan)
    const int m = static_cast<int>(steps);
    for (int j = 1; j < m; ++j) {
      const geom::Vec2 q = a + (b - a) * (static_cast<double>(j) / m);
      if ((q - origin).squaredNorm() <= reach2) out.push_back(q);
    }
  };
  // Points on the ray from the origin through a, beyond a, up to the reach.
  const auto beyond = [&](const geom::Vec2& a) {
    const geom::Vec2 d = a - origin;
    const double r = d.norm();
    if (!(r > 0) || r >= p.reach) return;
    const double steps = std::floor((p.reach - r) / p.spacing);
    if (steps > kMaxSteps) return;  // (a reach no sector map has)
    const geom::Vec2 u = d / r;
    for (int j = 1; j <= static_cast<int>(steps); ++j) out.push_back(a + u * (j * p.spacing));
  };
  for (size_t i = 0; i < n; ++i) {
    const size_t j = i + 1 < n ? i + 1 : 0;
    if (j == 0 && !full_circle) break;
    if (j == i) break;  // (one reading)
    const bool vi = ok(i), vj = ok(j);
    if (vi && vj) along(points[i], points[j]);
    else if (vi) beyond(points[i]);
    else if (vj) beyond(points[j]);
  }
}

}  // namespace lasonic
