#include "tactical/laser_join.hpp"

#include <cmath>

namespace lasonic {

std::vector<geom::Vec2> laserJoinPoints(const geom::Pose2& sensor, double range, double beam_width,
                                        const std::vector<geom::Segment>& radar_map, const LaserJoinParams& p) {
  std::vector<geom::Vec2> out;
  const geom::Vec2 o = sensor.position();
  if (!(o.allFinite() && std::isfinite(sensor.theta) && std::isfinite(range) && range > 0 &&
        geom::plausibleBeamWidth(beam_width) && p.cell_size > 0))
    return out;
  const double half_beam = 0.5 * beam_width;
  const double max_gap = range * std::tan(half_beam) + p.cell_size;
  double best = max_gap;
  geom::Vec2 foot = geom::Vec2::Zero(), end = geom::Vec2::Zero();
  bool found = false;
  for (const geom::Segment& s : radar_map) {
    const double len = s.length();
    if (!(len >= p.min_line_length && len > 1e-9) || !s.a.allFinite() || !s.b.allFinite()) continue;
    const geom::Vec2 u = (s.b - s.a) / len;
    const geom::Vec2 w = o - s.a;
    const double along = w.dot(u);
    const geom::Vec2 f = s.a + along * u;  // the perpendicular's foot on the line
    const geom::Vec2 to_f = f - o;
    const double dist = to_f.norm();
    if (std::abs(dist - range) > 0.5 * p.cell_size || !(dist > 1e-9)) continue;  // not this plane's echo
    if (std::abs(geom::angleDiff(std::atan2(to_f.y(), to_f.x()), sensor.theta)) > half_beam) continue;  // outside the beam
    // Beyond an end (alongside the segment the plane is the laser's own business).
    const double gap = along < 0 ? -along : along > len ? along - len : -1;
    if (gap <= 0 || gap > best) continue;
    best = gap;
    foot = f;
    end = along < 0 ? s.a : s.b;
    found = true;
  }
  if (!found) return out;
  const geom::Vec2 t = (end - foot) / (end - foot).norm();
  const double len = (end - foot).norm();
  const double step = 0.5 * p.cell_size;
  for (double s = 0; s < len; s += step) out.push_back(foot + s * t);
  out.push_back(end);
  return out;
}

}  // namespace lasonic
