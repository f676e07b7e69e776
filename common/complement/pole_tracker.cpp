#include "complement/pole_tracker.hpp"

#include <algorithm>
#include <cmath>
#include "core/utime.hpp"

namespace lasonic::complement {

std::vector<geom::Vec2> PoleTracker::update(int64_t utime, const geom::Vec2& robot,
                                            const std::vector<std::vector<geom::Vec2>>& candidates) {
  std::vector<geom::Vec2> poles;
  if (cfg_.min_points <= 0) return poles;
  if (!history_.empty() && utime < history_.back().utime) reset();
  const auto memory_us = secondsToUs(cfg_.memory_s);
  while (!history_.empty() && utime - history_.front().utime > memory_us) history_.pop_front();
  found_.erase(std::remove_if(found_.begin(), found_.end(),
                              [&](const Found& f) { return utime - f.utime > memory_us; }),
               found_.end());
  std::vector<Found> found_now;
  const double match2 = cfg_.match * cfg_.match, baseline2 = cfg_.baseline * cfg_.baseline;
  Seen now{utime, robot, {}};
  // (Each scan's centroids are kept sorted by x, so a match is looked up in the 2 * match wide
  // band around a candidate's x: a scan of a thousand one-point clusters -- rain, garbage --
  // stays cheap.)
  for (const auto& pts : candidates) {
    if (pts.empty() || pts.size() < static_cast<size_t>(cfg_.min_points)) continue;
    geom::Vec2 c = geom::Vec2::Zero();
    for (const geom::Vec2& p : pts) c += p;
    c /= static_cast<double>(pts.size());
    if (!std::isfinite(c.x()) || !std::isfinite(c.y())) continue;
    now.centroids.push_back(c);
    // Motion along the line of sight moves neither a pole nor a glint (the foot of the
    // perpendicular on a pane the robot drives at): only motion across it tells them apart.
    const geom::Vec2 sight = c - robot;
    const double sight2 = sight.squaredNorm();
    bool pole = false;
    for (const Seen& s : history_) {
      const geom::Vec2 m = robot - s.robot;
      const double across = m.x() * sight.y() - m.y() * sight.x();  // |m x sight| = |m_perp| |sight|
      if (!(across * across >= baseline2 * sight2)) continue;
      const auto from = std::lower_bound(s.centroids.begin(), s.centroids.end(), c.x() - cfg_.match,
                                         [](const geom::Vec2& e, double x) { return e.x() < x; });
      for (auto e = from; e != s.centroids.end() && e->x() <= c.x() + cfg_.match; ++e)
        if ((*e - c).squaredNorm() <= match2) {
          pole = true;
          break;
        }
      if (pole) break;
    }
    if (pole && cfg_.keep_confirmed) found_now.push_back({c, utime});
    // Found before and still there (within match of where it was found, not of where it was last
    // seen: a leg creeping a little per scan does not drag the pole along): a pole, whatever the
    // robot did since.
    if (!pole && cfg_.keep_confirmed) {
      const auto from = std::lower_bound(found_.begin(), found_.end(), c.x() - cfg_.match,
                                         [](const Found& e, double x) { return e.centroid.x() < x; });
      for (auto e = from; e != found_.end() && e->centroid.x() <= c.x() + cfg_.match; ++e)
        if ((e->centroid - c).squaredNorm() <= match2) {
          pole = true;
          found_now.push_back({e->centroid, utime});
          break;
        }
    }
    if (pole) poles.insert(poles.end(), pts.begin(), pts.end());
  }
  // The poles found now, and those found before that this scan did not see (kept for memory_s);
  // looked up in the band around each one's x, as above.
  if (cfg_.keep_confirmed) {
    const auto by_x = [](const Found& a, const Found& b) { return a.centroid.x() < b.centroid.x(); };
    std::sort(found_now.begin(), found_now.end(), by_x);
    const size_t now_n = found_now.size();
    for (const Found& f : found_) {
      const auto first = found_now.begin(), last = found_now.begin() + static_cast<std::ptrdiff_t>(now_n);
      auto e = std::lower_bound(first, last, f.centroid.x() - cfg_.match,
                                [](const Found& a, double x) { return a.centroid.x() < x; });
      bool seen = false;
      for (; !seen && e != last && e->centroid.x() <= f.centroid.x() + cfg_.match; ++e)
        seen = (e->centroid - f.centroid).squaredNorm() <= match2;
      if (!seen) found_now.push_back(f);
    }
    std::sort(found_now.begin(), found_now.end(), by_x);
    found_ = std::move(found_now);
  }
  std::sort(now.centroids.begin(), now.centroids.end(),
            [](const geom::Vec2& a, const geom::Vec2& b) { return a.x() < b.x(); });
  history_.push_back(std::move(now));
  return poles;
}

}  // namespace lasonic::complement
