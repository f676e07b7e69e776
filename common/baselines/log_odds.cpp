#include "baselines/log_odds.hpp"

namespace lasonic::baselines {

namespace {
double logit(double p) { return std::log(p / (1.0 - p)); }
}  // namespace

LogOddsParams logOddsParams(const Config& c, LogOddsParams p) {
  std::vector<std::string> keys = windowKeys();
  keys.insert(keys.end(), {"sonar_occupied", "sonar_free", "sonar_arc_thickness", "no_echo_clears", "laser_occupied",
                           "laser_free", "p_min", "p_max", "occupied_threshold"});
  c.allowOnly(keys);
  p.window = windowParams(c, p.window);
  const Range open01{0.0, 1.0, true};
  const auto prob = [&](const char* key, double def) {
    const double v = c.get(key, def, open01);
    if (v >= 1.0) c.fail(key, "must be < 1");
    return v;
  };
  p.sonar_occupied = prob("sonar_occupied", p.sonar_occupied);
  p.sonar_free = prob("sonar_free", p.sonar_free);
  p.sonar_arc_thickness = c.get("sonar_arc_thickness", p.sonar_arc_thickness, Range::positive());
  p.no_echo_clears = c.get("no_echo_clears", p.no_echo_clears);
  p.laser_occupied = prob("laser_occupied", p.laser_occupied);
  p.laser_free = prob("laser_free", p.laser_free);
  p.p_min = prob("p_min", p.p_min);
  p.p_max = prob("p_max", p.p_max);
  p.occupied_threshold = prob("occupied_threshold", p.occupied_threshold);
  if (p.sonar_occupied <= 0.5) c.fail("sonar_occupied", "must be > 0.5 (evidence of an obstacle)");
  if (p.laser_occupied <= 0.5) c.fail("laser_occupied", "must be > 0.5 (evidence of an obstacle)");
  if (p.sonar_free >= 0.5) c.fail("sonar_free", "must be < 0.5 (evidence of free space)");
  if (p.laser_free >= 0.5) c.fail("laser_free", "must be < 0.5 (evidence of free space)");
  if (!(p.p_min < 0.5 && p.p_max > 0.5)) c.fail("p_min", "p_min < 0.5 < p_max required");
  if (!(p.occupied_threshold > 0.5 && p.occupied_threshold <= p.p_max))
    c.fail("occupied_threshold", "must lie in (0.5, p_max]");
  return p;
}

LogOddsGrid::LogOddsGrid(const LogOddsParams& p)
    : p_(p),
      l_sonar_occ_(logit(p.sonar_occupied)),
      l_sonar_free_(logit(p.sonar_free)),
      l_laser_occ_(logit(p.laser_occupied)),
      l_laser_free_(logit(p.laser_free)),
      l_min_(logit(p.p_min)),
      l_max_(logit(p.p_max)),
      l_threshold_(logit(p.occupied_threshold)),
      w_(p.window, 0.0f) {
  const auto in01 = [](double v) { return v > 0 && v < 1; };
  if (!in01(p.sonar_occupied) || !in01(p.sonar_free) || !in01(p.laser_occupied) || !in01(p.laser_free) ||
      !in01(p.p_min) || !in01(p.p_max) || !(p.p_min < 0.5 && 0.5 < p.p_max) || !in01(p.occupied_threshold) ||
      !(p.sonar_arc_thickness > 0))
    throw std::invalid_argument("LogOddsGrid: inconsistent parameters");
}

void LogOddsGrid::add(size_t i, double l) {
  const double v = std::clamp(static_cast<double>(w_.value(i)) + l, l_min_, l_max_);
  w_.value(i) = static_cast<float>(v);
  w_.setOccupied(i, v >= l_threshold_);
}

void LogOddsGrid::insertSonar(const geom::Pose2& sensor, double range, bool no_echo, double beam_width,
                              double range_max) {
  if (!std::isfinite(sensor.x) || !std::isfinite(sensor.y) || !std::isfinite(sensor.theta)) return;
  if (!(beam_width > 0 && beam_width < geom::kPi)) return;
  const double half_t = 0.5 * p_.sonar_arc_thickness;
  double free_to = 0, outer = 0;
  if (no_echo) {
    if (!p_.no_echo_clears || !(std::isfinite(range_max) && range_max > 0)) return;
    free_to = outer = range_max;
  } else {
    if (!(std::isfinite(range) && range >= 0)) return;
    free_to = range - half_t;
    outer = range + half_t;
  }
  // Bounding box of the sector: apex, the two edge ends and the arc's extreme points.
  const geom::Vec2 apex = sensor.position();
  const double h = 0.5 * beam_width;
  double x0 = apex.x(), x1 = apex.x(), y0 = apex.y(), y1 = apex.y();
  const auto extend = [&](const geom::Vec2& q) {
    x0 = std::min(x0, q.x());
    x1 = std::max(x1, q.x());
    y0 = std::min(y0, q.y());
    y1 = std::max(y1, q.y());
  };
  extend(apex + outer * geom::unitVector(sensor.theta - h));
  extend(apex + outer * geom::unitVector(sensor.theta + h));
  for (int k = -4; k <= 4; ++k) {  // axis-aligned directions inside the beam
    const double a = k * 0.5 * geom::kPi;
    if (std::abs(geom::angleDiff(a, sensor.theta)) <= h) extend(apex + outer * geom::unitVector(a));
  }
  const geom::Vec2 axis = geom::unitVector(sensor.theta);
  const double cos_h = std::cos(h);
  // Only the part inside the window (a huge range_max costs nothing).
  const OccupancyWindow& win = w_.occupancy();
  const int64_t gx0 = std::max(w_.globalCell(x0), win.origin_x), gx1 = std::min(w_.globalCell(x1), win.origin_x + win.size - 1);
  const int64_t gy0 = std::max(w_.globalCell(y0), win.origin_y), gy1 = std::min(w_.globalCell(y1), win.origin_y + win.size - 1);
  for (int64_t gy = gy0; gy <= gy1; ++gy)
    for (int64_t gx = gx0; gx <= gx1; ++gx) {
      const geom::Vec2 d = w_.cellCentre(gx, gy) - apex;
      const double r = d.norm();
      if (r > outer) continue;
      if (r > 1e-9 && d.dot(axis) < cos_h * r) continue;  // outside the cone
      if (r < free_to) add(w_.index(gx, gy), l_sonar_free_);
      else if (!no_echo) add(w_.index(gx, gy), l_sonar_occ_);
    }
}

void LogOddsGrid::insertLaser(const geom::Vec2& origin, const geom::Vec2& hit) {
  if (!std::isfinite(origin.x()) || !std::isfinite(origin.y()) || !std::isfinite(hit.x()) || !std::isfinite(hit.y()))
    return;
  const int64_t hx = w_.globalCell(hit.x()), hy = w_.globalCell(hit.y());
  bool entered = false;
  forEachCellOnSegment(origin, hit, w_.cellSize(), [&](int64_t gx, int64_t gy) {
    const bool in = w_.inWindow(gx, gy);
    if (!in) return !entered;  // once the ray has left the window, nothing more is in it
    entered = true;
    add(w_.index(gx, gy), gx == hx && gy == hy ? l_laser_occ_ : l_laser_free_);
    return true;
  });
}

double LogOddsGrid::probability(const geom::Vec2& p) const {
  const int64_t gx = w_.globalCell(p.x()), gy = w_.globalCell(p.y());
  if (!w_.inWindow(gx, gy)) return 0.5;
  const double l = w_.value(w_.index(gx, gy));
  return 1.0 / (1.0 + std::exp(-l));
}

}  // namespace lasonic::baselines
