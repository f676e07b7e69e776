#include "operational/echo_placer.hpp"

#include <cmath>
#include <utility>

namespace lasonic {

EchoPlacementConfig echoPlacementConfig(const Config& c, EchoPlacementConfig p) {
  p.bearing = c.getChoice("agm_bearing", p.bearing, {{"axis", AgmBearing::Axis}, {"neighbours", AgmBearing::Neighbours}});
  p.placement = c.getChoice("agm_placement", p.placement,
                            {{"estimate", AgmPlacement::Estimate}, {"evidence", AgmPlacement::Evidence}});
  p.evidence_min_g = c.get("evidence_min_g", p.evidence_min_g, Range::between(1, 1e9));
  const Config nb = c.section("neighbour_bearing");
  nb.allowOnly({"beam_deg", "similar", "max_age_s"});
  p.params.beam_width =
      geom::deg2rad(nb.get("beam_deg", geom::rad2deg(p.params.beam_width), Range::between(1e-3, 180)));
  p.params.similar = nb.get("similar", p.params.similar, Range::nonNegative());
  p.params.max_age_s = nb.get("max_age_s", p.params.max_age_s, Range::nonNegative());
  return p;
}

std::vector<geom::Vec2> EchoPlacer::place(const std::vector<GroupReading>& group, const AccumulativeGridMap& agm) {
  std::vector<geom::Vec2> hits;
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
    BearingEstimate est{echo.sensor.theta, 0.5 * cfg_.params.beam_width};
    if (cfg_.bearing == AgmBearing::Neighbours) est = tracker_.estimate(r.sensor_id, echo);
    const double b = cfg_.placement == AgmPlacement::Evidence
                         ? evidenceBearing(agm, echo.sensor.position(), echo.range, est, cfg_.evidence_min_g)
                         : est.bearing;
    // On the axis: exactly the paper's point (the reading's own end point).
    hits.push_back(b == echo.sensor.theta ? r.axis_end : echo.sensor.position() + echo.range * geom::unitVector(b));
  }
  for (const auto& [id, echo] : latest) tracker_.record(id, echo);
  return hits;
}

}  // namespace lasonic
