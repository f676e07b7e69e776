#include "tactical/pass_through.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lasonic {

PassThroughParams passThroughParams(const Config& c, PassThroughParams p) {
  c.allowOnly({"core", "margin_m", "clear_after", "line_ratio", "line_min_cells", "line_radius_cells", "beyond_limit",
               "silence", "heard_from_gate", "silence_risk", "line_heard_at_normal"});
  p.core = c.get("core", p.core, Range::between(0, 1));
  p.margin_m = c.get("margin_m", p.margin_m, Range::between(0, 10));
  p.clear_after = c.get("clear_after", p.clear_after, Range::between(1, 1000));
  p.line_ratio = c.get("line_ratio", p.line_ratio, Range::between(0, 1));
  p.line_min_cells = c.get("line_min_cells", p.line_min_cells, Range::between(2, 1000));
  p.line_radius_cells = c.get("line_radius_cells", p.line_radius_cells, Range::between(1, 20));
  p.line_heard_at_normal = c.get("line_heard_at_normal", p.line_heard_at_normal);
  p.beyond_limit = c.get("beyond_limit", p.beyond_limit);
  p.silence = c.get("silence", p.silence);
  p.heard_from_gate = c.get("heard_from_gate", p.heard_from_gate);
  p.silence_risk = c.get("silence_risk", p.silence_risk, Range::between(0, 1));
  return p;
}

bool rememberedLineNormal(const AccumulativeGridMap& agm, int ix, int iy, const PassThroughParams& p,
                          geom::Vec2& normal) {
  const int r = p.line_radius_cells;
  int n = 0;
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  const geom::Vec2 o = agm.cellCorner(ix, iy);  // offsets from here keep the sums small
  agm.forEachPositiveCell(ix - r, iy - r, ix + r, iy + r, [&](int cx, int cy, int, int) {
    const geom::Vec2 q = agm.evidencePoint(cx, cy) - o;
    ++n;
    sx += q.x(), sy += q.y();
    sxx += q.x() * q.x(), syy += q.y() * q.y(), sxy += q.x() * q.y();
  });
  if (n < p.line_min_cells) return false;
  const double mx = sx / n, my = sy / n;
  const double cxx = sxx / n - mx * mx, cyy = syy / n - my * my, cxy = sxy / n - mx * my;
  // The line runs along the covariance's major axis; straight enough when the spread across it is
  // small beside the spread along it.
  const geom::PrincipalAxes ax = geom::principalAxes(cxx, cyy, cxy);
  if (!(ax.major > 0) || std::sqrt(ax.minor / ax.major) > p.line_ratio) return false;
  normal = geom::Vec2(-std::sin(ax.angle), std::cos(ax.angle));
  return true;
}

namespace {
// Erases the entries (by global cell) whose cell has left the map's window or is no longer live.
template <typename Map, typename Live>
void sweep(Map& map, const AccumulativeGridMap& agm, Live live) {
  const double c = agm.cellSize();
  for (auto it = map.begin(); it != map.end();) {
    int ix = 0, iy = 0;
    const geom::Vec2 centre((static_cast<double>(it->first.first) + 0.5) * c,
                            (static_cast<double>(it->first.second) + 0.5) * c);
    it = agm.cellAt(centre, ix, iy) && live(ix, iy, it->second) ? std::next(it) : map.erase(it);
  }
}
}  // namespace

int PassThrough::apply(const std::vector<Sounding>& group, AccumulativeGridMap& agm) {
  if (!p_.enabled()) return 0;
  cells_.clear();
  const double c = agm.cellSize();
  double r_half = std::numeric_limits<double>::quiet_NaN();  // the half width whose cos and sin r holds
  geom::Vec2 r(1, 0);
  for (const Sounding& s : group) {
    const double reach = s.reach - p_.margin_m;
    const double half = p_.core * 0.5 * s.beam_width;
    if (!(reach > p_.margin_m) || !(half > 0) || !std::isfinite(s.sensor.x) || !std::isfinite(s.sensor.y) ||
        !std::isfinite(s.sensor.theta) || reach > 100)
      continue;
    // The core sector's bounding box: the transducer, both edges' ends and the axis' end, a cell
    // of margin for the arc's bulge.
    // (The edges turned from the axis by the half width's cos and sin: within rounding of their
    // own unit vectors, far inside the cell of margin.)
    const geom::Vec2 o = s.sensor.position();
    if (half != r_half) r = geom::unitVector(half), r_half = half;
    const geom::Vec2 u = geom::unitVector(s.sensor.theta);
    geom::Vec2 lo = o, hi = o;
    for (const geom::Vec2& d : {u, geom::Vec2(r.x() * u.x() - r.y() * u.y(), r.y() * u.x() + r.x() * u.y()),
                                geom::Vec2(r.x() * u.x() + r.y() * u.y(), -r.y() * u.x() + r.x() * u.y())}) {
      const geom::Vec2 e = o + reach * d;
      lo = lo.cwiseMin(e), hi = hi.cwiseMax(e);
    }
    int ix0 = 0, iy0 = 0, ix1 = 0, iy1 = 0;
    const geom::Vec2 pad(c, c);
    const geom::Vec2 wlo = agm.originMetres(), whi = wlo + geom::Vec2(agm.size() * c, agm.size() * c) - pad * 1e-6;
    const geom::Vec2 a = (lo - pad).cwiseMax(wlo), b = (hi + pad).cwiseMin(whi);
    if (!(a.x() <= b.x() && a.y() <= b.y()) || !agm.cellAt(a, ix0, iy0) || !agm.cellAt(b, ix1, iy1)) continue;
    agm.forEachPositiveCell(ix0, iy0, ix1, iy1, [&](int ix, int iy, int, int) {
      const geom::Vec2 q = agm.evidencePoint(ix, iy) - o;
      const double d = q.norm();
      if (d < p_.margin_m || d > reach) return;
      if (std::abs(geom::angleDiff(std::atan2(q.y(), q.x()), s.sensor.theta)) > half) return;
      // A remembered plane answers only when the beam meets it near its normal (with
      // line_heard_at_normal: unless it was heard from off its normal, from here).
      geom::Vec2 n;
      if (rememberedLineNormal(agm, ix, iy, p_, n) &&
          (!p_.line_heard_at_normal ||
           heardAtNormal(agm.originX() + ix, agm.originY() + iy, n, s.beam_width) ||
           !heardFrom(agm.originX() + ix, agm.originY() + iy, agm.evidencePoint(ix, iy), o, 0.5 * s.beam_width))) {
        const double incidence = std::acos(std::min(1.0, std::abs(n.dot(geom::unitVector(s.sensor.theta)))));
        if (incidence > half) return;
      }
      // Silent: only from where it answered before (a plane's answers come from within the beam's
      // half width of its normal).
      if (s.unverifiable && p_.heard_from_gate &&
          !heardFrom(agm.originX() + ix, agm.originY() + iy, agm.evidencePoint(ix, iy), o, 0.5 * s.beam_width))
        return;
      cells_.push_back({ix, iy, s.unverifiable});
    });
  }
  // One look per cell and group; an echo's look where the group also held one.
  std::sort(cells_.begin(), cells_.end());
  cells_.erase(std::unique(cells_.begin(), cells_.end(),
                           [](const Look& a, const Look& b) { return a.ix == b.ix && a.iy == b.iy; }),
               cells_.end());
  int emptied = 0;
  emptied_by_silence_ = 0;
  for (const Look& l : cells_) {
    const int ix = l.ix, iy = l.iy;
    const std::pair<int64_t, int64_t> key{agm.originX() + ix, agm.originY() + iy};
    const int64_t last_hit = agm.lastHitCycle(ix, iy);
    Passes& e = passes_[key];
    if (e.last_hit != last_hit) e = {last_hit, 0, 0};
    int needed = p_.clear_after;
    if (l.silent) {
      ++e.silent;
      // Silence empties a cell only after as many silent looks in a row as make it unlikely
      // (silence_risk) that a reflector still there was silent each time, at the answer rate of
      // all its looks (this run of silence too, as it would be if the reflector were there): a
      // mesh answers now and then, a person or a post nearly always.
      const auto h = heard_.find(key);
      if (h != heard_.end()) {
        ++h->second.silent;
        needed = std::max(needed, silentLooksNeeded(h->second.hits, h->second.silent, p_.silence_risk));
      }
    } else {
      ++e.n;
    }
    if (e.n < p_.clear_after && e.n + e.silent < needed) continue;
    const geom::Vec2 centre = agm.cellCorner(ix, iy) + geom::Vec2(0.5 * c, 0.5 * c);
    const int n = agm.clearDisc(centre, 0.25 * c);
    emptied += n;
    if (e.n < p_.clear_after) emptied_by_silence_ += n;  // the echoes alone would not have
    passes_.erase(key);
    heard_.erase(key);
  }
  // Directions of cells forgotten since (by time, or emptied by the footprint) go; so do the
  // counts of cells emptied or hit since (their count would restart anyway). Amortised: a map
  // with more live cells than the bound is not swept at every group.
  if (heard_.size() > heard_prune_at_) {
    sweep(heard_, agm, [&agm](int ix, int iy, const Heard&) { return agm.g(ix, iy) > 0; });
    heard_prune_at_ = std::max<size_t>(4096, 2 * heard_.size());
  }
  if (passes_.size() > passes_prune_at_) {
    sweep(passes_, agm, [&agm](int ix, int iy, const Passes& e) { return agm.lastHitCycle(ix, iy) == e.last_hit; });
    passes_prune_at_ = std::max<size_t>(4096, 2 * passes_.size());
  }
  return emptied;
}

void PassThrough::noteHit(const geom::Vec2& point, const geom::Vec2& from, const AccumulativeGridMap& agm) {
  if (!notesHits()) return;
  int ix = 0, iy = 0;
  if (!agm.cellAt(point, ix, iy) || !std::isfinite(from.x()) || !std::isfinite(from.y())) return;
  const geom::Vec2 d = from - point;
  const double n = d.norm();
  if (!(n > 1e-6)) return;
  Heard& e = heard_[{agm.originX() + ix, agm.originY() + iy}];
  // Empty before this group: what was heard there before has been forgotten.
  if (agm.g(ix, iy) == 0 && e.cycle != agm.cycle()) e = Heard{};
  e.cycle = agm.cycle();
  e.sum += d / n;
  ++e.hits;
}

bool PassThrough::heardAtNormal(int64_t gx, int64_t gy, const geom::Vec2& n, double half) const {
  const auto it = heard_.find({gx, gy});
  if (it == heard_.end() || it->second.hits < 2 || !(it->second.sum.norm() > 1e-9) || !(n.norm() > 1e-9)) return true;
  const double cosine = std::abs(it->second.sum.normalized().dot(n.normalized()));
  return std::acos(std::min(1.0, cosine)) <= half;
}

int silentLooksNeeded(int hits, int silent, double risk) {
  if (!(risk > 0) || risk >= 1) return 1;
  // The answer rate: hits over hits and silent looks.
  const double p = static_cast<double>(std::max(hits, 1)) / static_cast<double>(std::max(hits, 1) + std::max(silent, 0));
  if (p >= 1) return 1;
  const double k = std::ceil(std::log(risk) / std::log(1 - p));
  return k > 1000 ? 1000 : std::max(1, static_cast<int>(k));
}

bool PassThrough::heardFrom(int64_t gx, int64_t gy, const geom::Vec2& cell, const geom::Vec2& sensor,
                            double half) const {
  const auto it = heard_.find({gx, gy});
  if (it == heard_.end() || !(it->second.sum.norm() > 1e-9)) return false;
  const geom::Vec2 u = sensor - cell;
  if (!(u.norm() > 1e-9)) return false;
  const double cosine = it->second.sum.normalized().dot(u.normalized());
  return std::acos(std::clamp(cosine, -1.0, 1.0)) <= half;
}

}  // namespace lasonic
