#pragma once
// Laser glints (beyond the paper; Jörg 1995 sec. 3.4 builds the tactical map from complementary
// echoes alone): a glass pane that the laser saw face-on.
//
// Why: a pane sends the laser beam straight back only within a few degrees of normal incidence
// and lets it through everywhere else. Driving along a pane, the scanner therefore sees a short
// piece of it -- the glint, centred on the foot of the perpendicular -- and the wall behind it
// to either side; the glint moves along the pane with the robot. Once the robot turns away or
// meets the pane at an angle, the laser sees through all of it, and a far glass wall heard
// face-on (beyond the hypothetical scan's 2.20 m, or explained by the glint itself) is never
// complementary: neither the Radar Map of the moment nor the tactical map holds the pane that
// the laser located, seconds earlier, along the whole stretch it drove past.
//
// A candidate is a segment of the scan (cut with the Radar Map's rules but no minimum length:
// within 2.2 m a glint is shorter than the Radar Map's 0.15 m; NavigatorStage) that is (1) seen
// only near its normal: each of its ends within max_incidence of it, from the scanner; (2) flat:
// its fit's RMS within range noise; (3) near: both ends within max_range, the published tactical
// window's half width (what the pilot and the lines read; a pane farther away glints again as the
// robot comes nearer), where the window (1) admits, 2 r tan(max_incidence), is still pane-sized
// rather than a far wall's width; (4) alone: no other segment ends within end_gap of either end
// (a surface that stays in view beside it -- a wall's next piece -- goes on; a glint's pane goes
// on unseen); (5) made of at least min_points returns.
//
// A round thing -- a person, a pillar -- always shows the laser a short piece facing it squarely,
// flat within range noise at the middle of its chord: a candidate too. What only a plane's glint
// does is move with the robot: it sits at the foot of the perpendicular, so when the robot has
// moved by d along the pane, the glint has moved by d along the same line. A pillar's or a
// standing person's facing piece stays where it is; a walking person's moves with their own
// velocity, and stays on no fixed line when they come nearer. So a candidate is a glint only when
// an earlier candidate within confirm_s lies on the same line (within line_tol) and the robot's
// foot on that line has moved by at least min_move since, with the candidate's middle moved by
// the same amount (within move_tol). Each return of a glint is then one hit in the tactical AGM,
// spread evenly along the segment: the weight of a complementary echo each, so a pane glinted at
// over a few scans reaches G_T as echoes that agree do. A robot standing still confirms nothing.
// What may still pass -- a person walking alongside at the robot's speed, a box face seen
// squarely -- is measured in the README ("Method", step 6).
#include <cstdint>
#include <deque>
#include <vector>

#include "complement/radar_map.hpp"
#include "core/config.hpp"
#include "core/geometry.hpp"

namespace lasonic {

struct LaserGlintParams {
  double max_incidence = 10 * geom::kPi / 180;  // [rad] ends seen within this of the normal (0: off)
  double max_rms = 0.02;          // [m] fit RMS of a flat pane (range noise ~1 cm)
  double end_gap = 0.15;          // [m] no other segment ends this near either end
  int min_points = 4;             // returns in the segment
  double max_range = 5.0;         // [m] both ends within this of the robot
  double confirm_s = 1.0;         // [s] how far back an earlier candidate may be
  double min_move = 0.06;         // [m] the foot's move that tells a glint from a standing thing
  double move_tol = 0.04;         // [m] the middle's move agrees with the foot's within this
  double line_tol = 0.03;         // [m] both candidates on one line within this
  bool enabled() const { return max_incidence > 0; }
};

// Reads a `laser_glints:` section over `base`. Throws ConfigError naming the key path.
LaserGlintParams laserGlintParams(const Config& c, LaserGlintParams base = {});

// The candidates of one Radar Map (segments in the odometry frame) seen from `viewpoint` (the
// robot at the scan, same frame): rules (1)-(5). Non-finite segments and viewpoints give nothing.
std::vector<complement::RmSegment> glintCandidates(const std::vector<complement::RmSegment>& radar_map,
                                                   const geom::Vec2& viewpoint, const LaserGlintParams& p);

// One point per return of each glint, evenly spread along it (the returns' own places within
// the segment's fit, at most 64 per glint): the tactical AGM's hits.
std::vector<geom::Vec2> glintHits(const std::vector<complement::RmSegment>& glints);

// The candidates of successive Radar Maps, and which of them are confirmed glints.
class GlintTracker {
 public:
  explicit GlintTracker(const LaserGlintParams& p = {}) : p_(p) {}
  // One Radar Map at utime from viewpoint: its candidates, kept for later maps, and returns those
  // confirmed by an earlier one. A map not later than the previous one forgets the earlier ones.
  std::vector<complement::RmSegment> update(int64_t utime, const geom::Vec2& viewpoint,
                                            const std::vector<complement::RmSegment>& radar_map);
  void clear() { seen_.clear(); }

 private:
  struct Seen {
    int64_t utime = 0;
    geom::Vec2 viewpoint;
    complement::RmSegment seg;
  };
  bool confirms(const Seen& earlier, const geom::Vec2& viewpoint, const complement::RmSegment& now) const;
  LaserGlintParams p_;
  std::deque<Seen> seen_;
};

}  // namespace lasonic
