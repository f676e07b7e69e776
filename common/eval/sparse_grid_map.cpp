#include "eval/sparse_grid_map.hpp"

#include <algorithm>
#include <limits>

namespace lasonic::eval {

SparseGridMap::SparseGridMap(const grid_map_t& m)
    : utime(m.utime),
      robot_pose(m.robot_pose),
      origin_x(m.origin_x),
      origin_y(m.origin_y),
      cell_size(m.cell_size),
      width(m.width),
      height(m.height),
      gp_threshold(m.gp_threshold) {
  const int64_t n = int64_t{m.width} * m.height;
  // A decoded message holds at most limits::kGridCells, so the index fits 32 bits.
  complete_ = m.width > 0 && m.height > 0 && n <= std::numeric_limits<int32_t>::max() &&
              static_cast<int64_t>(m.g.size()) >= n && static_cast<int64_t>(m.gp.size()) >= n;
  if (!complete_) return;
  for (int64_t i = 0; i < n; ++i) {
    const auto k = static_cast<size_t>(i);
    if (m.g[k] != 0 || m.gp[k] != 0) cells_.push_back({static_cast<int32_t>(i), m.gp[k], m.g[k]});
  }
  cells_.shrink_to_fit();  // kept for the whole evaluation: no spare capacity
}

const SparseGridMap::Cell* SparseGridMap::find(int64_t index) const {
  const auto it = std::lower_bound(cells_.begin(), cells_.end(), index,
                                   [](const Cell& c, int64_t i) { return c.index < i; });
  return it != cells_.end() && it->index == index ? &*it : nullptr;
}

int SparseGridMap::g(int64_t index) const {
  const Cell* c = find(index);
  return c ? c->g : 0;
}

int SparseGridMap::gp(int64_t index) const {
  const Cell* c = find(index);
  return c ? c->gp : 0;
}

}  // namespace lasonic::eval
