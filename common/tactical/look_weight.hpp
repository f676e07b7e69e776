#pragma once
// Look weight (beyond the paper, whose sec. 3.3 sets G_T between perceiving moving obstacles and
// the signal-to-noise ratio; tying it to how often a static surface is heard is this project's):
// how many hits one echo counts for in the tactical AGM.
//
// G_T counts echoes. A static surface is heard while the robot drives past it, for a time
// inversely proportional to the robot's speed, so at twice the speed it gives half the echoes and
// a G_T chosen for one speed no longer confirms it at another. A person walking through the
// neighbourhood gives echoes for the time they take to cross it, whatever the robot does. The look
// weight makes an echo count for what it would at the reference speed: w = max(1, v / v_ref) hits,
// v the robot's mean speed over the firing interval. Below v_ref nothing changes (the threshold's
// argument about people holds there as it is); above it a static surface keeps reaching G_T,
// while the margin against people shrinks as the robot approaches their walking speed (the
// next-scan check and the laser still see them).
//
// Optionally also below a low speed (off by default): w = v / v_low below v_low, so a robot
// standing or turning on the spot adds no hits. From one place the ring hears the same surfaces
// every cycle; their range arcs coincide instead of crossing, so the repeats are no new looks, yet
// they would confirm whatever cell the arc placement picked along the arc (README "Between
// drives": the memory of a waiting robot fills with such streaks). What was confirmed while
// driving stays until forgotten as usual.
//
// Integer G stays integer: each hit is copied floor(carry + w) - floor(carry) times with the
// fractional part carried to the next hit, so over many hits the mean is w, and the result depends
// only on the order of the hits (deterministic).
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

class LookWeight {
 public:
  // ref_speed [m/s]: the speed at or below which one echo is one hit; 0: never more (the paper).
  // low_speed [m/s]: below it an echo counts for speed / low_speed hits; 0: never fewer.
  explicit LookWeight(double ref_speed, double low_speed = 0) : ref_speed_(ref_speed), low_speed_(low_speed) {}
  double refSpeed() const { return ref_speed_; }
  double lowSpeed() const { return low_speed_; }
  bool enabled() const { return ref_speed_ > 0 || low_speed_ > 0; }
  // The weight at robot speed `speed` [m/s]: |speed| / low_speed below low_speed, else
  // max(1, |speed| / ref_speed); 1 when both are off or when the speed is not finite.
  double weight(double speed) const;
  // Replaces every hit by its copies (in order) at weight(speed). Returns how many were added
  // (negative: how many were dropped, at a weight below one).
  int apply(std::vector<geom::Vec2>& hits, double speed);
  // Mean speed [m/s] between two poses `dt_s` apart; nullopt-like -1 when dt_s is not positive
  // or the result not finite.
  static double meanSpeed(const geom::Vec2& from, const geom::Vec2& to, double dt_s);

 private:
  double ref_speed_ = 0;
  double low_speed_ = 0;
  double carry_ = 0;  // fractional hits owed, in [0, 1)
};

}  // namespace lasonic
