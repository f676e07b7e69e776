#include "operational/sound_passed.hpp"

#include <cmath>

namespace lasonic {

int markSoundPassed(AccumulativeGridMap& agm, const std::vector<Sounding>& group, double core, double margin_m,
                    bool at_range) {
  if (!(core > 0) || !(margin_m >= 0)) return 0;
  const double c = agm.cellSize();
  int marked = 0;
  for (const Sounding& s : group) {
    const double reach = s.reach + (at_range ? margin_m : -margin_m);
    const double half = std::min(core, 1.0) * 0.5 * s.beam_width;
    if (!(reach > margin_m) || !(half > 0) || !std::isfinite(s.sensor.x) || !std::isfinite(s.sensor.y) ||
        !std::isfinite(s.sensor.theta) || reach > 100)
      continue;
    // The sector's bounding box (transducer, both edges' ends, the axis' end), a cell of margin
    // for the arc's bulge.
    const geom::Vec2 o = s.sensor.position();
    geom::Vec2 lo = o, hi = o;
    for (const double a : {0.0, half, -half}) {
      const geom::Vec2 e = o + reach * geom::unitVector(s.sensor.theta + a);
      lo = lo.cwiseMin(e), hi = hi.cwiseMax(e);
    }
    const geom::Vec2 pad(c, c);
    const geom::Vec2 wlo = agm.originMetres(), whi = wlo + geom::Vec2(agm.size() * c, agm.size() * c) - pad * 1e-6;
    const geom::Vec2 a = (lo - pad).cwiseMax(wlo), b = (hi + pad).cwiseMin(whi);
    int ix0 = 0, iy0 = 0, ix1 = 0, iy1 = 0;
    if (!(a.x() <= b.x() && a.y() <= b.y()) || !agm.cellAt(a, ix0, iy0) || !agm.cellAt(b, ix1, iy1)) continue;
    std::vector<std::pair<int, int>> cells;
    agm.forEachWeightedCell(ix0, iy0, ix1, iy1, [&](int ix, int iy, int, int) {
      const geom::Vec2 q = agm.cellCorner(ix, iy) + geom::Vec2(0.5 * c, 0.5 * c) - o;
      const double d = q.norm();
      if (d < margin_m || d > reach) return;
      if (std::abs(geom::angleDiff(std::atan2(q.y(), q.x()), s.sensor.theta)) > half) return;
      cells.emplace_back(ix, iy);
    });
    for (const auto& [ix, iy] : cells) agm.markPassed(ix, iy);
    marked += static_cast<int>(cells.size());
  }
  return marked;
}

int markNearMovers(AccumulativeGridMap& agm, const std::vector<geom::Vec2>& points, double radius) {
  if (!(radius > 0) || points.empty()) return 0;
  const double c = agm.cellSize();
  const int k = static_cast<int>(std::ceil(radius / c));
  int marked = 0;
  for (const geom::Vec2& p : points) {
    int px = 0, py = 0;
    if (!agm.cellAt(p, px, py)) continue;
    for (int iy = std::max(0, py - k); iy <= std::min(agm.size() - 1, py + k); ++iy)
      for (int ix = std::max(0, px - k); ix <= std::min(agm.size() - 1, px + k); ++ix) {
        if ((agm.cellCorner(ix, iy) + geom::Vec2(0.5 * c, 0.5 * c) - p).norm() > radius) continue;
        agm.markPassed(ix, iy);
        ++marked;
      }
  }
  return marked;
}

int markNearMovers(AccumulativeGridMap& agm, const std::vector<SectorMap::MovingPoint>& movers, double radius) {
  if (!(radius > 0) || movers.empty()) return 0;
  std::vector<geom::Vec2> at;
  at.reserve(movers.size());
  for (const SectorMap::MovingPoint& q : movers) at.push_back(q.p);
  return markNearMovers(agm, at, radius);
}

}  // namespace lasonic
