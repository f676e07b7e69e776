#pragma once
// An Elfes-style probabilistic occupancy grid (A. Elfes, "Using occupancy grids for mobile robot
// perception and navigation", IEEE Computer 22(6), 1989; in the log-odds form of Thrun, Burgard
// and Fox, "Probabilistic Robotics", 2005, ch. 9): the evaluation's probabilistic baseline
// (README "Evaluation", baselines). Laser and sonar are both inserted, free space is cleared.
//
// Each cell holds l = log(p / (1 - p)), prior 0 (p = 0.5); every measurement adds the log odds
// of its inverse sensor model, and l is clamped to [logit(p_min), logit(p_max)] so that a cell
// can change its mind within a few readings (people walk through).
// - Sonar, cone model: the beam is a circular sector of the reading's own opening angle
//   (SONAR_RING.beam_width). With an echo at range r: cells whose centre lies in the cone nearer
//   than r - arc_thickness/2 are free (sonar_free); cells within arc_thickness/2 of the arc are
//   occupied (sonar_occupied: the obstacle lies somewhere on the arc, so each arc cell gets weak
//   evidence that readings from other places sharpen). Without an echo the whole cone up to
//   range_max is free (no_echo_clears).
// - Laser, ray model: every cell the ray passes through before its end point is free
//   (laser_free), the end point's cell occupied (laser_occupied). Readings without a return
//   say nothing (an absorbing surface is not free space).
// Read out: a cell with p >= occupied_threshold is an obstacle.
#include "baselines/grid_window.hpp"

namespace lasonic::baselines {

struct LogOddsParams {
  WindowParams window;
  double sonar_occupied = 0.65;       // p of an arc cell
  double sonar_free = 0.4;            // p of a cell inside the cone before the arc
  double sonar_arc_thickness = 0.10;  // [m]
  bool no_echo_clears = true;
  double laser_occupied = 0.9;
  double laser_free = 0.3;
  double p_min = 0.12, p_max = 0.97;  // clamp
  double occupied_threshold = 0.7;    // read out
};
// Reads a `log_odds:` section over `base`. Throws ConfigError naming the key path.
LogOddsParams logOddsParams(const Config& c, LogOddsParams base = {});

class LogOddsGrid {
 public:
  explicit LogOddsGrid(const LogOddsParams& p);
  const LogOddsParams& params() const { return p_; }

  bool follow(const geom::Vec2& robot) { return w_.follow(robot); }
  // One sonar reading: sensor's global pose (axis along theta), full beam opening [rad].
  void insertSonar(const geom::Pose2& sensor, double range, bool no_echo, double beam_width, double range_max);
  // One laser return: the sensor's global position at the reading's time and the return point.
  void insertLaser(const geom::Vec2& origin, const geom::Vec2& hit);

  // Occupancy probability of the cell holding p (0.5 outside the window: unknown).
  double probability(const geom::Vec2& p) const;
  const OccupancyWindow& occupancy() const { return w_.occupancy(); }

 private:
  void add(size_t i, double l);
  LogOddsParams p_;
  double l_sonar_occ_, l_sonar_free_, l_laser_occ_, l_laser_free_, l_min_, l_max_, l_threshold_;
  GridWindow<float> w_;
};

}  // namespace lasonic::baselines
