#pragma once
// ComplementStage: complement extraction (README "Method", steps 1-3) on a lasonic::Node.
//
// In:  ODOMETRY (pose history), LASER_SCAN, SONAR_RING (one firing group).
// Out: RADAR_MAP per laser scan; SONAR_HYPOTHESIS and SONAR_COMPLEMENT per firing group.
// Counters (PROCESS_STATUS): class.<complementary|redundant|false|unverifiable|invalid|
// outside_view|seen_before> (seen_before: complement/radar_map_memory.hpp),
// unverifiable.stale_radar_map, redundant.pole (of the redundant ones, those a pole of the
// Radar Map explained: complement/pole_tracker.hpp), redundant.crosstalk (those a right-angled
// Radar Map corner explained as another sensor's ping: rightAngleCorners), redundant.late_echo
// (those it explained as a late echo of an earlier group's ping: firstLateEcho), rejected.* for
// every kind of bad input, ring.overlapping_beams (pairs of sensors fired in one group close
// enough to hear each other's pings, complement::overlappingBeams; each pair reported once:
// their crosstalk passes as complementary, a ring configuration to fix).
//
// Time comes only from the messages, never from the wall clock, so a replay is deterministic.
//
// Policies:
// - Before the first laser scan, or when the newest Radar Map is more than rm_max_age_s (or
//   rm_max_age_scans of the laser's own periods, where longer) away from a firing, the Radar Map
//   is stale: the group is published with radar_map_stale = 1 and every reading is Unverifiable
//   (counted under unverifiable.stale_radar_map). Without the laser nothing can be verified, and
//   treating "no map" as "empty map" would make every echo complementary. A laser that had been
//   scanning and goes stale so is an outage: laser.lost, once (an error), and a log line when
//   it is back.
// - Bad input is reported (node.reportError, naming the field) and never stops the process:
//   ODOMETRY older than the newest is dropped; a LASER_SCAN not newer than the previous one is
//   dropped; bad laser readings become gaps; a scan with no usable reading (e.g. no odometry
//   for its time) leaves the previous Radar Map in place; bad sonar readings (NaN, negative or
//   huge range, sensor id outside [0, num_sensors), non-finite mount) and every reading of a
//   group fired when no odometry is known are classified Invalid.
// - An input whose time jumps back by more than TimeReset::kJumpUs (a restarted simulator or
//   driver, a looping log) resets the stage to its start state (counted: time_resets).
// - A laser scan or firing group whose time disagrees with the odometry's (StampAgreement: a
//   driver's computer whose clock runs ahead or behind) is reported and used as it is:
//   time.<laser|sonar>_<ahead_of|behind>_odometry, at most once per 5 s of message time each.
#include "complement/complement_config.hpp"
#include "complement/radar_map.hpp"
#include "complement/shared_placement.hpp"
#include "core/interval_window.hpp"
#include "core/pose_history.hpp"
#include "core/stamp_agreement.hpp"
#include "lcmio/node.hpp"
#include "lcmio/time_reset.hpp"
#include "stages/inputs.hpp"

#include <lasonic/complement_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>

#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>

namespace lasonic {

using complement::ComplementConfig;
using complement::complementConfig;

class ComplementStage {
 public:
  ComplementStage(Node& node, const ComplementConfig& cfg);
  // Where the pilot stage runs in the same process (lasonic-replay): the scan's placed readings
  // shared with it (complement/shared_placement.hpp; the same result, computed once).
  void sharePlacement(std::shared_ptr<complement::SharedPlacement> placement) { placement_ = std::move(placement); }

 private:
  void onOdometry(const odometry_t& m);
  void onLaserScan(const laser_scan_t& m);
  void onSonarRing(const sonar_ring_t& m);
  // Every input first: false for an absurd time (drop the message); a clock that jumped back
  // (lcmio/time_reset.hpp) -> start afresh.
  bool timeOk(int64_t utime, const char* channel);

  Node& node_;
  ComplementConfig cfg_;
  PoseHistory poses_;
  std::optional<complement::RadarMap> radar_map_;
  complement::PoleTracker poles_;
  complement::RadarMapMemory rm_memory_;  // earlier scans' lines where the newest does not look
  std::optional<int64_t> last_scan_utime_;
  std::optional<int64_t> last_ring_utime_;
  // The Radar Map's age limit: the configured one, or rm_max_age_scans of the laser's periods.
  ScanPeriod scan_period_;
  int64_t rm_max_age_base_us_ = 0;
  SensorOutage laser_outage_;  // (reported once per outage: laser.lost)  // (groups fire one after another: each is newer)
  TimeReset clock_;
  StampAgreement laser_stamps_, sonar_stamps_;  // each driver's clock against the odometry's
  std::shared_ptr<complement::SharedPlacement> placement_;  // null: placed here
  complement::PingHistory pings_;  // for late echoes
  std::set<std::pair<int, int>> overlapping_reported_;  // sensor pairs with overlapping beams, reported
  std::optional<complement::LaserScan> own_scan_;  // (without placement_: the decoded scan, storage reused)
  // The per-group channels' names made once (16 characters: a heap string for each publish).
  const std::string hypothesis_channel_ = channels::SONAR_HYPOTHESIS, complement_channel_ = channels::SONAR_COMPLEMENT;
  hypothetical_scan_t hyp_msg_{};  // (the two per-group messages, every field set per group; storage reused)
  complement_t comp_msg_{};
};

}  // namespace lasonic
