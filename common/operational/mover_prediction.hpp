#pragma once
// MoverPrediction (beyond the paper, for the Sector Map's laser part, Jörg 1995 sec. 3.4): where
// the people of the newest laser scan are now.
//
// The sector map takes the laser's obstacles from the newest scan, moved into the current robot
// pose: right for everything that stands still. A person walking at 1.2 m/s has moved up to
// 0.24 m by the time the next scan (5 Hz) replaces theirs: nearer than reported where they come
// closer, already in the next sector where they cross (missed there), still reported where they
// have left (a false alarm). Scan to scan, a person is a small cluster of returns whose centroid
// moves at walking speed; a wall or a pillar does not move. So:
// - each scan is cut into clusters (consecutive returns closer than cluster_gap); the small ones
//   (bounding box diagonal <= max_extent, at least min_points returns) are candidates;
// - a candidate is paired with the previous scan's candidate whose centroid is nearest, if each
//   is the other's nearest and the centroid moved no faster than max_speed;
// - a pair whose centroid moved at min_speed or faster, at a velocity that agrees (within
//   max(agree_speed, half of it)) with the one the earlier cluster had from the scan before
//   that, gives its returns that velocity: a person keeps walking, while the jitter of a
//   static cluster's centroid (range noise, odometry between two scans, an edge's mixed
//   pixels) points somewhere else every scan.
// The sector map then reports such a return at p + v * min(age, horizon_s), age = map time minus
// the return's own time (SectorMap::setLaserMovers). A static object seen from a driving robot
// shows another side of itself as the line of sight turns: the visible half of a round object
// of width w has its centroid w / pi from the centre, so that centroid turns with the line of
// sight at (w / pi) * v_perp / D (v_perp: the robot's speed across the line of sight, D: the
// distance). The speed a pair needs is min_speed plus that, with w the cluster's extent, so a
// drum passed at 1.2 m/s is not taken for a person. A flat face (a box's side, a piece of wall at
// grazing incidence: returns within flat_face_rms of their line over flat_face_min or more, in
// both scans) shows only the motion across it: what of it is in view changes as the robot
// passes (a nearer part hidden, a farther one appearing), so its centroid slides along it while
// the face stands (the aperture problem). Such a pair's velocity is its component along the
// face's normal. (A box's corner can still jump when a face comes into view; the scenes with
// boxes are in the README's results.) A cluster that cannot be paired (it appeared, split,
// merged with a wall) keeps its place, as without this.
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

struct MoverPredictionParams {
  double cluster_gap = 0.20;  // [m] a person's returns lie ~1 cm apart; a gap beside them is wider
  double max_extent = 1.0;    // [m] a person (0.5-0.6 m across) or two walking side by side
  int min_points = 3;         // fewer returns give no usable centroid
  double min_speed = 0.3;     // [m/s] slow walking is ~0.5 m/s; visible-centroid shifts stay below
  double max_speed = 2.5;     // [m/s] running; faster pairs are two different things
  double horizon_s = 0.3;     // [s] 1.5 scan periods of a 5 Hz laser: never further than the next
                              // scan is late
  double horizon_scans = 1.5; // the same in the laser's own scan periods once timed (ScanPeriod),
                              // for a slower laser; never below horizon_s. 0: horizon_s
  double agree_speed = 0.4;   // [m/s] two successive velocities of one person differ by less
                              // (a turn of 30 deg at 0.8 m/s); jitter of 2-3 cm per scan does not
  double flat_face_rms = 0.02;  // [m] a cluster whose returns lie within this (rms) of their line is
                                // a flat face: twice the laser's 1 cm range noise, while a person's
                                // visible half scatters ~8 cm about its axis. 0: never (the
                                // centroid's whole velocity)
  double flat_face_min = 0.4;   // [m] ... if it is at least this long (bounding box diagonal): a
                                // shorter piece of a person (0.25 m radius) -- partly hidden, at
                                // the edge of the view -- lies within 2 cm of its chord
};

// A laser return (global frame) and the time it was taken.
struct TimedPoint {
  geom::Vec2 p = geom::Vec2::Zero();
  int64_t utime = 0;
};

class MoverPrediction {
 public:
  explicit MoverPrediction(const MoverPredictionParams& p = {});
  const MoverPredictionParams& params() const { return p_; }
  // One scan's valid returns in scan order (global frame). Returns each return's velocity [m/s]
  // (zero: not a mover, or not known to be one) and keeps the scan's candidates for the next.
  // A scan not later than the previous one pairs with nothing (and replaces it).
  // `robot`: the robot's (odometry) position at the middle of the scan.
  std::vector<geom::Vec2> update(const std::vector<TimedPoint>& scan, const geom::Vec2& robot);
  // The same work, the result as runs instead of one velocity per return: scan[first..last]
  // moves at vel (a mover's returns; runs in scan order, apart), every other return's velocity
  // is zero. The reference is valid until the next call.
  struct MovingRun {
    size_t first = 0, last = 0;
    geom::Vec2 vel = geom::Vec2::Zero();
  };
  const std::vector<MovingRun>& track(const std::vector<TimedPoint>& scan, const geom::Vec2& robot);
  // Candidates paired and found moving in the last update.
  int movers() const { return movers_; }
  // Per return of the last update's scan: known to stand still -- kStill: it belongs to no
  // candidate (a wall, a large object, a cluster too small for a centroid); kStillCluster: to a
  // candidate paired with the scan before that moved slower than min_speed (plus the visible-side
  // allowance), person-sized, so it may walk off later. A candidate seen for the first time, or
  // one that moved faster without yet being a mover, is 0: a person who has just come into view
  // or is starting to walk (LaserMemory keeps only the still ones, a still cluster for less long).
  static constexpr uint8_t kStill = 1, kStillCluster = 2;
  const std::vector<uint8_t>& still() const { return still_; }

 private:
  struct Blob {
    geom::Vec2 centroid = geom::Vec2::Zero();
    double t_s = 0;  // mean time of its returns [s]
    double extent = 0;  // [m] its bounding box's diagonal
    double rms = 0;     // [m] its returns' rms distance from their line (principal axis)
    geom::Vec2 normal = geom::Vec2::UnitY();  // that line's normal
    size_t first = 0, last = 0;  // its returns: scan[first..last]
    bool paired = false;  // paired with the scan before; then vel is its centroid's velocity
    geom::Vec2 vel = geom::Vec2::Zero();
  };
  std::vector<Blob> candidates(const std::vector<TimedPoint>& scan) const;

  MoverPredictionParams p_;
  std::vector<Blob> prev_;
  geom::Vec2 prev_robot_ = geom::Vec2::Zero();
  int movers_ = 0;
  std::vector<uint8_t> still_;
  std::vector<MovingRun> runs_;
};

}  // namespace lasonic
