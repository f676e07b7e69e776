#pragma once
// TimeReset: tells a restarted clock from a late message. Processes compute from message time;
// when the time on an input channel jumps back by more than kJumpUs from that channel's newest,
// the source's clock has restarted (a simulator or driver restarted, a log played in a loop): the
// process starts afresh from that message on, as after a start, instead of refusing every
// message of the new timeline as "older than the newest" for ever. Per channel, because one
// input may legitimately run ahead of another (odometry published ahead of a slow sensor); after
// a reset every channel starts afresh, so one restart is one reset. Smaller steps back are late
// or reordered messages: the stages drop them (rejected.*_backwards).
//
// The other way (admit): a message more than kJumpUs AHEAD of the newest time of every input is
// held back until the next message on its channel shows which it was. Accepted at once, one
// stray time (a clock stepped on one computer, a stray publisher, a second log played into the
// same processes) would make the very next normal message look like a restart, and the stages
// would throw away everything they remember. If the channel goes on from the held time, its
// clock stepped forward: the held message is lost, the rest is used. If it comes back to the
// common time, the held one was a stray: reported, dropped, nothing reset.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
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

  // What admit() says of one message on `channel`.
  struct Admission {
    enum Kind { Ok, Restarted, HeldAhead } kind = Ok;
    int64_t reference = 0;               // HeldAhead: the newest input time it is ahead of
    std::optional<int64_t> stray;        // a time held on this channel that this message shows was a stray
    int64_t stray_reference = 0;         // the newest input time when that stray came
    std::optional<int64_t> stepped_from;  // the held time was confirmed: the newest input time it stepped from
  };
  // jumpedBack's restarts, and holding back a time far ahead of every input (see above): Ok and
  // Restarted are used (after a reset for Restarted), HeldAhead is dropped for now.
  Admission admit(std::string_view channel, int64_t utime) {
    Admission a;
    if (const auto h = held_.find(channel); h != held_.end()) {
      const Held held = h->second;
      held_.erase(h);
      if (utime >= held.utime) {
        a.stepped_from = held.reference;
        jumpedBack(channel, utime);  // (cannot jump back: later than every time kept)
        return a;
      }
      a.stray = held.utime;
      a.stray_reference = held.reference;
    }
    if (const auto latest = newestOfAll(); latest && utime > *latest + kJumpUs) {
      held_.insert_or_assign(std::string(channel), Held{utime, *latest});
      a.kind = Admission::HeldAhead;
      a.reference = *latest;
      return a;
    }
    if (jumpedBack(channel, utime)) {
      held_.clear();
      a.kind = Admission::Restarted;
    }
    return a;
  }

 private:
  std::optional<int64_t> newestOfAll() const {
    std::optional<int64_t> latest;
    for (const auto& [channel, t] : newest_)
      if (!latest || t > *latest) latest = t;
    return latest;
  }
  struct Held {
    int64_t utime = 0, reference = 0;
  };
  // (std::less<>: looked up by the channel's name as given, without a string made per message)
  std::map<std::string, int64_t, std::less<>> newest_;
  std::map<std::string, Held, std::less<>> held_;
};

// PassSpan: the time a log covers, summed over its passes. A jump back of more than
// TimeReset::kJumpUs starts a new pass (a log played with lcm-logplayer -l and recorded, or two
// runs concatenated), whose span adds to the earlier ones'; within a pass, times may arrive a
// little out of order (several publishers): the pass spans its earliest to its latest.
class PassSpan {
 public:
  void add(int64_t utime) {
    if (passes_ == 0) {
      first_ = last_ = utime;
      passes_ = 1;
      return;
    }
    if (utime < last_ - TimeReset::kJumpUs) {  // the log starts again
      done_us_ += last_ - first_;
      first_ = last_ = utime;
      ++passes_;
      return;
    }
    if (utime < first_) first_ = utime;
    if (utime > last_) last_ = utime;
  }
  int passes() const { return passes_; }
  int64_t totalUs() const { return passes_ > 0 ? done_us_ + last_ - first_ : 0; }
  double seconds() const { return static_cast<double>(totalUs()) * 1e-6; }

 private:
  int passes_ = 0;
  int64_t first_ = 0, last_ = 0;  // (of this pass)
  int64_t done_us_ = 0;           // the spans of the passes before it
};

}  // namespace lasonic
