#pragma once
// Scan matching (beyond the paper, whose tactical level keeps its map in the odometry frame):
// the navigator's pose is the odometry corrected by matching each laser scan to the lines of an
// earlier scan, so that what the tactical map remembers stays where it was heard.
//
// Why: the tactical map remembers a glass pane heard face-on for as long as the pose it was
// placed with stays right -- after that, the remembered cell is off its surface: a miss where it
// was and a false alarm where it is now. Dead reckoning drifts with every metre and every turn
// (and an uncalibrated base by per cents of each), so the map had to forget after ~15 m. The
// laser sees walls at 1 cm over metres; two scans a metre apart that share them fix the robot's
// motion between them far better than the wheels do, wherever the walls constrain it.
//
// The rule, per scan:
// - The scan's readings, placed with the odometry (each at its own time), are taken into the
//   navigator's frame by the current correction C (navigator frame <- odometry frame).
// - Consecutive returns within point_spacing of a cluster's first are matched as their mean,
//   weighted by their number: a near wall's returns lie a centimetre apart, and along a wall a
//   return's residual and Jacobian are linear in its position, so the mean carries the
//   cluster's information at a fraction of the cost.
// - They are matched to the lines of the keyframe, an earlier scan's segments (at least
//   min_line_length long: walls, not people) already in the navigator's frame: point-to-line
//   Gauss-Newton (Censi's PL-ICP without its second-order model) over a rigid motion about the
//   robot, pairs re-found each iteration, each point paired with the nearest line within `gate`
//   (along the line at most `gate` beyond its ends), residuals weighted by a Cauchy kernel of
//   scale point_sigma, so a person or a changed door costs little.
// - A Gaussian prior holds the motion at the odometry's: its spread grows with what was driven
//   and turned since the keyframe (prior_*). Where the lines do not constrain a direction (a
//   straight corridor, along its axis), the prior keeps the odometry's motion there.
// - With at least min_pairs pairs the motion corrects C; otherwise C stays (odometry alone).
// - The scan becomes the new keyframe once the robot has driven keyframe_distance or turned
//   keyframe_turn since the keyframe, or when the match failed: a keyframe is matched against
//   from many poses, so its errors do not add up scan by scan.
//
// Pure: no LCM, no clock. The same scans give the same correction, bit for bit.
#include <cstdint>
#include <vector>

#include "complement/radar_map.hpp"
#include "core/config.hpp"
#include "core/geometry.hpp"
#include "core/odometry_error.hpp"

namespace lasonic {

struct ScanMatchParams {
  bool enabled = true;
  double point_sigma = 0.02;      // [m] a point's distance from its line: range noise + line fit
  double gate = 0.3;              // [m] pair a point with a line only this near
  double max_range = 8.0;         // [m] readings beyond: their bearing error is a cm per 2 m
  double min_line_length = 1.0;   // [m] keyframe lines at least this long (a person is 0.5 m across)
  double max_line_rms = 0.03;     // [m] ... and this flat
  int min_pairs = 40;             // fewer pairs: no correction for this scan
  double point_spacing = 0.1;     // [m] returns within this of a cluster's first match as their mean
  int iterations = 8;
  // A match constrains the pose when the returns alone (without the prior) fix every direction
  // of the position to constrained_trans and the heading to constrained_heading (1 sigma).
  double constrained_trans = 0.01;    // [m]
  double constrained_heading = 0.005; // [rad]
  double keyframe_distance = 1.0; // [m] a new keyframe after this much driving ...
  double keyframe_turn = 20 * geom::kPi / 180;  // [rad] ... or turning
  // The prior's 1-sigma spread of the odometry's motion since the keyframe: per metre driven
  // (trans: along and across, heading: turn per metre) and per radian turned, plus a floor.
  double prior_trans_per_m = 0.05;    // [m/m]
  double prior_heading_per_m = 0.02;  // [rad/m]
  double prior_heading_per_rad = 0.05;// [rad/rad]
  double prior_trans_floor = 0.02;    // [m]
  double prior_heading_floor = 0.01;  // [rad] (0.57 deg)
  // The matched pose's own error, as a random walk (core/odometry_error.hpp): what the tactical
  // AGM's forgetting (forget_sigma_m) assumes instead of the odometry's when matching is on.
  OdometryNoise pose_noise{0.003, 0.002, 0.0005};
};

// Reads a `scan_matching:` section over `base`.
// Throws ConfigError naming the key path.
ScanMatchParams scanMatchParams(const Config& c, ScanMatchParams base = {});

struct LineMatch {
  geom::Pose2 motion;  // rigid motion (navigator frame) that puts the points on the lines
  int pairs = 0;       // returns paired in the last iteration
  bool constrained = false;  // the pairs alone fix the motion (ScanMatchParams::constrained_*)
};

// The rigid motion D that best puts D(points) on `lines` (both in one frame), as a rotation about
// `pivot` and a translation, against a zero-mean prior of 1-sigma sigma_trans [m] (each axis)
// and sigma_heading [rad]. Segments shorter than 1e-6 m and non-finite points are skipped.
// counts[i] (if given) is how many returns points[i] stands for: its weight, and what it adds
// to LineMatch::pairs.
LineMatch matchPointsToLines(const std::vector<geom::Vec2>& points, const std::vector<geom::Segment>& lines,
                             const geom::Vec2& pivot, double sigma_trans, double sigma_heading,
                             const ScanMatchParams& p, const std::vector<int>& counts = {});

class ScanMatcher {
 public:
  explicit ScanMatcher(const ScanMatchParams& p = {}) : p_(p) {}

  struct Result {
    bool matched = false;
    bool new_keyframe = false;
    bool constrained = false;  // matched, and the walls fixed every direction (else the odometry's)
    int pairs = 0;
  };
  // One scan: its readings and segments placed with the odometry (odometry frame), the robot's
  // odometry pose at the scan's end and the scanner's position (odometry frame). Updates the
  // correction.
  Result update(const std::vector<complement::ScanPoint>& points, const std::vector<complement::RmSegment>& segments,
                const geom::Pose2& robot_odometry, const geom::Vec2& scanner_odometry);
  // Navigator frame <- odometry frame.
  const geom::Pose2& correction() const { return c_; }
  // (Disabled: the input itself, bit for bit.)
  geom::Pose2 toNavigator(const geom::Pose2& odometry) const { return p_.enabled ? c_.compose(odometry) : odometry; }
  geom::Vec2 toNavigator(const geom::Vec2& odometry) const { return p_.enabled ? c_.transform(odometry) : odometry; }
  void clear();

 private:
  void takeKeyframe(const std::vector<complement::RmSegment>& segments);

  ScanMatchParams p_;
  geom::Pose2 c_;  // identity until the first match
  bool have_keyframe_ = false;
  std::vector<geom::Segment> key_lines_;  // navigator frame
  double driven_since_key_ = 0, turned_since_key_ = 0;  // [m], [rad] odometry
  geom::Pose2 last_robot_odometry_;
  std::vector<geom::Vec2> points_;  // storage reused: the returns (clusters) matched ...
  std::vector<int> counts_;         // ... and how many returns each stands for
};

}  // namespace lasonic
