#pragma once
// The window that every baseline mapper keeps (README "Evaluation", baselines): an N x N window
// of square cells on a global grid anchored at the odometry origin, laid out like the
// operational AGM (global cell (gx, gy) covers [gx*c, (gx+1)*c) x [gy*c, (gy+1)*c)), following
// the robot's translations in whole cells. Next to the mapper's own cell values it keeps the
// occupancy layer that the pilot's SectorMap reads (OccupancyWindow), so a baseline is read out
// exactly like the AGM.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"
#include "operational/sector_map.hpp"

namespace lasonic::baselines {

struct WindowParams {
  int size = 100;           // N (the operational AGM's 100 x 100)
  double cell_size = 0.10;  // [m]
  int recenter_cells = 5;   // the robot may be this many cells (Chebyshev) off the centre cell
};
// Reads size, cell_size, recenter_cells of `c` over `base`; ConfigError names the key path.
WindowParams windowParams(const Config& c, WindowParams base = {});
// The keys windowParams reads (for allowOnly lists).
inline const std::vector<std::string>& windowKeys() {
  static const std::vector<std::string> k = {"size", "cell_size", "recenter_cells"};
  return k;
}

template <typename T>
class GridWindow {
 public:
  GridWindow(const WindowParams& p, T init) : p_(p), init_(init) {
    if (p.size < 3 || !(p.cell_size > 0) || p.recenter_cells < 0 || p.recenter_cells > p.size / 2 - 1)
      throw std::invalid_argument("GridWindow: inconsistent parameters");
    const size_t n = static_cast<size_t>(p.size) * static_cast<size_t>(p.size);
    v_.assign(n, init);
    occ_.size = p.size;
    occ_.cell_size = p.cell_size;
    occ_.origin_x = occ_.origin_y = -(p.size / 2);  // on the global origin until the robot is known
    occ_.occupied.assign(n, 0);
  }

  const WindowParams& params() const { return p_; }
  double cellSize() const { return p_.cell_size; }
  // Clamped like the AGM's: a far (finite) point must not overflow the conversion.
  int64_t globalCell(double v) const {
    return static_cast<int64_t>(std::clamp(std::floor(v / p_.cell_size), -1e15, 1e15));
  }
  bool inWindow(int64_t gx, int64_t gy) const {
    return gx >= occ_.origin_x && gx < occ_.origin_x + p_.size && gy >= occ_.origin_y &&
           gy < occ_.origin_y + p_.size;
  }
  // Index of an in-window global cell.
  size_t index(int64_t gx, int64_t gy) const {
    return static_cast<size_t>(gy - occ_.origin_y) * static_cast<size_t>(p_.size) +
           static_cast<size_t>(gx - occ_.origin_x);
  }
  geom::Vec2 cellCentre(int64_t gx, int64_t gy) const {
    return {(static_cast<double>(gx) + 0.5) * p_.cell_size, (static_cast<double>(gy) + 0.5) * p_.cell_size};
  }
  T& value(size_t i) { return v_[i]; }
  const T& value(size_t i) const { return v_[i]; }
  void setOccupied(size_t i, bool occ) { occ_.occupied[i] = occ ? 1 : 0; }
  const OccupancyWindow& occupancy() const { return occ_; }

  // Re-centres (the robot's cell becomes the centre cell) when the robot is more than
  // recenter_cells off the centre; cells leaving the window are forgotten, new ones start at
  // the initial value. Returns true if the window moved.
  bool follow(const geom::Vec2& robot) {
    if (!std::isfinite(robot.x()) || !std::isfinite(robot.y())) return false;
    const int64_t rx = globalCell(robot.x()), ry = globalCell(robot.y());
    const int64_t cx = occ_.origin_x + p_.size / 2, cy = occ_.origin_y + p_.size / 2;
    if (std::max(std::abs(rx - cx), std::abs(ry - cy)) <= p_.recenter_cells) return false;
    moveTo(rx - p_.size / 2, ry - p_.size / 2);
    return true;
  }

 private:
  void moveTo(int64_t nox, int64_t noy) {
    const int n = p_.size;
    std::vector<T> v(v_.size(), init_);
    std::vector<uint8_t> o(v_.size(), 0);
    for (int iy = 0; iy < n; ++iy) {
      const int64_t gy = noy + iy;
      if (gy < occ_.origin_y || gy >= occ_.origin_y + n) continue;
      for (int ix = 0; ix < n; ++ix) {
        const int64_t gx = nox + ix;
        if (gx < occ_.origin_x || gx >= occ_.origin_x + n) continue;
        const size_t from = index(gx, gy);
        const size_t to = static_cast<size_t>(iy) * static_cast<size_t>(n) + static_cast<size_t>(ix);
        v[to] = v_[from];
        o[to] = occ_.occupied[from];
      }
    }
    v_.swap(v);
    occ_.occupied.swap(o);
    occ_.origin_x = nox;
    occ_.origin_y = noy;
  }

  WindowParams p_;
  T init_;
  std::vector<T> v_;
  OccupancyWindow occ_;
};

// Visits the global cells (cell size c) that the segment a -> b passes through, in order from
// a's cell to b's cell inclusive (Amanatides & Woo's traversal), calling f(gx, gy); f returns
// false to stop.
template <typename F>
void forEachCellOnSegment(const geom::Vec2& a, const geom::Vec2& b, double c, F&& f) {
  const auto cell = [c](double v) { return static_cast<int64_t>(std::clamp(std::floor(v / c), -1e15, 1e15)); };
  int64_t x = cell(a.x()), y = cell(a.y());
  const int64_t x1 = cell(b.x()), y1 = cell(b.y());
  const geom::Vec2 d = b - a;
  const int sx = d.x() > 0 ? 1 : (d.x() < 0 ? -1 : 0);
  const int sy = d.y() > 0 ? 1 : (d.y() < 0 ? -1 : 0);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double tx = sx != 0 ? ((static_cast<double>(x + (sx > 0 ? 1 : 0)) * c) - a.x()) / d.x() : kInf;
  double ty = sy != 0 ? ((static_cast<double>(y + (sy > 0 ? 1 : 0)) * c) - a.y()) / d.y() : kInf;
  const double dtx = sx != 0 ? c / std::abs(d.x()) : kInf;
  const double dty = sy != 0 ? c / std::abs(d.y()) : kInf;
  const int64_t steps = std::abs(x1 - x) + std::abs(y1 - y);
  for (int64_t i = 0;; ++i) {
    if (!f(x, y)) return;
    if (i >= steps || (x == x1 && y == y1)) return;
    // Never step past the end cell on an axis (rounding at exact cell boundaries).
    const bool step_x = y == y1 || (x != x1 && tx < ty);
    if (step_x) {
      x += sx;
      tx += dtx;
    } else {
      y += sy;
      ty += dty;
    }
  }
}

}  // namespace lasonic::baselines
