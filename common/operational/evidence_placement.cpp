#include "operational/evidence_placement.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic {

double evidenceBearing(const AccumulativeGridMap& agm, const geom::Vec2& sensor, double range,
                       const BearingEstimate& est, int min_g) {
  if (!(est.halfwidth > 0) || !(range > 0)) return est.bearing;
  // An arc longer than the window is wider than anything the AGM could say (and a malformed
  // huge range must not cost a huge loop): the estimate.
  if (!(range * est.halfwidth <= agm.size() * agm.cellSize())) return est.bearing;
  // Samples at most half a cell apart along the arc: no cell the arc crosses is skipped over.
  const double step = 0.5 * agm.cellSize() / range;
  const int half = static_cast<int>(std::ceil(est.halfwidth / step));
  const double inc = est.halfwidth / half;
  double best = est.bearing;
  int best_g = 0, best_q = 0;
  // Outwards from the estimate, so the first sample reaching a weight wins a tie.
  for (int q = 0; q <= half; ++q) {
    for (const int sign : {1, -1}) {
      if (q == 0 && sign < 0) continue;
      const double b = est.bearing + sign * q * inc;
      int ix = 0, iy = 0;
      if (!agm.cellAt(sensor + range * geom::unitVector(b), ix, iy)) continue;
      const int g = agm.g(ix, iy);
      if (g > best_g) {
        best_g = g;
        best = b;
        best_q = q;
      }
    }
  }
  return best_g >= std::max(min_g, 1) && best_q > 0 ? geom::normalizeAngle(best) : est.bearing;
}

}  // namespace lasonic
