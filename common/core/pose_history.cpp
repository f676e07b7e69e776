#include "core/pose_history.hpp"

#include <algorithm>
#include <cstring>

namespace lasonic {

PoseHistory::AddResult PoseHistory::add(int64_t utime, const geom::Pose2& pose) {
  if (!empty()) {
    if (utime < poses_.back().utime) return AddResult::WentBackwards;
    if (utime == poses_.back().utime) return AddResult::Duplicate;
  }
  poses_.push_back({utime, pose});
  while (poses_.size() - first_ > 2 && poses_[first_].utime < utime - max_age_us_) ++first_;
  if (first_ >= 64 && first_ * 2 >= poses_.size()) {
    poses_.erase(poses_.begin(), poses_.begin() + static_cast<std::ptrdiff_t>(first_));
    first_ = 0;
  }
  return AddResult::Ok;
}

bool PoseHistory::sameAs(const PoseHistory& other) const {
  static_assert(sizeof(Entry) == sizeof(int64_t) + 3 * sizeof(double), "Entry without padding: compared as bytes");
  const size_t n = poses_.size() - first_;
  return max_age_us_ == other.max_age_us_ && max_extrapolation_us_ == other.max_extrapolation_us_ &&
         n == other.poses_.size() - other.first_ &&
         (n == 0 || std::memcmp(poses_.data() + first_, other.poses_.data() + other.first_, n * sizeof(Entry)) == 0);
}

std::optional<geom::Pose2> PoseHistory::newest() const {
  if (empty()) return std::nullopt;
  return poses_.back().pose;
}

std::optional<geom::Pose2> PoseHistory::at(int64_t utime) const {
  if (empty()) return std::nullopt;
  const Entry& front = poses_[first_];
  if (utime >= poses_.back().utime) {
    const Entry& b = poses_.back();
    if (utime - b.utime > max_extrapolation_us_) return std::nullopt;
    // On at the velocity of the last interval: a reading taken after the newest odometry (which
    // comes only every 20-100 ms) is placed where the robot went on to, not where it was. Over
    // one period a robot's velocity hardly changes (1 m/s^2 for 0.1 s: 5 mm), while holding the
    // pose is off by all it moved (4 cm at 0.4 m/s, 0.08 rad turning at 0.8 rad/s). An interval
    // longer than the limit (odometry that paused) gives no velocity: held.
    if (utime > b.utime && poses_.size() - first_ >= 2) {
      const Entry& a = poses_[poses_.size() - 2];
      const int64_t dt = b.utime - a.utime;
      if (dt > 0 && dt <= max_extrapolation_us_) {
        const double s = static_cast<double>(utime - b.utime) / static_cast<double>(dt);
        return geom::Pose2{b.pose.x + s * (b.pose.x - a.pose.x), b.pose.y + s * (b.pose.y - a.pose.y),
                           geom::normalizeAngle(b.pose.theta + s * geom::angleDiff(b.pose.theta, a.pose.theta))};
      }
    }
    return b.pose;
  }
  if (utime <= front.utime) {
    if (front.utime - utime > max_extrapolation_us_) return std::nullopt;
    return front.pose;
  }
  // b = the first entry not older than utime (front < utime < back: first_ < i < size). Queries
  // come mostly in time order (a scan's readings), so the previous query's interval and the next
  // one are tried before the binary search; any of the three finds the same entry.
  const auto holds = [&](size_t i) {
    return i > first_ && i < poses_.size() && poses_[i - 1].utime < utime && utime <= poses_[i].utime;
  };
  size_t i = hint_;
  if (!holds(i) && !holds(++i))
    i = static_cast<size_t>(std::lower_bound(poses_.begin() + static_cast<std::ptrdiff_t>(first_), poses_.end(), utime,
                                             [](const Entry& e, int64_t t) { return e.utime < t; }) -
                            poses_.begin());
  hint_ = i;
  const Entry& b = poses_[i];
  const Entry& a = poses_[i - 1];
  const double s = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
  return geom::interpolate(a.pose, b.pose, s);
}

bool PoseHistory::Cursor::enter(int64_t utime) {
  const std::vector<Entry>& e = h_.poses_;
  if (h_.empty() || utime <= e[h_.first_].utime || utime >= e.back().utime) return false;
  // As at(): b = the first entry not older than utime, a the one before.
  const auto it = std::lower_bound(e.begin() + static_cast<std::ptrdiff_t>(h_.first_), e.end(), utime,
                                   [](const Entry& x, int64_t t) { return x.utime < t; });
  const Entry& b = *it;
  const Entry& a = *(it - 1);
  lo_ = a.utime;
  // at() returns the newest pose itself at its time, not the interpolation at s = 1.
  hi_ = it + 1 == e.end() ? b.utime - 1 : b.utime;
  a_ = a.pose;
  dx_ = b.pose.x - a.pose.x;
  dy_ = b.pose.y - a.pose.y;
  dtheta_ = geom::angleDiff(b.pose.theta, a.pose.theta);
  den_ = static_cast<double>(b.utime - a.utime);
  small_turn_ = std::abs(dtheta_) <= 0.1;
  if (small_turn_) ca_ = std::cos(a.pose.theta), sa_ = std::sin(a.pose.theta);
  return true;
}

}  // namespace lasonic
