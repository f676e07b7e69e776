#pragma once
// NavigatorStage: the tactical level (Jörg 1995 sec. 3.4, "Tactical abstraction level") on a
// lasonic::Node.
//
// In:  ODOMETRY (pose history, speed), SONAR_COMPLEMENT (one firing group), RADAR_MAP, and
//      LASER_SCAN for scan matching and the laser glints (not subscribed when both are off).
// Out, at publish_hz of message time (independent of the pilot's rate):
//      AGM_TACTICAL        the tactical Accumulative Grid Map (grid_map_t)
//      AGM_LINES           the lines generated from it (line_map_t, source SONAR)
//      CURRENT_SENSOR_MAP  the Radar Map's lines and the AGM's lines, tagged by source, each with
//                          the time it was last supported (line_map_t)
// Counters (PROCESS_STATUS): agm.cycles, agm.hits, agm.hits_outside_window, agm.recentred,
// agm.look_weight_hits (the hits the look weight added), agm.laser_join_hits (the laser join's),
// agm.laser_glints and agm.laser_glint_hits (confirmed laser glints and their hits),
// agm.passed_through (cells emptied by pass_through),
// lines.published, publish.no_odometry, rejected.* for every kind of bad input.
//
// Definitions:
// - The tactical AGM is a second AccumulativeGridMap with its own parameters (high G_T, large
//   h_max: stable, moving obstacles suppressed), fed by the same complementary readings as the
//   operational one: one update cycle = one SONAR_COMPLEMENT message; the one cell of each echo
//   is chosen by EchoPlacer against the tactical grid's own evidence. It stays in the odometry
//   frame and follows the robot's translation (pose at the firing time) like the operational AGM.
// - Verification by the next scan (verify_with_next_scan): the complement stage compares a
//   reading with the Radar Map of the scan BEFORE the firing (up to 0.2-0.4 s old). A person
//   walking towards the robot, or into a beam, is then shorter than that map: complementary,
//   rightly for the pilot, but a ghost in a long-memory map. The tactical level is not in a
//   hurry, so it waits for the first scan that started after the firing and keeps only the
//   readings still shorter than the ideal sonar's hypothesis on that map (same beam, limit and
//   tolerance as the complement stage used, from SONAR_COMPLEMENT): what the laser still cannot
//   see (glass, mesh, black surfaces, thin poles). Readings the next scan explains still help
//   their neighbours' bearings. Counted: verify.kept, verify.explained, verify.timed_out.
// - The navigator's frame: with scan matching on, every input (echoes, Radar Map lines, glints,
//   the robot's pose) is taken from the odometry frame into the navigator's by the correction
//   of the newest scan that ended 0.3 s before the input (correctionAt), and so is everything
//   published; robot_pose in the messages is the robot
//   in that frame, so a consumer places their content by its own pose at utime composed with
//   robot_pose's inverse. The tactical AGM forgets by the matched pose's error model after a
//   scan whose match fixed every direction, by the odometry's after one that did not (a straight
//   corridor). Counted: scan_match.matched, scan_match.unmatched, scan_match.unconstrained,
//   scan_match.keyframes.
// - The navigator's clock is the newest SONAR_COMPLEMENT / RADAR_MAP time it has processed; it
//   publishes when that clock has advanced 1/publish_hz since the last publication, with the
//   robot pose interpolated from ODOMETRY at that time (no pose: nothing published, counted).
//   Lines are generated from the robot's position then.
//
// Time comes only from the messages, so a replay is deterministic. Bad input is reported
// (node.reportError, naming the field) and never stops the stage: ODOMETRY and SONAR_COMPLEMENT
// as every stage checks them (stages/inputs.hpp); a RADAR_MAP not newer than the previous one is
// dropped; a Radar Map segment with a non-finite or absurd coordinate is skipped. An input whose
// time jumps back by more than TimeReset::kJumpUs (a restarted simulator, a looping log) resets
// the stage to its start state (counted: time_resets).
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/odometry_t.hpp>

#include "complement/hypothetical_scan.hpp"
#include "complement/messages.hpp"
#include "core/config.hpp"
#include "core/interval_window.hpp"
#include "core/pose_history.hpp"
#include "lcmio/node.hpp"
#include "lcmio/time_reset.hpp"
#include "operational/agm.hpp"
#include "operational/echo_placer.hpp"
#include "operational/sonar_bearing.hpp"
#include "stages/inputs.hpp"
#include "tactical/current_sensor_map.hpp"
#include "tactical/echo_provenance.hpp"
#include "tactical/laser_glint.hpp"
#include "tactical/laser_join.hpp"
#include "tactical/line_generation.hpp"
#include "tactical/pass_through.hpp"
#include "tactical/look_weight.hpp"
#include "tactical/scan_matcher.hpp"

namespace lasonic {

struct NavigatorConfig {
  AgmParams agm = tacticalAgmDefaults();
  EchoPlacementConfig placement = tacticalPlacementDefaults();
  LineGenerationParams lines;
  // [m/s] G_T from the ring (walkerGThreshold, operational/agm.hpp): the slowest walk whose echoes
  // must not reach it, with the ring cycle timed from the groups' own firings (RingGroups) and
  // the beams that overlap at most (maxBeamOverlap) from the readings' sensor poses;
  // agm.g_threshold until the ring is timed. 0: agm.g_threshold always.
  double g_threshold_walking_speed = 0.8;
  // agm.g_threshold was configured: that G_T, whatever the ring.
  bool g_threshold_fixed = false;
  // lines.gp_threshold was not configured: the line candidates are the cells at G_T, whatever G_T
  // the ring gives.
  bool lines_follow_g_threshold = true;
  double publish_hz = 2.0;  // AGM_TACTICAL, AGM_LINES, CURRENT_SENSOR_MAP (message time)
  // Cells per side of AGM_TACTICAL and of the window lines are generated from: the middle of the
  // tactical AGM (which may be larger: it remembers what the robot may come back to, the
  // published part is what the pilot and a display need). 0: the whole AGM.
  int published_size = 100;
  // A complementary reading enters the tactical AGM only if it is still shorter than the ideal
  // sonar's hypothesis on the first Radar Map whose scan started after the firing (false: as
  // classified, against the scan before it). Groups wait at most verify_max_wait_s of message
  // time for that scan; then they go in as classified (the laser is gone).
  bool verify_with_next_scan = true;
  double verify_max_wait_s = 0.5;
  // ... or this many of the laser's own scan periods, timed from its scans (ScanPeriod,
  // core/interval_window.hpp), if that is longer (a slower laser; at most 4 s, within the
  // 5 s of scan-matching corrections kept). 0: verify_max_wait_s always.
  double verify_max_wait_scans = 2.5;
  // [m/s] Look weight (tactical/look_weight.hpp): above this robot speed an echo counts for
  // speed / hit_weight_speed hits in the tactical AGM. 0: one hit per echo (the paper).
  double hit_weight_speed = 0.4;
  // [m/s] ... and below this one an echo counts for speed / hit_weight_low_speed hits: a robot
  // standing or turning on the spot adds none; at hit_weight_speed, G_T counts echoes per metre
  // driven at every speed. 0: off (the paper).
  double hit_weight_low_speed = 0.4;
  // ... and the arc votes too (agm_placement: arc_votes): below hit_weight_low_speed an echo's
  // arc adds speed / hit_weight_low_speed votes, so arcs heard standing or turning on the spot,
  // which coincide instead of crossing, fix no cell along them. false: one vote per arc.
  bool look_weight_votes = false;
  // Footprint (beyond the paper): after every update the cells that lie wholly inside the robot's
  // body (centre within robot_radius - cell_size / sqrt(2) of the robot) are emptied: nothing
  // static stands where the robot is. A phantom echo (a late echo, crosstalk) placed near the
  // robot's path would otherwise be remembered there. false: the paper.
  bool clear_footprint = true;
  // [m] The robot's boundary: the pilot's `pilot.robot_radius` (navigatorConfigFromRoot), one key
  // for both levels.
  double robot_radius = 0.35;
  // Laser join (tactical/laser_join.hpp): a complementary echo of a plane that continues a Radar
  // Map line within the beam's footprint of the line's end also hits the cells from its foot to
  // that end. false: one cell per echo (the paper).
  bool laser_join = true;
  double laser_join_min_line_m = 0.5;  // [m] LaserJoinParams::min_line_length
  // Laser glints (tactical/laser_glint.hpp): each return of a Radar Map segment seen only near
  // its normal, flat and alone, that moved along its own line with the robot -- a glass pane's
  // glint -- is one hit in the tactical AGM, with the next firing group. max_incidence 0: off
  // (the paper: complementary echoes only).
  LaserGlintParams laser_glints;
  // Pass-through (tactical/pass_through.hpp): a remembered cell that the sonar has since heard
  // through, where it would have answered, is emptied. core 0: off (the paper: only time forgets).
  PassThroughParams pass_through;
  // Scan matching (tactical/scan_matcher.hpp): the tactical AGM, its lines and the Current Sensor
  // Map are kept in the navigator's frame, the odometry corrected by matching each LASER_SCAN to
  // an earlier one, and forgotten by the matched pose's error model (scan_matching.pose_*)
  // instead of the odometry's (agm.odometry_*). enabled false: the odometry frame (the paper).
  ScanMatchParams scan_matching;
  // How scan matching and the glints cut LASER_SCAN into segments (jumps, end-point fit): the
  // laser's own rule, the complement's `complement.radar_map` keys (navigatorConfigFromRoot),
  // with laser_glints.min_points as the minimum and no minimum length.
  complement::RadarMapConfig scan_cut;
  // The AGM parameters the stage runs with: agm, its forgetting by the matched pose's error
  // model when scan matching is on.
  AgmParams effectiveAgm() const;

  // The tactical AGM's defaults (the shipped configuration; reasons in deploy/config/lasonic.yaml).
  static AgmParams tacticalAgmDefaults();
  static EchoPlacementConfig tacticalPlacementDefaults();
};
// Reads the `navigator:` section. Throws ConfigError naming the key path.
NavigatorConfig navigatorConfig(const Config& navigator_section);
// The same from the whole configuration: `navigator:`, and the laser's cut from
// `complement.radar_map` (what lasonic-navigator and lasonic-replay read).
NavigatorConfig navigatorConfigFromRoot(const Config& root);

class NavigatorStage {
 public:
  NavigatorStage(Node& node, const NavigatorConfig& cfg);
  const AccumulativeGridMap& agm() const { return agm_; }

 private:
  void onOdometry(const odometry_t& m);
  void onRadarMap(const line_map_t& m);
  void onComplement(const complement_t& m);
  void onLaserScan(const laser_scan_t& m);  // scan matching and laser glints
  void processScan();                       // own_scan_, once its odometry is there
  // The robot's pose at utime in the navigator's frame (the odometry's, corrected).
  std::optional<geom::Pose2> poseAt(int64_t utime) const;
  // The correction (navigator frame <- odometry frame) for an input of time utime: that of the
  // newest scan that ended at least kCorrectionDelayUs before it. The delay makes it independent
  // of whether a scan or a later sonar message reached the navigator first (live, over LCM, or
  // from a log); the correction moves by millimetres per scan, so the delay costs nothing.
  geom::Pose2 correctionAt(int64_t utime) const;
  void toNavigatorFrame(std::vector<GroupReading>& group, int64_t utime) const;
  void toNavigatorFrame(std::vector<Sounding>& soundings, int64_t utime) const;
  static constexpr int64_t kCorrectionDelayUs = 300'000;
  static constexpr double kMaxScanWaitS = 4.0;  // (verify_max_wait_scans' cap)
  // Beams that share at most twice this of bearing do not overlap (maxBeamOverlap): MOBOT-IV's
  // every other beam touches, and a mount's measured bearing may be off by a fraction of this.
  static constexpr double kBeamOverlapMarginDeg = 1.0;
  // Transducers whose beams are learnt (no ring has more; a further sensor id is counted,
  // ring.sensors_ignored, and left out).
  static constexpr size_t kMaxRingSensors = 256;
  // A learnt transducer whose axis or beam moves by more than this is another ring (remounted,
  // recalibrated): two interpolations of the same odometry at one firing agree far closer.
  static constexpr double kRingChangeDeg = 2.0;
  bool timeOk(int64_t utime, const char* channel);  // as ComplementStage::timeOk
  void integrate(std::vector<GroupReading> group, const std::vector<Sounding>& soundings, int64_t utime);
  void joinToLaserLines(std::vector<geom::Vec2>& hits);
  void flushPending();
  void advance(int64_t utime);
  void publish();
  int64_t cycleUtime(int64_t cycle) const;
  // G_T (and the lines' threshold, if it follows) from the ring's timing and beams, once timed.
  void followRing();
  // Each transducer's axis in the robot frame and its beam, from the first of its readings whose
  // firing the odometry has passed (sensor pose less the robot's heading then); beam_overlap_
  // follows. A reading that puts a learnt one elsewhere (kRingChangeDeg) starts the ring afresh
  // (counted: ring.relearnt).
  void learnBeams(const std::vector<complement::ComplementInput>& readings, int64_t utime);

  Node& node_;
  NavigatorConfig cfg_;
  LineGenerationParams lines_;  // cfg_.lines with the G_T the ring gives (lines_follow_g_threshold)
  RingGroups ring_groups_;
  ScanPeriod scan_period_;  // the laser's (the wait for the next scan in scan periods)
  std::map<int, BeamAxis> beams_;  // per sensor id (learnBeams)
  int beam_overlap_ = 0;           // maxBeamOverlap of beams_
  PoseHistory poses_;
  double speed_ = 0;  // [m/s] newest ODOMETRY.v
  AccumulativeGridMap agm_;
  EchoPlacer placer_;
  LookWeight look_weight_;
  PassThrough pass_through_;
  GlintTracker glints_;  // laser glints (tactical/laser_glint.hpp)
  EchoProvenance heard_;  // which echoes made each cell (tactical/echo_provenance.hpp)
  ScanMatcher matcher_;  // navigator frame <- odometry frame
  struct Correction {
    int64_t utime = 0;         // the scan's last reading
    geom::Pose2 c;             // the correction after it
    bool constrained = false;  // its match fixed the pose (else the odometry's error goes on)
  };
  std::deque<Correction> corrections_;
  const Correction* correctionEntryAt(int64_t utime) const;
  std::optional<int64_t> last_integrated_utime_;  // the previous firing group put into the AGM
  CurrentSensorMap csm_;
  grid_map_t grid_msg_{};  // (the AGM_TACTICAL message, every field set per map; storage reused)
  struct PendingGroup {
    int64_t utime = 0;
    std::vector<GroupReading> readings;
    std::vector<bool> outside_view;  // per reading: beyond the laser's view (kept unverified)
    std::vector<Sounding> soundings;  // pass_through
    complement::IdealSonarModel model;
    double tolerance = 0;
  };
  std::deque<PendingGroup> pending_;  // firing groups waiting for the next scan's Radar Map
  std::vector<complement::RmSegment> rm_;  // the newest Radar Map
  std::optional<int64_t> rm_source_utime_;  // its scan's start
  std::vector<geom::Vec2> glint_hits_;  // laser glints since the last firing group went in
  std::optional<complement::LaserScan> own_scan_;  // the decoded LASER_SCAN (storage reused)
  std::vector<complement::ScanPoint> placed_;       // its readings placed (storage reused)
  std::vector<complement::RmSegment> segments_;     // its segments, cut for the glints
  std::optional<int64_t> last_scan_utime_;
  bool scan_waiting_ = false;  // own_scan_ not yet processed
  std::optional<int64_t> newest_odometry_utime_;
  std::vector<int64_t> cycle_utime_;  // firing time of cycle c at c % size (the last h_max + 2 cycles)
  std::optional<int64_t> last_complement_utime_, last_rm_utime_, last_publish_;
  int64_t now_ = 0;  // newest SONAR_COMPLEMENT / RADAR_MAP time processed
  TimeReset clock_;
  OdometryOutage odometry_outage_;  // (reported once per outage)
};

}  // namespace lasonic
