#pragma once
// Histogramic In-Motion Mapping (HIMM; J. Borenstein and Y. Koren, "Histogramic in-motion
// mapping for mobile robot obstacle avoidance", IEEE Trans. Robotics and Automation 7(4), 1991):
// the sonar-only baseline of the evaluation (README "Evaluation", baselines).
//
// Each cell holds a certainty value CV in [0, cv_max]. Per sonar reading with an echo:
// - the one cell on the acoustic axis at the measured range gets CV += increment (I+ = 3), and
//   then the growth-rate operator (GRO): its CV becomes the 3 x 3 mask sum with weight 1 for
//   itself and 0.5 for each of its 8 neighbours, CV += floor(0.5 * sum of the neighbours' CV),
//   so a cell next to known obstacles grows fast and an isolated one slowly; clamped to cv_max;
// - every other cell the acoustic axis passes through between the sensor and that cell gets
//   CV -= decrement (I- = 1), not below 0.
// A reading without an echo decrements the cells along the whole axis up to range_max when
// no_echo_clears is set (nothing answered on the axis within the sensor's range).
// Read out: a cell with CV >= threshold is an obstacle.
#include "baselines/grid_window.hpp"

namespace lasonic::baselines {

struct HimmParams {
  WindowParams window;
  int increment = 3;          // I+ (Borenstein & Koren)
  int decrement = 1;          // I-
  int cv_max = 15;            // CVmax (CVmin = 0)
  bool growth_rate_operator = true;
  int threshold = 4;          // CV >= this: an obstacle (more than one increment alone)
  bool no_echo_clears = true;
};
// Reads a `sonar_himm:` section over `base`. Throws ConfigError naming the key path.
HimmParams himmParams(const Config& c, HimmParams base = {});

class HimmGrid {
 public:
  explicit HimmGrid(const HimmParams& p);
  const HimmParams& params() const { return p_; }

  bool follow(const geom::Vec2& robot) { return w_.follow(robot); }
  // One reading; sensor: global pose, acoustic axis along theta. Non-finite input is ignored.
  void insert(const geom::Pose2& sensor, double range, bool no_echo, double range_max);

  // CV of the cell holding p; -1 outside the window.
  int cv(const geom::Vec2& p) const;
  const OccupancyWindow& occupancy() const { return w_.occupancy(); }

 private:
  void set(size_t i, int v);
  HimmParams p_;
  GridWindow<uint8_t> w_;
};

}  // namespace lasonic::baselines
