#include "baselines/himm.hpp"

namespace lasonic::baselines {

HimmParams himmParams(const Config& c, HimmParams p) {
  std::vector<std::string> keys = windowKeys();
  keys.insert(keys.end(), {"increment", "decrement", "cv_max", "growth_rate_operator", "threshold", "no_echo_clears"});
  c.allowOnly(keys);
  p.window = windowParams(c, p.window);
  p.cv_max = c.get("cv_max", p.cv_max, Range::between(1, 255));
  p.increment = c.get("increment", p.increment, Range::between(0, p.cv_max));
  p.decrement = c.get("decrement", p.decrement, Range::between(0, p.cv_max));
  p.growth_rate_operator = c.get("growth_rate_operator", p.growth_rate_operator);
  p.threshold = c.get("threshold", p.threshold, Range::between(1, p.cv_max));
  p.no_echo_clears = c.get("no_echo_clears", p.no_echo_clears);
  return p;
}

HimmGrid::HimmGrid(const HimmParams& p) : p_(p), w_(p.window, 0) {
  if (p.cv_max < 1 || p.cv_max > 255 || p.increment < 0 || p.decrement < 0 || p.threshold < 1)
    throw std::invalid_argument("HimmGrid: inconsistent parameters");
}

void HimmGrid::set(size_t i, int v) {
  v = std::clamp(v, 0, p_.cv_max);
  w_.value(i) = static_cast<uint8_t>(v);
  w_.setOccupied(i, v >= p_.threshold);
}

void HimmGrid::insert(const geom::Pose2& sensor, double range, bool no_echo, double range_max) {
  if (!std::isfinite(sensor.x) || !std::isfinite(sensor.y) || !std::isfinite(sensor.theta)) return;
  if (no_echo) {
    if (!p_.no_echo_clears || !std::isfinite(range_max) || range_max <= 0) return;
    range = range_max;
  } else if (!std::isfinite(range) || range < 0) {
    return;
  }
  const geom::Vec2 from = sensor.position();
  const geom::Vec2 to = from + range * geom::unitVector(sensor.theta);
  const int64_t hx = w_.globalCell(to.x()), hy = w_.globalCell(to.y());
  // I- along the axis in front of the hit cell (the whole axis without an echo). Once the axis
  // has left the window nothing more of it is inside (a huge range costs nothing).
  bool entered = false;
  forEachCellOnSegment(from, to, w_.cellSize(), [&](int64_t gx, int64_t gy) {
    if (!no_echo && gx == hx && gy == hy) return false;
    if (!w_.inWindow(gx, gy)) return !entered;
    entered = true;
    const size_t i = w_.index(gx, gy);
    set(i, w_.value(i) - p_.decrement);
    return true;
  });
  if (no_echo || !w_.inWindow(hx, hy)) return;
  const size_t i = w_.index(hx, hy);
  int v = w_.value(i) + p_.increment;
  if (p_.growth_rate_operator) {
    int neighbours = 0;
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dx = -1; dx <= 1; ++dx)
        if ((dx != 0 || dy != 0) && w_.inWindow(hx + dx, hy + dy)) neighbours += w_.value(w_.index(hx + dx, hy + dy));
    v += neighbours / 2;  // the mask's 0.5 weights, in whole certainty units
  }
  set(i, v);
}

int HimmGrid::cv(const geom::Vec2& p) const {
  const int64_t gx = w_.globalCell(p.x()), gy = w_.globalCell(p.y());
  return w_.inWindow(gx, gy) ? w_.value(w_.index(gx, gy)) : -1;
}

}  // namespace lasonic::baselines
