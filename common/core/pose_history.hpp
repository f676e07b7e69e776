#pragma once
// A short history of timestamped poses (e.g. ODOMETRY), interpolated at any time inside it,
// so each laser reading and each sonar firing is placed with the pose at its own time.
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

class PoseHistory {
 public:
  // max_age_us: entries older than (newest - max_age_us) are dropped.
  // max_extrapolation_us: how far beyond the newest (or before the oldest) pose a query may
  // reach. Beyond the newest the robot goes on at the velocity of the last interval (if that
  // interval is no longer than this limit; else, and before the oldest, the pose is held).
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

    // atRotated's series. sin: phi - phi^3/3! + ... - phi^11/11!, cos: 1 - phi^2/2! + ... - phi^10/10!.
    static constexpr double s3 = -1.0 / 6, s5 = 1.0 / 120, s7 = -1.0 / 5040, s9 = 1.0 / 362880, s11 = -1.0 / 39916800;
    static constexpr double c2 = -0.5, c4 = 1.0 / 24, c6 = -1.0 / 720, c8 = 1.0 / 40320, c10 = -1.0 / 3628800;

    // at(utime), and the cos and sin of its heading. Inside an interval that turns by at most
    // 0.1 rad (a robot at 5 rad/s with 50 Hz odometry) they come by angle addition from the
    // interval's first heading, whose cos and sin are taken once, and a Taylor series of the
    // turn since (the first omitted terms below 1e-20): within a few 1e-16 of std::cos and
    // std::sin of the heading, but not bit for bit. Elsewhere std::cos and std::sin.
    std::optional<geom::Pose2> atRotated(int64_t utime, double& c, double& s) {
      if (!(lo_ < utime && utime <= hi_) && !enter(utime)) {
        const auto p = h_.at(utime);
        if (p) c = std::cos(p->theta), s = std::sin(p->theta);
        return p;
      }
      const double f = static_cast<double>(utime - lo_) / den_;
      const double phi = f * dtheta_;
      const geom::Pose2 p{a_.x + f * dx_, a_.y + f * dy_, geom::normalizeAngle(a_.theta + phi)};
      if (!small_turn_) {
        c = std::cos(p.theta), s = std::sin(p.theta);
        return p;
      }
      const double q = phi * phi;
      const double sp = phi + phi * q * (s3 + q * (s5 + q * (s7 + q * (s9 + q * s11))));
      const double cp = 1.0 + q * (c2 + q * (c4 + q * (c6 + q * (c8 + q * c10))));
      c = ca_ * cp - sa_ * sp;
      s = sa_ * cp + ca_ * sp;
      return p;
    }

    // For loops that do atRotated's arithmetic for several times at once (placeReadings' vector
    // loops): true when atRotated(utime) interpolates in an interval by the series, entering the
    // interval holding utime if needed. Its values are then, with f = double(utime - lo()) / den()
    // and phi = f * dtheta(): x = ax() + f * dx(), y = ay() + f * dy(), and c and s from the series
    // of phi, ca() and sa() as atRotated computes them. The interval holds the times lo() < t <= hi().
    bool seriesAt(int64_t utime) {
      if (!(lo_ < utime && utime <= hi_) && !enter(utime)) return false;
      return small_turn_;
    }
    int64_t lo() const { return lo_; }
    int64_t hi() const { return hi_; }
    double ax() const { return a_.x; }
    double ay() const { return a_.y; }
    double dx() const { return dx_; }
    double dy() const { return dy_; }
    double dtheta() const { return dtheta_; }
    double den() const { return den_; }
    double ca() const { return ca_; }
    double sa() const { return sa_; }

   private:
    bool enter(int64_t utime);  // the interval holding utime, if at() interpolates there
    const PoseHistory& h_;
    int64_t lo_ = 0, hi_ = -1;  // at(t) interpolates in this interval for lo_ < t <= hi_
    geom::Pose2 a_;
    double dx_ = 0, dy_ = 0, dtheta_ = 0, den_ = 1;
    double ca_ = 1, sa_ = 0;   // cos and sin of a_.theta
    bool small_turn_ = false;  // |dtheta_| <= 0.1
  };

  // The same entries, bit for bit, and the same limits: at() (and a Cursor) give the same pose
  // for every time on both.
  bool sameAs(const PoseHistory& other) const;

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
