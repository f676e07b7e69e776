// Motion confirmation (beyond the paper; README "Method", step 4): the Accumulative Grid Map
// confirms a surface when two echoes land within one neighbourhood (t cells) of each other. A
// transducer that passes a surface hears its foot, the nearest point in its beam, move along the
// surface as far as the transducer moved: one ring cycle (0.18 s on MOBOT-IV) apart, 0.07 m at
// 0.4 m/s, inside the 3 x 3 neighbourhood, but 0.22 m at 1.2 m/s, beyond it, so a mesh beside a
// fast robot stays below G_T however often it is heard. Here an echo whose own sensor's previous
// echo (at its previous firing, one ring cycle before) lies outside its neighbourhood, yet no
// farther from it than the transducer moved plus a tolerance (the placement's own error), counts
// twice: the two echoes together confirm it, as they would have standing closer. A single echo
// (crosstalk, a foreign source) never does, nor does a robot that stands (its transducers do not
// move) or drives slowly (the two echoes are neighbours anyway).
//
// "One ring cycle" is taken from the firings themselves, not from a configured time: the previous
// echo must come from the sensor's previous firing (a firing in between without a placed echo,
// or a lost message, breaks the pair), and that cycle must be regular (SensorFiring,
// operational/sonar_bearing.hpp: at most 1.5 times the sensor's cycle before it). So any ring,
// whatever its groups and their timing, works without a key.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/geometry.hpp"
#include "operational/agm.hpp"
#include "operational/echo_placer.hpp"

namespace lasonic {

struct MotionConfirmationParams {
  bool enabled = false;
  double tolerance_m = 0.10;  // [m] beyond the transducer's own displacement
};

class MotionConfirmation {
 public:
  static constexpr size_t kMaxSensors = 1024;
  explicit MotionConfirmation(const MotionConfirmationParams& p) : p_(p) {}
  const MotionConfirmationParams& params() const { return p_; }
  // For each echo of `placed` (in order): appends its point to `hits` once more where its
  // sensor's previous echo confirms it as above, then records it as that sensor's latest echo
  // and firing. Returns the number of points appended. Echoes without a sensor id (< 0) are
  // skipped.
  int apply(const std::vector<PlacedEcho>& placed, const AccumulativeGridMap& agm, std::vector<geom::Vec2>& hits);
  // Records a firing of sensor `id` at `utime` that placed no echo (no echo, not complementary,
  // left out): its next echo then has no previous one to pair with. The caller reports every
  // reading of a group after apply(); a firing already recorded (the placed echoes') is ignored.
  void fired(int id, int64_t utime);
  // How many sensors' latest firings are kept (at most kMaxSensors).
  size_t sensors() const { return last_.size(); }

 private:
  struct Last {
    geom::Vec2 point = geom::Vec2::Zero();  // the latest placed echo
    geom::Vec2 sensor = geom::Vec2::Zero();
    int64_t echo_utime = SensorFiring::kNone;  // its firing time
    SensorFiring firing;                       // the latest firing, with or without a placed echo
  };
  // The entry of sensor `id`, new if it has none (the table is emptied first once full).
  Last& entry(int id);
  MotionConfirmationParams p_;
  std::unordered_map<int, Last> last_;
};

}  // namespace lasonic
