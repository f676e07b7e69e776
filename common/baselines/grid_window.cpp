#include "baselines/grid_window.hpp"

namespace lasonic::baselines {

WindowParams windowParams(const Config& c, WindowParams p) {
  p.size = c.get("size", p.size, Range::between(3, 10000));
  p.cell_size = c.get("cell_size", p.cell_size, Range::positive());
  p.recenter_cells = c.get("recenter_cells", p.recenter_cells, Range::between(0, p.size / 2 - 1));
  return p;
}

}  // namespace lasonic::baselines
