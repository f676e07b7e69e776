#include "baselines/naive_fusion.hpp"

#include <cmath>
#include <utility>

namespace lasonic::baselines {

NaiveFusion::NaiveFusion(const NaiveFusionParams& p) : p_(p), agm_(p.agm), placer_(p.placement) {}

int NaiveFusion::insertGroup(int64_t utime, const std::vector<Reading>& readings,
                             const std::optional<geom::Vec2>& robot, double speed, int group_id) {
  // As the pilot places a complementary reading, for every echo.
  std::vector<GroupReading> group;
  group.reserve(readings.size());
  for (const Reading& r : readings) {
    GroupReading g;
    g.sensor_id = r.sensor_id;
    g.utime = utime;
    g.echo = r.echo && std::isfinite(r.range) && r.range >= 0 && std::isfinite(r.sensor.x) &&
             std::isfinite(r.sensor.y) && std::isfinite(r.sensor.theta);
    if (g.echo) {
      g.e = SonarEcho{utime, r.range, r.sensor, r.beam_width};
      g.axis_end = r.sensor.transform({r.range, 0.0});
    }
    group.push_back(g);
  }
  if (group_id >= 0) ring_groups_.fired(group_id);
  agm_.setHMax(ring_groups_.hMax(p_.h_max_ring_cycles, p_.agm.h_max));
  const std::vector<geom::Vec2> hits = placer_.place(group, agm_);
  if (robot) agm_.follow(*robot, speed);
  return agm_.update(hits);
}

}  // namespace lasonic::baselines
