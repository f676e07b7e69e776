#include "eval/baselines.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "complement/messages.hpp"
#include "core/pose_msg.hpp"
#include "stages/pilot_stage.hpp"

namespace lasonic::eval {

namespace {
// The baseline windows must hold the sector map's reach wherever re-centring lets the robot be
// (the pilot's rule for its AGM).
void checkReach(const Config& c, const baselines::WindowParams& w, const SectorMapParams& s) {
  const double view = (w.size / 2 - w.recenter_cells - 1) * w.cell_size;
  if (view < s.robot_radius + s.max_range) {
    std::ostringstream msg;
    msg << "the window's guaranteed view ((size/2 - recenter_cells - 1) * cell_size = " << view
        << " m) must hold pilot robot_radius + max_range = " << s.robot_radius + s.max_range << " m";
    c.fail("size", msg.str());
  }
}
}  // namespace

BaselinesConfig baselinesConfig(const Config& root) {
  BaselinesConfig b;
  const PilotConfig pilot = pilotConfig(root.section("pilot"));
  b.readout = pilot.sector_map;
  b.naive_fusion.agm = pilot.agm;
  b.naive_fusion.h_max_ring_cycles = pilot.h_max_ring_cycles;
  b.naive_fusion.placement = pilot.placement;
  const Config c = root.section("baselines");
  c.allowOnly({"enabled", "sonar_himm", "log_odds"});
  b.enabled = c.get("enabled", b.enabled);
  const Config himm = c.section("sonar_himm"), log_odds = c.section("log_odds");
  b.himm = baselines::himmParams(himm);
  b.log_odds = baselines::logOddsParams(log_odds);
  checkReach(himm, b.himm.window, b.readout);
  checkReach(log_odds, b.log_odds.window, b.readout);
  return b;
}

RawChannelReplay::RawChannelReplay(const RunLog& log) : log_(&log) {
  events_.reserve(log.odometry.size() + log.laser_scans.size() + log.sonar_rings.size());
  for (size_t i = 0; i < log.odometry.size(); ++i) events_.push_back({log.odometry[i].utime, 0, i});
  for (size_t i = 0; i < log.laser_scans.size(); ++i) {
    const laser_scan_t& s = log.laser_scans[i];
    // Delivered when its latest reading is in; an offset the pipeline rejects (outside the scan's
    // sweep, complement::input_limits) delays nothing.
    int64_t last = 0;
    for (const int32_t off : s.offset_us)
      if (complement::input_limits::offsetInSweep(off)) last = std::max<int64_t>(last, off);
    events_.push_back({s.utime + last, 1, i});
  }
  for (size_t i = 0; i < log.sonar_rings.size(); ++i) events_.push_back({log.sonar_rings[i].utime, 2, i});
  std::stable_sort(events_.begin(), events_.end(),
                   [](const Event& a, const Event& b) { return a.t < b.t || (a.t == b.t && a.kind < b.kind); });
}

void RawChannelReplay::advanceTo(int64_t utime, const Handlers& h) {
  std::vector<complement::InputProblem> problems;  // bad input is the pipeline's to report
  const auto pose_at = [this](int64_t t) { return poses_.at(t); };
  for (; next_ < events_.size() && events_[next_].t <= utime; ++next_) {
    const Event& ev = events_[next_];
    problems.clear();
    if (ev.kind == 0) {
      const odometry_t& od = log_->odometry[ev.i];
      if (!std::isfinite(od.pose.x) || !std::isfinite(od.pose.y) || !std::isfinite(od.pose.theta) ||
          !std::isfinite(od.v))
        continue;
      if (poses_.add(od.utime, toPose(od.pose)) == PoseHistory::AddResult::Ok) speed_ = od.v;
    } else if (ev.kind == 1) {
      const laser_scan_t& msg = log_->laser_scans[ev.i];
      if (last_scan_ && msg.utime <= *last_scan_) continue;
      const auto scan = complement::laserScanFromMessage(msg, problems);
      if (!scan) continue;
      last_scan_ = msg.utime;
      const auto placed = complement::placeReadings(*scan, pose_at);
      if (h.laser) h.laser(msg, *scan, placed, ev.t);
    } else {
      const sonar_ring_t& msg = log_->sonar_rings[ev.i];
      if (last_ring_ && msg.utime <= *last_ring_) continue;
      last_ring_ = msg.utime;
      const complement::SonarGroup g = complement::sonarGroupFromMessage(msg, problems);
      if (h.sonar) h.sonar(msg, g, poses_.at(msg.utime));
    }
  }
}

std::vector<size_t> mapsInTimeOrder(const RunLog& log, const SectorTruthTable& truth) {
  std::vector<size_t> order(truth.maps.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return log.sector_maps[truth.maps[a]].utime < log.sector_maps[truth.maps[b]].utime;
  });
  return order;
}

void evalBaselines(const RunLog& log, const SectorTruthTable& truth, const BaselinesConfig& cfg,
                   const EvalOptions& o, Metrics& m) {
  if (!cfg.enabled || truth.maps.empty() || log.odometry.empty() || log.sonar_rings.empty()) return;
  // Read out at the pilot's map times, in time order, with the pilot's read-out for the robot and
  // sector layout its maps describe.
  const std::vector<size_t> order = mapsInTimeOrder(log, truth);
  SectorMapParams rp = cfg.readout;
  const sector_map_t& first = log.sector_maps[truth.maps[order.front()]];
  rp.sectors = first.nsectors;
  if (std::isfinite(first.robot_radius) && first.robot_radius >= 0) rp.robot_radius = first.robot_radius;
  if (std::isfinite(first.max_range) && first.max_range > 0) rp.max_range = first.max_range;

  baselines::HimmGrid himm(cfg.himm);
  baselines::NaiveFusion naive(cfg.naive_fusion);
  baselines::LogOddsGrid log_odds(cfg.log_odds);
  SectorMap himm_map(rp), naive_map(rp), log_odds_map(rp), laser_map(rp);
  SectorScore himm_score, naive_score, log_odds_score, laser_score;
  const OccupancyWindow no_cells;  // laser only: the newest scan and nothing else
  RawChannelReplay replay(log);

  RawChannelReplay::Handlers h;
  h.laser = [&](const laser_scan_t&, const complement::LaserScan& scan, const std::vector<complement::ScanPoint>& placed,
                int64_t newest) {
    std::vector<geom::Vec2> points;
    if (const auto robot = replay.poses().at(newest)) log_odds.follow(robot->position());
    for (size_t i = 0; i < placed.size(); ++i) {
      if (!placed[i].valid) continue;
      points.push_back(placed[i].p);
      if (const auto robot = replay.poses().at(scan.readings[i].utime))
        log_odds.insertLaser(robot->transform(scan.mount.position()), placed[i].p);
    }
    if (points.empty()) return;
    naive_map.setLaserPoints(newest, points);
    laser_map.setLaserPoints(newest, points);
    log_odds_map.setLaserPoints(newest, std::move(points));
  };
  h.sonar = [&](const sonar_ring_t& msg, const complement::SonarGroup& g, const std::optional<geom::Pose2>& robot) {
    const double range_max = std::isfinite(msg.range_max) && msg.range_max > 0 ? msg.range_max : 0.0;
    std::vector<baselines::NaiveFusion::Reading> readings;
    if (robot) {
      himm.follow(robot->position());
      log_odds.follow(robot->position());
      for (size_t i = 0; i < g.readings.size(); ++i) {
        const complement::SonarReading& r = g.readings[i];
        if (!r.valid) continue;
        const geom::Pose2 sensor = robot->compose(r.mount);
        const double beam = r.beam_width > 0 ? r.beam_width : cfg.naive_fusion.placement.params.beam_width;
        readings.push_back({r.sensor_id, sensor, r.range, !r.no_echo, beam});
        himm.insert(sensor, r.range, r.no_echo, range_max);
        log_odds.insertSonar(sensor, r.range, r.no_echo, beam, range_max);
      }
    }
    naive.insertGroup(msg.utime, readings, robot ? std::optional<geom::Vec2>(robot->position()) : std::nullopt,
                      replay.speed(), msg.group);
    himm_map.setSonarTime(msg.utime);
    naive_map.setSonarTime(msg.utime);
    log_odds_map.setSonarTime(msg.utime);
  };

  for (const size_t j : order) {
    const sector_map_t& sm = log.sector_maps[truth.maps[j]];
    replay.advanceTo(sm.utime, h);
    if (truth.sectors(j) != rp.sectors) continue;  // a map of another layout: not comparable
    const SectorSample* s = truth.mapSamples(j);
    const auto pose = replay.poses().at(sm.utime);
    const auto score = [&](SectorMap& map, const auto& grid, SectorScore& sc) {
      if (!pose) {  // no pose, no map: nothing reported
        for (int k = 0; k < rp.sectors; ++k) sc.add(-1, s[k], o);
        return;
      }
      const SectorMapState& st = map.update(sm.utime, *pose, grid);
      for (size_t k = 0; k < st.distance.size(); ++k) sc.add(st.distance[k], s[k], o);
    };
    score(himm_map, himm.occupancy(), himm_score);
    score(naive_map, naive.agm(), naive_score);
    score(log_odds_map, log_odds.occupancy(), log_odds_score);
    score(laser_map, no_cells, laser_score);
  }
  laser_score.write(m, "baselines.laser_only.sector_map", false, truth.materials);
  himm_score.write(m, "baselines.sonar_himm.sector_map", false, truth.materials);
  naive_score.write(m, "baselines.naive_fusion.sector_map", false, truth.materials);
  log_odds_score.write(m, "baselines.log_odds.sector_map", false, truth.materials);
}

}  // namespace lasonic::eval
