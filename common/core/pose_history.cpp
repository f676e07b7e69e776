#include "core/pose_history.hpp"

#include <algorithm>

namespace lasonic {

PoseHistory::AddResult PoseHistory::add(int64_t utime, const geom::Pose2& pose) {
  if (!poses_.empty()) {
    if (utime < poses_.back().utime) return AddResult::WentBackwards;
    if (utime == poses_.back().utime) return AddResult::Duplicate;
  }
  poses_.push_back({utime, pose});
  while (poses_.size() > 2 && poses_.front().utime < utime - max_age_us_) poses_.pop_front();
  return AddResult::Ok;
}

std::optional<geom::Pose2> PoseHistory::newest() const {
  if (poses_.empty()) return std::nullopt;
  return poses_.back().pose;
}

std::optional<geom::Pose2> PoseHistory::at(int64_t utime) const {
  if (poses_.empty()) return std::nullopt;
  if (utime >= poses_.back().utime) {
    if (utime - poses_.back().utime > max_extrapolation_us_) return std::nullopt;
    return poses_.back().pose;
  }
  if (utime <= poses_.front().utime) {
    if (poses_.front().utime - utime > max_extrapolation_us_) return std::nullopt;
    return poses_.front().pose;
  }
  // b = the first entry not older than utime (front < utime < back: 1 <= i < size). Queries come
  // mostly in time order (a scan's readings), so the previous query's interval and the next one
  // are tried before the binary search; any of the three finds the same entry.
  const auto holds = [&](size_t i) { return i >= 1 && i < poses_.size() && poses_[i - 1].utime < utime && utime <= poses_[i].utime; };
  size_t i = hint_;
  if (!holds(i) && !holds(++i))
    i = static_cast<size_t>(std::lower_bound(poses_.begin(), poses_.end(), utime,
                                             [](const Entry& e, int64_t t) { return e.utime < t; }) -
                            poses_.begin());
  hint_ = i;
  const Entry& b = poses_[i];
  const Entry& a = poses_[i - 1];
  const double s = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
  return geom::interpolate(a.pose, b.pose, s);
}

}  // namespace lasonic
