#pragma once
// Motion along a waypoint path at constant speed, as the robot and the movers do it: drive
// straight legs, turn on the spot at each waypoint (instantly for movers), and at the end stop
// (once), go round again (loop) or come back the same way (pingpong).
#include <limits>
#include <vector>

#include "core/geometry.hpp"
#include "sim/scenario.hpp"

namespace lasonic::sim {

class PathFollower {
 public:
  struct State {
    geom::Pose2 pose;  // heading = direction of travel (or of the turn in progress)
    double v = 0;      // [m/s]
    double omega = 0;  // [rad/s]
  };

  // path: >= 2 waypoints, no two consecutive ones equal. turn_rate = infinity turns instantly.
  // Until start_delay_s the follower waits at the first waypoint facing the second.
  PathFollower(const std::vector<geom::Vec2>& path, PathMode mode, double speed,
               double turn_rate = std::numeric_limits<double>::infinity(), double start_delay_s = 0);

  // State t seconds after the start (t < 0 counts as 0).
  State at(double t) const;
  // Length of one pass (once) or one full cycle (loop, pingpong) [s].
  double cycleDuration() const { return cycle_; }

 private:
  struct Phase {
    double t0 = 0, duration = 0;  // [s] within the cycle
    geom::Pose2 from, to;
    bool turn = false;
  };
  std::vector<Phase> phases_;
  PathMode mode_;
  double speed_, turn_rate_, delay_;
  double cycle_ = 0;
};

}  // namespace lasonic::sim
