#pragma once
// The latest intervals between successive time stamps of one stream (a laser's scans, a sonar
// ring's firings), for timing a sensor from its own messages instead of a configured period.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lasonic {

class IntervalWindow {
 public:
  explicit IntervalWindow(size_t capacity) : capacity_(capacity > 0 ? capacity : 1) {}
  // A stamp: the interval since the latest stamp so far is kept (the oldest kept one dropped
  // once `capacity` are kept). The first stamp, and one not after the latest (a repeat, a clock
  // going backwards), keep nothing; the latest stays the newest stamp seen.
  // Returns whether an interval was kept.
  bool stamp(int64_t utime);
  size_t size() const { return intervals_.size(); }
  // The kept intervals, in no particular order [us].
  const std::vector<int64_t>& intervals() const { return intervals_; }
  // Their median (the upper one of an even count) [us]; 0 while none is kept.
  int64_t median() const;

 private:
  size_t capacity_;
  std::vector<int64_t> intervals_;  // ring buffer
  size_t next_ = 0;
  int64_t last_ = 0;
  bool have_last_ = false;
  mutable std::vector<int64_t> scratch_;  // (median)
};

// The laser's scan period, timed from its scans' start times (LASER_SCAN.utime), so that what is
// said in scan periods (the pilot's staleness and its movers' horizon, the navigator's wait for
// the next scan) holds for a 2 Hz scanner as for the 5 Hz one the seconds were set for: the median of
// the latest kIntervals intervals between successive scans (a lost scan makes one interval twice
// as long, a late one one long and the next short: neither is the median), once kMinIntervals
// are kept; an interval that is not positive is not kept.
class ScanPeriod {
 public:
  static constexpr size_t kIntervals = 15;
  static constexpr size_t kMinIntervals = 3;  // the median of three: one lost or late scan is passed over
  void scanned(int64_t utime);
  int64_t periodUs() const { return period_us_; }  // 0: not timed yet
  // n scan periods [s], but at least at_least_s (what a fast scanner's data need anyway: the
  // driver's and the network's latency); at_least_s while not timed, or with n 0.
  double scans(double n, double at_least_s) const {
    return n > 0 && period_us_ > 0 ? std::max(at_least_s, n * static_cast<double>(period_us_) / 1e6) : at_least_s;
  }

 private:
  IntervalWindow intervals_{kIntervals};
  int64_t period_us_ = 0;
};

}  // namespace lasonic
