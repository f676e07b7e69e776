#pragma once
// What the laser actually saw (README "Evaluation": "laser-invisible" means the laser did not see
// it, scan by scan). Under the physical laser model whether a surface returns the beam depends on
// its remission, the range and the incidence (black cardboard within ~2.7 m, glass near normal
// incidence, a thin pipe when it fills enough of the footprint), so a material cannot say it.
//
// The index holds, per LASER_SCAN that has its LASER_TRUTH (same utime and seq), every reading
// that a surface returned (FLAG_OK and LASER_TRUTH obstacle != -1: mixed pixels and gaps are left
// out), placed in the true world frame with the true robot pose (SIM_STATE) at the reading's own
// time utime + offset_us[i] and the scan's mount, together with the obstacle that returned it.
// A mover's returns are kept in the mover's own frame (relative to its centre at the reading's
// time), so a query at another time compares them with the same part of the person.
//
// Per scan the points are sorted by (obstacle, cell x, cell y) in cells of `cell` metres, so a
// query looks at a few short runs of one obstacle's points of one scan.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry.hpp"
#include "eval/evaluate.hpp"

namespace lasonic::eval {

class LaserSeen {
 public:
  // Keeps a reference to log.sim_states (for the movers): the log must outlive the index.
  explicit LaserSeen(const RunLog& log, double cell = 0.10);

  // False when the log has no SIM_STATE or no LASER_TRUTH that matches a LASER_SCAN (utime, seq,
  // number of readings): old logs and logs of real robots. The evaluation then falls back to the
  // material rule (Scenario::laserVisible) and says so (sensors.laser_truth = 0).
  bool available() const { return !scans_.empty(); }
  size_t scans() const { return scans_.size(); }
  // LASER_SCAN messages left out because no matching LASER_TRUTH came with them.
  int64_t scansWithoutTruth() const { return without_truth_; }
  size_t points() const;

  // The newest indexed scan completed (its last reading taken) at or before utime; -1 if none.
  int newestAt(int64_t utime) const;
  // The indexed scan whose last reading was taken at exactly utime (a Radar Map's time,
  // SONAR_COMPLEMENT.radar_map_utime); -1 if none.
  int completedAt(int64_t utime) const;
  int64_t completionTime(int scan) const { return scans_.at(static_cast<size_t>(scan)).done; }

  // True if scan `scan` returned from `obstacle` within `radius` of p (true world frame). For a
  // mover (obstacle <= -2) p is a point of the mover at time `utime`: the comparison is made in
  // the mover's frame. False for scan < 0.
  bool saw(int scan, int obstacle, const geom::Vec2& p, double radius, int64_t utime = 0) const;
  // ... from `obstacle` or, where its surface at p is drawn on others' (sim::Scenario::partnersAt),
  // from any of them: the laser names whichever surface its ray met first.
  bool saw(const sim::Scenario& sc, int scan, int obstacle, const geom::Vec2& p, double radius,
           int64_t utime = 0) const {
    return sc.eitherSeen(obstacle, p, [&](int o) { return saw(scan, o, p, radius, utime); });
  }
  // The same for the newest scan completed at or before utime (false if there is none).
  bool sawBy(int64_t utime, int obstacle, const geom::Vec2& p, double radius) const {
    return saw(newestAt(utime), obstacle, p, radius, utime);
  }
  // Distance from sec.apex to the nearest return of `scan` inside the sector, each return where
  // the laser saw it (a mover where it was then: the scan's picture, as the Radar Map has it);
  // nullopt if none or scan < 0.
  std::optional<double> nearestInSector(int scan, const geom::Sector& sec) const;

 private:
  // README "An hour of driving": an hour's index holds ~12.6 M points, so a point is kept small.
  // Its cell is not stored but recomputed from its position (cellOf is a pure function of it, so
  // the order and the runs are exactly those of stored cells, whatever the range of the scene).
  // Its world position is kept only for movers: for any other obstacle it is the position itself.
  struct Point {
    int obstacle;
    double x, y;  // the query frame: true world frame; for a mover relative to its centre then
    geom::Vec2 p() const { return {x, y}; }
  };
  struct Scan {
    int64_t done;                     // [us] time of its last reading
    std::vector<Point> points;        // sorted by (obstacle, cell x, cell y)
    // True world frame, where the reading was taken, of the movers' points: they sort first
    // (obstacle <= -2), so mover_world[i] belongs to points[i].
    std::vector<geom::Vec2> mover_world;
    geom::Vec2 world(size_t i) const { return i < mover_world.size() ? mover_world[i] : points[i].p(); }
  };
  int64_t cellOf(double v) const;
  std::optional<geom::Vec2> moverCentre(int obstacle, int64_t utime) const;

  double cell_;
  TruthTrack truth_;
  std::vector<Scan> scans_;  // by completion time
  int64_t without_truth_ = 0;
};

}  // namespace lasonic::eval
