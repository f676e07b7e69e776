// Whether a sensor's message times agree with the odometry's (README "Clocks"). Every stage
// joins readings to poses by message time: a laser scan's readings are placed with the odometry
// pose of each reading's time, a sonar firing with the pose of its firing time. A driver on
// another computer stamps with that computer's clock; if it runs 50 ms ahead or behind the
// odometry's, every reading is placed with the pose of 50 ms earlier or later: 2 cm at 0.4 m/s,
// but 8 cm at 2 m while the robot turns at 0.8 rad/s, nearly the 0.10 m classification
// tolerance. Nothing in the data says so; only the times can. Two signs, in message time alone
// (so a replayed log gives the same findings):
//  - ahead: a datum stamped later than the newest odometry by more than the odometry's period
//    plus `margin_us`. A driver sends after it measured, so on one clock the newest odometry is
//    at most one period older; more is a clock running ahead (or odometry that stalls).
//  - behind: every datum (at least `min_data`) of a window of `window_us` handled more than
//    `margin_us` after its stamp (after its own listening time: a sonar reports once its echoes
//    could have come back), by the newest odometry's time. Transport takes a few ms; a clock
//    running behind (or a link that delays everything) adds its offset to all of them, so the
//    window's smallest lag is it.
// `margin_us` is 20 ms: the offset at which the scene suite's missed rate starts to rise (README
// "Clocks": 10 ms costs nothing measurable, 20 ms a tenth more misses, 50 ms half more).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace lasonic {

class StampAgreement {
 public:
  struct Params {
    int64_t margin_us = 20'000;
    int64_t window_us = 5'000'000;
    int min_data = 10;  // a window says "every datum" of a stream (a 5 Hz scanner gives 25), not of a few
  };
  struct Finding {
    bool ahead = false;     // else behind
    int64_t offset_us = 0;  // ahead: by how much the datum was later than the newest odometry;
                            // behind: the window's smallest lag beyond the listening time
    int64_t odometry_period_us = 0;  // (ahead) the largest odometry interval of the last windows
  };
  StampAgreement() = default;
  explicit StampAgreement(const Params& p) : p_(p) {}
  // Each odometry message's time, in order: the odometry's period.
  void noteOdometry(int64_t utime);
  // A datum measured at `utime` (a scan: its last reading) handled when the newest odometry is
  // at `odometry_utime`; `listening_us`: how long after `utime` its driver can send at the
  // earliest. A finding at most once per window and kind.
  std::optional<Finding> check(int64_t utime, int64_t odometry_utime, int64_t listening_us = 0);
  // Start afresh (a clock that restarted).
  void reset() { *this = StampAgreement(p_); }
  // The finding as a sentence about `channel` (e.g. "LASER_SCAN").
  std::string describe(const Finding& f, const char* channel) const;
  const Params& params() const { return p_; }

 private:
  Params p_{};
  std::optional<int64_t> window_start_;  // odometry time the current window began
  int64_t min_lag_us_ = 0;
  int data_ = 0;  // in the current window
  std::optional<int64_t> last_ahead_report_;
  std::optional<int64_t> last_odometry_;
  int64_t max_interval_us_ = 0, prev_max_interval_us_ = 0;  // this window's and the one before
  std::optional<int64_t> interval_window_start_;
};

}  // namespace lasonic
