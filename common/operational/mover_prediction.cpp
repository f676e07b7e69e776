#include "operational/mover_prediction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lasonic {

MoverPrediction::MoverPrediction(const MoverPredictionParams& p) : p_(p) {
  if (!(p.cluster_gap > 0) || !(p.max_extent > 0) || p.min_points < 2 || !(p.min_speed >= 0) ||
      !(p.max_speed > p.min_speed) || !(p.horizon_s >= 0) || !(p.horizon_scans >= 0) || !(p.agree_speed > 0) ||
      !(p.flat_face_rms >= 0) || !(p.flat_face_min >= 0))
    throw std::invalid_argument("MoverPrediction: inconsistent parameters");
}

std::vector<MoverPrediction::Blob> MoverPrediction::candidates(const std::vector<TimedPoint>& scan) const {
  std::vector<Blob> out;
  const double gap2 = p_.cluster_gap * p_.cluster_gap, extent2 = p_.max_extent * p_.max_extent;
  size_t first = 0;
  for (size_t i = 1; i <= scan.size(); ++i) {
    if (i < scan.size() && (scan[i].p - scan[i - 1].p).squaredNorm() <= gap2) continue;
    // scan[first .. i-1] is one cluster.
    const size_t n = i - first;
    // A cluster whose ends lie more than max_extent apart is wider than that (its box holds both
    // ends, and each rounded step below is monotonic: the box's squared diagonal is at least
    // theirs): dropped without the walk below (a wall's ends, not its hundreds of points).
    if (n >= static_cast<size_t>(p_.min_points) && !((scan[i - 1].p - scan[first].p).squaredNorm() > extent2)) {
      geom::Vec2 lo = scan[first].p, hi = scan[first].p, sum = geom::Vec2::Zero();
      double t = 0;
      bool too_wide = false;
      for (size_t j = first; j < i && !too_wide; ++j) {
        lo = lo.cwiseMin(scan[j].p);
        hi = hi.cwiseMax(scan[j].p);
        sum += scan[j].p;
        t += static_cast<double>(scan[j].utime - scan[first].utime);
        // The box only grows point by point (and its squared diagonal with it, rounded
        // monotonically), so a cluster already wider than max_extent stays so: a wall's hundreds
        // of points are not all summed to be dropped.
        too_wide = (hi - lo).squaredNorm() > extent2;
      }
      if (!too_wide && (hi - lo).squaredNorm() <= extent2 && std::isfinite(sum.x()) && std::isfinite(sum.y())) {
        Blob blob{sum / static_cast<double>(n),
                  static_cast<double>(scan[first].utime) * 1e-6 + t * 1e-6 / static_cast<double>(n),
                  (hi - lo).norm(), 0.0, geom::Vec2::UnitY(), first, i - 1};
        // Its line: the principal axis of the returns' scatter; rms = the root of the smaller
        // eigenvalue (the mean squared distance from that axis).
        double sxx = 0, sxy = 0, syy = 0;
        for (size_t j = first; j < i; ++j) {
          const geom::Vec2 d = scan[j].p - blob.centroid;
          sxx += d.x() * d.x(), sxy += d.x() * d.y(), syy += d.y() * d.y();
        }
        sxx /= static_cast<double>(n), sxy /= static_cast<double>(n), syy /= static_cast<double>(n);
        const geom::PrincipalAxes ax = geom::principalAxes(sxx, syy, sxy);
        blob.rms = std::sqrt(ax.minor);
        blob.normal = geom::Vec2(-std::sin(ax.angle), std::cos(ax.angle));
        out.push_back(blob);
      }
    }
    first = i;
  }
  return out;
}

std::vector<geom::Vec2> MoverPrediction::update(const std::vector<TimedPoint>& scan, const geom::Vec2& robot) {
  std::vector<geom::Vec2> v(scan.size(), geom::Vec2::Zero());
  for (const MovingRun& r : track(scan, robot))
    for (size_t j = r.first; j <= r.last; ++j) v[j] = r.vel;
  return v;
}

const std::vector<MoverPrediction::MovingRun>& MoverPrediction::track(const std::vector<TimedPoint>& scan,
                                                                       const geom::Vec2& robot) {
  runs_.clear();
  std::vector<Blob> now = candidates(scan);
  movers_ = 0;
  still_.assign(scan.size(), kStill);
  for (const Blob& b : now)
    for (size_t j = b.first; j <= b.last; ++j) still_[j] = 0;
  const auto nearest = [](const geom::Vec2& c, const std::vector<Blob>& in) {
    size_t best = in.size();
    double d2 = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < in.size(); ++k)
      if (const double e = (in[k].centroid - c).squaredNorm(); e < d2) {
        d2 = e;
        best = k;
      }
    return best;
  };
  for (size_t a = 0; a < now.size(); ++a) {
    const size_t b = nearest(now[a].centroid, prev_);
    if (b == prev_.size() || nearest(prev_[b].centroid, now) != a) continue;  // not mutually nearest
    const double dt = now[a].t_s - prev_[b].t_s;
    if (!(dt > 0) || dt > 1.0) continue;  // not the scan before (or time went back)
    geom::Vec2 vel = (now[a].centroid - prev_[b].centroid) / dt;
    if (!(vel.norm() <= p_.max_speed)) continue;  // two different things
    // A flat face in both scans shows only the motion across it (file comment).
    if (p_.flat_face_rms > 0 && now[a].rms <= p_.flat_face_rms && prev_[b].rms <= p_.flat_face_rms &&
        now[a].extent >= p_.flat_face_min && prev_[b].extent >= p_.flat_face_min)
      vel = now[a].normal * vel.dot(now[a].normal);
    const double speed = vel.norm();
    // What a static object's visible centroid can do as the line of sight turns (file comment).
    const geom::Vec2 los = now[a].centroid - robot;
    const double dist = los.norm();
    const geom::Vec2 v_robot = (robot - prev_robot_) / dt;
    const double v_perp = dist > 0 ? std::abs(v_robot.x() * los.y() - v_robot.y() * los.x()) / dist : 0.0;
    const double apparent = dist > 0 ? std::max(now[a].extent, prev_[b].extent) / geom::kPi * v_perp / dist : 0.0;
    now[a].paired = true;
    now[a].vel = vel;
    if (!(speed >= p_.min_speed + apparent)) {
      for (size_t j = now[a].first; j <= now[a].last; ++j) still_[j] = kStillCluster;
      continue;
    }
    if (!prev_[b].paired) continue;
    if (!((vel - prev_[b].vel).norm() <= std::max(p_.agree_speed, 0.5 * speed))) continue;
    ++movers_;
    runs_.push_back({now[a].first, now[a].last, vel});
  }
  prev_ = std::move(now);
  prev_robot_ = robot;
  return runs_;
}

}  // namespace lasonic
