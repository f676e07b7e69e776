#include "operational/remembered_on_lines.hpp"

namespace lasonic {

void moveOntoLines(std::vector<geom::Vec2>& points, const std::vector<geom::Segment>& lines, double radius) {
  if (!(radius > 0) || lines.empty()) return;
  const double r2 = radius * radius;
  for (geom::Vec2& p : points) {
    double best = r2;
    geom::Vec2 foot = p;
    for (const geom::Segment& s : lines) {
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
      }
    }
    p = foot;
  }
}

}  // namespace lasonic
