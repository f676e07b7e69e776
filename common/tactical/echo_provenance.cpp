#include "tactical/echo_provenance.hpp"

#include <algorithm>
#include <limits>

namespace lasonic {

void EchoProvenance::note(const geom::Vec2& p, bool checked, const AccumulativeGridMap& agm) {
  int ix = 0, iy = 0;
  if (!agm.cellAt(p, ix, iy)) return;
  const std::pair<int64_t, int64_t> key{agm.originX() + ix, agm.originY() + iy};
  Made& m = cells_[key];
  // Empty until this cycle: what made it before is gone (another hit of this cycle is not).
  if (agm.g(ix, iy) == 0 && m.cycle != agm.cycle()) m.bits = kUnknown;
  m.bits = static_cast<int8_t>(m.bits | (checked ? kChecked : kUnchecked));
  m.cycle = agm.cycle();
  if (cells_.size() <= prune_at_) return;
  // Entries of cells emptied since (forgotten, passed through) or outside the window: swept;
  // those noted this cycle are about to be hit.
  const int n = agm.size();
  for (auto it = cells_.begin(); it != cells_.end();) {
    const int64_t jx = it->first.first - agm.originX(), jy = it->first.second - agm.originY();
    const bool live = it->second.cycle == agm.cycle() || (jx >= 0 && jy >= 0 && jx < n && jy < n &&
                                                          agm.g(static_cast<int>(jx), static_cast<int>(jy)) > 0);
    it = live ? std::next(it) : cells_.erase(it);
  }
  prune_at_ = std::max<size_t>(4096, 2 * cells_.size());
}

int8_t EchoProvenance::at(const AccumulativeGridMap& agm, int ix, int iy) const {
  if (agm.g(ix, iy) == 0) return kUnknown;
  const auto it = cells_.find({agm.originX() + ix, agm.originY() + iy});
  return it == cells_.end() ? kUnknown : it->second.bits;
}

void EchoProvenance::exportWindow(const AccumulativeGridMap& agm, int ix0, int iy0, int w,
                                  std::vector<int8_t>& out) const {
  out.assign(static_cast<size_t>(std::max(0, w)) * static_cast<size_t>(std::max(0, w)), kUnknown);
  const int64_t gx0 = agm.originX() + ix0, gy0 = agm.originY() + iy0;
  // From the record's entries (far fewer than the window's cells), those inside the window.
  for (auto it = cells_.lower_bound({gx0, std::numeric_limits<int64_t>::min()}); it != cells_.end() && it->first.first < gx0 + w; ++it) {
    const int64_t jy = it->first.second - gy0, jx = it->first.first - gx0;
    if (jy < 0 || jy >= w) continue;
    const int ix = ix0 + static_cast<int>(jx), iy = iy0 + static_cast<int>(jy);
    if (agm.g(ix, iy) == 0) continue;
    out[static_cast<size_t>(jy) * static_cast<size_t>(w) + static_cast<size_t>(jx)] = it->second.bits;
  }
}

}  // namespace lasonic
