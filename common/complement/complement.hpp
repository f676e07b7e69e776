#pragma once
// Complement extraction (Jörg 1995, sec. 3.1; README "Method", step 3): each real sonar reading, placed
// in global coordinates (the Segment Map), is superposed on the hypothetical scan of the Radar
// Map; only readings shorter than the hypothesis carry information the laser lacks.
//
// Stale Radar Map policy: a reading can only be verified against a Radar Map that describes the
// scene at its firing time. With no Radar Map yet (before the first laser scan) or one older than
// max_rm_age_us, every reading is classified Unverifiable and the result is flagged stale: a
// missing laser must never make all sonar readings look complementary. The hypothesis is still
// computed on the newest Radar Map (none: the limit) so that a viewer shows what was compared.
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "complement/hypothetical_scan.hpp"
#include "complement/radar_map.hpp"
#include "core/geometry.hpp"
#include "core/physics.hpp"

namespace lasonic::complement {

class RadarMapMemory;  // complement/radar_map_memory.hpp

// Values equal to complement_reading_t::CLASS_* (the message layer relies on it).
enum class SonarClass : int8_t { Complementary = 0, Redundant = 1, False = 2, Unverifiable = 3, Invalid = 4, OutsideView = 5,
                              SeenBefore = 6 };
const char* className(SonarClass c);  // "complementary", ... (counter names)

// README "Method", step 3, with real range r, hypothesis h and tolerance tol:
//   no echo, or r > limit  -> Unverifiable
//   r < h - tol            -> Complementary
//   |r - h| <= tol         -> Redundant
//   r > h + tol            -> False (specular reflection)
SonarClass classify(double real, bool no_echo, double hyp, double tol, double limit);

// Segment Map: the reading's global point on the acoustic axis at the real range.
inline geom::Vec2 segmentMapPoint(const geom::Pose2& sensor, double range) {
  return sensor.transform({range, 0.0});
}

struct SonarReading {
  int sensor_id = 0;
  double range = 0;        // [m] meaningless when no_echo
  bool no_echo = false;
  geom::Pose2 mount;       // robot frame
  bool valid = true;       // false: rejected by the message layer -> Invalid
  double beam_width = 0;   // [rad] the transducer's full opening (SONAR_RING); 0: the model's
};

struct SonarGroup {
  int64_t utime = 0;  // [us] firing time
  int group = 0;
  std::vector<SonarReading> readings;
};

struct ComplementParams {
  IdealSonarModel model;
  // [m] measured on fig4_room/fig7_lab: above ~0.10 invisible recall falls, below it sonar and
  // Radar Map noise turn wall echoes complementary.
  double tolerance = 0.10;
  int64_t max_rm_age_us = 500'000;      // older Radar Map -> stale
  // A redundant or false reading whose echo arc (its range, across its beam) reaches where the
  // scanner cannot see (behind a 270 deg laser) is OutsideView instead: the echo may come from
  // there, where the laser has nothing to say, so the levels use it as a complementary echo.
  // false: the paper's rule everywhere. A full-circle scanner sees everywhere: no effect.
  bool outside_view_complementary = true;
  // A complementary reading at the range a ping of another sensor of the same group would read
  // by way of a right-angled corner of the Radar Map (twice reflected: RadarMap::corners,
  // crosstalkRange) is that crosstalk, explained by what the laser sees: Redundant. false: the
  // paper's rule (such a reading stays complementary).
  bool crosstalk_corners = true;
  // Late echoes (beyond the paper; paper: such a reading stays complementary). A ping of an
  // earlier firing group that met a laser-seen wall beyond the sonar's range comes back while
  // this group listens, at half its path less half the way sound went between the two
  // firings, and reads short. A complementary reading within `tolerance` of the first such
  // arrival the Radar Map predicts (firstLateEcho) is that echo: redundant (counted
  // redundant.late_echo). Pings fired up to late_echo_window_us before the group are followed.
  bool late_echoes = true;
  int64_t late_echo_window_us = 65'000;
};

// A ping fired before the group being classified: when, from where (global frame, acoustic
// axis along theta) and how wide its beam.
struct Ping {
  int64_t utime = 0;
  geom::Pose2 sensor;
  double beam_width = 0;  // [rad]
};

// Half the length of the path from a transducer at e to one at p by way of segment s as a
// mirror (|e' - p| / 2, e' = e mirrored in s's line), if both lie in front of the same face,
// the mirror point lies on s, and the path leaves e and reaches p within their lobes (unit axes
// axis_*; cos_lobe: the cosine of the lobe's half angle); else nullopt.
std::optional<double> mirrorHalfPath(const geom::Segment& s, const geom::Vec2& e, const geom::Vec2& axis_e,
                                     const geom::Vec2& p, const geom::Vec2& axis_p, double cos_lobe);

// The range at which a listener (global pose, beam width) firing at `utime` reads the first
// late echo the Radar Map predicts: over the earlier pings fired within window_us before utime,
// and every Radar Map line (as a mirror, mirrorHalfPath) and right-angled corner (sending the
// sound back parallel: the half path |2v - e - p| / 2), with the path within one full opening
// of both axes (the main lobe and the first side lobes), the least positive (half path - half
// the distance sound travelled since that ping). nullopt: none predicted.
std::optional<double> firstLateEcho(const geom::Pose2& listener, double listener_beam, int64_t utime,
                                    const std::vector<Ping>& earlier, const RadarMap& rm, int64_t window_us);

// The range a listener at p reads for a ping sent from e by way of the corner: half the length of
// the path e -> corner -> p, |(2v - e) - p| / 2; nullopt if either lies outside the corner or
// the path leaves or reaches either transducer outside its lobe (heading along `axis_*`, unit
// vectors): the corner sends the sound back parallel to how it came, so both ends of the path
// point along 2v - e - p, whose cosine with each axis must exceed cos_lobe (0: from in front).
std::optional<double> crosstalkRange(const RmCorner& c, const geom::Vec2& e, const geom::Vec2& axis_e,
                                     const geom::Vec2& p, const geom::Vec2& axis_p, double cos_lobe = 0.0);

// True if the scanner's view covers the whole arc at `range` across the sensor's beam.
bool arcSeen(const geom::Pose2& sensor, double range, double beam_width, const LaserView& view);

struct ClassifiedReading {
  int sensor_id = 0;
  SonarClass cls = SonarClass::Invalid;
  double range = 0;
  double hypothetical_range = 0;  // NaN when the sensor pose is unknown
  double beam_width = 0;          // [rad] the ideal beam its hypothesis used
  std::optional<geom::Pose2> sensor_pose;  // global, at firing time
  std::optional<geom::Vec2> end;           // Segment Map point (echo readings only)
  bool by_pole = false;  // Redundant because it matched a pole of the Radar Map (poleEcho)
  bool by_crosstalk = false;  // Redundant because it matched crosstalk by way of a corner
  bool by_late_echo = false;  // Redundant because it matched a late echo of an earlier ping (firstLateEcho)
  // Its echo arc lies wholly inside the Radar Map's view (arcSeen; true without an echo or a map).
  bool arc_seen = true;
  // Its echo arc lies (partly) where the newest scan does not look, but an earlier one saw it:
  // judged with that scan's lines too (RadarMapMemory), not outside_view.
  bool seen_before = false;
  double seen_before_range = 0;  // [m] the hypothesis on the newest and that scan's lines
};

struct GroupComplement {
  int64_t utime = 0;
  int group = 0;
  int64_t radar_map_utime = 0;  // 0: none
  bool radar_map_stale = true;
  std::vector<ClassifiedReading> readings;
};

// Pairs of sensor ids of one firing group that hear each other's pings: a wall returns one
// transducer's ping to the other from the point midway between their axes, and a near wall
// answers up to about one full opening off a transducer's axis (its side lobes: README "Sonar",
// +-31 deg for a 30 deg transducer within 1 m). So a pair whose axes lie no farther apart than
// the sum of their openings (a reading's own beam, else `default_beam_width`) crosstalks. The listener
// reads the mirror path, shorter than the nearest wall point its own beam covers, so the
// reading passes as complementary; a ring fires such sensors in different groups.
struct BeamOverlap {
  int a = 0, b = 0;  // sensor ids, a < b
  double apart = 0;  // [rad] between their axes
  double width_a = 0, width_b = 0;  // [rad] the openings compared
};
std::vector<BeamOverlap> overlappingBeams(const SonarGroup& g, double default_beam_width);

// True if the Radar Map cannot verify readings fired at `utime` (missing or too old).
bool radarMapStale(const RadarMap* rm, int64_t utime, int64_t max_rm_age_us);

// Classifies one firing group. robot_pose: the robot's global pose at the firing time (nullopt:
// unknown, every reading Invalid). rm: the newest Radar Map, or nullptr.
// earlier: the pings fired before g (PingHistory::before), for late echoes.
GroupComplement extractComplement(const SonarGroup& g, const std::optional<geom::Pose2>& robot_pose,
                                  const RadarMap* rm, const ComplementParams& p,
                                  const std::vector<Ping>& earlier = {}, const RadarMapMemory* memory = nullptr);

// The pings of the groups classified so far that late echoes may still come from.
class PingHistory {
 public:
  // The pings fired within window_us before utime (the group about to be classified).
  const std::vector<Ping>& before(int64_t utime, int64_t window_us);
  // A classified group's pings: every reading whose transducer pose was known (and finite).
  void add(const GroupComplement& g);
  void clear() { pings_.clear(); }

 private:
  std::deque<Ping> pings_;
  std::vector<Ping> out_;
};

}  // namespace lasonic::complement
