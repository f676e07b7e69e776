#include "operational/motion_confirmation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace lasonic {

int MotionConfirmation::apply(const std::vector<PlacedEcho>& placed, const AccumulativeGridMap& agm,
                              std::vector<geom::Vec2>& hits) {
  if (!p_.enabled) return 0;
  int added = 0;
  const auto max_age_us = static_cast<int64_t>(p_.max_age_s * 1e6);
  for (const PlacedEcho& e : placed) {
    if (e.sensor_id < 0 || !e.point.allFinite() || !e.sensor.position().allFinite()) continue;
    const geom::Vec2 sensor = e.sensor.position();
    const auto it = last_.find(e.sensor_id);
    if (it != last_.end()) {
      const Last& prev = it->second;
      const int64_t age = e.utime - prev.utime;
      int ix = 0, iy = 0, px = 0, py = 0;
      if (age > 0 && age <= max_age_us && agm.cellAt(e.point, ix, iy) && agm.cellAt(prev.point, px, py) &&
          std::max(std::abs(ix - px), std::abs(iy - py)) > agm.params().t &&
          (e.point - prev.point).norm() <= (sensor - prev.sensor).norm() + p_.tolerance_m) {
        hits.push_back(e.point);
        ++added;
      }
      // (an echo that waited for later arcs is older than its sensor's latest: not recorded)
      if (e.utime > prev.utime) it->second = {e.point, sensor, e.utime};
      continue;
    }
    // No ring has this many transducers: a stream of ever new ids (malformed messages) must not
    // grow the table without bound.
    if (last_.size() >= kMaxSensors) last_.clear();
    last_.emplace(e.sensor_id, Last{e.point, sensor, e.utime});
  }
  return added;
}

}  // namespace lasonic
