#include "baselines/naive_fusion.hpp"

#include <cmath>
#include <utility>

namespace lasonic::baselines {

NaiveFusion::NaiveFusion(const NaiveFusionParams& p) : p_(p), agm_(p.agm), tracker_(p.bearing_params) {}

int NaiveFusion::insertGroup(int64_t utime, const std::vector<Reading>& readings,
                             const std::optional<geom::Vec2>& robot, double speed) {
  // As the pilot places a complementary reading (stages/pilot_stage.cpp), for every echo.
  std::vector<geom::Vec2> hits;
  std::vector<std::pair<int, std::optional<SonarEcho>>> latest;
  for (const Reading& r : readings) {
    latest.emplace_back(r.sensor_id, std::nullopt);
    const bool ok = r.echo && std::isfinite(r.range) && r.range >= 0 && std::isfinite(r.sensor.x) &&
                    std::isfinite(r.sensor.y) && std::isfinite(r.sensor.theta);
    if (!ok) continue;
    const SonarEcho echo{utime, r.range, r.sensor};
    latest.back().second = echo;
    BearingEstimate est{echo.sensor.theta, 0.5 * p_.bearing_params.beam_width};
    if (p_.bearing == AgmBearing::Neighbours) est = tracker_.estimate(r.sensor_id, echo);
    const double b = p_.placement == AgmPlacement::Evidence
                         ? evidenceBearing(agm_, echo.sensor.position(), echo.range, est, p_.evidence_min_g)
                         : est.bearing;
    hits.push_back(b == echo.sensor.theta ? echo.sensor.transform({echo.range, 0.0})
                                          : echo.sensor.position() + echo.range * geom::unitVector(b));
  }
  for (const auto& [id, echo] : latest) tracker_.record(id, echo);
  if (robot) agm_.follow(*robot, speed);
  return agm_.update(hits);
}

}  // namespace lasonic::baselines
