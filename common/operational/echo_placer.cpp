#include "operational/echo_placer.hpp"

#include <cmath>
#include <utility>

namespace lasonic {

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
      hits.push_back(r.axis_end);
      continue;
    }
    latest.back().second = echo;
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
