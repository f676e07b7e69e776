#include "tactical/look_weight.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic {

double LookWeight::weight(double speed) const {
  if (!std::isfinite(speed)) return 1.0;
  const double v = std::abs(speed);
  if (low_speed_ > 0 && v < low_speed_) return v / low_speed_;
  return ref_speed_ > 0 ? std::max(1.0, v / ref_speed_) : 1.0;
}

int LookWeight::apply(std::vector<geom::Vec2>& hits, double speed) {
  const double w = weight(speed);
  if (w == 1.0 || hits.empty()) return 0;
  // A weight beyond any real speed (a corrupt odometry message) is capped: 10 x the reference.
  const double wc = std::min(w, 10.0);
  std::vector<geom::Vec2> out;
  out.reserve(static_cast<size_t>(static_cast<double>(hits.size()) * wc) + 1);
  for (const geom::Vec2& p : hits) {
    const double total = carry_ + wc;
    const auto n = static_cast<int>(std::floor(total));
    carry_ = total - n;
    for (int i = 0; i < n; ++i) out.push_back(p);
  }
  const int added = static_cast<int>(out.size()) - static_cast<int>(hits.size());
  hits = std::move(out);
  return added;
}

double LookWeight::meanSpeed(const geom::Vec2& from, const geom::Vec2& to, double dt_s) {
  if (!(dt_s > 0)) return -1;
  const double v = (to - from).norm() / dt_s;
  return std::isfinite(v) ? v : -1;
}

}  // namespace lasonic
