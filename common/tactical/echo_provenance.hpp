#pragma once
// Echo provenance (beyond the paper): which echoes made each cell of the tactical AGM.
//
// The paper's AGM holds complementary readings only: echoes the laser could have seen and did
// not. A scanner of less than a full turn adds two kinds the laser could not check when they were
// heard (README "Method", step 3): echoes whose arc reaches beyond its view (`outside_view`) and
// echoes only an earlier scan's lines explain (`seen_before`). The tactical level keeps both --
// what the scan does not see now is its to remember -- but most are laser-visible walls beside and
// behind the robot, placed on their arcs' crossings 0.1-0.3 m in front of the wall (an oblique
// wall answers from the beam's edge), and a person standing where no scan looked. The pilot has
// its own memory of what the laser saw, at the laser's precision; from the tactical map it wants
// only what the laser could not see. So each cell records, since it was last empty, whether a
// checked hit (a complementary echo, a laser glint) and whether an unchecked one made it, and
// AGM_TACTICAL says so per cell (grid_map_t::heard).
//
// Cells are kept by global index; a noted hit on a cell whose G is 0 starts it afresh. Entries
// whose cell has been emptied or has left the window are swept out as the record grows. (Hits the
// caller does not note -- the navigator's surface fill and laser join -- add nothing: a cell only
// they make is unknown, and one emptied and made again only by them before the sweep keeps what
// was noted before.)
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "operational/agm.hpp"

namespace lasonic {

class EchoProvenance {
 public:
  // Values equal grid_map_t::HEARD_*.
  static constexpr int8_t kUnknown = 0, kChecked = 1, kUnchecked = 2, kBoth = 3;
  // A hit at `p` (global frame) about to go into `agm` (call before agm.update(), every hit of
  // one update cycle with the map as it is before it): checked by the laser or not. A point
  // outside the window is ignored.
  void note(const geom::Vec2& p, bool checked, const AccumulativeGridMap& agm);
  // What made the cell (ix, iy) of the window: kUnknown where nothing was noted.
  int8_t at(const AccumulativeGridMap& agm, int ix, int iy) const;
  // The w x w cells from window cell (ix0, iy0), row-major, as at() gives them.
  void exportWindow(const AccumulativeGridMap& agm, int ix0, int iy0, int w, std::vector<int8_t>& out) const;
  size_t size() const { return cells_.size(); }
  void clear() { cells_.clear(); }

 private:
  struct Made {
    int8_t bits = kUnknown;
    int64_t cycle = -1;  // the map's cycle at the last note (its hits not in the map before update())
  };
  std::map<std::pair<int64_t, int64_t>, Made> cells_;    // by global cell
  size_t prune_at_ = 4096;                               // size above which dead entries are swept
};

}  // namespace lasonic
