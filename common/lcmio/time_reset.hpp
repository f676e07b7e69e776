#pragma once
// TimeReset: tells a restarted clock from a late message. Processes compute from message time;
// when the time of an input jumps back by more than kJump, the source's clock has restarted (a
// simulator or driver restarted, a log played in a loop): the process starts afresh from that
// message on, as after a start, instead of refusing every message of the new timeline as "older
// than the newest" for ever. Smaller steps back are late or reordered messages: the stages drop
// them (rejected.*_backwards).
#include <cstdint>
#include <optional>

namespace lasonic {

class TimeReset {
 public:
  // 1 s: well above any reordering or latency between sensors (the sector map calls data stale
  // after 0.5 s), well below the time a restarted process takes to come back.
  static constexpr int64_t kJumpUs = 1'000'000;

  // True when utime lies more than kJumpUs before the newest time seen: the caller resets.
  // Either way utime is remembered (after a reset it is the newest).
  bool jumpedBack(int64_t utime) {
    const bool jumped = newest_ && utime < *newest_ - kJumpUs;
    if (jumped || !newest_ || utime > *newest_) newest_ = utime;
    return jumped;
  }

 private:
  std::optional<int64_t> newest_;
};

}  // namespace lasonic
