#include "operational/echo_placer.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace lasonic {

std::vector<std::string> echoPlacementKeys() {
  return {"agm_bearing",       "agm_placement", "evidence_min_g",    "arc_halfwidth_deg",
          "arc_min_votes",     "arc_require_votes", "arc_wait_cycles", "surface_fill", "surface_spread_m",
          "surface_max_angle_deg", "surface_min_agree", "surface_max_gap_m", "neighbour_bearing"};
}

EchoPlacementConfig echoPlacementConfig(const Config& c, EchoPlacementConfig p) {
  p.bearing = c.getChoice("agm_bearing", p.bearing, {{"axis", AgmBearing::Axis}, {"neighbours", AgmBearing::Neighbours}});
  p.placement = c.getChoice("agm_placement", p.placement,
                            {{"estimate", AgmPlacement::Estimate}, {"evidence", AgmPlacement::Evidence},
                             {"arc_votes", AgmPlacement::ArcVotes}});
  p.evidence_min_g = c.get("evidence_min_g", p.evidence_min_g, Range::between(1, 1e9));
  p.arc_halfwidth = geom::deg2rad(c.get("arc_halfwidth_deg", geom::rad2deg(p.arc_halfwidth), Range::between(0, 89)));
  p.arc_min_votes = c.get("arc_min_votes", p.arc_min_votes, Range::nonNegative());
  p.arc_require_votes = c.get<bool>("arc_require_votes", p.arc_require_votes);
  p.arc_wait_cycles = c.get("arc_wait_cycles", p.arc_wait_cycles, Range::between(0, 1e6));
  p.surface_fill = c.get<bool>("surface_fill", p.surface_fill);
  p.surface_spread_m = c.get("surface_spread_m", p.surface_spread_m, Range::between(0, 5));
  p.surface_min_agree = c.get("surface_min_agree", p.surface_min_agree, Range::between(1, 100));
  p.surface_max_gap_m = c.get("surface_max_gap_m", p.surface_max_gap_m, Range::positive());
  p.surface_max_angle =
      geom::deg2rad(c.get("surface_max_angle_deg", geom::rad2deg(p.surface_max_angle), Range::between(0, 45)));
  const Config nb = c.section("neighbour_bearing");
  nb.allowOnly({"beam_deg", "similar", "max_age_s"});
  p.params.beam_width =
      geom::deg2rad(nb.get("beam_deg", geom::rad2deg(p.params.beam_width), Range::between(1e-3, 180)));
  p.params.similar = nb.get("similar", p.params.similar, Range::nonNegative());
  p.params.max_age_s = nb.get("max_age_s", p.params.max_age_s, Range::duration());
  return p;
}

namespace {
// ArcVotes: the bearing within +-halfwidth of the axis whose arc cell holds the most votes (at
// least min_votes; ties: the one nearest to the estimate), else the estimate.
// nullopt: no cell with min_votes.
std::optional<double> votedBearing(const AccumulativeGridMap& agm, const SonarEcho& e, double centre, double halfwidth,
                                   double min_votes, double estimate) {
  const double range = e.range;
  if (!(range > 0) || !(halfwidth >= 0) || !(range * halfwidth <= agm.size() * agm.cellSize())) return std::nullopt;
  const double step = 0.5 * agm.cellSize() / range;
  const int half = std::max(1, static_cast<int>(std::ceil(halfwidth / step)));
  double best = estimate, best_v = 0, best_off = 1e9;
  // Samples are half a cell apart: most cells come twice in a row, their votes looked up once.
  int last_ix = -1, last_iy = -1;
  double last_v = 0;
  AccumulativeGridMap::ArcCells arc(agm, e.sensor.position(), range, halfwidth / half);
  for (int q = -half; q <= half; ++q) {
    const double b = centre + halfwidth * q / half;
    int ix = 0, iy = 0;
    if (!arc.cellAt(b, ix, iy)) continue;  // (agm.cellAt(e.sensor.position() + range * geom::unitVector(b)))
    if (ix != last_ix || iy != last_iy) {
      last_v = agm.arcVotes(ix, iy);
      last_ix = ix;
      last_iy = iy;
    }
    const double v = last_v;
    const double off = std::abs(geom::angleDiff(b, estimate));
    if (v > best_v + 1e-9 || (std::abs(v - best_v) <= 1e-9 && v > 0 && off < best_off)) {
      best_v = v;
      best = b;
      best_off = off;
    }
  }
  if (best_v >= min_votes && best_v > 0) return geom::normalizeAngle(best);
  return std::nullopt;
}
}  // namespace

void EchoPlacer::spread(const geom::Vec2& sensor, double range, double beam_width, const geom::Vec2& p,
                        AccumulativeGridMap& agm, std::vector<geom::Vec2>& hits) {
  if (!cfg_.surface_fill) return;
  const geom::Vec2 d = p - sensor;
  if (!(d.norm() > 1e-6) || !std::isfinite(d.x()) || !std::isfinite(d.y())) return;
  const geom::Vec2 n = d / d.norm();
  const double cell = agm.cellSize();
  const double half_beam = 0.5 * (beam_width > 0 ? beam_width : cfg_.params.beam_width);
  const double footprint = range * std::tan(half_beam);  // the beam's half footprint on a face-on plane
  auto addEmpty = [&](const geom::Vec2& x) {
    int ix = 0, iy = 0;
    if (!agm.cellAt(x, ix, iy) || agm.g(ix, iy) > 0) return;
    for (size_t k = 0; k < hits.size(); ++k) {  // one hit per cell and cycle
      int jx = 0, jy = 0;
      if (agm.cellAt(hits[k], jx, jy) && jx == ix && jy == iy) return;
    }
    int px = 0, py = 0;
    if (agm.cellAt(p, px, py) && px == ix && py == iy) return;  // the echo's own cell
    hits.push_back(x);
  };
  // The most recent agreeing echo: parallel bearings, both points on one line across them.
  const Placed* best = nullptr;
  int agree = 0;
  for (const Placed& q : placed_) {
    if (n.dot(q.normal) < std::cos(cfg_.surface_max_angle)) continue;
    const geom::Vec2 dq = q.p - p;
    const double along = dq.norm();
    if (along < cell || along > std::min(2.0 * footprint, cfg_.surface_max_gap_m)) continue;
    if (std::abs(n.dot(dq)) > 0.5 * cell) continue;
    // Tangent to one line: on a plane the foot moves exactly as the sensor moves along it; a
    // pole's or a corner's echoes stay where they are while the robot drives on.
    const geom::Vec2 t(-n.y(), n.x());
    if (std::abs(t.dot(dq) - t.dot(q.sensor - sensor)) > 0.5 * cell) continue;
    ++agree;
    if (!best || along < (best->p - p).norm()) best = &q;  // the nearest agreeing foot
  }
  if (best && agree >= cfg_.surface_min_agree) {
    const geom::Vec2 t = (best->p - p) / (best->p - p).norm();  // along the surface, towards q
    const double len = (best->p - p).norm();
    const double step = 0.5 * cell;
    for (double s = step; s < len; s += step) addEmpty(p + s * t);
    for (double s = step; s <= cfg_.surface_spread_m + 1e-9; s += step) addEmpty(p - s * t);
  }
  placed_.push_back({p, n, sensor, agm.cycle()});
}

std::vector<geom::Vec2> EchoPlacer::place(const std::vector<GroupReading>& group, AccumulativeGridMap& agm) {
  std::vector<geom::Vec2> hits;
  hits.reserve(group.size());  // (one hit per reading, but for waiting echoes and surface fill)
  last_placed_.clear();
  if (cfg_.surface_fill) {
    const int64_t keep = std::max(1, cfg_.arc_wait_cycles);
    placed_.erase(std::remove_if(placed_.begin(), placed_.end(),
                                 [&](const Placed& q) { return !(agm.cycle() - q.cycle <= keep); }),
                  placed_.end());  // (in place, in order: no list per group)
  }
  // Echoes that waited for later arcs: placed now if those crossed theirs, forgotten when too old.
  if (!waiting_.empty()) {
    size_t still = 0;  // waiting_[0 .. still): those that wait on (in place, in order)
    for (size_t i = 0; i < waiting_.size(); ++i) {
      const Waiting w = waiting_[i];
      if (agm.cycle() - w.cycle > cfg_.arc_wait_cycles) continue;
      // Its own arc voted too, after its group: it needs arc_min_votes from other arcs, as when it came.
      const auto b = votedBearing(agm, w.echo, w.estimate, w.halfwidth, cfg_.arc_min_votes + 1.0, w.estimate);
      const geom::Vec2 p = w.echo.sensor.position() + w.echo.range * geom::unitVector(b.value_or(w.estimate));
      int ix = 0, iy = 0;
      if (b && agm.cellAt(p, ix, iy) && agm.g(ix, iy) > 0) {
        hits.push_back(p);
        last_placed_.push_back({p, w.echo.sensor, w.echo.range, w.echo.beam_width, w.sensor_id, w.echo.utime, w.checked});
        spread(w.echo.sensor.position(), w.echo.range, w.echo.beam_width, p, agm, hits);
      } else
        waiting_[still++] = w;
    }
    waiting_.erase(waiting_.begin() + static_cast<std::ptrdiff_t>(still), waiting_.end());
  }
  std::vector<Latest>& latest = latest_;
  latest.clear();
  for (const GroupReading& r : group) {
    latest.push_back({r.sensor_id, r.echo ? r.e.utime : r.utime, std::nullopt});
    if (!r.echo) continue;
    const SonarEcho& echo = r.e;
    const bool pose_ok =
        std::isfinite(echo.sensor.x) && std::isfinite(echo.sensor.y) && std::isfinite(echo.sensor.theta);
    if (!pose_ok) {
      if (r.hit) hits.push_back(r.axis_end);
      continue;
    }
    latest.back().echo = echo;
    if (!r.hit) continue;
    // The paper's axis is the estimate, uncertain by half the beam width.
    BearingEstimate est{echo.sensor.theta, 0.5 * (echo.beam_width > 0 ? echo.beam_width : cfg_.params.beam_width)};
    if (cfg_.bearing == AgmBearing::Neighbours) est = tracker_.estimate(r.sensor_id, echo);
    double b = est.bearing;
    if (cfg_.placement == AgmPlacement::Evidence)
      b = evidenceBearing(agm, echo.sensor.position(), echo.range, est, cfg_.evidence_min_g);
    else if (cfg_.placement == AgmPlacement::ArcVotes) {
      const auto voted = votedBearing(agm, echo, echo.sensor.theta, cfg_.arc_halfwidth, cfg_.arc_min_votes, est.bearing);
      if (!voted && cfg_.arc_require_votes) {
        if (cfg_.arc_wait_cycles > 0) waiting_.push_back({echo, r.sensor_id, est.bearing, est.halfwidth, agm.cycle(), r.checked});
        continue;
      }
      b = voted.value_or(est.bearing);
    }
    // On the axis: exactly the paper's point (the reading's own end point).
    hits.push_back(b == echo.sensor.theta ? r.axis_end : echo.sensor.position() + echo.range * geom::unitVector(b));
    const geom::Vec2 p = hits.back();
    last_placed_.push_back({p, echo.sensor, echo.range, echo.beam_width, r.sensor_id, echo.utime, r.checked});
    spread(echo.sensor.position(), echo.range, echo.beam_width, p, agm, hits);
  }
  for (const Latest& l : latest) tracker_.record(l.id, l.utime, l.echo);
  if (cfg_.placement == AgmPlacement::ArcVotes)
    for (const Latest& l : latest)
      if (const std::optional<SonarEcho>& echo = l.echo)
        agm.addArcVotes(echo->sensor.position(), echo->range, echo->sensor.theta - cfg_.arc_halfwidth,
                        echo->sensor.theta + cfg_.arc_halfwidth, vote_weight_);
  return hits;
}

}  // namespace lasonic
