#pragma once
// The thin layer between LCM messages (used as plain data here, no transport) and the
// algorithms' structs: input validation that names the offending field, and output filling.
// Bad input is never fatal: a bad reading becomes a gap (laser) or Invalid (sonar), a message
// that cannot be used at all is refused; every problem is returned for the caller to report.
#include <optional>
#include <string>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>

#include "complement/complement.hpp"
#include "complement/radar_map.hpp"

namespace lasonic::complement {

struct InputProblem {
  std::string counter;  // e.g. "rejected.sonar_range"
  std::string message;  // e.g. "SONAR_RING.range[2] = nan"
};

// Limits on incoming values, one per quantity, for every stage that reads them (the caps on
// array lengths are in lcmio/lengths.hpp).
namespace input_limits {
// [m] No sonar hears this far (the ring's own range_max is 3 m; a Polaroid transducer's 10.7 m):
// a range beyond it is a malformed reading, whatever the message claims as range_max.
inline constexpr double kMaxSonarRange = 50.0;
// [m] No transducer hears an echo nearer than this: it rings after its own pulse (an HC-SR04's
// 2 cm, a Polaroid 6500's 15 cm), so a nearer range (0, some drivers' "no reading") is no echo
// and is refused, not put at the robot's skin.
inline constexpr double kMinSonarRange = 0.02;
// [m] The longest-range laser scanners reach a few hundred metres: a larger range_max is not a
// scanner's.
inline constexpr double kMaxLaserRange = 1000.0;
// [us] A reading's time within its scan (offset_us): a rotating 2D scanner sweeps in 0.01-0.2 s
// (100-5 Hz), so a reading a second or more after the scan's first is not that scan's; it would
// put the Radar Map's time, and the pose it is seen from, where no odometry is.
inline constexpr int32_t kMaxLaserOffsetUs = 1000000;
// Whether a reading's offset_us lies within its scan's sweep; a reading outside it is rejected
// (and is neither a point nor a time of its scan, wherever the message is read).
inline constexpr bool offsetInSweep(int64_t offset_us) { return offset_us >= 0 && offset_us <= kMaxLaserOffsetUs; }
// [m] Positions (odometry, mounts, end points, sensor poses): 1000 km from the frame's origin is
// beyond any robot's local frame, and keeps squares and products of coordinates (line fits,
// intersections) far from overflow.
inline constexpr double kMaxCoordinate = 1e6;
}  // namespace input_limits

// The input checks every stage shares, with one set of counter names:
//   rejected.odometry_nan        ODOMETRY with a non-finite pose, v or omega (field named), or a
//                                position farther than kMaxCoordinate
//   rejected.laser_scan / laser_range / laser_flag / laser_offset   (laserScanFromMessage)
//   rejected.sonar_ring / sonar_id / sonar_mount / sonar_range      (sonarGroupFromMessage)
//   rejected.complement_class / complement_nan / complement_range   (complementFromMessage)
// and, in stages/inputs.hpp, time going backwards: rejected.<odometry|laser|complement>_backwards.

struct OdometryInput {
  int64_t utime = 0;
  geom::Pose2 pose;
  double v = 0, omega = 0;
};
// nullopt (and a problem naming the field) when any value is not finite.
std::optional<OdometryInput> odometryFromMessage(const odometry_t& m, std::vector<InputProblem>& problems);

// One reading of SONAR_COMPLEMENT as a consumer (pilot, navigator) may use it.
struct ComplementInput {
  int sensor_id = 0;
  SonarClass cls = SonarClass::Invalid;
  // Complementary (and outside-view) readings: usable = finite range and end point, range in
  // [0, kMaxSonarRange]; the sensor pose when it is finite. Redundant and false readings (an echo
  // at or beyond the hypothesis): usable = finite range in [0, kMaxSonarRange] and hypothetical
  // range, and a plausible sensor pose (what the sound passed through: tactical/pass_through.hpp).
  // Unverifiable readings (no echo, or an echo beyond the hypothesis' range limit): usable = a
  // fresh Radar Map (the message's radar_map_stale = 0), a hypothetical range in [0, range_limit]
  // and a plausible sensor pose; `echo` tells an echo beyond the limit (a finite end point) from
  // none (then `range` is the hypothesis: as far as the sound is known to have gone).
  bool usable = false;
  bool echo = true;  // false: an unverifiable reading without an echo
  // An unverifiable echo of a group without a recent Radar Map (radar_map_stale: the laser lost,
  // or not yet scanning) within the hypothesis' range limit, with a finite range, end point and
  // plausible pose, all kept; `usable` stays false (no hypothesis: no sound known to have passed
  // anything).
  bool unverified_echo = false;
  double range = 0;
  double hypothetical_range = 0;  // [m] (all classes; an outside-view echo's: the newest lines')
  geom::Vec2 end{0, 0};
  std::optional<geom::Pose2> sensor_pose;
  double beam_width = 0;  // [rad] the transducer's (the message's); 0: not given, the configured one
};
// Readings with an unknown class are left out (counted); the others keep their order.
std::vector<ComplementInput> complementFromMessage(const complement_t& m, std::vector<InputProblem>& problems);

// nullopt when the scan as a whole is unusable (arrays of different length, no readings, bad
// angles, range limits or mount).
// A clockwise scan (angle_increment < 0: a scanner mounted upside down, or one that turns that
// way) becomes a LaserScan in counter-clockwise order: its readings from the last to the first,
// each with its own time, so the LaserScan's readings always run by increasing angle (and a
// problem names the index the sender gave the reading).
std::optional<LaserScan> laserScanFromMessage(const laser_scan_t& m, std::vector<InputProblem>& problems);
// The same into `out` (its readings' storage reused, scan after scan); false where
// laserScanFromMessage gives nothing (then `out` holds nothing of use).
bool laserScanFromMessageInto(const laser_scan_t& m, std::vector<InputProblem>& problems, LaserScan& out);
// `m` with its readings in counter-clockwise order: for angle_increment < 0 (and arrays of
// nranges' length) the arrays reversed, angle_min the last reading's angle and the increment
// positive; otherwise a plain copy. Reading i's time stays utime + offset_us[i].
void counterClockwiseCopy(const laser_scan_t& m, laser_scan_t& out);
// laserScanFromMessage(m, problems) into `slot` (a LaserScan kept from message to message, its
// storage reused; empty where the message gives nothing); returns `slot`.
const std::optional<LaserScan>& laserScanFromMessageInto(const laser_scan_t& m, std::vector<InputProblem>& problems,
                                                         std::optional<LaserScan>& slot);
SonarGroup sonarGroupFromMessage(const sonar_ring_t& m, std::vector<InputProblem>& problems);

line_map_t radarMapToMessage(const RadarMap& rm);
hypothetical_scan_t hypothesisToMessage(const GroupComplement& g, const ComplementParams& p);
complement_t complementToMessage(const GroupComplement& g, const ComplementParams& p);
// The same into a message kept from group to group (every field set; the arrays' storage reused).
void hypothesisToMessageInto(hypothetical_scan_t& m, const GroupComplement& g, const ComplementParams& p);
void complementToMessageInto(complement_t& m, const GroupComplement& g, const ComplementParams& p);

}  // namespace lasonic::complement
