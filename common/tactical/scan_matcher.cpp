#include "tactical/scan_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

namespace lasonic {

ScanMatchParams scanMatchParams(const Config& c, ScanMatchParams p) {
  c.allowOnly({"enabled", "point_sigma_m", "gate_m", "max_range_m", "min_line_length_m", "max_line_rms_m", "min_pairs", "point_spacing_m",
               "iterations", "constrained_m", "constrained_rad", "keyframe_distance_m", "keyframe_turn_deg", "prior_trans_per_m", "prior_heading_per_m",
               "prior_heading_per_rad", "prior_trans_floor_m", "prior_heading_floor", "pose_trans_noise", "pose_rot_noise",
               "pose_drift_noise"});
  p.enabled = c.get<bool>("enabled", p.enabled);
  p.point_sigma = c.get("point_sigma_m", p.point_sigma, Range::between(1e-4, 1));
  p.gate = c.get("gate_m", p.gate, Range::between(1e-3, 5));
  p.max_range = c.get("max_range_m", p.max_range, Range::positive());
  p.min_line_length = c.get("min_line_length_m", p.min_line_length, Range::nonNegative());
  p.max_line_rms = c.get("max_line_rms_m", p.max_line_rms, Range::between(0, 1));
  p.min_pairs = c.get("min_pairs", p.min_pairs, Range::between(3, 100000));
  p.point_spacing = c.get("point_spacing_m", p.point_spacing, Range::between(0, 1));
  p.iterations = c.get("iterations", p.iterations, Range::between(1, 100));
  p.constrained_trans = c.get("constrained_m", p.constrained_trans, Range::between(0, 10));
  p.constrained_heading = c.get("constrained_rad", p.constrained_heading, Range::between(0, 10));
  p.keyframe_distance = c.get("keyframe_distance_m", p.keyframe_distance, Range::between(0, 100));
  p.keyframe_turn = geom::deg2rad(c.get("keyframe_turn_deg", geom::rad2deg(p.keyframe_turn), Range::between(0, 180)));
  p.prior_trans_per_m = c.get("prior_trans_per_m", p.prior_trans_per_m, Range::between(0, 1));
  p.prior_heading_per_m = c.get("prior_heading_per_m", p.prior_heading_per_m, Range::between(0, 1));
  p.prior_heading_per_rad = c.get("prior_heading_per_rad", p.prior_heading_per_rad, Range::between(0, 1));
  p.prior_trans_floor = c.get("prior_trans_floor_m", p.prior_trans_floor, Range::between(1e-4, 1));
  p.prior_heading_floor = c.get("prior_heading_floor", p.prior_heading_floor, Range::between(1e-5, 1));
  p.pose_noise.trans = c.get("pose_trans_noise", p.pose_noise.trans, Range::between(0, 1));
  p.pose_noise.rot = c.get("pose_rot_noise", p.pose_noise.rot, Range::between(0, 1));
  p.pose_noise.drift = c.get("pose_drift_noise", p.pose_noise.drift, Range::between(0, 1));
  return p;
}

namespace {

struct Line {
  geom::Vec2 a, u, n;  // start, unit direction, unit normal
  double length = 0;
};

}  // namespace

LineMatch matchPointsToLines(const std::vector<geom::Vec2>& points, const std::vector<geom::Segment>& lines,
                             const geom::Vec2& pivot, double sigma_trans, double sigma_heading,
                             const ScanMatchParams& p, const std::vector<int>& counts) {
  std::vector<Line> ls;
  ls.reserve(lines.size());
  for (const geom::Segment& s : lines) {
    const geom::Vec2 d = s.b - s.a;
    const double len = d.norm();
    if (!(len > 1e-6) || !s.a.allFinite() || !s.b.allFinite()) continue;
    const geom::Vec2 u = d / len;
    ls.push_back({s.a, u, {-u.y(), u.x()}, len});
  }
  LineMatch out;
  if (ls.empty() || points.empty()) return out;

  // The lines each point can pair with: those within gate + kReach of where it starts (x = 0).
  // In an iteration a point lies at most |t| + |heading| |v| from there, so while that stays
  // below kReach no other line comes within the gate (the distance to a segment changes no
  // faster than the point moves): the same pairs as searching every line, from the few near it.
  constexpr double kReach = 0.25;  // [m] far more than a match moves a point (centimetres)
  struct Point {
    geom::Vec2 v;       // from the pivot
    int count = 1;      // the returns it stands for
    double v_norm = 0;  // |v|: how far a turn moves it
    uint32_t first = 0, end = 0;  // its lines: near[first, end)
  };
  std::vector<Point> pts;
  std::vector<uint32_t> near;
  pts.reserve(points.size());
  near.reserve(points.size() * 2);
  const double reach2 = (p.gate + kReach) * (p.gate + kReach);
  for (size_t i = 0; i < points.size(); ++i) {
    const geom::Vec2& q0 = points[i];
    if (!q0.allFinite()) continue;
    Point pt;
    pt.v = q0 - pivot;
    if (i < counts.size()) pt.count = std::max(1, counts[i]);
    pt.v_norm = pt.v.norm();
    pt.first = static_cast<uint32_t>(near.size());
    for (size_t k = 0; k < ls.size(); ++k) {
      const geom::Vec2 e = q0 - ls[k].a;
      const double along = e.dot(ls[k].u);
      const double beyond = std::max({0.0, -along, along - ls[k].length});
      const double across = e.dot(ls[k].n);
      if (across * across + beyond * beyond <= reach2) near.push_back(static_cast<uint32_t>(k));
    }
    pt.end = static_cast<uint32_t>(near.size());
    pts.push_back(pt);
  }

  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // tx, ty, heading about pivot
  Eigen::Matrix3d data = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d prior = Eigen::Matrix3d::Zero();
  prior(0, 0) = prior(1, 1) = 1.0 / (sigma_trans * sigma_trans);
  prior(2, 2) = 1.0 / (sigma_heading * sigma_heading);
  const double w0 = 1.0 / (p.point_sigma * p.point_sigma);
  const double gate2 = p.gate * p.gate;
  // Per iteration the pairs first (residual r and Jacobian j), then their Cauchy weights in one
  // pass (the divisions independent of each other, so they overlap), then the sums in pair order.
  std::vector<double> r(pts.size()), w(pts.size()), returns(pts.size());
  std::vector<Eigen::Vector3d> j(pts.size());
  for (int it = 0; it < p.iterations; ++it) {
    const double c = std::cos(x(2)), s = std::sin(x(2));
    const double moved = std::hypot(x(0), x(1)), turned = std::abs(x(2));
    size_t pairs = 0;
    int paired_returns = 0;
    for (const Point& pt : pts) {
      const geom::Vec2& v = pt.v;
      const geom::Vec2 rv{c * v.x() - s * v.y(), s * v.x() + c * v.y()};
      const geom::Vec2 q = rv + pivot + geom::Vec2{x(0), x(1)};
      int best = -1;
      double best_d2 = gate2;
      auto consider = [&](size_t k) {
        const Line& l = ls[k];
        const geom::Vec2 e = q - l.a;
        const double along = e.dot(l.u);
        const double beyond = std::max({0.0, -along, along - l.length});
        const double across = e.dot(l.n);
        const double d2 = across * across + beyond * beyond;
        if (d2 < best_d2) best_d2 = d2, best = static_cast<int>(k);
      };
      if (moved + turned * pt.v_norm < kReach - 1e-6)
        for (uint32_t i = pt.first; i < pt.end; ++i) consider(near[i]);
      else
        for (size_t k = 0; k < ls.size(); ++k) consider(k);
      if (best < 0) continue;
      const Line& l = ls[static_cast<size_t>(best)];
      r[pairs] = (q - l.a).dot(l.n);
      // d q / d heading = perp(R v)
      j[pairs] = {l.n.x(), l.n.y(), l.n.x() * -rv.y() + l.n.y() * rv.x()};
      returns[pairs] = pt.count;
      paired_returns += pt.count;
      ++pairs;
    }
    for (size_t i = 0; i < pairs; ++i) {
      const double z = r[i] / p.point_sigma;
      w[i] = returns[i] * (w0 / (1.0 + z * z));  // Cauchy, once per return the point stands for
    }
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();  // the pairs' information (the prior's below)
    Eigen::Vector3d g = prior * x;
    for (size_t i = 0; i < pairs; ++i) {
      h.noalias() += w[i] * j[i] * j[i].transpose();
      g.noalias() += w[i] * r[i] * j[i];
    }
    out.pairs = paired_returns;
    data = h;
    const Eigen::Vector3d step = -(h + prior).ldlt().solve(g);
    if (!step.allFinite()) break;
    x += step;
    if (step.head<2>().norm() < 1e-5 && std::abs(step(2)) < 1e-6) break;
  }
  // What the pairs alone fix: their covariance, if they fix every direction at all.
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(data);
  if (lu.isInvertible()) {
    const Eigen::Matrix3d cov = lu.inverse();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov.topLeftCorner<2, 2>());
    const double worst_trans = std::sqrt(std::max(0.0, es.eigenvalues()(1)));
    const double heading = std::sqrt(std::max(0.0, cov(2, 2)));
    out.constrained = std::isfinite(worst_trans) && worst_trans <= p.constrained_trans && heading <= p.constrained_heading;
  }
  const double c = std::cos(x(2)), s = std::sin(x(2));
  const geom::Vec2 rp{c * pivot.x() - s * pivot.y(), s * pivot.x() + c * pivot.y()};
  out.motion = {pivot.x() + x(0) - rp.x(), pivot.y() + x(1) - rp.y(), x(2)};
  return out;
}

void ScanMatcher::clear() { *this = ScanMatcher(p_); }

void ScanMatcher::takeKeyframe(const std::vector<complement::RmSegment>& segments) {
  key_lines_.clear();
  const geom::PoseTransform c(c_);
  for (const complement::RmSegment& s : segments)
    if (s.seg.length() >= p_.min_line_length && s.rms <= p_.max_line_rms) key_lines_.push_back(c(s.seg));
  driven_since_key_ = turned_since_key_ = 0;
  have_keyframe_ = true;
}

ScanMatcher::Result ScanMatcher::update(const std::vector<complement::ScanPoint>& points,
                                        const std::vector<complement::RmSegment>& segments,
                                        const geom::Pose2& robot_odometry, const geom::Vec2& scanner_odometry) {
  Result r;
  if (!p_.enabled) return r;
  if (have_keyframe_) {
    driven_since_key_ += (robot_odometry.position() - last_robot_odometry_.position()).norm();
    turned_since_key_ += std::abs(geom::angleDiff(robot_odometry.theta, last_robot_odometry_.theta));
  }
  last_robot_odometry_ = robot_odometry;
  if (!have_keyframe_) {
    takeKeyframe(segments);
    r.new_keyframe = true;
    return r;
  }
  const double max2 = p_.max_range * p_.max_range;
  // Consecutive returns within point_spacing of a cluster's first are matched as their mean,
  // weighted by their number: the same information (their residuals to a wall average out, their
  // weights add up) at a fraction of the cost, since a 0.5 deg scanner puts a near wall's returns
  // a centimetre apart.
  points_.clear();
  counts_.clear();
  const geom::PoseTransform c(c_);
  const double spacing2 = p_.point_spacing * p_.point_spacing;
  geom::Vec2 first{0, 0}, sum{0, 0};
  int n = 0;
  auto close = [&] {
    if (n == 0) return;
    points_.push_back(c(n == 1 ? sum : geom::Vec2(sum / n)));
    counts_.push_back(n);
    n = 0;
  };
  for (const complement::ScanPoint& q : points) {
    if (!q.valid || !q.p.allFinite() || (q.p - scanner_odometry).squaredNorm() > max2) {
      close();
      continue;
    }
    if (n > 0 && (q.p - first).squaredNorm() < spacing2) {
      sum += q.p;
      ++n;
      continue;
    }
    close();
    first = sum = q.p;
    n = 1;
  }
  close();
  const double sigma_trans = std::max(p_.prior_trans_floor, p_.prior_trans_per_m * driven_since_key_);
  const double sigma_heading = std::max(
      p_.prior_heading_floor, p_.prior_heading_per_m * driven_since_key_ + p_.prior_heading_per_rad * turned_since_key_);
  const LineMatch m =
      matchPointsToLines(points_, key_lines_, c(robot_odometry.position()), sigma_trans, sigma_heading, p_, counts_);
  r.pairs = m.pairs;
  if (m.pairs >= p_.min_pairs) {
    c_ = m.motion.compose(c_);
    r.matched = true;
    r.constrained = m.constrained;
  }
  if (!r.matched || driven_since_key_ >= p_.keyframe_distance || turned_since_key_ >= p_.keyframe_turn) {
    takeKeyframe(segments);
    r.new_keyframe = true;
  }
  return r;
}

}  // namespace lasonic
