#pragma once
// ReplayMeter: progress and speed of an offline run over a log, for the user (stderr), never for
// the output: what it prints depends on the wall clock, what the run writes must not.
//
// Progress: a line when another tenth of the log has been read, at most one per second of wall
// time (a short log prints none). Summary: the log's duration (first to last event time), the
// wall time, their ratio (the real-time factor) and input events per second.
#include <chrono>
#include <cstdint>
#include <string>

namespace lasonic {

class ReplayMeter {
 public:
  using Clock = std::chrono::steady_clock;
  explicit ReplayMeter(int64_t total_bytes, Clock::time_point start = Clock::now())
      : total_bytes_(total_bytes), start_(start), last_line_(start) {}

  // After each input event: its log time and the bytes read so far. Returns a progress line
  // when one is due, else an empty string.
  std::string update(int64_t event_utime, int64_t bytes_read);
  std::string update(int64_t event_utime, int64_t bytes_read, Clock::time_point now);

  // The summary line (call at the end).
  std::string summary(Clock::time_point now = Clock::now()) const;

  int64_t events() const { return events_; }
  // Log time replayed: the span of event times, summed over the passes of a looped log (a jump
  // back of more than TimeReset::kJumpUs starts a new pass, as for the stages).
  double logSeconds() const {
    return events_ > 0 ? static_cast<double>(passes_us_ + last_utime_ - first_utime_) * 1e-6 : 0.0;
  }
  static double realTimeFactor(double log_s, double wall_s) { return wall_s > 0 ? log_s / wall_s : 0.0; }

 private:
  void note(int64_t event_utime);
  bool tenthDue(int64_t bytes_read) const;
  std::string line(int64_t bytes_read, Clock::time_point now);  // the progress line if a second has passed

  int64_t total_bytes_;
  Clock::time_point start_, last_line_;
  int64_t events_ = 0, first_utime_ = 0, last_utime_ = 0;  // (of this pass)
  int64_t passes_us_ = 0;                                  // the spans of the passes before it
  int next_tenth_ = 1;
};

}  // namespace lasonic
