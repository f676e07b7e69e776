#include "eval/laser_seen.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "complement/messages.hpp"
#include "core/pose_msg.hpp"

namespace lasonic::eval {

namespace {

// The number of readings a scan message really carries (its arrays may disagree when malformed).
size_t readingsOf(const laser_scan_t& s) {
  if (s.nranges <= 0) return 0;
  return std::min({static_cast<size_t>(s.nranges), s.ranges.size(), s.flags.size(), s.offset_us.size()});
}
}  // namespace

LaserSeen::LaserSeen(const RunLog& log, double cell) : cell_(cell > 0 ? cell : 0.10), truth_(log.sim_states) {
  if (log.sim_states.empty()) {
    without_truth_ = static_cast<int64_t>(log.laser_scans.size());
    return;
  }
  std::map<std::pair<int64_t, int32_t>, const laser_truth_t*> truths;
  for (const auto& t : log.laser_truths) truths[{t.utime, t.seq}] = &t;
  for (const laser_scan_t& s : log.laser_scans) {
    const auto it = truths.find({s.utime, s.seq});
    const size_t n = readingsOf(s);
    if (it == truths.end() || it->second->obstacle.size() != static_cast<size_t>(s.nranges) || n == 0 ||
        !finitePose(s.mount) || !std::isfinite(s.angle_min) || !std::isfinite(s.angle_increment)) {
      ++without_truth_;
      continue;
    }
    const laser_truth_t& t = *it->second;
    Scan scan;
    scan.done = s.utime;
    // A reading whose time offset the pipeline rejects (outside the scan's sweep) was not seen:
    // it neither completes the scan later (the Radar Map's time leaves it out) nor is a point.
    const auto in_sweep = [&s](size_t i) { return complement::input_limits::offsetInSweep(s.offset_us[i]); };
    for (size_t i = 0; i < n; ++i)
      if (in_sweep(i)) scan.done = std::max<int64_t>(scan.done, s.utime + s.offset_us[i]);
    const geom::Pose2 mount = toPose(s.mount);
    // Sorted with their cells at hand, then kept compact (Point).
    struct Reading {
      int obstacle;
      int64_t cx, cy;
      geom::Vec2 p, world;
    };
    std::vector<Reading> readings;
    readings.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      const int obstacle = t.obstacle[i];
      const float r = s.ranges[i];
      if (s.flags[i] != laser_scan_t::FLAG_OK || obstacle == -1 || !std::isfinite(r) || r < 0 || !in_sweep(i)) continue;
      const int64_t when = s.utime + s.offset_us[i];
      const geom::Pose2 sensor = truth_.robotAt(when).compose(mount);
      const geom::Vec2 w =
          sensor.transform(r * geom::unitVector(s.angle_min + static_cast<double>(i) * s.angle_increment));
      geom::Vec2 p = w;
      if (obstacle <= -2) {
        const auto c = moverCentre(obstacle, when);
        if (!c) continue;  // a mover SIM_STATE does not know
        p -= *c;
      }
      readings.push_back({obstacle, cellOf(p.x()), cellOf(p.y()), p, w});
    }
    std::sort(readings.begin(), readings.end(), [](const Reading& a, const Reading& b) {
      return std::tie(a.obstacle, a.cx, a.cy) < std::tie(b.obstacle, b.cx, b.cy);
    });
    // Each scan is kept for the whole evaluation: exactly as much room as it needs.
    size_t movers = 0;
    while (movers < readings.size() && readings[movers].obstacle <= -2) ++movers;
    scan.points.reserve(readings.size());
    scan.mover_world.reserve(movers);
    for (const Reading& r : readings) scan.points.push_back({r.obstacle, r.p.x(), r.p.y()});
    for (size_t i = 0; i < movers; ++i) scan.mover_world.push_back(readings[i].world);
    scans_.push_back(std::move(scan));
  }
  // Live logs interleave processes: keep the scans in the order they were completed.
  std::stable_sort(scans_.begin(), scans_.end(), [](const Scan& a, const Scan& b) { return a.done < b.done; });
}

size_t LaserSeen::points() const {
  size_t n = 0;
  for (const Scan& s : scans_) n += s.points.size();
  return n;
}

int64_t LaserSeen::cellOf(double v) const {
  return static_cast<int64_t>(std::clamp(std::floor(v / cell_), -1e15, 1e15));
}

std::optional<geom::Vec2> LaserSeen::moverCentre(int obstacle, int64_t utime) const {
  const int id = -obstacle - 2;
  for (const sim::MoverPose& m : truth_.moversAt(utime))
    if (m.id == id) return m.position;
  return std::nullopt;
}

int LaserSeen::newestAt(int64_t utime) const {
  const auto it = std::upper_bound(scans_.begin(), scans_.end(), utime,
                                   [](int64_t t, const Scan& s) { return t < s.done; });
  return static_cast<int>(it - scans_.begin()) - 1;
}

int LaserSeen::completedAt(int64_t utime) const {
  const int i = newestAt(utime);
  return i >= 0 && scans_[static_cast<size_t>(i)].done == utime ? i : -1;
}

bool LaserSeen::saw(int scan, int obstacle, const geom::Vec2& p, double radius, int64_t utime) const {
  if (scan < 0 || static_cast<size_t>(scan) >= scans_.size() || obstacle == -1 || !(radius >= 0)) return false;
  geom::Vec2 q = p;
  if (obstacle <= -2) {
    const auto c = moverCentre(obstacle, utime);
    if (!c) return false;
    q -= *c;
  }
  if (!std::isfinite(q.x()) || !std::isfinite(q.y())) return false;
  const std::vector<Point>& pts = scans_[static_cast<size_t>(scan)].points;
  const int64_t k = static_cast<int64_t>(std::ceil(radius / cell_));
  const int64_t cx = cellOf(q.x()), cy = cellOf(q.y());
  const double r2 = radius * radius;
  const auto key_less = [this](const Point& a, const std::tuple<int, int64_t, int64_t>& b) {
    return std::make_tuple(a.obstacle, cellOf(a.x), cellOf(a.y)) < b;
  };
  for (int64_t x = cx - k; x <= cx + k; ++x) {
    // One run per cell column: (obstacle, x, cy - k) .. (obstacle, x, cy + k).
    auto it = std::lower_bound(pts.begin(), pts.end(), std::make_tuple(obstacle, x, cy - k), key_less);
    for (; it != pts.end() && it->obstacle == obstacle && cellOf(it->x) == x && cellOf(it->y) <= cy + k; ++it)
      if ((it->p() - q).squaredNorm() <= r2) return true;
  }
  return false;
}

std::optional<double> LaserSeen::nearestInSector(int scan, const geom::Sector& sec) const {
  if (scan < 0 || static_cast<size_t>(scan) >= scans_.size() || !(sec.radius >= 0)) return std::nullopt;
  // Inside: within the radius, and within half the opening of the axis (dot products: this runs
  // for every point of a scan, for every echo).
  const geom::Vec2 axis = geom::unitVector(sec.heading);
  const double cos_half = std::cos(0.5 * sec.opening), r2 = sec.radius * sec.radius;
  std::optional<double> best;
  const Scan& s = scans_[static_cast<size_t>(scan)];
  for (size_t i = 0; i < s.points.size(); ++i) {
    const geom::Vec2 d = s.world(i) - sec.apex;
    const double d2 = d.squaredNorm();
    if (d2 > r2 || (best && d2 >= *best * *best)) continue;
    const double r = std::sqrt(d2);
    if (r > 0 && d.dot(axis) < r * cos_half - 1e-12) continue;
    best = r;
  }
  return best;
}

}  // namespace lasonic::eval
