#pragma once
// StatusBoard: what a process reports about itself in PROCESS_STATUS — message counts and rates
// per channel, named counters, the error total and the newest error message, the newest message
// time. Errors are logged at most once per counter and second, so a flood of bad input cannot
// flood the log. No LCM here: Node feeds it and publishes what it builds.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

#include <lasonic/process_status_t.hpp>

namespace lasonic {

class StatusBoard {
 public:
  explicit StatusBoard(std::string process_name);

  void count(std::string_view counter, int64_t n = 1);
  int64_t counter(const std::string& name) const;
  // Counted under `counter` and in errors(), logged (rate-limited), kept as the last error.
  void reportError(const std::string& counter, const std::string& message);
  void noteMessageTime(int64_t utime);

  // Channel statistics. received() before decoding; decodeError() for one that did not decode.
  void declareInput(const std::string& channel) { in_[channel]; }
  void received(const std::string& channel) { ++in_[channel].messages; }
  void decodeError(const std::string& channel) { ++in_[channel].decode_errors; }
  void sent(const std::string& channel) { ++out_[channel].messages; }

  // The PROCESS_STATUS message now; rates are over the time since the previous snapshot.
  process_status_t snapshot();

  const std::string& name() const { return name_; }
  int64_t errors() const { return errors_; }
  const std::string& lastError() const { return last_error_; }
  // Every named counter (count() and reportError()), by name.
  const std::map<std::string, int64_t, std::less<>>& counters() const { return counters_; }

 private:
  struct ChannelStats {
    int64_t messages = 0;
    int64_t at_last_status = 0;
    int64_t decode_errors = 0;
  };
  std::string name_;
  std::map<std::string, ChannelStats> in_, out_;
  std::map<std::string, int64_t, std::less<>> counters_;  // (std::less<>: counted by name without a string made per count)
  int64_t errors_ = 0;
  std::string last_error_;
  int64_t last_msg_utime_ = 0;
  std::chrono::steady_clock::time_point start_, last_snapshot_;
  std::map<std::string, std::chrono::steady_clock::time_point> last_logged_;
};

// Heartbeat: due() once per period of the steady clock (liveness only, never message time).
class Heartbeat {
 public:
  explicit Heartbeat(std::chrono::milliseconds period = std::chrono::seconds(1))
      : period_(period), last_(std::chrono::steady_clock::now()) {}
  bool due() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < period_) return false;
    last_ = now;
    return true;
  }
  void reset() { last_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::milliseconds period_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace lasonic
