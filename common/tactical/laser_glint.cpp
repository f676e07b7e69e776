#include "tactical/laser_glint.hpp"

#include <algorithm>
#include <cmath>
#include "core/utime.hpp"

namespace lasonic {

namespace {

// Angle between the line of sight from `v` to `p` and the normal of a line of unit direction
// `u`: 0 when the line faces v squarely at p.
double incidence(const geom::Vec2& v, const geom::Vec2& p, const geom::Vec2& u) {
  const geom::Vec2 d = p - v;
  const double n = d.norm();
  if (!(n > 1e-9)) return geom::kPi / 2;
  return std::asin(std::min(1.0, std::abs(d.dot(u)) / n));
}

bool finite(const geom::Segment& s) { return s.a.allFinite() && s.b.allFinite(); }

}  // namespace

LaserGlintParams laserGlintParams(const Config& c, LaserGlintParams p) {
  c.allowOnly({"max_incidence_deg", "max_rms_m", "end_gap_m", "min_points", "max_range_m", "confirm_s", "min_move_m",
               "move_tol_m", "line_tol_m"});
  p.max_incidence = geom::deg2rad(c.get("max_incidence_deg", geom::rad2deg(p.max_incidence), Range::between(0, 45)));
  p.max_rms = c.get("max_rms_m", p.max_rms, Range::between(0, 1));
  p.end_gap = c.get("end_gap_m", p.end_gap, Range::between(0, 5));
  p.min_points = c.get("min_points", p.min_points, Range::between(1, 1000));
  p.max_range = c.get("max_range_m", p.max_range, Range::nonNegative());
  p.confirm_s = c.get("confirm_s", p.confirm_s, Range::between(0, 60));
  p.min_move = c.get("min_move_m", p.min_move, Range::between(0, 10));
  p.move_tol = c.get("move_tol_m", p.move_tol, Range::between(0, 10));
  p.line_tol = c.get("line_tol_m", p.line_tol, Range::between(0, 10));
  return p;
}

std::vector<complement::RmSegment> glintCandidates(const std::vector<complement::RmSegment>& radar_map,
                                                   const geom::Vec2& viewpoint, const LaserGlintParams& p) {
  std::vector<complement::RmSegment> out;
  if (!p.enabled() || !viewpoint.allFinite()) return out;
  const double gap2 = p.end_gap * p.end_gap, range2 = p.max_range * p.max_range;
  for (size_t i = 0; i < radar_map.size(); ++i) {
    const complement::RmSegment& s = radar_map[i];
    const double len = s.seg.length();
    if (!finite(s.seg) || !(len > 1e-9) || s.npoints < p.min_points || !(s.rms <= p.max_rms)) continue;
    if (p.max_range > 0 &&
        ((s.seg.a - viewpoint).squaredNorm() > range2 || (s.seg.b - viewpoint).squaredNorm() > range2))
      continue;
    const geom::Vec2 u = (s.seg.b - s.seg.a) / len;
    if (incidence(viewpoint, s.seg.a, u) > p.max_incidence || incidence(viewpoint, s.seg.b, u) > p.max_incidence)
      continue;
    bool alone = true;
    for (size_t j = 0; j < radar_map.size() && alone; ++j) {
      if (j == i || !finite(radar_map[j].seg)) continue;
      const geom::Segment& o = radar_map[j].seg;
      for (const geom::Vec2& e : {s.seg.a, s.seg.b})
        if ((o.a - e).squaredNorm() <= gap2 || (o.b - e).squaredNorm() <= gap2) alone = false;
    }
    if (alone) out.push_back(s);
  }
  return out;
}

std::vector<geom::Vec2> glintHits(const std::vector<complement::RmSegment>& glints) {
  // A glint spans a few degrees of the scan: even at 0.1 deg per reading far fewer returns than
  // this; more is a malformed count, not more evidence.
  constexpr int kMaxHitsPerGlint = 64;
  std::vector<geom::Vec2> out;
  for (const complement::RmSegment& g : glints) {
    if (g.npoints <= 0 || !finite(g.seg)) continue;
    const auto n = static_cast<size_t>(std::min(g.npoints, kMaxHitsPerGlint));
    for (size_t k = 0; k < n; ++k) {
      const double f = n == 1 ? 0.5 : static_cast<double>(k) / static_cast<double>(n - 1);
      out.push_back(g.seg.a + f * (g.seg.b - g.seg.a));
    }
  }
  return out;
}

bool GlintTracker::confirms(const Seen& earlier, const geom::Vec2& viewpoint, const complement::RmSegment& now) const {
  const geom::Segment& e = earlier.seg.seg;
  const double len = e.length();
  if (!(len > 1e-9)) return false;
  const geom::Vec2 u = (e.b - e.a) / len;
  const geom::Vec2 n(-u.y(), u.x());
  // Both ends of the new candidate on the earlier one's line.
  if (std::abs((now.seg.a - e.a).dot(n)) > p_.line_tol || std::abs((now.seg.b - e.a).dot(n)) > p_.line_tol) return false;
  // The robot's foot on that line moved by d; the glint's middle must have moved by d too.
  const double foot_move = (viewpoint - earlier.viewpoint).dot(u);
  if (std::abs(foot_move) < p_.min_move) return false;
  const geom::Vec2 mid_then = 0.5 * (e.a + e.b), mid_now = 0.5 * (now.seg.a + now.seg.b);
  return std::abs((mid_now - mid_then).dot(u) - foot_move) <= p_.move_tol;
}

std::vector<complement::RmSegment> GlintTracker::update(int64_t utime, const geom::Vec2& viewpoint,
                                                        const std::vector<complement::RmSegment>& radar_map) {
  std::vector<complement::RmSegment> out;
  if (!p_.enabled()) return out;
  if (!seen_.empty() && utime <= seen_.back().utime) seen_.clear();
  const auto window = secondsToUs(p_.confirm_s);
  while (!seen_.empty() && utime - seen_.front().utime > window) seen_.pop_front();
  const std::vector<complement::RmSegment> candidates = glintCandidates(radar_map, viewpoint, p_);
  for (const complement::RmSegment& c : candidates)
    if (std::any_of(seen_.begin(), seen_.end(), [&](const Seen& s) { return confirms(s, viewpoint, c); }))
      out.push_back(c);
  // A few candidates per map are a scene's glass; a bound keeps a flood of malformed maps cheap.
  constexpr size_t kMaxKept = 256;
  for (const complement::RmSegment& c : candidates) seen_.push_back({utime, viewpoint, c});
  while (seen_.size() > kMaxKept) seen_.pop_front();
  return out;
}

}  // namespace lasonic
