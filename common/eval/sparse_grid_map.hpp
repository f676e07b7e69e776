#pragma once
// An Accumulative Grid Map window (grid_map_t: AGM_OPERATIONAL, AGM_TACTICAL) as the evaluation
// keeps it: the header, and only the cells whose G or Gp is not 0. The scores look at occupied
// cells and at the largest G and Gp near a point, never at H, and a window is mostly zeros: the
// two grids of an hour's log take 1.1 GB decoded whole, 7 MB so (README "Performance", *An hour
// of driving*).
#include <cstdint>
#include <vector>

#include <lasonic/grid_map_t.hpp>

#include "core/geometry.hpp"

namespace lasonic::eval {

class SparseGridMap {
 public:
  struct Cell {
    int32_t index;  // iy * width + ix, as in the message's arrays
    int32_t gp;
    int16_t g;
  };

  // As in grid_map_t.
  int64_t utime = 0;
  pose2d_t robot_pose{};
  double origin_x = 0;
  double origin_y = 0;
  float cell_size = 0;
  int32_t width = 0;
  int32_t height = 0;
  int32_t gp_threshold = 0;

  SparseGridMap() = default;
  // Implicit, so that a RunLog can be filled with grid_map_t messages as they are (tests).
  SparseGridMap(const grid_map_t& m);  // NOLINT(google-explicit-constructor)

  // False when width or height is not positive or g or gp has fewer than width*height cells (a
  // message lasonic's processes cannot send: setLengths refuses it); such a map holds no cells.
  bool complete() const { return complete_; }
  // The cells whose G or Gp is not 0, in index order (row by row, as the message's arrays).
  const std::vector<Cell>& cells() const { return cells_; }
  // The centre of a cell (index iy * width + ix), in the map's (odometry) frame.
  geom::Vec2 cellCentre(int64_t index) const {
    const int64_t ix = index % width, iy = index / width;
    return {origin_x + (static_cast<double>(ix) + 0.5) * cell_size, origin_y + (static_cast<double>(iy) + 0.5) * cell_size};
  }
  // The message's G and Gp of one cell (index iy * width + ix; 0 outside the window).
  int g(int64_t index) const;
  int gp(int64_t index) const;

 private:
  const Cell* find(int64_t index) const;

  std::vector<Cell> cells_;
  bool complete_ = false;
};

}  // namespace lasonic::eval
