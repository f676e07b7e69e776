#pragma once
// Neighbour-aware bearing of a sonar echo (operational AGM's one-cell sensor model; README "Method",
// step 4, beyond the paper).
//
// The paper's trivial sensor model puts every echo on the sensor's acoustic axis. But a sonar's
// first echo comes from the surface point NEAREST to the sensor anywhere in its beam (width b):
// - an oblique wall/fence: the nearest point of the wall inside the beam is at the beam edge
//   towards the wall's foot of perpendicular, so the axis point lies in FRONT of the wall, a
//   consistent ghost line the AGM reinforces;
// - a thin object (pipe) anywhere within +-b/2 of the axis is put on the axis.
// Adjacent sensors of a ring overlap (24 sensors of 30 deg: the beam of sensor i covers the axes
// of i-1 and i+1), so their readings locate the echo better, still as ONE point per reading:
//   neighbours j of reading i: readings of other sensors of this ring cycle whose beam overlaps
//   i's (|angleDiff(psi_j, psi_i)| < (b_i + b_j) / 2, each reading's own beam width; for equal
//   beams, the axis lies inside i's beam). Per side of i's axis (left: psi_j > psi_i):
//   - "shorter": some neighbour on that side reads r_j < r_i - similar: the surface comes nearer
//     on that side, so i's nearest point is at its beam edge on that side: psi_i +- b/2;
//   - "similar": some neighbour reads |r_j - r_i| <= similar: the same nearest point is most
//     likely in both beams, i.e. in their overlap, which lies between the two axes: bearing =
//     bisector of psi_i and psi_j (error <= half the axis spacing; the axis alone: <= b/2);
//   - otherwise (no neighbour, or only longer readings): nothing on that side.
//   Exactly one side "shorter" (the other side not "shorter" or "similar") -> its beam edge;
//   exactly one side "similar" (the other side nothing) -> that bisector; both sides something
//   (the object straddles i's axis, or a concave corner) or neither -> the axis.
// The echo point is at range r from the sensor along the chosen bearing. Everything is in the
// global frame (the sensor poses at their firing times), so the robot's rotation between two
// firings is accounted for.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <map>
#include <vector>

#include "core/geometry.hpp"
#include "core/interval_window.hpp"

namespace lasonic {

enum class AgmBearing { Axis, Neighbours };

struct SonarBearingParams {
  double beam_width = geom::deg2rad(30.0);  // [rad] full opening b
  double similar = 0.10;                    // [m] |r_j - r_i| <= this: the same nearest point
  // [s] Neighbour readings older than this are ignored; 0: no limit here -- the tracker takes the
  // readings of this ring cycle from the firings (those since the sensor's previous firing).
  double max_age_s = 0;
};

// One sonar echo: firing time, range, sensor pose (global frame, at firing time).
struct SonarEcho {
  int64_t utime = 0;
  double range = 0;
  geom::Pose2 sensor;
  double beam_width = 0;  // [rad] this transducer's full opening (from the message); 0: params' beam_width
};

// A chosen bearing and how far (either way) the echo's true bearing may lie from it:
// axis (no usable neighbour, or both sides): b/2, the paper's "half the beam width";
// bisector with a similar neighbour at axis offset o: the overlap's half width (b - |o|)/2;
// beam edge: 0 (a surface coming nearer on that side has its nearest point at the edge).
struct BearingEstimate {
  double bearing = 0;    // [rad] global frame
  double halfwidth = 0;  // [rad]
};

// The chosen bearing (global frame) of echo `self`, given the other sensors' latest echoes
// (the caller leaves out the sensor of `self`; beam overlap, readings newer than `self` and,
// with p.max_age_s > 0, ages are checked here).
// Its bearing is exactly self.sensor.theta when the axis is chosen.
BearingEstimate echoBearingEstimate(const SonarEcho& self, const std::vector<SonarEcho>& others,
                                    const SonarBearingParams& p);
// echoBearingEstimate(...).bearing.
double echoBearing(const SonarEcho& self, const std::vector<SonarEcho>& others, const SonarBearingParams& p);
// The point at self.range from the sensor along echoBearing().
geom::Vec2 echoPoint(const SonarEcho& self, const std::vector<SonarEcho>& others, const SonarBearingParams& p);

// One transducer's firings, for "one ring cycle" taken from the firings themselves (here and in
// operational/motion_confirmation.hpp): a ring fires at a steady cadence, a driver's jitter
// stretches a cycle by a fraction of a group (the Pioneer's 0.32-0.384 s by 1.2 at most), a
// firing skipped or lost, or a sonar that stopped for a while, by 2 or more.
struct SensorFiring {
  static constexpr double kIrregularCycle = 1.5;
  static constexpr int64_t kNone = std::numeric_limits<int64_t>::min();
  int64_t last = kNone;  // the latest firing
  int64_t cycle = 0;     // [us] the interval before it (0: not known yet)
  bool known() const { return last != kNone; }
  // A firing at `utime` (after `last`) ends a regular cycle: at most kIrregularCycle times the one
  // before it (or that one is not known).
  bool regular(int64_t utime) const {
    return cycle == 0 || static_cast<double>(utime - last) <= kIrregularCycle * static_cast<double>(cycle);
  }
  // Records a firing at `utime`; an earlier or repeated one changes nothing.
  void fire(int64_t utime) {
    if (!known()) last = utime;
    else if (utime > last) cycle = utime - last, last = utime;
  }
};

// How many firing groups (update cycles: one SONAR_COMPLEMENT message each) make one ring cycle,
// counted from the groups' own firings: the messages since a group last fired, the most frequent
// count among the latest kWindow (a lost message makes one count short and the lost group's next
// long; neither is the most frequent). 0 until a group has fired twice. Group ids outside
// [0, kMaxGroups) are not counted.
class RingGroups {
 public:
  static constexpr int kMaxGroups = 1024;
  static constexpr size_t kWindow = 16;
  static constexpr size_t kIntervals = 256;    // intervals kept (~8 s of MOBOT-IV's ring)
  static constexpr size_t kMinIntervals = 64;  // before these, the ring is not timed
  void fired(int group);
  // The same with the firing's time: also keeps the latest kIntervals intervals between
  // consecutive firings (of any group; not positive ones, a firing time going backwards, are not
  // kept).
  void fired(int group, int64_t utime);
  int perCycle() const { return per_cycle_; }
  // The ring cycle at its quickest [s]: perCycle() times the shortest of those intervals. A
  // driver fires each group at its period or a little late, so this is the period the driver is
  // set to, not its mean. An interval under half their median is no firing interval (a duplicate,
  // a clock glitch) and is passed over. 0 until kMinIntervals are kept: the shortest of a few is
  // not yet the period (with 0-8 ms of lateness the shortest of 64 lies more than 1.25 ms above
  // it with a chance of 2e-5, the shortest of 8 with one of 0.26).
  double shortestCycleS() const;
  // An AGM's h_max [update cycles] for a memory of `ring_cycles` ring cycles: that many times
  // perCycle(), or `fallback` while the ring is not counted yet (or ring_cycles is 0).
  int hMax(double ring_cycles, int fallback) const {
    return ring_cycles > 0 && per_cycle_ > 0 ? static_cast<int>(std::lround(ring_cycles * per_cycle_)) : fallback;
  }

 private:
  int64_t messages_ = 0;
  std::vector<int64_t> last_;   // message index of each group's latest firing (-1: never)
  std::vector<int> counts_;     // the latest counts, oldest first (at most kWindow)
  int per_cycle_ = 0;
  IntervalWindow intervals_{kIntervals};
};

// One transducer of a ring as the walker rule (operational/agm.hpp, walkerGThreshold) sees it:
// its axis in the robot frame and its full opening [rad].
struct BeamAxis {
  double axis = 0;
  double beam = 0;
};
// The most beams that cover one bearing of the robot frame: how many transducers at most hear a
// person there each ring cycle (MOBOT-IV's 24 beams of 30 deg, 15 deg apart: 2; a Pioneer's 2,
// where its front and side pairs overlap; 8 beams of 30 deg, 45 deg apart: 1). Two beams count as
// overlapping only where they share more than 2 `margin` [rad]: beams that merely touch (MOBOT-IV's
// every other one) do not, however a mount's bearing was measured (each beam's edges are taken
// `margin` inwards, at most a quarter of its opening). Beams with a non-finite axis or an opening
// not in (0, 2 pi) are left out; 0 for none.
int maxBeamOverlap(const std::vector<BeamAxis>& beams, double margin);

// Keeps, per sensor id, its latest echo and firing, and places new echoes with echoPoint(). The
// neighbours of an echo are the other sensors' latest readings of this ring cycle: fired since
// the echo's own sensor fired before (with params().max_age_s 0; > 0: no older than that). A
// cycle that is not regular (SensorFiring) is a gap (a sonar that stopped, a lost message): then
// only readings within kIrregularCycle of that earlier cycle count. So any ring,
// whatever its groups and their timing (a driver fires each group a little late at random),
// needs no time to configure.
class SonarBearingTracker {
 public:
  static constexpr size_t kMaxSensors = 1024;
  explicit SonarBearingTracker(const SonarBearingParams& p) : p_(p) {}
  const SonarBearingParams& params() const { return p_; }
  // Bearing / point of the echo of sensor `id` against the latest echoes of the other sensors.
  // Does not record it (so the echoes of one firing group do not depend on their order).
  double bearing(int id, const SonarEcho& e) const;
  BearingEstimate estimate(int id, const SonarEcho& e) const;
  geom::Vec2 place(int id, const SonarEcho& e) const;
  // Records the latest reading of sensor `id`, fired at `utime`; nullopt: it has no usable echo.
  void record(int id, int64_t utime, const std::optional<SonarEcho>& e);
  // How many sensors' latest readings are kept (at most kMaxSensors).
  size_t sensors() const { return latest_.size(); }

 private:
  SonarBearingParams p_;
  std::map<int, std::optional<SonarEcho>> latest_;
  std::map<int, SensorFiring> fired_;
  mutable std::vector<SonarEcho> scratch_;
};

}  // namespace lasonic
