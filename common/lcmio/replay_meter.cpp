#include "lcmio/replay_meter.hpp"

#include <algorithm>
#include <cstdio>

#include "lcmio/time_reset.hpp"

namespace lasonic {

namespace {
double seconds(ReplayMeter::Clock::duration d) { return std::chrono::duration<double>(d).count(); }
}  // namespace

void ReplayMeter::note(int64_t event_utime) {
  ++events_;
  span_.add(event_utime);  // a log need not be sorted: each pass spans its earliest to its latest
}

bool ReplayMeter::tenthDue(int64_t bytes_read) const {
  return total_bytes_ > 0 && bytes_read * 10 >= total_bytes_ * next_tenth_;
}

std::string ReplayMeter::update(int64_t event_utime, int64_t bytes_read) {
  note(event_utime);
  // The clock is read only when a line may be due, and then on every 64th event: reading it for
  // each event was a measurable part of a fast replay.
  if (!tenthDue(bytes_read) || events_ % 64 != 0) return {};
  return line(bytes_read, Clock::now());
}

std::string ReplayMeter::update(int64_t event_utime, int64_t bytes_read, Clock::time_point now) {
  note(event_utime);
  if (!tenthDue(bytes_read)) return {};
  return line(bytes_read, now);
}

std::string ReplayMeter::line(int64_t bytes_read, Clock::time_point now) {
  const int tenth = static_cast<int>(std::min<int64_t>(10, bytes_read * 10 / total_bytes_));
  if (seconds(now - last_line_) < 1.0) return {};
  next_tenth_ = tenth + 1;
  last_line_ = now;
  const double wall = seconds(now - start_);
  char line[160];
  std::snprintf(line, sizeof line, "%3d %% of the log: %.1f s of log time in %.1f s (%.0fx real time)", tenth * 10,
                logSeconds(), wall, realTimeFactor(logSeconds(), wall));
  return line;
}

std::string ReplayMeter::summary(Clock::time_point now) const {
  const double wall = seconds(now - start_);
  char line[200];
  std::snprintf(line, sizeof line,
                "%.1f s of log in %.3f s wall: real-time factor %.0f, %.0f input events/s", logSeconds(), wall,
                realTimeFactor(logSeconds(), wall), wall > 0 ? static_cast<double>(events_) / wall : 0.0);
  return line;
}

}  // namespace lasonic
