#pragma once
// Look weight (beyond the paper; Jörg 1995 sec. 3.4 sets the tactical G_T by how often a static
// obstacle is heard): how many hits one echo counts for in the tactical AGM.
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
// Integer G stays integer: each hit is copied floor(carry + w) - floor(carry) times with the
// fractional part carried to the next hit, so over many hits the mean is w, and the result depends
// only on the order of the hits (deterministic).
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

class LookWeight {
 public:
  // ref_speed [m/s]: the speed at which one echo is one hit; 0: always one hit (the paper).
  explicit LookWeight(double ref_speed) : ref_speed_(ref_speed) {}
  double refSpeed() const { return ref_speed_; }
  // The weight at robot speed `speed` [m/s]: max(1, |speed| / ref_speed); 1 when off or when the
  // speed is not finite.
  double weight(double speed) const;
  // Replaces every hit by its copies (in order) at weight(speed). Returns how many were added.
  int apply(std::vector<geom::Vec2>& hits, double speed);
  // Mean speed [m/s] between two poses `dt_s` apart; nullopt-like -1 when dt_s is not positive
  // or the result not finite.
  static double meanSpeed(const geom::Vec2& from, const geom::Vec2& to, double dt_s);

 private:
  double ref_speed_ = 0;
  double carry_ = 0;  // fractional hits owed, in [0, 1)
};

}  // namespace lasonic
