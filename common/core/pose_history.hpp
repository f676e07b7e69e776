#pragma once
// A short history of timestamped poses (e.g. ODOMETRY), interpolated at any time inside it,
// so each laser reading and each sonar firing is placed with the pose at its own time.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

class PoseHistory {
 public:
  // max_age_us: entries older than (newest - max_age_us) are dropped.
  // max_extrapolation_us: how far beyond the newest (or before the oldest) pose a query may
  // reach; the pose is then held constant (the robot cannot have moved far).
  explicit PoseHistory(int64_t max_age_us = 5'000'000, int64_t max_extrapolation_us = 200'000)
      : max_age_us_(max_age_us), max_extrapolation_us_(max_extrapolation_us) {}

  enum class AddResult { Ok, Duplicate, WentBackwards };
  // Poses must come in time order; an older one is refused (counted by the caller), an equal
  // timestamp replaces nothing.
  AddResult add(int64_t utime, const geom::Pose2& pose);

  // Pose at utime, or nullopt if the history is empty or utime is too far outside it. Keeps a
  // search hint: not for concurrent callers on one history (each stage owns its own).
  std::optional<geom::Pose2> at(int64_t utime) const;

  // Poses at many times, mostly increasing (a laser scan's readings): exactly the values of
  // at(), with the odometry interval that holds a time and its differences found once per
  // interval instead of once per query. Valid while the history is not changed.
  class Cursor {
   public:
    explicit Cursor(const PoseHistory& h) : h_(h) {}
    std::optional<geom::Pose2> at(int64_t utime) {
      if (!(lo_ < utime && utime <= hi_) && !enter(utime)) return h_.at(utime);
      // geom::interpolate(a, b, s) with b - a taken once: the same operations, the same values.
      const double s = static_cast<double>(utime - lo_) / den_;
      return geom::Pose2{a_.x + s * dx_, a_.y + s * dy_, geom::normalizeAngle(a_.theta + s * dtheta_)};
    }

   private:
    bool enter(int64_t utime);  // the interval holding utime, if at() interpolates there
    const PoseHistory& h_;
    int64_t lo_ = 0, hi_ = -1;  // at(t) interpolates in this interval for lo_ < t <= hi_
    geom::Pose2 a_;
    double dx_ = 0, dy_ = 0, dtheta_ = 0, den_ = 1;
  };

  bool empty() const { return first_ == poses_.size(); }
  int64_t newestTime() const { return empty() ? 0 : poses_.back().utime; }
  std::optional<geom::Pose2> newest() const;
  void clear() {
    poses_.clear();
    first_ = 0;
  }

 private:
  struct Entry {
    int64_t utime;
    geom::Pose2 pose;
  };
  // The history is poses_[first_..]: dropping the oldest moves first_ on, and the dropped
  // entries are erased in bulk now and then (contiguous, unlike a deque: cheap to index).
  std::vector<Entry> poses_;
  size_t first_ = 0;
  mutable size_t hint_ = 0;  // index of the entry the previous at() interpolated towards
  int64_t max_age_us_, max_extrapolation_us_;
};

}  // namespace lasonic
