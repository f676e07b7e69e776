#include "operational/laser_memory.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_set>

#include <Eigen/LU>

namespace lasonic {

std::optional<geom::Vec2> LaserMemory::roundCluster(size_t first, size_t end) const {
  // Centred on the mean for conditioning: minimise sum (u^2 + v^2 + D u + E v + F)^2.
  geom::Vec2 m = geom::Vec2::Zero();
  for (size_t k = first; k < end; ++k) m += last_[k].p;
  m /= static_cast<double>(end - first);
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (size_t k = first; k < end; ++k) {
    const geom::Vec2 q = last_[k].p - m;
    const Eigen::Vector3d row(q.x(), q.y(), 1.0);
    a += row * row.transpose();
    b -= row * q.squaredNorm();
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(a);
  if (lu.rank() < 3) return std::nullopt;  // collinear: no circle
  const Eigen::Vector3d x = lu.solve(b);
  const geom::Vec2 centre(-0.5 * x(0), -0.5 * x(1));
  const double r2 = centre.squaredNorm() - x(2);
  if (!(r2 > 0)) return std::nullopt;
  const double r = std::sqrt(r2);
  if (!(r >= h_.min_radius && r <= h_.max_radius)) return std::nullopt;
  double ss = 0;
  for (size_t k = first; k < end; ++k) {
    const double e = (last_[k].p - m - centre).norm() - r;
    ss += e * e;
  }
  if (!(std::sqrt(ss / static_cast<double>(end - first)) <= h_.fit_rms)) return std::nullopt;
  return m;
}

void LaserMemory::groupClusters(int64_t utime) {
  // The newest scan's still-cluster returns, in scan order: a run ends at a return of no cluster
  // or a gap.
  const double gap2 = h_.cluster_gap * h_.cluster_gap;
  size_t i = 0;
  while (i < last_.size()) {
    if (!last_[i].cluster) {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < last_.size() && last_[j].cluster && (last_[j].p - last_[j - 1].p).squaredNorm() <= gap2) ++j;
    // Round: the returns lie on a circle (least squares, Kasa's algebraic fit) of a person's,
    // a post's or a bin's radius, within fit_rms.
    if (const auto centroid = j - i >= 3 ? roundCluster(i, j) : std::nullopt) {
      const uint32_t id = next_round_++;
      rounds_.push_back({id, utime, *centroid, 0});
      for (size_t k = i; k < j; ++k) last_[k].round = id;
    }
    i = j;
  }
  // Clusters with no return left (the view covered them, they aged out, they left the reach).
  std::unordered_set<uint32_t> alive;
  for (const Remembered& r : remembered_)
    if (r.round) alive.insert(r.round);
  for (const Remembered& r : last_)
    if (r.round) alive.insert(r.round);
  rounds_.erase(std::remove_if(rounds_.begin(), rounds_.end(), [&](const Round& q) { return !alive.count(q.id); }),
                rounds_.end());
}

int LaserMemory::heardThrough(int64_t utime, const std::vector<Sounding>& group) {
  const LaserMemoryHeardThrough& h = h_;
  if (!enabled() || h.clear_after <= 0 || !(h.core > 0) || !(h.margin_m >= 0) || group.empty()) return 0;
  std::unordered_set<uint32_t> gone;
  for (Round& q : rounds_) {
    if (q.utime >= utime) continue;
    bool through = false, answered = false;
    for (const Sounding& s : group) {
      const double half = std::min(h.core, 1.0) * 0.5 * s.beam_width;
      const geom::Vec2 v = q.centroid - s.sensor.position();
      const double d = v.norm();
      if (!(half > 0) || !(d >= h.margin_m) || std::abs(geom::angleDiff(std::atan2(v.y(), v.x()), s.sensor.theta)) > half)
        continue;
      // (Silence -- nothing within the range limit -- answers nothing, wherever the limit lies.)
      if (!s.unverifiable && std::abs(s.range - d) <= h.margin_m) answered = true;
      else if (s.range > d + h.margin_m) through = true;
    }
    if (answered) q.silent = 0;
    else if (through && ++q.silent >= h.clear_after) gone.insert(q.id);
  }
  if (gone.empty()) return 0;
  const auto drop = [&](const Remembered& r) { return r.round && gone.count(r.round); };
  const size_t before = remembered_.size() + last_.size();
  remembered_.erase(std::remove_if(remembered_.begin(), remembered_.end(), drop), remembered_.end());
  last_.erase(std::remove_if(last_.begin(), last_.end(), drop), last_.end());
  rounds_.erase(std::remove_if(rounds_.begin(), rounds_.end(), [&](const Round& q) { return gone.count(q.id) > 0; }),
                rounds_.end());
  points_.clear();
  for (const Remembered& r : remembered_) points_.push_back(r.p);
  return static_cast<int>(before - remembered_.size() - last_.size());
}

}  // namespace lasonic
