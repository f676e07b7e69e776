#include "core/odometry_error.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic {

void OdometryError::advance(double step, double turn) {
  step = std::abs(step);
  turn = std::abs(turn);
  m_.driven += step;
  m_.t += n_.trans * n_.trans * step;
  const double dv = n_.drift * n_.drift * step + n_.rot * n_.rot * turn;
  m_.a += dv;
  m_.b += dv * m_.driven;
  m_.c += dv * m_.driven * m_.driven;
}

double OdometryError::varianceBetween(const Mark& then, const Mark& later) const {
  const double d = later.driven;
  const double heading = d * d * (later.a - then.a) - 2 * d * (later.b - then.b) + (later.c - then.c);
  return std::max(0.0, later.t - then.t) + std::max(0.0, heading);
}

}  // namespace lasonic
