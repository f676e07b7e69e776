#pragma once
// PilotStage: the operational level (README "Method", steps 4-5) on a lasonic::Node.
//
// In:  ODOMETRY (pose history, speed), LASER_SCAN, SONAR_COMPLEMENT (one firing group), and with
//      `remembered` the navigator's AGM_TACTICAL.
// Out: SECTOR_MAP after every SONAR_COMPLEMENT message and every laser scan, and on ODOMETRY
//      when no map was made for map_max_interval_s of message time (a sensor died);
//      AGM_OPERATIONAL after an update cycle when at least 1/agm_publish_hz of message time has
//      passed since the last one (the first cycle always publishes).
// Counters (PROCESS_STATUS): agm.cycles, agm.hits, agm.hits_outside_window, agm.recentred,
// laser.moving_returns (returns moved by MoverPrediction), laser.remembered_returns (earlier
// scans' returns outside the newest scan's view, LaserMemory), laser.coasting_returns (movers
// that walked on out of the view, LaserMemory), agm.seen_before_left_out (seen_before echoes
// whose surface the laser's returns report in their sector: onComplement),
// agm.outside_view_redundant_left_out (outside-view echoes the newest scan's lines explain, in a
// sector where the laser reports something: onComplement),
// sector_map.no_odometry, rejected.* for every kind of bad input; laser.lost and sonar.lost
// (errors, once per outage: a sensor that had been delivering is stale in the sector map, which
// holds its last values meanwhile, flagged laser_stale / sonar_stale; logged when it is back).
//
// Definitions:
// - One AGM update cycle = one SONAR_COMPLEMENT message (one firing group, every 0.03 s with the
//   default ring): its complementary readings are the hits, and H counts firing groups. The
//   group is the sonar's natural time step (its readings are simultaneous), a message with no
//   complementary reading still ages the grid, and the result does not depend on when messages
//   arrive, only on their order.
// - Before a cycle the window follows the robot (pose at the firing time, speed from the newest
//   ODOMETRY); see AccumulativeGridMap::recenterLimit.
// - The cell of a complementary reading: cfg.placement (operational/echo_placer.hpp). Per sensor id the
//   stage keeps its latest reading; only a complementary one counts as a neighbour's echo.
// - The sector map's time is the newest sensor time seen (laser: the scan's last reading;
//   sonar: the firing time), with the robot pose interpolated from ODOMETRY at that time, so the
//   map never goes back in time and both sensors' ages are measured from it. No pose -> no map.
//
// Time comes only from the messages, never from the wall clock, so a replay is deterministic.
// Bad input is reported (node.reportError, naming the field) and never stops the stage:
// ODOMETRY with a non-finite field or older than the newest is dropped; a LASER_SCAN or
// SONAR_COMPLEMENT not newer than the previous one is dropped; bad laser readings are skipped
// (the complement stage's validation); a complement reading with an unknown class, or a
// complementary one with a non-finite range or end point or a negative range, is skipped.
// An input whose time jumps back by more than TimeReset::kJumpUs (a restarted simulator or
// driver, a looping log) resets the stage to its start state (counted: time_resets).
#include <cstdint>
#include <memory>
#include <optional>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "complement/dark_continuation.hpp"
#include "complement/shared_placement.hpp"
#include "core/config.hpp"
#include "core/interval_window.hpp"
#include "core/pose_history.hpp"
#include "lcmio/node.hpp"
#include "lcmio/time_reset.hpp"
#include "operational/echo_placer.hpp"
#include "operational/agm.hpp"
#include "operational/evidence_placement.hpp"
#include "operational/laser_memory.hpp"
#include "operational/mover_prediction.hpp"
#include "operational/motion_confirmation.hpp"
#include "operational/sector_map.hpp"
#include "operational/sonar_bearing.hpp"
#include "stages/inputs.hpp"

namespace lasonic {

// Defaults: the shipped configuration (deploy/config/lasonic.yaml says why each value); the
// libraries' own defaults (AgmParams, SectorMapParams) are the paper's.
struct PilotConfig {
  AgmParams agm = operationalAgmDefaults();
  // Beyond the paper (which gives h_max in update cycles, one firing group each): the AGM's
  // memory in ring cycles, its h_max = this many times the firing groups per ring cycle, counted
  // from the firings (RingGroups); agm.h_max until the ring has been counted. 0: agm.h_max always.
  double h_max_ring_cycles = 3;
  // Beyond the paper: a cell no sound went through since its last hit is kept up to this many
  // ring cycles beyond h_max (AgmParams::hold_unpassed, operational/sound_passed.hpp): through =
  // within `core` of a reading's half beam width of its axis and `margin_m` nearer than its
  // range. ring_cycles 0: the paper's forgetting.
  struct HoldUnpassed {
    double ring_cycles = 4;
    double core = 1.0;
    double margin_m = 0.10;
    bool at_range = false;        // cells within margin_m beyond the range count as heard through too
    double mover_radius_m = 0.3;  // cells this near a return of a person the laser sees walking are not kept
  } hold_unpassed;
  SectorMapParams sector_map = sectorMapDefaults();
  // Beyond the paper: the laser is stale after this many of its own scan periods, timed from its
  // scans (ScanPeriod, core/interval_window.hpp), and never before
  // sector_map.laser_stale_s. 0: sector_map.laser_stale_s always.
  double laser_stale_scans = 2;
  double agm_publish_hz = 2.0;  // AGM_OPERATIONAL rate (message time); ~90 kB per message
  // A SECTOR_MAP at least this often in message time: when neither sensor triggers one (both
  // silent, or the sonar dead and the next scan not yet due), ODOMETRY does, so a dead sensor is
  // flagged stale in time. Above the longest gap of a normal run (a firing group, 30 ms, plus an
  // odometry tick, 20 ms): normal runs never trigger it.
  double map_max_interval_s = 0.1;
  // The one cell a complementary reading increments (operational/echo_placer.hpp).
  EchoPlacementConfig placement;
  // Beyond the paper: an echo that its sensor's previous echo, spread apart by the robot's own
  // motion, confirms counts twice (operational/motion_confirmation.hpp): one ring cycle is the
  // sensor's own previous firing, no time to configure. enabled false: the paper.
  MotionConfirmationParams motion_confirmation = {true, 0.10};
  // Beyond the paper: the navigator's AGM_TACTICAL as a remembered sector-map source
  // (operational/sector_map.hpp); false: the paper's pilot, AGM_TACTICAL is not subscribed.
  bool remembered = true;
  // Whether a remembered cell that only echoes the laser could not check made (AGM_TACTICAL's
  // heard = HEARD_UNCHECKED: outside its view, or explained only by an earlier scan) is used. Those
  // are mostly walls the scanner saw or will see, placed in front of them, and people who stood
  // where it did not look; the laser memory reports what the laser saw. false: left out.
  bool remembered_unchecked = false;
  // Beyond the paper: an outside-view echo that the newest scan's lines explain (redundant by the
  // hypothesis, its arc reaching beyond the scanner's view) is left out where the sector map holds
  // a laser return in the echo's own sector (the pilot's onComplement); false: every outside-view
  // echo goes in.
  bool outside_view_redundant_laser = true;
  // Beyond the paper: a group the complement could not verify for want of a recent Radar Map (the
  // laser lost, or not scanning yet) has its echoes within the hypothesis' range limit put in the
  // AGM as complementary ones (onComplement; G_T still asks for two); false: the paper, such echoes
  // are unverifiable and unused.
  bool stale_radar_map_echoes = true;
  // [m] A remembered cell within this of one of the navigator's AGM_LINES is taken at its foot on
  // the line (operational/remembered_on_lines.hpp); 0: cells at their centres, AGM_LINES not
  // subscribed.
  double remembered_on_lines_m = 0.2;
  // [m] Between two remembered cells one line took, the line is remembered too, a point at most
  // this far apart (operational/remembered_on_lines.hpp); 0: only the cells.
  double remembered_fill_m = 0.05;
  // Beyond the paper: the laser's returns of people moved to where they are now
  // (operational/mover_prediction.hpp); false: every return where the scan saw it (the paper).
  bool predict_movers = true;
  MoverPredictionParams mover_prediction;
  // Beyond the paper: a scanner of less than a full turn leaves a wedge it does not see; there
  // the sector map takes the returns earlier scans saw, for this long (operational/laser_memory.hpp).
  // 0: the newest scan only (the paper). A full-circle scanner is unaffected but for
  // laser_memory_dark (below).
  double laser_memory_s = 30.0;
  // A person the laser saw walking, who walked on where it does not look, is reported where they
  // would be by now for this long after the laser last saw them (LaserMemoryParams::coast_s).
  double laser_memory_coast_s = 1.0;
  // Returns of a still person-sized cluster (a person who stands; LaserMemoryParams::cluster_s)
  // are kept only this long: a person may walk off unseen. 0: laser_memory_s.
  double laser_memory_cluster_s = 0;
  // Beyond the paper: a remembered round cluster (a person who stood where the scanner does not
  // look) that the sonar has since heard through, clear_after looks in a row, is dropped
  // (LaserMemoryHeardThrough); clear_after 0: kept for its time as above.
  LaserMemoryHeardThrough laser_memory_heard_through = laserMemoryHeardThroughDefaults();
  // Beyond the paper: the laser memory also keeps an earlier return where the newest scan's
  // reading in its bearing came back empty, for any scanner (a 360 deg one too). An empty reading
  // is no free space: a dark face at its detection limit (black cardboard up to 2.7 m head-on)
  // returns in one scan and not in the next, and a return's surface is then still there. A return
  // in that bearing (nearer or farther) decides, as everywhere else. false: the memory only where
  // the scanner does not look.
  bool laser_memory_dark = true;
  // Beyond the paper, with laser_memory_dark: a 360 deg scan during which the robot turned
  // against the sweep left a wedge at its seam that none of its readings looked into
  // (complement::laserViewOf with the first reading's pose); earlier returns stay there. false:
  // a 360 deg scan covers every bearing.
  bool laser_memory_seam = true;
  // Beyond the paper: a straight run of returns that ends in readings with no return is continued
  // along its line into them, up to `length` past its last return (complement/dark_continuation.hpp):
  // a return stands for its surface 0.10 m around it, as for laser_explains_radius. 0: off (the paper).
  complement::DarkContinuationConfig dark_continuation = darkContinuationDefaults();
  // How the dark continuation cuts a scan into runs (jumps, end-point fit): the laser's own rule,
  // the complement's `complement.radar_map` keys (pilotConfigFromRoot), not a key of its own.
  complement::RadarMapConfig scan_cut;

  static AgmParams operationalAgmDefaults();
  static SectorMapParams sectorMapDefaults();
  static complement::DarkContinuationConfig darkContinuationDefaults();
  static LaserMemoryHeardThrough laserMemoryHeardThroughDefaults();
};
// The laser memory's heard-through rule as the pilot runs it: its keys, with the mover
// prediction's cluster gap.
LaserMemoryHeardThrough laserMemoryHeardThrough(const PilotConfig& c);

// Reads the `pilot:` section. Throws ConfigError naming the key path.
PilotConfig pilotConfig(const Config& pilot_section);
// The same from the whole configuration: `pilot:`, and the laser's cut from `complement.radar_map`
// (what lasonic-pilot and lasonic-replay read).
PilotConfig pilotConfigFromRoot(const Config& root);

// A scan's valid returns in scan order into `points` (and, with `timed`, with their reading's
// time into `timed`: timed[k].p is points[k]); `newest` raised to the newest reading's time.
// (Storage reused: both are resized to the count.)
void validReturns(const std::vector<complement::ScanPoint>& placed, const std::vector<complement::LaserReading>& readings,
                  std::vector<geom::Vec2>& points, std::vector<TimedPoint>* timed, int64_t& newest);

// The pilot's split of a scan's valid returns (points[k] is scan[k].p): the returns of the runs
// with a velocity go to `moving` with it and their times, the others stay in `points`, in order
// (a velocity of zero is none).
void takeOutMovers(const std::vector<TimedPoint>& scan, const std::vector<MoverPrediction::MovingRun>& runs,
                   std::vector<geom::Vec2>& points, std::vector<SectorMap::MovingPoint>& moving);

// StaleValues::Frontier: a placed scan's readings, in scan order, to `sector_map` for the shadow
// edges it makes once the laser is stale (SectorMap::setLaserScan), seen from the scanner at the
// scan's last reading (`robot`: the robot's pose then). (`xy`, `valid`: storage swapped with the
// sector map's.)
void giveScanForShadow(SectorMap& sector_map, const complement::LaserScan& scan,
                       const std::vector<complement::ScanPoint>& placed, const geom::Pose2& robot,
                       std::vector<geom::Vec2>& xy, std::vector<uint8_t>& valid);

// The readings of `m` that came back empty (1), in the order of the LaserScan made from it (a
// clockwise scan reversed) -- the gaps the dark continuation may go into; a
// reading the message layer rejected (a time offset outside the scan's sweep) is no gap,
// whatever its flag. (Storage reused.)
void noReturnMask(const laser_scan_t& m, std::vector<uint8_t>& mask);

// The remembered obstacles from the navigator's cells: moved onto the AGM_LINES lines of the same
// cycle (`lines` empty: left at their centres) and the line filled between them, as the pilot
// sets them (remembered_on_lines_m, remembered_fill_m; a gap the robot could drive through stays).
std::vector<geom::Vec2> rememberedPoints(std::vector<geom::Vec2> cells, const std::vector<geom::Segment>& lines,
                                         const PilotConfig& cfg);

// The navigator keeps its maps in its own frame (the odometry corrected by scan matching) and
// says where the robot was in it (`there`); through that pose and ours at the same time
// (`here`), its points come into our odometry frame. Without scan matching the two are equal.
void navigatorToOdometryFrame(std::vector<geom::Vec2>& points, const geom::Pose2& here, const geom::Pose2& there);

class PilotStage {
 public:
  PilotStage(Node& node, const PilotConfig& cfg);
  // Where the complement stage runs in the same process (lasonic-replay): the scan's placed
  // readings shared with it (complement/shared_placement.hpp; the same result, computed once).
  void sharePlacement(std::shared_ptr<complement::SharedPlacement> placement) { placement_ = std::move(placement); }

 private:
  void onOdometry(const odometry_t& m);
  void onLaserScan(const laser_scan_t& m);
  void onComplement(const complement_t& m);
  void onTacticalMap(const grid_map_t& m);
  void onAgmLines(const line_map_t& m);
  void setRemembered();
  bool timeOk(int64_t utime, const char* channel);  // as ComplementStage::timeOk
  void publishSectorMap();
  void publishAgm(int64_t utime);

  Node& node_;
  PilotConfig cfg_;
  PoseHistory poses_;
  double speed_ = 0;  // [m/s] newest ODOMETRY.v
  AccumulativeGridMap agm_;
  SectorMap sector_map_;
  EchoPlacer placer_;
  MotionConfirmation motion_confirmation_;
  RingGroups ring_groups_;
  ScanPeriod scan_period_;  // the laser's (staleness and the movers' horizon in scan periods)
  MoverPrediction movers_;
  LaserMemory laser_memory_;
  std::optional<int64_t> last_scan_utime_, last_complement_utime_, last_agm_publish_, last_map_utime_,
      last_tactical_utime_;
  int64_t now_ = 0;  // newest sensor time: the sector map's time
  TimeReset clock_;
  OdometryOutage odometry_outage_;  // (reported once per outage)
  SensorOutage laser_outage_, sonar_outage_;  // (each reported once per outage)
  std::shared_ptr<complement::SharedPlacement> placement_;  // null: placed here
  sector_map_t map_msg_{};  // (the SECTOR_MAP message, every field set per map; storage reused)
  // The newest AGM_TACTICAL's occupied cells and the newest AGM_LINES' segments (the navigator's frame); the
  // cells move onto the lines when both are of the same navigator cycle (same utime).
  std::vector<geom::Vec2> tactical_points_;  // the navigator's frame
  geom::Pose2 tactical_robot_pose_;           // the robot in that frame at the map's utime
  std::vector<geom::Segment> agm_lines_;
  std::optional<int64_t> agm_lines_utime_;
  grid_map_t agm_msg_{};    // (the same for AGM_OPERATIONAL)
  std::optional<complement::LaserScan> own_scan_;  // (without placement_: the decoded scan, storage reused)
  std::vector<TimedPoint> timed_;  // (the scan's valid returns with their times; storage reused)
  std::vector<geom::Vec2> laser_points_;  // (the sector map's previous list, handed back: storage reused)
  std::vector<geom::Vec2> still_;         // (the returns the laser memory may keep: storage reused)
  std::vector<uint8_t> still_cluster_;    // (per still_ return: of a still person-sized cluster)
  std::vector<complement::ScanPoint> own_placed_;  // (without placement_: the scan's points, storage reused)
  std::vector<geom::Vec2> shadow_points_;  // (StaleValues::Frontier: the scan's returns in order; storage reused)
  std::vector<uint8_t> shadow_valid_;
  std::vector<uint8_t> no_return_;  // (per reading of the scan: FLAG_NO_RETURN; storage reused)
};

}  // namespace lasonic
