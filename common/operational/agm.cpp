#include "operational/agm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace lasonic {

AgmParams agmParams(const Config& c, AgmParams p) {
  c.allowOnly({"size", "cell_size", "g_max", "h_max", "t", "g_threshold", "recenter_max_cells",
               "recenter_min_cells", "recenter_lookahead_s", "hit_centroids", "h_max_m", "forget_sigma_m", "odometry_trans_noise",
               "odometry_rot_noise", "odometry_drift_noise", "arc_vote_tau"});
  p.size = c.get("size", p.size, Range::between(3, 10000));
  // (A cell finer than 5 mm is below the sonar's range resolution, one wider than 2 m wider
  // than the robot: neither locates an obstacle.)
  p.cell_size = c.get("cell_size", p.cell_size, Range::between(0.005, 2.0));
  p.g_max = c.get("g_max", p.g_max, Range::between(1, std::numeric_limits<int16_t>::max()));
  // (At most 10^6 cycles: 8 h of 30 ms groups; the navigator keeps a time per cycle.)
  p.h_max = c.get("h_max", p.h_max, Range::between(0, 1e6));
  p.t = c.get("t", p.t, Range::between(0, (p.size - 1) / 2));
  // (G saturates at g_max: a higher G_T is never reached, and the map stays empty.)
  p.g_threshold = c.get("g_threshold", p.g_threshold, Range::between(1, p.g_max));
  p.recenter_max_cells = c.get("recenter_max_cells", p.recenter_max_cells, Range::between(0, p.size / 2 - 1));
  p.recenter_min_cells = c.get("recenter_min_cells", p.recenter_min_cells, Range::between(0, p.recenter_max_cells));
  p.recenter_lookahead_s = c.get("recenter_lookahead_s", p.recenter_lookahead_s, Range::duration());
  p.hit_centroids = c.get<bool>("hit_centroids", p.hit_centroids);
  p.h_max_m = c.get("h_max_m", p.h_max_m, Range::nonNegative());
  p.forget_sigma_m = c.get("forget_sigma_m", p.forget_sigma_m, Range::nonNegative());
  p.odometry_trans_noise = c.get("odometry_trans_noise", p.odometry_trans_noise, Range::between(0, 10));
  p.odometry_rot_noise = c.get("odometry_rot_noise", p.odometry_rot_noise, Range::between(0, 10));
  p.odometry_drift_noise = c.get("odometry_drift_noise", p.odometry_drift_noise, Range::between(0, 10));
  p.arc_vote_tau = c.get("arc_vote_tau", p.arc_vote_tau, Range::nonNegative());
  return p;
}

AccumulativeGridMap::AccumulativeGridMap(const AgmParams& p)
    : p_(p), n_(p.size), odometry_error_({p.odometry_trans_noise, p.odometry_rot_noise, p.odometry_drift_noise}) {
  if (n_ < 3 || !(p.cell_size > 0) || p.t < 0 || 2 * p.t + 1 > n_ || p.g_max < 1 || p.h_max < 0 ||
      p.recenter_min_cells < 0 || p.recenter_min_cells > p.recenter_max_cells)
    throw std::invalid_argument("AccumulativeGridMap: inconsistent parameters");
  const size_t cells = static_cast<size_t>(n_) * static_cast<size_t>(n_);
  g_.assign(cells, 0);
  gu_.assign(cells, 0);
  gp_.assign(cells, 0);
  last_hit_.assign(cells, 0);
  passed_.assign(cells, 0);
  is_held_.assign(cells, 0);
  if (p_.hit_centroids) {
    hx_.assign(cells, 0.f);
    hy_.assign(cells, 0.f);
    hn_.assign(cells, 0);
  }
  if (p_.arc_vote_tau > 0) {
    av_.assign(cells, 0.f);
    av_cycle_.assign(cells, 0);
    fade_.resize(kFadeAges);
    for (int64_t age = 0; age < kFadeAges; ++age) fade_[age] = std::exp(-static_cast<double>(age) / p_.arc_vote_tau);
  }
  ox_ = oy_ = -(n_ / 2);  // centred on the global origin until the robot is known
}

geom::Vec2 AccumulativeGridMap::originMetres() const {
  return {static_cast<double>(ox_) * p_.cell_size, static_cast<double>(oy_) * p_.cell_size};
}

int64_t AccumulativeGridMap::globalCell(double v) const {
  // Clamped: a far-away (but finite) point must not overflow the conversion (undefined behaviour);
  // +-1e15 cells is outside any window.
  return static_cast<int64_t>(std::clamp(std::floor(v / p_.cell_size), -1e15, 1e15));
}

int AccumulativeGridMap::recenterLimit(double speed) const {
  const double driven = std::abs(speed) * p_.recenter_lookahead_s / p_.cell_size;
  const double k = p_.recenter_max_cells - std::floor(std::min(driven, 1e9));
  return static_cast<int>(std::clamp(k, double(p_.recenter_min_cells), double(p_.recenter_max_cells)));
}

bool AccumulativeGridMap::follow(const geom::Vec2& robot, double speed, double heading) {
  if (!std::isfinite(robot.x()) || !std::isfinite(robot.y())) return false;
  const double step = have_robot_ ? std::min((robot - last_robot_).norm(), 1e6) : 0.0;
  odometer_ += step;
  have_robot_ = true;
  last_robot_ = robot;
  if (p_.forget_sigma_m > 0) {
    double turn = 0;
    if (std::isfinite(heading)) {
      if (std::isfinite(last_heading_)) turn = std::abs(geom::angleDiff(heading, last_heading_));
      last_heading_ = heading;
    }
    odometry_error_.advance(step, turn);
  }
  const int64_t rx = globalCell(robot.x()), ry = globalCell(robot.y());
  const int64_t off = std::max(std::abs(rx - (ox_ + n_ / 2)), std::abs(ry - (oy_ + n_ / 2)));
  if (off <= recenterLimit(std::isfinite(speed) ? speed : 0.0)) return false;
  moveTo(rx - n_ / 2, ry - n_ / 2);
  return true;
}

void AccumulativeGridMap::centreOn(const geom::Vec2& p) {
  moveTo(globalCell(p.x()) - n_ / 2, globalCell(p.y()) - n_ / 2);
}

void AccumulativeGridMap::setGThreshold(int g_threshold) {
  p_.g_threshold = std::max(1, g_threshold);
  for (size_t s = 0; s < gp_.size(); ++s) gp_[s] = (g_[s] > 0 && gu_[s] >= p_.g_threshold) ? gu_[s] : 0;
}

int walkerGThreshold(double neighbourhood_m, double walking_speed, double ring_cycle_s, int transducers) {
  const auto ok = [](double v) { return std::isfinite(v) && v > 0; };
  if (!ok(neighbourhood_m) || !ok(walking_speed) || !ok(ring_cycle_s) || transducers < 1) return -1;
  const double echoes = static_cast<double>(transducers) * neighbourhood_m / (walking_speed * ring_cycle_s);
  return static_cast<int>(std::min(1e6, std::floor(echoes))) + 1;
}

void AccumulativeGridMap::addWeight(int64_t gx, int64_t gy, int delta) {
  g_[slotGlobal(gx, gy)] += delta;
  const int64_t x0 = std::max(gx - p_.t, ox_), x1 = std::min(gx + p_.t, ox_ + n_ - 1);
  const int64_t y0 = std::max(gy - p_.t, oy_), y1 = std::min(gy + p_.t, oy_ + n_ - 1);
  const int64_t sx0 = floorMod(x0, n_);
  int64_t sy = floorMod(y0, n_);
  for (int64_t y = y0; y <= y1; ++y) {
    int64_t sx = sx0;
    for (int64_t x = x0; x <= x1; ++x) {
      const size_t s = static_cast<size_t>(sx + sy * n_);
      gu_[s] += delta;
      gp_[s] = (g_[s] > 0 && gu_[s] >= p_.g_threshold) ? gu_[s] : 0;
      if (++sx == n_) sx = 0;
    }
    if (++sy == n_) sy = 0;
  }
}

namespace {
// The part of [a, a+n) outside [b, b+n) (both of length n, overlapping): one interval [lo, hi).
std::pair<int64_t, int64_t> outside(int64_t a, int64_t b, int64_t n) {
  if (b >= a) return {a, std::min(b, a + n)};
  return {std::max(b + n, a), a + n};
}
int64_t floorModN(int64_t a, int64_t n) { return ((a % n) + n) % n; }
// Slots of the columns (or rows) of a window: the column a + d (0 <= d < n) of the window whose
// first column is a lives in slot floorMod(a, n) + d, less n past the end. Computed by an add
// and a compare instead of two divisions per cell (re-centring visits whole rows of cells).
struct SlotOf {
  int64_t a, sa, n;
  SlotOf(int64_t first, int64_t size) : a(first), sa(floorModN(first, size)), n(size) {}
  int64_t operator()(int64_t v) const {  // v in [a, a + n)
    const int64_t s = sa + (v - a);
    return s >= n ? s - n : s;
  }
};
// Calls f(gx, gy, slot) for every cell of window A (origin ax, ay) that is not in window B. (The
// order of the calls differs from a plain row-by-row walk; moveTo's passes do not depend on it.)
template <typename F>
void forEachOutside(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t n, F&& f) {
  const SlotOf sx(ax, n), sy(ay, n);
  const auto [xl, xh] = outside(ax, bx, n);
  const auto [yl, yh] = outside(ay, by, n);
  for (int64_t x = xl; x < xh; ++x) {
    const int64_t cx = sx(x);
    for (int64_t y = ay; y < ay + n; ++y) f(x, y, static_cast<size_t>(cx + sy(y) * n));
  }
  for (int64_t y = yl; y < yh; ++y) {
    const int64_t row = sy(y) * n;
    for (int64_t x = ax; x < ax + n; ++x)
      if (x < xl || x >= xh) f(x, y, static_cast<size_t>(row + sx(x)));
  }
}
}  // namespace

void AccumulativeGridMap::moveTo(int64_t nox, int64_t noy) {
  if (nox == ox_ && noy == oy_) return;
  if (std::abs(nox - ox_) >= n_ || std::abs(noy - oy_) >= n_) {  // nothing survives
    clearAll();
    ox_ = nox;
    oy_ = noy;
    return;
  }
  // Leaving cells: withdraw their weight from the surviving neighbours' Gu, then forget them.
  // (Each cell's Gp is recomputed from its final G and Gu at its last change, so the order of
  // the withdrawals does not matter.)
  forEachOutside(ox_, oy_, nox, noy, n_, [&](int64_t x, int64_t y, size_t s) {
    const int gv = g_[s];
    if (gv > 0) addWeight(x, y, -gv);
  });
  const int64_t old_x = ox_, old_y = oy_;
  ox_ = nox;
  oy_ = noy;
  // Entering cells reuse the freed slots (the slots the leaving cells free are exactly the ones
  // the entering cells take), forgotten here, with G = 0 (so Gp = 0); their Gu must still count
  // the surviving neighbours, for when they are hit later. Only an entering cell within t of the
  // old window has one: the others' neighbourhoods hold entering cells (G = 0) only.
  const SlotOf sx(ox_, n_), sy(oy_, n_);
  const int64_t t = p_.t;
  const auto far = [t](int64_t v, int64_t first, int64_t last) { return v < first - t || v > last + t; };
  forEachOutside(nox, noy, old_x, old_y, n_, [&](int64_t x, int64_t y, size_t s) {
    gu_[s] = gp_[s] = 0;
    last_hit_[s] = 0;
    passed_[s] = 0;
    is_held_[s] = 0;  // a held entry of the cell that left is dropped by reviseHeld
    forgetHits(s);
    if (!av_.empty()) av_[s] = 0.f;
    if (far(x, old_x, old_x + n_ - 1) || far(y, old_y, old_y + n_ - 1)) return;
    int sum = 0;
    const int64_t qx0 = std::max(x - t, ox_), qx1 = std::min(x + t, ox_ + n_ - 1);
    for (int64_t qy = std::max(y - t, oy_); qy <= std::min(y + t, oy_ + n_ - 1); ++qy) {
      const int64_t row = sy(qy) * n_;
      for (int64_t qx = qx0; qx <= qx1; ++qx) sum += g_[static_cast<size_t>(row + sx(qx))];
    }
    gu_[s] = sum;
  });
}

void AccumulativeGridMap::clearAll() {
  std::fill(g_.begin(), g_.end(), 0);
  std::fill(gu_.begin(), gu_.end(), 0);
  std::fill(gp_.begin(), gp_.end(), 0);
  std::fill(last_hit_.begin(), last_hit_.end(), 0);
  std::fill(passed_.begin(), passed_.end(), 0);
  std::fill(is_held_.begin(), is_held_.end(), 0);
  held_.clear();
  std::fill(av_.begin(), av_.end(), 0.f);
  if (p_.hit_centroids) {
    std::fill(hx_.begin(), hx_.end(), 0.f);
    std::fill(hy_.begin(), hy_.end(), 0.f);
    std::fill(hn_.begin(), hn_.end(), 0);
  }
  hits_.clear();
}

int AccumulativeGridMap::clearDisc(const geom::Vec2& c, double r) {
  if (!(r > 0) || !std::isfinite(c.x()) || !std::isfinite(c.y())) return 0;
  int cleared = 0;
  const int64_t x0 = std::max(globalCell(c.x() - r), ox_), x1 = std::min(globalCell(c.x() + r), ox_ + n_ - 1);
  const int64_t y0 = std::max(globalCell(c.y() - r), oy_), y1 = std::min(globalCell(c.y() + r), oy_ + n_ - 1);
  for (int64_t gy = y0; gy <= y1; ++gy)
    for (int64_t gx = x0; gx <= x1; ++gx) {
      const size_t s = slotGlobal(gx, gy);
      if (g_[s] <= 0) continue;
      const geom::Vec2 centre((static_cast<double>(gx) + 0.5) * p_.cell_size, (static_cast<double>(gy) + 0.5) * p_.cell_size);
      if ((centre - c).norm() > r) continue;
      addWeight(gx, gy, -g_[s]);
      forgetHits(s);
      ++cleared;
    }
  return cleared;
}

int AccumulativeGridMap::update(const std::vector<geom::Vec2>& hits) {
  ++cycle_;
  // Accumulation: the trivial sensor model, one cell per reading.
  int inside = 0;
  for (const auto& p : hits) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
    const int64_t gx = globalCell(p.x()), gy = globalCell(p.y());
    if (!inWindow(gx, gy)) continue;
    ++inside;
    const size_t s = slotGlobal(gx, gy);
    if (g_[s] < p_.g_max) addWeight(gx, gy, +1);
    last_hit_[s] = cycle_;
    if (p_.hit_centroids) {
      hx_[s] += static_cast<float>(p.x() - static_cast<double>(gx) * p_.cell_size);
      hy_[s] += static_cast<float>(p.y() - static_cast<double>(gy) * p_.cell_size);
      ++hn_[s];
    }
    hits_.push_back({gx, gy, cycle_, odometer_, odometry_error_.now()});
  }
  // Revision: H = cycle_ - last_hit > h_max -> G = 0 (and, with h_max_m, when the robot has
  // driven more than h_max_m since). Only cells hit that long ago can qualify (the queue is in
  // cycle order, hence in odometer order); entries of cells hit again since, or forgotten by
  // re-centring, are skipped.
  // The same holds for forget_sigma_m: the displacement variance only grows with time.
  const double max_var = p_.forget_sigma_m * p_.forget_sigma_m;
  while (!hits_.empty() &&
         (cycle_ - hits_.front().cycle > p_.h_max ||
          (p_.h_max_m > 0 && odometer_ - hits_.front().odometer > p_.h_max_m) ||
          (p_.forget_sigma_m > 0 && odometry_error_.varianceSince(hits_.front().odometry) > max_var))) {
    const Hit hit = hits_.front();
    hits_.pop_front();
    if (!inWindow(hit.gx, hit.gy)) continue;
    const size_t s = slotGlobal(hit.gx, hit.gy);
    if (g_[s] > 0 && last_hit_[s] == hit.cycle) {
      // No sound went through it since its last hit: kept (reviseHeld decides when it goes).
      if (p_.hold_unpassed > 0 && passed_[s] <= hit.cycle && cycle_ - hit.cycle <= p_.h_max + p_.hold_unpassed) {
        if (!is_held_[s]) held_.push_back(hit), is_held_[s] = 1;
        continue;
      }
      addWeight(hit.gx, hit.gy, -g_[s]);
      forgetHits(s);
    }
  }
  if (!held_.empty()) reviseHeld();
  return inside;
}

void AccumulativeGridMap::reviseHeld() {
  size_t kept = 0;
  for (const Hit& hit : held_) {
    const bool in = inWindow(hit.gx, hit.gy);
    const size_t s = slotGlobal(hit.gx, hit.gy);
    // Re-centred away, emptied (clearDisc), or hit again (back in the revision queue): its slot's
    // flag belongs to this entry only while the cell is still in the window.
    if (!in || g_[s] <= 0 || last_hit_[s] != hit.cycle) {
      if (in) is_held_[s] = 0;
      continue;
    }
    if (passed_[s] > hit.cycle || cycle_ - hit.cycle > p_.h_max + p_.hold_unpassed) {
      addWeight(hit.gx, hit.gy, -g_[s]);
      forgetHits(s);
      is_held_[s] = 0;
      continue;
    }
    held_[kept++] = hit;
  }
  held_.resize(kept);
}

void AccumulativeGridMap::markPassed(int ix, int iy) {
  if (ix < 0 || iy < 0 || ix >= n_ || iy >= n_) return;
  passed_[slot(ix, iy)] = cycle_ + 1;
}

bool AccumulativeGridMap::cellAt(const geom::Vec2& p, int& ix, int& iy) const {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return false;
  const int64_t gx = globalCell(p.x()), gy = globalCell(p.y());
  if (!inWindow(gx, gy)) return false;
  ix = static_cast<int>(gx - ox_);
  iy = static_cast<int>(gy - oy_);
  return true;
}

AccumulativeGridMap::ArcCells::ArcCells(const AccumulativeGridMap& agm, const geom::Vec2& centre, double range,
                                        double step)
    : agm_(agm), centre_(centre), range_(range), step_(step), inv_cell_(1.0 / agm.p_.cell_size) {
  turn_ = std::isfinite(centre.x()) && std::isfinite(centre.y()) && std::abs(centre.x()) < 1e9 &&
          std::abs(centre.y()) < 1e9 && range > 0 && range < 1e6 && std::abs(step) < 1.0 && std::isfinite(inv_cell_);
  if (turn_) {
    const geom::Vec2 r = geom::unitVector(step);
    c_ = r.x(), s_ = r.y();
  }
}

bool AccumulativeGridMap::ArcCells::cellAt(double b, int& ix, int& iy) {
  if (turn_ && seeded_ && std::isfinite(b)) {
    const double nx = c_ * ux_ - s_ * uy_, ny = s_ * ux_ + c_ * uy_;
    ux_ = nx, uy_ = ny;
    ++k_;
    // |u - unitVector(b)|: each turn adds at most ~1e-15 (the step's cos and sin, three
    // roundings), and b may differ from seed + k step by the caller's rounding.
    const double drift = std::abs(b - (seed_ + static_cast<double>(k_) * step_));
    const double err_u = static_cast<double>(k_ + 1) * 4e-15 + 2 * drift + 1e-14 * (1 + std::abs(b));
    const double x = centre_.x() + range_ * ux_, y = centre_.y() + range_ * uy_;
    // The point's distance from the defining one (with both roundings), in cells, and the
    // quotient's own rounding.
    const double err_cells = (range_ * err_u + 1e-13 * (std::abs(centre_.x()) + std::abs(centre_.y()) + range_ + 1)) *
                             inv_cell_ * 1.001;
    const double qx = x * inv_cell_, qy = y * inv_cell_;
    const double tol_x = err_cells + 1e-12 * (1 + std::abs(qx)), tol_y = err_cells + 1e-12 * (1 + std::abs(qy));
    const double fx = std::floor(qx), fy = std::floor(qy);
    if (err_u < 1e-6 && std::abs(qx) < 1e12 && std::abs(qy) < 1e12 && qx - fx > tol_x && fx + 1 - qx > tol_x &&
        qy - fy > tol_y && fy + 1 - qy > tol_y) {
      const auto gx = static_cast<int64_t>(fx), gy = static_cast<int64_t>(fy);
      if (!agm_.inWindow(gx, gy)) return false;
      ix = static_cast<int>(gx - agm_.ox_);
      iy = static_cast<int>(gy - agm_.oy_);
      return true;
    }
  }
  const geom::Vec2 u = geom::unitVector(b);
  ux_ = u.x(), uy_ = u.y(), seed_ = b, k_ = 0;
  seeded_ = true;
  return agm_.cellAt(centre_ + range_ * u, ix, iy);
}

geom::Vec2 AccumulativeGridMap::cellCorner(int ix, int iy) const {
  return {static_cast<double>(ox_ + ix) * p_.cell_size, static_cast<double>(oy_ + iy) * p_.cell_size};
}

int AccumulativeGridMap::h(int ix, int iy) const {
  const size_t s = slot(ix, iy);
  if (g_[s] <= 0) return 0;
  return static_cast<int>(std::min<int64_t>(cycle_ - last_hit_[s], std::numeric_limits<int16_t>::max()));
}

int64_t AccumulativeGridMap::lastHitCycle(int ix, int iy) const {
  const size_t s = slot(ix, iy);
  return g_[s] > 0 ? last_hit_[s] : 0;
}

double AccumulativeGridMap::fadedVotes(size_t s) const {
  if (av_[s] == 0.f) return 0.0;
  const int64_t age = cycle_ - av_cycle_[s];
  if (age >= 0 && age < kFadeAges) return static_cast<double>(av_[s]) * fade_[static_cast<size_t>(age)];
  return static_cast<double>(av_[s]) * std::exp(-static_cast<double>(age) / p_.arc_vote_tau);
}

double AccumulativeGridMap::arcVotes(int ix, int iy) const {
  return av_.empty() ? 0.0 : fadedVotes(slot(ix, iy));
}

void AccumulativeGridMap::addArcVotes(const geom::Vec2& centre, double range, double lo, double hi, double weight) {
  if (av_.empty() || !(range > 0) || !(hi >= lo) || !std::isfinite(centre.x()) || !std::isfinite(centre.y())) return;
  if (!(weight > 0) || !std::isfinite(weight)) return;
  // An arc longer than the window (a malformed huge range) says nothing the window could hold.
  if (!(range * (hi - lo) <= 2.0 * n_ * p_.cell_size)) return;
  // Samples at most half a cell apart; each cell crossed gets one vote however many samples fall in it.
  const int steps = std::max(1, static_cast<int>(std::ceil(range * (hi - lo) / (0.5 * p_.cell_size))));
  size_t last = static_cast<size_t>(-1);
  std::vector<size_t> voted;
  ArcCells arc(*this, centre, range, (hi - lo) / steps);
  for (int q = 0; q <= steps; ++q) {
    const double b = lo + (hi - lo) * q / steps;
    int ix = 0, iy = 0;
    if (!arc.cellAt(b, ix, iy)) continue;  // (the cell of centre + range * geom::unitVector(b))
    const size_t s = slot(ix, iy);
    if (s == last || std::find(voted.begin(), voted.end(), s) != voted.end()) continue;
    last = s;
    voted.push_back(s);
    av_[s] = static_cast<float>(fadedVotes(s) + weight);
    av_cycle_[s] = cycle_;
  }
}

geom::Vec2 AccumulativeGridMap::evidencePoint(int ix, int iy) const {
  const size_t s = slot(ix, iy);
  const geom::Vec2 corner = cellCorner(ix, iy);
  if (p_.hit_centroids && g_[s] > 0 && hn_[s] > 0)
    return corner + geom::Vec2(hx_[s] / static_cast<float>(hn_[s]), hy_[s] / static_cast<float>(hn_[s]));
  return corner + geom::Vec2(0.5 * p_.cell_size, 0.5 * p_.cell_size);
}

void AccumulativeGridMap::exportGrids(std::vector<int16_t>& g, std::vector<int16_t>& h,
                                      std::vector<int32_t>& gp) const {
  exportGrids(0, 0, n_, g, h, gp);
}

void AccumulativeGridMap::exportGrids(int ix0, int iy0, int w, std::vector<int16_t>& g, std::vector<int16_t>& h,
                                      std::vector<int32_t>& gp) const {
  if (ix0 < 0 || iy0 < 0 || w < 0 || ix0 + w > n_ || iy0 + w > n_)
    throw std::invalid_argument("AccumulativeGridMap::exportGrids: sub-window outside the window");
  const size_t cells = static_cast<size_t>(w) * static_cast<size_t>(w);
  g.assign(cells, 0);
  h.assign(cells, 0);
  gp.assign(cells, 0);
  // Row by row, each row in at most two runs of consecutive slots (the ring wraps once).
  const int64_t sx0 = floorMod(ox_ + ix0, n_);
  int64_t sy = floorMod(oy_ + iy0, n_);
  const auto before_wrap = static_cast<size_t>(std::min<int64_t>(w, n_ - sx0));
  const auto width = static_cast<size_t>(w);
  const int32_t* const gs = g_.data();
  const int32_t* const gps = gp_.data();
  const int64_t* const hit = last_hit_.data();
  int16_t* const go = g.data();
  int16_t* const ho = h.data();
  int32_t* const gpo = gp.data();
  const int64_t cycle = cycle_;
  const auto copyRun = [=](size_t s, size_t out, size_t len) {
    forEachAtLeast(gs + s, len, 1, [=](size_t j) {
      go[out + j] = static_cast<int16_t>(gs[s + j]);
      ho[out + j] = static_cast<int16_t>(std::min<int64_t>(cycle - hit[s + j], std::numeric_limits<int16_t>::max()));
      gpo[out + j] = gps[s + j];
    });
  };
  for (size_t iy = 0; iy < width; ++iy) {
    const auto row = static_cast<size_t>(sy * n_);
    copyRun(row + static_cast<size_t>(sx0), iy * width, before_wrap);
    copyRun(row, iy * width + before_wrap, width - before_wrap);
    if (++sy == n_) sy = 0;
  }
}

}  // namespace lasonic
