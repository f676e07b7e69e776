#include "core/stamp_agreement.hpp"

#include <algorithm>
#include <cstdio>

namespace lasonic {

void StampAgreement::noteOdometry(int64_t utime) {
  if (last_odometry_ && utime > *last_odometry_) max_interval_us_ = std::max(max_interval_us_, utime - *last_odometry_);
  last_odometry_ = utime;
  if (!interval_window_start_ || utime < *interval_window_start_) interval_window_start_ = utime;
  if (utime - *interval_window_start_ >= p_.window_us) {
    prev_max_interval_us_ = max_interval_us_;
    max_interval_us_ = 0;
    interval_window_start_ = utime;
  }
}

std::optional<StampAgreement::Finding> StampAgreement::check(int64_t utime, int64_t odometry_utime, int64_t listening_us) {
  const int64_t lag = odometry_utime - utime;
  const int64_t period = std::max(max_interval_us_, prev_max_interval_us_);
  std::optional<Finding> out;
  // (Until two odometry messages give its period, nothing is ahead of it.)
  if (period > 0 && -lag > period + p_.margin_us &&
      (!last_ahead_report_ || odometry_utime - *last_ahead_report_ >= p_.window_us || odometry_utime < *last_ahead_report_)) {
    last_ahead_report_ = odometry_utime;
    out = Finding{true, -lag, period};
  }
  // The window's smallest lag beyond the listening time; a window ends by the odometry's time
  // (and starts afresh if that went back).
  const int64_t late = lag - std::max<int64_t>(0, listening_us);
  if (!window_start_ || odometry_utime < *window_start_) {
    window_start_ = odometry_utime;
    min_lag_us_ = late;
    data_ = 1;
    return out;
  }
  min_lag_us_ = std::min(min_lag_us_, late);
  ++data_;
  if (odometry_utime - *window_start_ >= p_.window_us) {
    if (min_lag_us_ > p_.margin_us && data_ >= p_.min_data && !out) out = Finding{false, min_lag_us_, period};
    window_start_ = odometry_utime;
    min_lag_us_ = late;
    data_ = 1;
  }
  return out;
}

std::string StampAgreement::describe(const Finding& f, const char* channel) const {
  char buf[400];
  const double ms = static_cast<double>(f.offset_us) * 1e-3;
  if (f.ahead)
    std::snprintf(buf, sizeof buf,
                  "%s stamped %.0f ms later than the newest ODOMETRY (which comes every %.0f ms): its computer's "
                  "clock runs ahead of the odometry's, or the odometry arrives that late or stalls; its readings are "
                  "placed with poses extrapolated past the newest odometry, of the wrong time if the clocks disagree "
                  "(README \"Clocks\")",
                  channel, ms, static_cast<double>(f.odometry_period_us) * 1e-3);
  else
    std::snprintf(buf, sizeof buf,
                  "%s at least %.0f ms older than the newest ODOMETRY for %.0f s: its computer's clock runs behind "
                  "the odometry's, and its readings are placed with poses of the wrong time, or its data arrive that "
                  "late (README \"Clocks\")",
                  channel, ms, static_cast<double>(p_.window_us) * 1e-6);
  return buf;
}

}  // namespace lasonic
