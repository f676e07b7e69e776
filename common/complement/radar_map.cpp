#include "complement/radar_map.hpp"

#include "core/pose_history.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace lasonic::complement {

using geom::Vec2;

namespace {
// Pose2::transform with cos/sin computed only when the angle changes (bit for bit the same
// values: the mount's angle is the same for a whole scan, the robot's while it does not turn).
class CachedRotation {
 public:
  Vec2 transform(const geom::Pose2& f, const Vec2& l) {
    if (std::memcmp(&f.theta, &theta_, sizeof theta_) != 0) {
      theta_ = f.theta;
      c_ = std::cos(theta_);
      s_ = std::sin(theta_);
    }
    return {f.x + c_ * l.x() - s_ * l.y(), f.y + s_ * l.x() + c_ * l.y()};
  }

 private:
  double theta_ = std::numeric_limits<double>::quiet_NaN(), c_ = 0, s_ = 0;
};


// cos/sin of each reading's angle, kept from the previous scan: a scanner's angles are the same
// scan after scan, and a value is reused only for the very same angle (bit for bit).
class UnitVectors {
 public:
  Vec2 at(size_t i, double angle) {
    if (i >= cache_.size()) cache_.resize(i + 1, {std::numeric_limits<double>::quiet_NaN(), Vec2::Zero()});
    Entry& e = cache_[i];
    if (std::memcmp(&e.angle, &angle, sizeof angle) != 0) e = {angle, geom::unitVector(angle)};
    return e.u;
  }

 private:
  struct Entry {
    double angle;
    Vec2 u;
  };
  std::vector<Entry> cache_;
};
}  // namespace

namespace {
// Reading -> global point; pose_at(utime) -> std::optional<geom::Pose2>.
template <typename PoseAt>
std::vector<ScanPoint> placeWith(const LaserScan& scan, PoseAt&& pose_at, int* no_pose) {
  std::vector<ScanPoint> out(scan.readings.size());
  int missing = 0;
  CachedRotation mount_rot, robot_rot;
  thread_local UnitVectors unit;  // a memo only: the result depends on the arguments alone
  for (size_t i = 0; i < scan.readings.size(); ++i) {
    const LaserReading& r = scan.readings[i];
    if (!r.valid) continue;
    const auto robot = pose_at(r.utime);
    if (!robot) {
      ++missing;
      continue;
    }
    const Vec2 local = mount_rot.transform(scan.mount, r.range * unit.at(i, r.angle));
    out[i] = {robot_rot.transform(*robot, local), r.range, true};
  }
  if (no_pose) *no_pose = missing;
  return out;
}
}  // namespace

std::vector<ScanPoint> placeReadings(const LaserScan& scan, const PoseLookup& pose_at, int* no_pose) {
  return placeWith(scan, pose_at, no_pose);
}

std::vector<ScanPoint> placeReadings(const LaserScan& scan, const PoseHistory& poses, int* no_pose) {
  // As placeWith, with the robot's rotation from the cursor (angle addition while it turns).
  std::vector<ScanPoint> out(scan.readings.size());
  int missing = 0;
  CachedRotation mount_rot;
  thread_local UnitVectors unit;  // a memo only: the result depends on the arguments alone
  PoseHistory::Cursor cursor(poses);
  for (size_t i = 0; i < scan.readings.size(); ++i) {
    const LaserReading& r = scan.readings[i];
    if (!r.valid) continue;
    double c = 1, s = 0;
    const auto robot = cursor.atRotated(r.utime, c, s);
    if (!robot) {
      ++missing;
      continue;
    }
    const Vec2 l = mount_rot.transform(scan.mount, r.range * unit.at(i, r.angle));
    out[i] = {Vec2(robot->x + c * l.x() - s * l.y(), robot->y + s * l.x() + c * l.y()), r.range, true};
  }
  if (no_pose) *no_pose = missing;
  return out;
}

namespace {
// std::sqrt(d2) > t, decided on d2 against t * t where that is safe. sqrt is correctly rounded, so
// outside a relative band of 2^-48 around t * t (both roundings are within 2^-52 of it) the
// squares decide as the roots would; inside it, and for NaN, the root itself.
inline bool rootGreater(double d2, double t) {
  if (!(t > 1e-150 && t < 1e150)) return std::sqrt(d2) > t;  // (t * t neither underflows nor overflows)
  const double t2 = t * t;
  if (d2 > t2 * (1.0 + 0x1p-48)) return true;
  if (d2 < t2 * (1.0 - 0x1p-48)) return false;
  return std::sqrt(d2) > t;
}

// A range jump: the threshold grows with range because neighbouring rays diverge.
bool isJump(const ScanPoint& a, const ScanPoint& b, const RadarMapConfig& cfg) {
  // (a.p - b.p).norm() > threshold
  return rootGreater((a.p - b.p).squaredNorm(), cfg.jump_abs + cfg.jump_rel * std::min(a.range, b.range));
}
}  // namespace

std::vector<Cluster> splitClusters(const std::vector<ScanPoint>& points, bool full_circle,
                                   const RadarMapConfig& cfg) {
  const size_t n = points.size();
  std::vector<Cluster> clusters;
  if (n == 0) return clusters;
  // breakBefore(i): point i cannot continue the cluster of point i-1.
  auto breakBefore = [&](size_t i) {
    if (i == 0 && !full_circle) return true;
    const ScanPoint& prev = points[i == 0 ? n - 1 : i - 1];
    const ScanPoint& cur = points[i];
    return !prev.valid || !cur.valid || isJump(prev, cur, cfg);
  };
  // Start at a break so that a cluster spanning the end of a full circle stays whole.
  std::optional<size_t> start;
  for (size_t i = 0; i < n && !start; ++i)
    if (breakBefore(i)) start = i;
  if (!start) {  // a full circle without a single break
    Cluster all;
    all.points.reserve(n);
    for (const ScanPoint& p : points) all.points.push_back(p.p);
    all.closed = true;
    clusters.push_back(std::move(all));
    return clusters;
  }
  // Each cluster's points are gathered in one buffer and copied out once, at their number.
  std::vector<geom::Vec2> cur;
  cur.reserve(n);
  const auto close = [&] {
    if (cur.empty()) return;
    clusters.emplace_back();
    clusters.back().points.assign(cur.begin(), cur.end());
    cur.clear();
  };
  for (size_t k = 0, i = *start; k < n; ++k, i = i + 1 == n ? 0 : i + 1) {  // i = (start + k) % n
    if (k > 0 && breakBefore(i)) close();
    if (points[i].valid) cur.push_back(points[i].p);
  }
  close();
  return clusters;
}

namespace {
// geom::distance(chord, p) for many points p: the chord's direction and squared length once
// (the same operations as closestPoint, so the same values).
class ChordDistance {
 public:
  explicit ChordDistance(const geom::Segment& s) : a_(s.a), e_(s.b - s.a), l2_(e_.squaredNorm()) {}
  // The square of the distance (norm() is the root of squaredNorm()).
  double squared(const Vec2& p) const {
    if (l2_ <= 0.0) return (a_ - p).squaredNorm();
    const double u = std::clamp((p - a_).dot(e_) / l2_, 0.0, 1.0);
    const Vec2 closest = a_ + u * e_;
    return (closest - p).squaredNorm();
  }

 private:
  Vec2 a_, e_;
  double l2_;
};

// sqrt(d2) > sqrt(m2) for d2 > m2 >= 0: on the squares unless they are within 2^-48 (then both
// roots may round to the same double).
inline bool rootOfLarger(double d2, double m2) {
  return d2 > m2 * (1.0 + 0x1p-48) || std::sqrt(d2) > std::sqrt(m2);
}

void splitRecursive(const std::vector<Vec2>& pts, size_t i, size_t j, double threshold,
                    std::vector<IndexRange>& out) {
  // The first point farthest from the chord: a point takes over only if its distance (the root
  // of its square) is larger, so ties keep the first. m2: the leader's square, -1 for none.
  double m2 = -1;
  size_t kmax = i;
  const ChordDistance distance(geom::Segment{pts[i], pts[j]});
  for (size_t k = i + 1; k < j; ++k) {
    const double d2 = distance.squared(pts[k]);
    if (d2 > m2 && (m2 < 0 || rootOfLarger(d2, m2))) {  // (NaN never takes over)
      m2 = d2;
      kmax = k;
    }
  }
  const double dmax = m2 < 0 ? -1.0 : std::sqrt(m2);
  if (dmax < threshold) {
    out.push_back({i, j});
    return;
  }
  splitRecursive(pts, i, kmax, threshold, out);
  splitRecursive(pts, kmax, j, threshold, out);
}
}  // namespace

std::vector<IndexRange> iterativeEndPointFit(const std::vector<Vec2>& points, IndexRange r,
                                             double threshold) {
  std::vector<IndexRange> out;
  if (points.empty() || r.last >= points.size() || r.first > r.last) return out;
  splitRecursive(points, r.first, r.last, threshold, out);
  return out;
}

RmSegment fitLine(const std::vector<Vec2>& points, IndexRange r) {
  const double n = static_cast<double>(r.size());
  Vec2 c = Vec2::Zero();
  for (size_t k = r.first; k <= r.last; ++k) c += points[k];
  c /= n;
  double sxx = 0, syy = 0, sxy = 0;
  for (size_t k = r.first; k <= r.last; ++k) {
    const Vec2 d = points[k] - c;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  // Principal axis of the scatter: minimises the sum of squared orthogonal distances.
  const double phi = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const Vec2 dir = geom::unitVector(phi);
  const Vec2 nrm(-dir.y(), dir.x());
  double ss = 0;
  for (size_t k = r.first; k <= r.last; ++k) {
    const double e = (points[k] - c).dot(nrm);
    ss += e * e;
  }
  RmSegment s;
  s.seg = {c + dir * (points[r.first] - c).dot(dir), c + dir * (points[r.last] - c).dot(dir)};
  s.npoints = static_cast<int>(r.size());
  s.rms = std::sqrt(ss / n);
  return s;
}

void joinCorner(RmSegment& a, RmSegment& b, double max_shift) {
  const Vec2 da = a.seg.b - a.seg.a, db = b.seg.b - b.seg.a;
  const double denom = da.x() * db.y() - da.y() * db.x();
  // Below ~10 deg between the lines the intersection is ill-conditioned (and no real corner).
  if (std::abs(denom) < std::sin(geom::deg2rad(10.0)) * da.norm() * db.norm()) return;
  const Vec2 w = b.seg.a - a.seg.a;
  const Vec2 x = a.seg.a + da * ((w.x() * db.y() - w.y() * db.x()) / denom);
  if ((x - a.seg.b).norm() > max_shift || (x - b.seg.a).norm() > max_shift) return;
  a.seg.b = x;
  b.seg.a = x;
}

std::vector<RmSegment> clusterSegments(const Cluster& cluster, const RadarMapConfig& cfg) {
  std::vector<RmSegment> out;
  const size_t min_points = static_cast<size_t>(std::max(2, cfg.min_points));
  if (cluster.points.size() < min_points) return out;
  // An open cluster is fitted in place; a closed one is first cut at a breakpoint of a first
  // pass (a corner) and closed there, in a copy.
  std::vector<Vec2> loop;
  if (cluster.closed) {
    loop = cluster.points;
    const auto first = iterativeEndPointFit(loop, {0, loop.size() - 1}, cfg.split_threshold);
    const size_t corner = first.size() > 1 ? first.front().last : 0;
    std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(corner), loop.end());
    loop.push_back(loop.front());
  }
  const std::vector<Vec2>& pts = cluster.closed ? loop : cluster.points;
  for (const IndexRange& r : iterativeEndPointFit(pts, {0, pts.size() - 1}, cfg.split_threshold)) {
    if (r.size() < min_points) continue;
    RmSegment s = fitLine(pts, r);
    if (s.seg.length() < cfg.min_length) continue;
    if (!out.empty()) joinCorner(out.back(), s, cfg.jump_abs);
    out.push_back(s);
  }
  if (cluster.closed && out.size() > 2) joinCorner(out.back(), out.front(), cfg.jump_abs);
  return out;
}

bool LaserView::covers(const geom::Vec2& p) const {
  if (full_circle) return true;
  const geom::Vec2 d = p - sensor.position();
  // The bearing relative to the first reading, in [0, 2 pi): inside when not beyond the last one.
  double a = std::atan2(d.y(), d.x()) - sensor.theta - angle_min;
  a -= 2 * geom::kPi * std::floor(a / (2 * geom::kPi));
  return a <= angle_max - angle_min;
}

LaserView laserViewOf(const LaserScan& scan, const geom::Pose2& robot) {
  LaserView v;
  v.full_circle = scan.full_circle || scan.readings.empty();
  v.sensor = robot.compose(scan.mount);
  if (!scan.readings.empty()) {
    v.angle_min = scan.readings.front().angle;
    v.angle_max = scan.readings.back().angle;
  }
  return v;
}

namespace {
RadarMap radarMapOf(const LaserScan& scan, const std::vector<ScanPoint>& points, std::optional<geom::Pose2> pose,
                    const RadarMapConfig& cfg) {
  RadarMap rm;
  rm.source_utime = scan.readings.empty() ? scan.utime : scan.readings.front().utime;
  rm.utime = scan.readings.empty() ? scan.utime : scan.readings.back().utime;
  rm.robot_pose = pose.value_or(geom::Pose2{});
  rm.view = laserViewOf(scan, rm.robot_pose);
  for (Cluster& cl : splitClusters(points, scan.full_circle, cfg)) {
    const std::vector<RmSegment> segs = clusterSegments(cl, cfg);
    rm.segments.insert(rm.segments.end(), segs.begin(), segs.end());
    if (segs.empty() && cfg.pole_min_points > 0 && cl.points.size() >= static_cast<size_t>(cfg.pole_min_points))
      rm.pole_candidates.push_back(std::move(cl.points));  // the cluster is not needed after this
  }
  return rm;
}
int64_t lastReadingTime(const LaserScan& scan) {
  return scan.readings.empty() ? scan.utime : scan.readings.back().utime;
}
}  // namespace

RadarMap extractRadarMap(const LaserScan& scan, const PoseLookup& pose_at, const RadarMapConfig& cfg,
                         int* no_pose) {
  const auto pose = pose_at(lastReadingTime(scan));
  return radarMapOf(scan, placeReadings(scan, pose_at, no_pose), pose, cfg);
}

RadarMap extractRadarMap(const LaserScan& scan, const PoseHistory& poses, const RadarMapConfig& cfg, int* no_pose) {
  const auto pose = poses.at(lastReadingTime(scan));
  return radarMapOf(scan, placeReadings(scan, poses, no_pose), pose, cfg);
}

RadarMap radarMapFromPlaced(const LaserScan& scan, const std::vector<ScanPoint>& placed, const PoseHistory& poses,
                            const RadarMapConfig& cfg) {
  return radarMapOf(scan, placed, poses.at(lastReadingTime(scan)), cfg);
}

}  // namespace lasonic::complement
