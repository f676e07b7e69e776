#include "operational/echo_placer.hpp"

#include <cmath>
#include <utility>

namespace lasonic {

std::vector<std::string> echoPlacementKeys() {
  return {"agm_bearing",       "agm_placement", "evidence_min_g",    "arc_halfwidth_deg",
          "arc_min_votes",     "arc_require_votes", "arc_wait_cycles", "neighbour_bearing"};
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
  const Config nb = c.section("neighbour_bearing");
  nb.allowOnly({"beam_deg", "similar", "max_age_s"});
  p.params.beam_width =
      geom::deg2rad(nb.get("beam_deg", geom::rad2deg(p.params.beam_width), Range::between(1e-3, 180)));
  p.params.similar = nb.get("similar", p.params.similar, Range::nonNegative());
  p.params.max_age_s = nb.get("max_age_s", p.params.max_age_s, Range::nonNegative());
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
  for (int q = -half; q <= half; ++q) {
    const double b = centre + halfwidth * q / half;
    int ix = 0, iy = 0;
    if (!agm.cellAt(e.sensor.position() + range * geom::unitVector(b), ix, iy)) continue;
    const double v = agm.arcVotes(ix, iy);
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

std::vector<geom::Vec2> EchoPlacer::place(const std::vector<GroupReading>& group, AccumulativeGridMap& agm) {
  std::vector<geom::Vec2> hits;
  // Echoes that waited for later arcs: placed now if those crossed theirs, forgotten when too old.
  if (!waiting_.empty()) {
    std::vector<Waiting> still;
    for (const Waiting& w : waiting_) {
      if (agm.cycle() - w.cycle > cfg_.arc_wait_cycles) continue;
      // Its own arc voted too, after its group: it needs arc_min_votes from other arcs, as when it came.
      const auto b = votedBearing(agm, w.echo, w.estimate, w.halfwidth, cfg_.arc_min_votes + 1.0, w.estimate);
      const geom::Vec2 p = w.echo.sensor.position() + w.echo.range * geom::unitVector(b.value_or(w.estimate));
      int ix = 0, iy = 0;
      if (b && agm.cellAt(p, ix, iy) && agm.g(ix, iy) > 0)
        hits.push_back(p);
      else
        still.push_back(w);
    }
    waiting_ = std::move(still);
  }
  std::vector<std::pair<int, std::optional<SonarEcho>>> latest;
  latest.reserve(group.size());
  for (const GroupReading& r : group) {
    latest.emplace_back(r.sensor_id, std::nullopt);
    if (!r.echo) continue;
    const SonarEcho& echo = r.e;
    const bool pose_ok =
        std::isfinite(echo.sensor.x) && std::isfinite(echo.sensor.y) && std::isfinite(echo.sensor.theta);
    if (!pose_ok) {
      if (r.hit) hits.push_back(r.axis_end);
      continue;
    }
    latest.back().second = echo;
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
        if (cfg_.arc_wait_cycles > 0) waiting_.push_back({echo, est.bearing, est.halfwidth, agm.cycle()});
        continue;
      }
      b = voted.value_or(est.bearing);
    }
    // On the axis: exactly the paper's point (the reading's own end point).
    hits.push_back(b == echo.sensor.theta ? r.axis_end : echo.sensor.position() + echo.range * geom::unitVector(b));
  }
  for (const auto& [id, echo] : latest) tracker_.record(id, echo);
  if (cfg_.placement == AgmPlacement::ArcVotes)
    for (const auto& [id, echo] : latest)
      if (echo) agm.addArcVotes(echo->sensor.position(), echo->range, echo->sensor.theta - cfg_.arc_halfwidth,
                                echo->sensor.theta + cfg_.arc_halfwidth);
  return hits;
}

}  // namespace lasonic
