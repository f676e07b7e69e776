#pragma once
// What every stage does with its inputs before its own work, in one place: report the problems
// the message checks found (complement/messages.hpp), add ODOMETRY to the pose history, and drop
// messages that go back in time. Counter names:
//   rejected.odometry_nan, rejected.odometry_backwards, odometry_duplicates (not an error),
//   rejected.<what>_backwards for LASER_SCAN (laser), SONAR_COMPLEMENT (complement), ...
#include <cstdint>
#include <optional>
#include <vector>

#include <lasonic/odometry_t.hpp>

#include "complement/messages.hpp"
#include "core/geometry.hpp"
#include "core/pose_history.hpp"
#include "lcmio/node.hpp"
#include "lcmio/time_reset.hpp"
#include "operational/echo_placer.hpp"
#include "operational/sound_passed.hpp"

namespace lasonic {

void reportProblems(Node& node, const std::vector<complement::InputProblem>& problems);

// What a firing group's sound went through (operational/sound_passed.hpp): each usable reading's
// beam out to its range, for a false one (longer than the hypothesis: a mirror there turned the
// sound away) to the hypothesis; an unverifiable one (nothing answered within the range limit)
// to the hypothesis, if `beyond_limit` (an echo from beyond the limit) or `silence` (no echo) let
// it count. beam_width [rad]: for readings whose message gave none.
std::vector<Sounding> soundingsOf(const std::vector<complement::ComplementInput>& readings, double beam_width,
                                  bool beyond_limit, bool silence);

// Checks ODOMETRY and adds it to `poses`; returns it when it was added (not a duplicate, not
// older than the newest, all finite).
std::optional<complement::OdometryInput> acceptOdometry(Node& node, PoseHistory& poses, const odometry_t& m);

// True when utime is newer than `last` (or there is none); else reports
// rejected.<what>_backwards naming the channel and both times. The caller moves `last` on once
// the message was used.
bool isNewer(Node& node, const std::optional<int64_t>& last, int64_t utime, const char* channel, const char* what);

// Every input's time first: Bad = outside [0, kMaxUtime] (reported as rejected.time; drop the
// message); Restarted = the sources' clock restarted (TimeReset; counted under time_resets and
// logged: start afresh, then use the message); HeldAhead = more than a second ahead of every
// input (TimeReset::admit; counted under time.held_ahead.<CHANNEL>; drop it: the channel's next message
// tells a stepped clock, time.steps_forward, from a stray time, rejected.time_ahead); Ok.
enum class ClockCheck { Ok, Restarted, HeldAhead, Bad };
ClockCheck checkClock(Node& node, TimeReset& clock, int64_t utime, const char* channel);

// OdometryOutage: a map that cannot be made for want of the robot's pose is counted by its
// stage (sector_map.no_odometry, publish.no_odometry); once odometry that was flowing has been
// silent for kLostUs, that is an outage, reported once as an error (odometry.lost: "no maps
// until it returns") and logged when it ends, so a dead odometry driver is not only a counter.
// Before the first ODOMETRY (start-up in any order) nothing is reported.
class OdometryOutage {
 public:
  static constexpr int64_t kLostUs = 500'000;  // the sector map's staleness limit for its sensors
  // A map for time `utime` was not made (no pose): `what` names it in the message.
  void missing(Node& node, const PoseHistory& poses, int64_t utime, const char* what);
  // A map was made again.
  void present(int64_t utime);

 private:
  std::optional<int64_t> since_;  // newest odometry time when the outage was reported
  int64_t missed_ = 0;
};

// SensorOutage: a sensor that was delivering and has gone stale for the stage (older than the
// stage's limit for it: SECTOR_MAP's laser_stale, a Radar Map too old to verify a ring) and
// silent for more than two of its own latest intervals (it missed a datum at its own pace: a
// 1 Hz scanner is not lost while the stage still times it against the 5 Hz limit) is an outage,
// reported once as an error (`counter`, e.g. laser.lost, saying what the stage does meanwhile)
// and logged when the sensor is back, so a dead driver is not only a flag in the output or a
// count per reading. Before the sensor's second datum (no interval yet) nothing is reported.
class SensorOutage {
 public:
  // At `utime` the sensor's newest datum is from `newest` (none yet: nullopt) and `stale` says
  // whether the stage finds it too old.
  void update(Node& node, int64_t utime, std::optional<int64_t> newest, bool stale, const char* counter,
              const char* channel, const char* meanwhile);
  void reset() { *this = SensorOutage{}; }

 private:
  std::optional<int64_t> since_;  // the newest datum's time when the outage was reported
  std::optional<int64_t> seen_;   // the newest datum's time at the last update
  int64_t interval_us_ = 0;       // between the last two data (0: not yet two)
};

// SONAR_COMPLEMENT's readings as the AGM's EchoPlacer takes them: a usable complementary reading
// is an echo (fired at utime; without a known sensor pose it is placed at its axis end point).
// seen_before: whether a SeenBefore reading is an echo (the navigator's) or not (the pilot's);
// unverified: whether an unverified echo (no recent Radar Map) is (the pilot's stale_radar_map).
// Only a Complementary reading is `checked` (the newest scan could have seen what it heard).
std::vector<GroupReading> toGroupReadings(const std::vector<complement::ComplementInput>& readings, int64_t utime,
                                          bool seen_before = false, bool unverified = false);

// True if one of `laser` (global returns: the sector map's) lies within half of `sector_width`
// [rad] of the axis of `sensor` (global pose) and within `tolerance` of `range` from it: the
// surface a SeenBefore echo came from is reported in the echo's own sector already.
bool laserReportsEcho(const std::vector<geom::Vec2>& laser, const geom::Pose2& sensor, double range, double tolerance,
                      double sector_width);
// True if one of `laser` lies within half of `sector_width` [rad] of the axis of `sensor`, at any
// range: the laser reports something in the echo's own sector.
bool laserInSector(const std::vector<geom::Vec2>& laser, const geom::Pose2& sensor, double sector_width);

}  // namespace lasonic
