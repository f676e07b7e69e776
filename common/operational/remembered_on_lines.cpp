#include "operational/remembered_on_lines.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic {

std::vector<int> moveOntoLines(std::vector<geom::Vec2>& points, const std::vector<geom::Segment>& lines,
                               double radius) {
  std::vector<int> taken_by(points.size(), -1);
  if (!(radius > 0) || lines.empty()) return taken_by;
  const double r2 = radius * radius;
  for (size_t i = 0; i < points.size(); ++i) {
    geom::Vec2& p = points[i];
    double best = r2;
    geom::Vec2 foot = p;
    for (size_t k = 0; k < lines.size(); ++k) {
      const geom::Segment& s = lines[k];
      const geom::Vec2 d = s.b - s.a;
      const double len2 = d.squaredNorm();
      if (!(len2 > 0)) continue;
      const double t = (p - s.a).dot(d) / len2;
      if (t < 0 || t > 1) continue;  // beyond an end: the line says nothing about this cell
      const geom::Vec2 f = s.a + t * d;
      const double e2 = (p - f).squaredNorm();
      if (e2 <= best) {
        best = e2;
        foot = f;
        taken_by[i] = static_cast<int>(k);
      }
    }
    p = foot;
  }
  return taken_by;
}

std::vector<geom::Vec2> fillBetweenOnLines(const std::vector<geom::Vec2>& points, const std::vector<int>& taken_by,
                                           const std::vector<geom::Segment>& lines, double step, double max_gap) {
  std::vector<geom::Vec2> fill;
  if (!(step > 0) || taken_by.size() != points.size()) return fill;
  // Each line's feet by their position along it, from its first end.
  std::vector<std::vector<double>> along(lines.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const int k = taken_by[i];
    if (k < 0 || static_cast<size_t>(k) >= lines.size()) continue;
    along[static_cast<size_t>(k)].push_back((points[i] - lines[static_cast<size_t>(k)].a).norm());
  }
  for (size_t k = 0; k < lines.size(); ++k) {
    std::vector<double>& t = along[k];
    if (t.size() < 2) continue;
    std::sort(t.begin(), t.end());
    const geom::Vec2 d = lines[k].b - lines[k].a;
    const geom::Vec2 u = d / d.norm();  // a line that took two feet has a length
    for (size_t j = 0; j + 1 < t.size(); ++j) {
      const double gap = t[j + 1] - t[j];
      if (!(gap > step) || !(gap < max_gap)) continue;
      // n - 1 points, at most `step` apart (a gap of exactly k steps is k steps, not k + 1)
      const int n = static_cast<int>(std::ceil(gap / step - 1e-9));
      for (int m = 1; m < n; ++m) fill.push_back(lines[k].a + u * (t[j] + gap * m / n));
    }
  }
  return fill;
}

}  // namespace lasonic
