#include "operational/motion_confirmation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace lasonic {

MotionConfirmation::Last& MotionConfirmation::entry(int id) {
  // No ring has this many transducers: a stream of ever new ids (malformed messages) must not
  // grow the table without bound.
  if (last_.size() >= kMaxSensors && last_.find(id) == last_.end()) last_.clear();
  return last_[id];
}

int MotionConfirmation::apply(const std::vector<PlacedEcho>& placed, const AccumulativeGridMap& agm,
                              std::vector<geom::Vec2>& hits) {
  if (!p_.enabled) return 0;
  int added = 0;
  for (const PlacedEcho& e : placed) {
    if (e.sensor_id < 0 || !e.point.allFinite() || !e.sensor.position().allFinite()) continue;
    const geom::Vec2 sensor = e.sensor.position();
    Last& prev = entry(e.sensor_id);
    // (an echo that waited for later arcs is older than its sensor's latest firing: ignored)
    if (prev.firing.known() && e.utime <= prev.firing.last) continue;
    int ix = 0, iy = 0, px = 0, py = 0;
    if (prev.firing.known() && prev.echo_utime == prev.firing.last && prev.firing.regular(e.utime) &&
        agm.cellAt(e.point, ix, iy) && agm.cellAt(prev.point, px, py) &&
        std::max(std::abs(ix - px), std::abs(iy - py)) > agm.params().t &&
        (e.point - prev.point).norm() <= (sensor - prev.sensor).norm() + p_.tolerance_m) {
      hits.push_back(e.point);
      ++added;
    }
    prev.point = e.point;
    prev.sensor = sensor;
    prev.echo_utime = e.utime;
    prev.firing.fire(e.utime);
  }
  return added;
}

void MotionConfirmation::fired(int id, int64_t utime) {
  if (!p_.enabled || id < 0) return;
  entry(id).firing.fire(utime);
}

}  // namespace lasonic
