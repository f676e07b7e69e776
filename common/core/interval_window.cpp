#include "core/interval_window.hpp"

#include <algorithm>

namespace lasonic {

bool IntervalWindow::stamp(int64_t utime) {
  const bool keep = have_last_ && utime > last_;
  if (keep) {
    const int64_t d = utime - last_;
    if (intervals_.size() < capacity_) intervals_.push_back(d);
    else intervals_[next_] = d;
    next_ = (next_ + 1) % capacity_;
  }
  if (!have_last_ || utime > last_) last_ = utime;
  have_last_ = true;
  return keep;
}

int64_t IntervalWindow::median() const {
  if (intervals_.empty()) return 0;
  scratch_.assign(intervals_.begin(), intervals_.end());
  const auto mid = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
  std::nth_element(scratch_.begin(), mid, scratch_.end());
  return *mid;
}

void ScanPeriod::scanned(int64_t utime) {
  if (intervals_.stamp(utime) && intervals_.size() >= kMinIntervals) period_us_ = intervals_.median();
}

}  // namespace lasonic
