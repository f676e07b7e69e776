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

#include "lcmio/time_reset.hpp"

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
  // Log time replayed: the span of event times, summed over the passes of a looped log
  // (PassSpan: a jump back of more than TimeReset::kJumpUs starts a new pass, as for the stages).
  double logSeconds() const { return span_.seconds(); }
  static double realTimeFactor(double log_s, double wall_s) { return wall_s > 0 ? log_s / wall_s : 0.0; }

 private:
  void note(int64_t event_utime);
  bool tenthDue(int64_t bytes_read) const;
  std::string line(int64_t bytes_read, Clock::time_point now);  // the progress line if a second has passed

  int64_t total_bytes_;
  Clock::time_point start_, last_line_;
  int64_t events_ = 0;
  PassSpan span_;
  int next_tenth_ = 1;
};

}  // namespace lasonic
