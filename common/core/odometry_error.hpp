#pragma once
// How far apart dead reckoning puts two moments of a drive: the variance of the displacement,
// relative to the robot at the later moment, of a point fixed in the odometry frame at the
// earlier one. Odometry is modelled as random walks (the simulator's model, README "Sensor
// models"): distance error trans [m/sqrt(m)], heading error drift [rad/sqrt(m)] from driving and
// rot [rad/sqrt(rad)] from turning. A heading error made at one moment displaces what was seen
// before it by the distance driven after it, so
//   var(t0, t) = trans^2 (D(t) - D(t0)) + sum over steps s in (t0, t] of dv(s) (D(t) - D(s))^2,
// dv(s) = drift^2 |step| + rot^2 |turn|, D = distance driven. The sum expands into differences of
// three running sums, so a moment is remembered by a Mark and any two compare in O(1).
namespace lasonic {

struct OdometryNoise {
  double trans = 0.01;   // [m/sqrt(m)]
  double rot = 0.005;    // [rad/sqrt(rad)]
  double drift = 0.002;  // [rad/sqrt(m)]
};

class OdometryError {
 public:
  struct Mark {
    double driven = 0;          // [m] D
    double a = 0, b = 0, c = 0;  // sum dv, sum dv * D(s), sum dv * D(s)^2
    double t = 0;                // sum trans^2 |step|
  };
  explicit OdometryError(const OdometryNoise& n = {}) : n_(n) {}
  // The robot drove `step` metres and turned `turn` radians (signs ignored) since the last call.
  void advance(double step, double turn);
  const Mark& now() const { return m_; }
  // The model of the steps from now on (a pose source that changes: scan matching where the
  // walls constrain the pose, the odometry where they do not); what was accumulated stays.
  void setNoise(const OdometryNoise& n) { n_ = n; }
  // var(then, now) [m^2] (0 for then == now; never negative).
  double varianceSince(const Mark& then) const { return varianceBetween(then, m_); }
  // var(then, later) for two marks of this model, then before later.
  double varianceBetween(const Mark& then, const Mark& later) const;

 private:
  OdometryNoise n_;
  Mark m_;
};

}  // namespace lasonic
