// Per firing group and per laser scan, on a shipped scene: the work the complement and pilot
// stages do for each, measured on the pipeline's own data. Run: build/bench/bench_pipeline.
//
// Input: fig7_lab (deploy/scenarios) simulated in memory with the shipped configuration
// (deploy/config/lasonic.yaml), then run once through the real ComplementStage, PilotStage and
// NavigatorStage (on a LocalBus, as lasonic-replay does) to record every message in order,
// AGM_TACTICAL and AGM_LINES included (the pilot's remembered obstacles, taken onto their lines).
// The timed loop then replays the
// sensor messages, in order, through the same library calls the two stages make, without the
// message layer (encoding, publishing; decoding the sensor messages into their structs is in):
//   BM_Fig7LabFiringGroup: one iteration = one firing group: hypothetical scan + classification
//     (extractComplement) + AGM cycle (echo placement, follow, update) + sector map;
//   BM_Fig7LabLaserScan: one iteration = one laser scan: Radar Map (extractRadarMap) + the
//     pilot's scan handling (placeReadings, movers, the dark continuation, the first sector map
//     after the scan);
//   BM_Fig7LabLaserScanOneProcess: the same with the scan decoded and its readings placed once
//     for both stages (SharedPlacement, as lasonic-replay runs them), the pilot keeping its own
//     pose history.
// The other events in between are processed with the timer stopped (CPU time, so another
// process taking the core does not count). At the end of the 60 s run the replay starts afresh.
// Before timing, one pass checks that every sector map equals the SECTOR_MAP the real PilotStage
// published: the benchmark measures the pipeline's work, not an approximation of it.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <lasonic/grid_map_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "complement/complement.hpp"
#include "complement/dark_continuation.hpp"
#include "complement/messages.hpp"
#include "complement/radar_map.hpp"
#include "complement/shared_placement.hpp"
#include "core/config.hpp"
#include "core/pose_history.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/local_bus.hpp"
#include "lcmio/node.hpp"
#include "sim/drivers.hpp"
#include "sim/setup.hpp"
#include "stages/complement_stage.hpp"
#include "stages/inputs.hpp"
#include "stages/navigator_stage.hpp"
#include "stages/pilot_stage.hpp"
#include "operational/laser_memory.hpp"

using namespace lasonic;
namespace cp = lasonic::complement;

namespace {

const std::string kSource = LASONIC_SOURCE_DIR;

template <typename T>
T decodeAs(const std::vector<uint8_t>& data) {
  T m;
  m.decode(data.data(), 0, static_cast<int>(data.size()));
  return m;
}

// The scene's messages in the order the pilot sees them.
struct Run {
  Config root;
  using Event = std::variant<odometry_t, laser_scan_t, sonar_ring_t, grid_map_t, line_map_t>;
  std::vector<Event> inputs;
  std::vector<sector_map_t> sector_maps;  // what the real PilotStage published, in order
  int64_t groups = 0, scans = 0;
};

const Run& recordedRun() {
  static const Run run = [] {
    Run r;
    const std::string config = kSource + "/deploy/config/lasonic.yaml";
    r.root = Config::loadFiles({config});
    const sim::SimSetup setup = sim::loadSimSetup({config}, kSource + "/deploy/scenarios/fig7_lab.yaml");
    auto bus = std::make_shared<LocalBus>();
    const Node::Options offline{false, false};
    Node cn("c", bus, offline), pn("p", bus, offline), nn("n", bus, offline);
    ComplementStage complement(cn, complementConfig(r.root.section("complement")));
    PilotStage pilot(pn, pilotConfigFromRoot(r.root));
    NavigatorStage navigator(nn, navigatorConfigFromRoot(r.root));
    bus->subscribe(".*", [&r](const lcm::ReceiveBuffer* rb, const std::string& ch) {
      const auto* p = static_cast<const uint8_t*>(rb->data);
      const std::vector<uint8_t> data(p, p + rb->data_size);
      if (ch == channels::AGM_TACTICAL) r.inputs.emplace_back(decodeAs<grid_map_t>(data));
      if (ch == channels::AGM_LINES) r.inputs.emplace_back(decodeAs<line_map_t>(data));
      if (ch == channels::SECTOR_MAP) r.sector_maps.push_back(decodeAs<sector_map_t>(data));
    });
    sim::WorldCore world(setup.scenario, sim::odometryConfigFor(setup));
    sim::LaserDriverCore laser(setup.scenario, sim::laserConfigFor(setup), setup.scenario.seed);
    sim::SonarDriverCore sonar(setup.scenario, sim::sonarConfigFor(setup), setup.scenario.seed);
    auto publish = [&](const char* ch, auto& msg) {
      r.inputs.emplace_back(msg);
      const std::vector<uint8_t> data = encodeMsg(msg);
      bus->publish(ch, data.data(), data.size());
      bus->handleAll();
    };
    for (int64_t t = world.startUtime(); !world.finished(t); t += world.periodUs()) {
      sim_state_t st = world.stateAt(t);
      odometry_t od = world.odometry();
      publish(channels::ODOMETRY, od);
      for (auto& o : laser.onSimState(st)) publish(channels::LASER_SCAN, o.scan), ++r.scans;
      for (auto& o : sonar.onSimState(st)) publish(channels::SONAR_RING, o.ring), ++r.groups;
    }
    return r;
  }();
  return run;
}

// The two stages' per-message work, as ComplementStage and PilotStage do it (their input checks
// left out: the scene's messages are all good), one input event at a time.
class Replayer {
 public:
  // one_process: the two stages share the scan's placed readings (SharedPlacement), as in
  // lasonic-replay; otherwise each places them, as the live processes do.
  explicit Replayer(const Run& run, bool one_process = false)
      : run_(run),
        one_process_(one_process),
        ccfg_(complementConfig(run.root.section("complement"))),
        pcfg_(pilotConfigFromRoot(run.root)),
        agm_(pcfg_.agm),
        sector_map_(pcfg_.sector_map),
        placer_(pcfg_.placement),
        motion_confirmation_(pcfg_.motion_confirmation),
        movers_(pcfg_.mover_prediction),
        laser_memory_(LaserMemoryParams{pcfg_.laser_memory_s, pcfg_.sector_map.robot_radius + pcfg_.sector_map.max_range,
                                        pcfg_.laser_memory_coast_s, pcfg_.laser_memory_cluster_s},
                      laserMemoryHeardThrough(pcfg_)) {}

  bool done() const { return next_ >= run_.inputs.size(); }
  bool nextIsGroup() const { return !done() && std::holds_alternative<sonar_ring_t>(run_.inputs[next_]); }
  bool nextIsOdometry() const { return !done() && std::holds_alternative<odometry_t>(run_.inputs[next_]); }
  bool nextIsScan() const { return !done() && std::holds_alternative<laser_scan_t>(run_.inputs[next_]); }
  // The sector map just made equals the one the real PilotStage published at this point.
  bool mapMatches() {
    if (map_index_ >= run_.sector_maps.size()) return false;
    const sector_map_t& m = run_.sector_maps[map_index_++];
    const SectorMapState& s = sector_map_.state();
    return m.utime == s.utime && m.distance == s.distance && m.laser_distance == s.laser &&
           m.sonar_distance == s.sonar && m.remembered_distance == s.remembered;
  }
  bool allMapsSeen() const { return map_index_ == run_.sector_maps.size(); }

  // Processes the next input event; returns true if it made a sector map.
  bool step() {
    const Run::Event& ev = run_.inputs[next_++];
    if (const auto* od = std::get_if<odometry_t>(&ev)) {
      if (const auto odo = cp::odometryFromMessage(*od, problems_);
          odo && poses_.add(odo->utime, odo->pose) == PoseHistory::AddResult::Ok) {
        speed_ = odo->v;
        if (one_process_) pilot_poses_.add(odo->utime, odo->pose);  // the pilot stage's own history
      }
      return false;
    }
    if (const auto* ls = std::get_if<laser_scan_t>(&ev)) {
      // In one process both stages take the scan from SharedPlacement::scanFrom (decoded once,
      // and known to place() without a comparison), as ComplementStage and PilotStage do there.
      const std::optional<cp::LaserScan>& scan =
          one_process_ ? shared_.scanFrom(*ls, problems_) : cp::laserScanFromMessageInto(*ls, problems_, own_scan_);
      // Complement stage: the Radar Map.
      rm_ = one_process_ ? cp::radarMapFromPlaced(*scan, shared_.place(*scan, poses_), poses_, ccfg_.radar_map)
                         : cp::extractRadarMap(*scan, poses_, ccfg_.radar_map);
      rm_->poles = poles_.update(rm_->utime, rm_->robot_pose.position(), rm_->pole_candidates);
      // Pilot stage: the scan's points, then the first sector map after it.
      if (one_process_) shared_.scanFrom(*ls, problems_);  // (the pilot's own call: the same message)
      if (!one_process_) cp::placeReadingsInto(*scan, poses_, own_placed_);  // (as PilotStage: storage reused)
      const std::vector<cp::ScanPoint>& placed = one_process_ ? shared_.place(*scan, pilot_poses_) : own_placed_;
      std::vector<geom::Vec2>& points = points_;  // (as PilotStage: the previous scan's storage)
      int64_t newest = ls->utime;
      // (as PilotStage: staleness and the movers' horizon in the laser's own scan periods)
      scan_period_.scanned(ls->utime);
      sector_map_.setLaserStaleS(scan_period_.scans(pcfg_.laser_stale_scans, pcfg_.sector_map.laser_stale_s));
      validReturns(placed, scan->readings, points, pcfg_.predict_movers ? &timed_ : nullptr, newest);  // (as PilotStage)
      // pilot.laser_memory_s / laser_memory_dark: what earlier scans saw where this one does not
      // look or read nothing (PilotStage::onLaserScan).
      const bool remember = laser_memory_.enabled() && (!scan->full_circle || pcfg_.laser_memory_dark) &&
                      !scan->readings.empty();
      bool mask_made = false;
      if (remember && pcfg_.laser_memory_dark) {
        noReturnMask(*ls, no_return_);
        mask_made = true;
      }
      if (!remember) laser_memory_.clear();
      // pilot.predict_movers: returns of small clusters moving scan to scan (PilotStage::onLaserScan).
      std::vector<SectorMap::MovingPoint> moving;
      std::vector<geom::Vec2>& still = still_;  // (storage reused scan to scan)
  still.clear();
      if (pcfg_.predict_movers) {
        const int64_t mid = ls->utime + (newest - ls->utime) / 2;
        const std::vector<MoverPrediction::MovingRun>& runs =
            movers_.track(timed_, poses_.at(mid).value_or(poses_.at(newest).value_or(geom::Pose2{})).position());
        still_cluster_.clear();
        if (remember) {
          still.reserve(timed_.size());
          for (size_t i = 0; i < timed_.size(); ++i)
            if (const uint8_t st = movers_.still()[i]; st != 0) {
              still.push_back(timed_[i].p);
              still_cluster_.push_back(st == MoverPrediction::kStillCluster);
            }
        }
        takeOutMovers(timed_, runs, points, moving);
        if (pcfg_.hold_unpassed.ring_cycles > 0) markNearMovers(agm_, moving, pcfg_.hold_unpassed.mover_radius_m);
      } else if (remember) {
        still.assign(points.begin(), points.end());
      }
      if (pcfg_.dark_continuation.length > 0 && !mask_made) noReturnMask(*ls, no_return_);
      if (pcfg_.dark_continuation.length > 0) {  // (as PilotStage: a surface that goes dark goes on)
        cp::darkContinuation(*scan, placed, no_return_, [this](int64_t t) { return poses_.at(t); }, pcfg_.scan_cut,
                             pcfg_.dark_continuation, points);
      }
      if (const auto robot = poses_.at(newest); remember && robot) {
        const cp::LaserView view = cp::laserViewOf(*scan, *robot);
        const cp::DarkBearings dark(*scan, view, no_return_);
        const bool use_dark = pcfg_.laser_memory_dark;
        laser_memory_.update(
            newest, robot->position(), still, moving,
            [&](const geom::Vec2& p) { return view.covers(p) && !(use_dark && dark.at(p)); }, &still_cluster_);
        const auto& coasting = laser_memory_.coastingMovers();
        moving.insert(moving.end(), coasting.begin(), coasting.end());
        const auto& remembered = laser_memory_.points();
        points.insert(points.end(), remembered.begin(), remembered.end());
      }
      points_ = sector_map_.setLaserPoints(newest, std::move(points));
      if (pcfg_.sector_map.stale_values == StaleValues::Frontier)  // (as PilotStage: for when it is the last)
        if (const auto robot = poses_.at(newest))
          giveScanForShadow(sector_map_, *scan, placed, *robot, shadow_xy_, shadow_valid_);
      sector_map_.setLaserMovers(std::move(moving),
                                 scan_period_.scans(pcfg_.mover_prediction.horizon_scans, pcfg_.mover_prediction.horizon_s));
      now_ = std::max(now_, newest);
      benchmark::DoNotOptimize(sector_map_.update(now_, *poses_.at(now_), agm_).distance.data());
      return true;
    }
    if (const auto* ring = std::get_if<sonar_ring_t>(&ev)) {
      // Complement stage: hypothetical scan and classification.
      const cp::SonarGroup group = cp::sonarGroupFromMessage(*ring, problems_);
      const cp::GroupComplement result =
          cp::extractComplement(group, poses_.at(ring->utime), rm_ ? &*rm_ : nullptr, ccfg_.params,
                                pings_.before(ring->utime, ccfg_.params.late_echo_window_us));
      pings_.add(result);
      benchmark::DoNotOptimize(result.readings.data());
      // Pilot stage: the AGM cycle on the SONAR_COMPLEMENT message (its readings as the pilot
      // decodes them, prepared by Run: the message layer is not timed), then the sector map.
      const Prepared& prepared = groupReadings(group_index_++, result);
      const std::vector<GroupReading>& readings = prepared.readings;
      ring_groups_.fired(ring->group);
      agm_.setHMax(ring_groups_.hMax(pcfg_.h_max_ring_cycles, pcfg_.agm.h_max));
      if (pcfg_.hold_unpassed.ring_cycles > 0) {
        agm_.setHoldUnpassed(ring_groups_.hMax(pcfg_.hold_unpassed.ring_cycles, pcfg_.agm.h_max));
        markSoundPassed(agm_, prepared.soundings, pcfg_.hold_unpassed.core, pcfg_.hold_unpassed.margin_m,
                        pcfg_.hold_unpassed.at_range);
      }
      if (pcfg_.laser_memory_heard_through.clear_after > 0) laser_memory_.heardThrough(ring->utime, prepared.soundings);
      std::vector<geom::Vec2> hits = placer_.place(readings, agm_);
      motion_confirmation_.apply(placer_.lastPlaced(), agm_, hits);
      for (const GroupReading& r : readings) motion_confirmation_.fired(r.sensor_id, ring->utime);
      if (const auto pose = poses_.at(ring->utime)) agm_.follow(pose->position(), speed_);
      agm_.update(hits);
      sector_map_.setSonarTime(ring->utime);
      now_ = std::max(now_, ring->utime);
      benchmark::DoNotOptimize(sector_map_.update(now_, *poses_.at(now_), agm_).distance.data());
      return true;
    }
    if (const auto* l = std::get_if<line_map_t>(&ev)) {  // PilotStage::onAgmLines
      lines_.clear();
      for (const line_segment_t& seg : l->segments) lines_.push_back({{seg.x0, seg.y0}, {seg.x1, seg.y1}});
      lines_utime_ = l->utime;
      if (tactical_utime_ == lines_utime_) setRemembered();
      return false;
    }
    const auto& g = std::get<grid_map_t>(ev);  // PilotStage::onTacticalMap: the occupied cells' centres
    tactical_points_.clear();
    const int threshold = std::max(1, g.gp_threshold);
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix)
        if (g.gp[static_cast<size_t>(iy) * static_cast<size_t>(g.width) + static_cast<size_t>(ix)] >= threshold)
          tactical_points_.emplace_back(g.origin_x + (ix + 0.5) * g.cell_size, g.origin_y + (iy + 0.5) * g.cell_size);
    tactical_utime_ = g.utime;
    tactical_pose_ = {g.robot_pose.x, g.robot_pose.y, g.robot_pose.theta};
    setRemembered();
    return false;
  }

  // Every group's readings as the pilot gets them: made once, through the real messages.
  // A SONAR_COMPLEMENT message as the pilot decodes it: its group readings and its soundings.
  struct Prepared {
    std::vector<GroupReading> readings;
    std::vector<Sounding> soundings;
  };
  static std::vector<Prepared>& prepared() {
    static std::vector<Prepared> readings;
    return readings;
  }

 private:
  // PilotStage::setRemembered: the cells taken onto the lines of the same navigator cycle, in
  // the odometry frame.
  void setRemembered() {
    std::vector<geom::Vec2> points =
        rememberedPoints(tactical_points_, lines_utime_ == tactical_utime_ ? lines_ : kNoLines, pcfg_);
    const auto here = (one_process_ ? pilot_poses_ : poses_).at(tactical_utime_);
    if (!here) return;
    navigatorToOdometryFrame(points, *here, tactical_pose_);
    sector_map_.setRemembered(tactical_utime_, std::move(points));
  }
  static inline const std::vector<geom::Segment> kNoLines;

  const Prepared& groupReadings(size_t i, const cp::GroupComplement& result) {
    auto& all = prepared();
    if (i >= all.size()) {
      const complement_t msg = cp::complementToMessage(result, ccfg_.params);
      const auto inputs = cp::complementFromMessage(msg, problems_);
      const double beam = geom::plausibleBeamWidth(msg.beam_width) ? msg.beam_width : pcfg_.placement.params.beam_width;
      all.push_back({toGroupReadings(inputs, msg.utime, false, pcfg_.stale_radar_map_echoes),
                     soundingsOf(inputs, beam, true, true)});
    }
    return all[i];
  }

  const Run& run_;
  bool one_process_;
  cp::SharedPlacement shared_;
  PoseHistory pilot_poses_;
  cp::ComplementConfig ccfg_;
  PilotConfig pcfg_;
  PoseHistory poses_;
  double speed_ = 0;
  std::optional<cp::RadarMap> rm_;
  cp::PoleTracker poles_{ccfg_.poles};
  cp::PingHistory pings_;  // the earlier groups' pings, for late echoes (as ComplementStage)
  AccumulativeGridMap agm_;
  RingGroups ring_groups_;
  SectorMap sector_map_;
  EchoPlacer placer_;
  MotionConfirmation motion_confirmation_;
  MoverPrediction movers_;
  ScanPeriod scan_period_;
  LaserMemory laser_memory_;
  std::vector<uint8_t> still_cluster_;
  int64_t now_ = 0;
  size_t next_ = 0, map_index_ = 0, group_index_ = 0;
  std::vector<cp::InputProblem> problems_;
  std::vector<TimedPoint> timed_;
  std::optional<cp::LaserScan> own_scan_;  // (as the stages without SharedPlacement: storage reused)
  std::vector<cp::ScanPoint> own_placed_;
  std::vector<geom::Vec2> points_;  // (handed back by SectorMap::setLaserPoints)
  std::vector<geom::Vec2> shadow_xy_;  // (giveScanForShadow's storage)
  std::vector<uint8_t> shadow_valid_;
  std::vector<uint8_t> no_return_;
  std::vector<geom::Vec2> still_;
  std::vector<geom::Vec2> tactical_points_;
  std::vector<geom::Segment> lines_;
  geom::Pose2 tactical_pose_;  // where the navigator says the robot was, in its frame
  int64_t tactical_utime_ = -1, lines_utime_ = -2;
};

// One pass that checks the replayer against the real stages (and prepares the group readings),
// with and without the shared placement.
bool checkedOnce(benchmark::State& state) {
  static const bool ok = [] {
    for (const bool one_process : {false, true}) {
      Replayer r(recordedRun(), one_process);
      while (!r.done())
        if (r.step() && !r.mapMatches()) return false;
      if (!r.allMapsSeen()) return false;
    }
    return true;
  }();
  if (!ok) state.SkipWithError("the benchmark's sector maps differ from the PilotStage's SECTOR_MAP messages");
  return ok;
}

// Iteration = one firing group. The events between groups are processed with the timer
// stopped, except odometry (a pose added to the history, tens of ns; stopping the timer
// around it would cost more than it does).
void BM_Fig7LabFiringGroup(benchmark::State& state) {
  if (!checkedOnce(state)) return;
  const Run& run = recordedRun();
  auto r = std::make_unique<Replayer>(run);
  for (auto _ : state) {
    while (!r->nextIsGroup()) {
      if (r->done()) {
        state.PauseTiming();
        r = std::make_unique<Replayer>(run);
        state.ResumeTiming();
      } else if (r->nextIsOdometry()) {
        r->step();
      } else {
        state.PauseTiming();
        r->step();
        state.ResumeTiming();
      }
    }
    r->step();
  }
  state.counters["groups"] = static_cast<double>(run.groups);
}
BENCHMARK(BM_Fig7LabFiringGroup)->Unit(benchmark::kMicrosecond);

// Iteration = one laser scan (Radar Map + the pilot's scan handling); everything between scans
// is processed with the timer stopped.
void laserScans(benchmark::State& state, bool one_process) {
  if (!checkedOnce(state)) return;
  const Run& run = recordedRun();
  auto r = std::make_unique<Replayer>(run, one_process);
  for (auto _ : state) {
    state.PauseTiming();
    while (!r->nextIsScan()) {
      if (r->done()) r = std::make_unique<Replayer>(run, one_process);
      else r->step();
    }
    state.ResumeTiming();
    r->step();
  }
  state.counters["scans"] = static_cast<double>(run.scans);
}
// As the live processes do it: each stage places the readings.
void BM_Fig7LabLaserScan(benchmark::State& state) { laserScans(state, false); }
BENCHMARK(BM_Fig7LabLaserScan)->Unit(benchmark::kMicrosecond);
// As lasonic-replay does it: placed once, shared by the two stages (SharedPlacement).
void BM_Fig7LabLaserScanOneProcess(benchmark::State& state) { laserScans(state, true); }
BENCHMARK(BM_Fig7LabLaserScanOneProcess)->Unit(benchmark::kMicrosecond);

}  // namespace
