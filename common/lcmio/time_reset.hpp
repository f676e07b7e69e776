#pragma once
// TimeReset: tells a restarted clock from a late message. Processes compute from message time;
// when the time on an input channel jumps back by more than kJumpUs from that channel's newest,
// the source's clock has restarted (a simulator or driver restarted, a log played in a loop): the
// process starts afresh from that message on, as after a start, instead of refusing every
// message of the new timeline as "older than the newest" for ever. Per channel, because one
// input may legitimately run ahead of another (odometry published ahead of a slow sensor); after
// a reset every channel starts afresh, so one restart is one reset. Smaller steps back are late
// or reordered messages: the stages drop them (rejected.*_backwards).
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

namespace lasonic {

// [us] Message times outside [0, kMaxUtime] are malformed (kMaxUtime: the year 5100 in
// microseconds since 1970; differences of two valid times never overflow int64).
inline constexpr int64_t kMaxUtime = 100'000'000'000'000'000;
inline bool plausibleUtime(int64_t utime) { return utime >= 0 && utime <= kMaxUtime; }

class TimeReset {
 public:
  // 1 s: well above any reordering or latency between sensors (the sector map calls data stale
  // after 0.5 s), well below the time a restarted process takes to come back.
  static constexpr int64_t kJumpUs = 1'000'000;

  // True when utime lies more than kJumpUs before the newest time seen on `channel`: the caller
  // resets. Either way utime is remembered (after a reset it is the only time known).
  bool jumpedBack(std::string_view channel, int64_t utime) {
    auto it = newest_.find(channel);
    const bool jumped = it != newest_.end() && utime < it->second - kJumpUs;
    if (jumped) {
      newest_.clear();
      it = newest_.end();
    }
    if (it == newest_.end()) it = newest_.emplace(std::string(channel), utime).first;
    if (utime > it->second) it->second = utime;
    return jumped;
  }

 private:
  // (std::less<>: looked up by the channel's name as given, without a string made per message)
  std::map<std::string, int64_t, std::less<>> newest_;
};

}  // namespace lasonic
