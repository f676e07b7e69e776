#include "stages/pilot_stage.hpp"

#include <algorithm>
#include <optional>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <lasonic/grid_map_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "complement/complement_config.hpp"
#include "complement/dark_continuation.hpp"
#include "complement/messages.hpp"
#include "complement/radar_map.hpp"
#include "core/int_scan.hpp"
#include "core/pose_msg.hpp"
#include "core/utime.hpp"
#include "operational/remembered_on_lines.hpp"
#include "stages/inputs.hpp"
#include "stages/stage_messages.hpp"

namespace lasonic {

static_assert(static_cast<int8_t>(SectorSource::None) == sector_map_t::SOURCE_NONE &&
              static_cast<int8_t>(SectorSource::Laser) == sector_map_t::SOURCE_LASER &&
              static_cast<int8_t>(SectorSource::Sonar) == sector_map_t::SOURCE_SONAR &&
              static_cast<int8_t>(SectorSource::SonarCopied) == sector_map_t::SOURCE_SONAR_COPIED &&
              static_cast<int8_t>(SectorSource::Remembered) == sector_map_t::SOURCE_REMEMBERED);

AgmParams PilotConfig::operationalAgmDefaults() {
  AgmParams p;
  p.h_max = 18;
  return p;
}

SectorMapParams PilotConfig::sectorMapDefaults() {
  SectorMapParams s;
  s.laser_stale_s = 0.4;
  s.sonar_stale_s = 0.36;
  s.sonar_cell_point = CellPoint::Centre;
  s.copy_rule = CopyRule::UnlessLaserConfirmed;
  s.copy_over_own = true;
  s.copy_held = false;
  s.laser_explains_radius = 0.10;
  return s;
}

complement::DarkContinuationConfig PilotConfig::darkContinuationDefaults() {
  complement::DarkContinuationConfig d;
  d.length = 0.10;  // what a scan point stands for (laser_explains_radius)
  return d;
}

LaserMemoryHeardThrough PilotConfig::laserMemoryHeardThroughDefaults() {
  LaserMemoryHeardThrough h;
  h.clear_after = 3;
  return h;
}

namespace {
LaserMemoryParams laserMemoryParams(const PilotConfig& c) {
  // Beyond the sector map's reach a point is never reported; it comes back only by driving
  // back, and then the scanner sees it again.
  return {c.laser_memory_s, c.sector_map.robot_radius + c.sector_map.max_range, c.laser_memory_coast_s,
          c.laser_memory_cluster_s};
}
}  // namespace

LaserMemoryHeardThrough laserMemoryHeardThrough(const PilotConfig& c) {
  LaserMemoryHeardThrough h = c.laser_memory_heard_through;
  // One cluster as the mover prediction cuts it.
  h.cluster_gap = c.mover_prediction.cluster_gap;
  return h;
}

PilotConfig pilotConfigFromRoot(const Config& root) {
  PilotConfig cfg = pilotConfig(root.section("pilot"));
  cfg.scan_cut = complement::radarMapConfig(root.section("complement").section("radar_map"));
  return cfg;
}

PilotConfig pilotConfig(const Config& c) {
  std::vector<std::string> keys = {"agm", "sectors", "robot_radius", "max_range", "gp_threshold", "laser_stale_s",
                                   "sonar_stale_s", "agm_publish_hz", "map_max_interval_s", "sonar_cell_point",
                                   "copy_rule", "copy_confirm_tolerance", "laser_explains_radius", "remembered", "remembered_unchecked",
                                   "remembered_stale_s", "remembered_explains_radius", "remembered_on_lines_m", "remembered_fill_m",
                                   "copy_over_own", "predict_movers", "mover_prediction", "laser_memory_s",
                                   "laser_memory_coast_s", "laser_memory_cluster_s", "laser_memory_dark",
                                   "laser_memory_heard_through",
                                   "laser_memory_seam", "dark_continuation_m", "motion_confirmation",
                                   "outside_view_redundant", "h_max_ring_cycles", "hold_unpassed", "laser_stale_scans",
                                   "stale_radar_map", "stale_values"};
  for (const auto& k : echoPlacementKeys()) keys.push_back(k);
  c.allowOnly(keys);
  PilotConfig p;
  p.agm = agmParams(c.section("agm"), p.agm);
  p.h_max_ring_cycles = c.get("h_max_ring_cycles", p.h_max_ring_cycles, Range::between(0, 1000));
  {
    const Config h = c.section("hold_unpassed");
    h.allowOnly({"ring_cycles", "core", "margin_m", "copied", "at_range", "mover_radius_m"});
    p.hold_unpassed.mover_radius_m = h.get("mover_radius_m", p.hold_unpassed.mover_radius_m, Range::between(0, 2));
    p.hold_unpassed.at_range = h.get<bool>("at_range", p.hold_unpassed.at_range);
    p.sector_map.copy_held = h.get<bool>("copied", p.sector_map.copy_held);
    p.hold_unpassed.ring_cycles = h.get("ring_cycles", p.hold_unpassed.ring_cycles, Range::between(0, 1000));
    p.hold_unpassed.core = h.get("core", p.hold_unpassed.core, Range::between(0, 1));
    p.hold_unpassed.margin_m = h.get("margin_m", p.hold_unpassed.margin_m, Range::between(0, 1));
  }
  SectorMapParams& s = p.sector_map;
  s.sectors = c.get("sectors", s.sectors, Range::between(3, 3600));
  s.robot_radius = c.get("robot_radius", s.robot_radius, Range::nonNegative());
  // (A reach below 10 cm reports nothing a robot could act on.)
  s.max_range = c.get("max_range", s.max_range, Range::between(0.1, 1e3));
  s.gp_threshold = c.get("gp_threshold", p.agm.g_threshold, Range::between(1, p.agm.maxGp()));
  s.laser_stale_s = c.get("laser_stale_s", s.laser_stale_s, Range::positiveDuration());
  p.laser_stale_scans = c.get("laser_stale_scans", p.laser_stale_scans, Range::between(0, 1000));
  s.sonar_stale_s = c.get("sonar_stale_s", s.sonar_stale_s, Range::positiveDuration());
  s.stale_values = c.getChoice("stale_values", s.stale_values,
                               {{"held_min", StaleValues::HeldMin}, {"moved", StaleValues::Moved},
                                {"frontier", StaleValues::Frontier}});
  // (Bounded: a period or interval in µs must fit an int64; a display rate below one per 100 s or
  // a map interval of a minute has no use on a moving robot.)
  p.agm_publish_hz = c.get("agm_publish_hz", p.agm_publish_hz, Range::between(0.01, 1000));
  p.map_max_interval_s = c.get("map_max_interval_s", p.map_max_interval_s, Range::between(0.001, 60));
  p.placement = echoPlacementConfig(c, p.placement);
  {
    const Config m = c.section("motion_confirmation");
    m.allowOnly({"enabled", "tolerance_m"});
    p.motion_confirmation.enabled = m.get<bool>("enabled", p.motion_confirmation.enabled);
    p.motion_confirmation.tolerance_m = m.get("tolerance_m", p.motion_confirmation.tolerance_m, Range::between(0, 1));
  }
  s.sonar_cell_point = c.getChoice("sonar_cell_point", s.sonar_cell_point,
                                   {{"nearest", CellPoint::Nearest}, {"centre", CellPoint::Centre}});
  s.copy_rule = c.getChoice("copy_rule", s.copy_rule,
                            {{"paper", CopyRule::Paper},
                             {"unless_laser_confirmed", CopyRule::UnlessLaserConfirmed},
                             {"cell_extent", CopyRule::CellExtent}});
  s.copy_confirm_tolerance = c.get("copy_confirm_tolerance", s.copy_confirm_tolerance, Range::nonNegative());
  s.laser_explains_radius = c.get("laser_explains_radius", s.laser_explains_radius, Range::between(0, 1));
  p.remembered = c.get<bool>("remembered", p.remembered);
  p.remembered_unchecked = c.get<bool>("remembered_unchecked", p.remembered_unchecked);
  p.outside_view_redundant_laser = c.getChoice("outside_view_redundant", p.outside_view_redundant_laser,
                                               {{"laser_sector", true}, {"echo", false}});
  p.stale_radar_map_echoes = c.getChoice("stale_radar_map", p.stale_radar_map_echoes,
                                         {{"echoes", true}, {"paper", false}});
  s.remembered_stale_s = c.get("remembered_stale_s", s.remembered_stale_s, Range::positiveDuration());
  s.remembered_explains_radius =
      c.get("remembered_explains_radius", s.remembered_explains_radius, Range::between(0, 1));
  p.remembered_on_lines_m = c.get("remembered_on_lines_m", p.remembered_on_lines_m, Range::between(0, 1));
  p.remembered_fill_m = c.get("remembered_fill_m", p.remembered_fill_m, Range::between(0, 1));
  s.copy_over_own = c.get<bool>("copy_over_own", s.copy_over_own);
  p.predict_movers = c.get<bool>("predict_movers", p.predict_movers);
  p.laser_memory_s = c.get("laser_memory_s", p.laser_memory_s, Range::between(0, 60));
  p.laser_memory_coast_s = c.get("laser_memory_coast_s", p.laser_memory_coast_s, Range::between(0, 10));
  p.laser_memory_cluster_s = c.get("laser_memory_cluster_s", p.laser_memory_cluster_s, Range::between(0, 60));
  p.laser_memory_dark = c.get<bool>("laser_memory_dark", p.laser_memory_dark);
  {
    const Config h = c.section("laser_memory_heard_through");
    h.allowOnly({"clear_after", "core", "margin_m", "min_radius_m", "max_radius_m", "fit_rms_m"});
    LaserMemoryHeardThrough& t = p.laser_memory_heard_through;
    t.clear_after = h.get("clear_after", t.clear_after, Range::between(0, 1000));
    t.core = h.get("core", t.core, Range::between(0, 1));
    t.margin_m = h.get("margin_m", t.margin_m, Range::between(0, 1));
    t.min_radius = h.get("min_radius_m", t.min_radius, Range::between(0, 10));
    t.max_radius = h.get("max_radius_m", t.max_radius, Range::between(0, 10));
    t.fit_rms = h.get("fit_rms_m", t.fit_rms, Range::between(0, 1));
    if (t.min_radius > t.max_radius)
      h.fail("max_radius_m", "(" + showNumber(t.max_radius) + ") must not be less than min_radius_m (" +
                                 showNumber(t.min_radius) + ")");
  }
  p.laser_memory_seam = c.get<bool>("laser_memory_seam", p.laser_memory_seam);
  p.dark_continuation.length = c.get("dark_continuation_m", p.dark_continuation.length, Range::between(0, 1));
  {
    const Config m = c.section("mover_prediction");
    m.allowOnly({"cluster_gap", "max_extent", "min_points", "min_speed", "max_speed", "horizon_s", "horizon_scans",
                 "agree_speed", "flat_face_rms", "flat_face_min"});
    MoverPredictionParams& mp = p.mover_prediction;
    mp.cluster_gap = m.get("cluster_gap", mp.cluster_gap, Range::between(0.01, 2));
    mp.max_extent = m.get("max_extent", mp.max_extent, Range::between(0.05, 10));
    mp.min_points = m.get("min_points", mp.min_points, Range::between(2, 1000));
    mp.min_speed = m.get("min_speed", mp.min_speed, Range::between(0, 10));
    mp.max_speed = m.get("max_speed", mp.max_speed, Range::between(0.01, 20));
    mp.horizon_s = m.get("horizon_s", mp.horizon_s, Range::between(0, 2));
    mp.horizon_scans = m.get("horizon_scans", mp.horizon_scans, Range::between(0, 100));
    mp.agree_speed = m.get("agree_speed", mp.agree_speed, Range::between(0.01, 10));
    mp.flat_face_rms = m.get("flat_face_rms", mp.flat_face_rms, Range::between(0, 1));
    mp.flat_face_min = m.get("flat_face_min", mp.flat_face_min, Range::between(0, 10));
    if (!(mp.max_speed > mp.min_speed))
      m.fail("max_speed", "(" + showNumber(mp.max_speed) + ") must be greater than min_speed (" +
                              showNumber(mp.min_speed) + ")");
  }
  // The window must hold the whole sector map's reach wherever re-centring lets the robot be.
  const double view = p.agm.guaranteedView();
  if (view < s.robot_radius + s.max_range) {
    std::ostringstream msg;
    msg << "robot_radius + max_range = " << s.robot_radius + s.max_range << " m exceeds the AGM's guaranteed view of "
        << view << " m ((agm.size/2 - agm.recenter_max_cells - 1) * agm.cell_size)";
    c.fail("max_range", msg.str());
  }
  return p;
}

PilotStage::PilotStage(Node& node, const PilotConfig& cfg)
    : node_(node),
      cfg_(cfg),
      agm_(cfg.agm),
      sector_map_(cfg.sector_map),
      placer_(cfg.placement),
      motion_confirmation_(cfg.motion_confirmation),
      movers_(cfg.mover_prediction),
      laser_memory_(laserMemoryParams(cfg), laserMemoryHeardThrough(cfg)) {
  node_.subscribe<odometry_t>(channels::ODOMETRY, [this](const odometry_t& m) { onOdometry(m); });
  node_.subscribe<laser_scan_t>(channels::LASER_SCAN, [this](const laser_scan_t& m) { onLaserScan(m); });
  node_.subscribe<complement_t>(channels::SONAR_COMPLEMENT, [this](const complement_t& m) { onComplement(m); });
  if (cfg_.remembered)
    node_.subscribe<grid_map_t>(channels::AGM_TACTICAL, [this](const grid_map_t& m) { onTacticalMap(m); });
  if (cfg_.remembered && cfg_.remembered_on_lines_m > 0)
    node_.subscribe<line_map_t>(channels::AGM_LINES, [this](const line_map_t& m) { onAgmLines(m); });
}

void PilotStage::onAgmLines(const line_map_t& m) {
  // Published right after the AGM_TACTICAL of the same cycle; either may come first. A bad one is
  // dropped whole: the cells then stay at their centres.
  if (!timeOk(m.utime, channels::AGM_LINES)) return;
  if (!isNewer(node_, agm_lines_utime_, m.utime, channels::AGM_LINES, "agm_lines")) return;
  std::vector<geom::Segment> lines;
  lines.reserve(m.segments.size());
  for (size_t i = 0; i < m.segments.size(); ++i) {
    const line_segment_t& s = m.segments[i];
    if (!std::isfinite(s.x0) || !std::isfinite(s.y0) || !std::isfinite(s.x1) || !std::isfinite(s.y1)) {
      node_.reportError("rejected.agm_lines",
                        "AGM_LINES: segments[" + std::to_string(i) + "] has a non-finite end point: dropped");
      return;
    }
    lines.push_back({{s.x0, s.y0}, {s.x1, s.y1}});
  }
  agm_lines_ = std::move(lines);
  agm_lines_utime_ = m.utime;
  node_.count("remembered.line_maps");
  if (last_tactical_utime_ && *last_tactical_utime_ == m.utime) setRemembered();
}

std::vector<geom::Vec2> rememberedPoints(std::vector<geom::Vec2> cells, const std::vector<geom::Segment>& lines,
                                         const PilotConfig& cfg) {
  if (lines.empty()) return cells;
  const std::vector<int> taken_by = moveOntoLines(cells, lines, cfg.remembered_on_lines_m);
  // A gap the robot could drive through stays a gap (the navigator splits its lines there too).
  const std::vector<geom::Vec2> fill =
      fillBetweenOnLines(cells, taken_by, lines, cfg.remembered_fill_m, 2 * cfg.sector_map.robot_radius);
  cells.insert(cells.end(), fill.begin(), fill.end());
  return cells;
}

void navigatorToOdometryFrame(std::vector<geom::Vec2>& points, const geom::Pose2& here, const geom::Pose2& there) {
  if (here.x == there.x && here.y == there.y && here.theta == there.theta) return;
  const geom::PoseTransform ours_from_theirs(here.compose(there.inverse()));
  for (geom::Vec2& p : points) p = ours_from_theirs(p);
}

void PilotStage::setRemembered() {
  static const std::vector<geom::Segment> kNoLines;
  const bool same_cycle = agm_lines_utime_ && last_tactical_utime_ && *agm_lines_utime_ == *last_tactical_utime_;
  std::vector<geom::Vec2> points = rememberedPoints(tactical_points_, same_cycle ? agm_lines_ : kNoLines, cfg_);
  const auto here = poses_.at(*last_tactical_utime_);
  if (!here) {
    node_.count("remembered.no_odometry");
    return;
  }
  navigatorToOdometryFrame(points, *here, tactical_robot_pose_);
  sector_map_.setRemembered(*last_tactical_utime_, std::move(points));
}

void PilotStage::onTacticalMap(const grid_map_t& m) {
  // Not a sensor: it does not advance the map's time (a navigator ahead of the pilot's clock is
  // simply fresh), and a bad one is dropped whole -- memory may only add what is sure.
  if (!timeOk(m.utime, channels::AGM_TACTICAL)) return;
  if (!isNewer(node_, last_tactical_utime_, m.utime, channels::AGM_TACTICAL, "tactical")) return;
  const int64_t cells = int64_t{m.width} * int64_t{m.height};
  if (m.width <= 0 || m.height <= 0 || cells != static_cast<int64_t>(m.gp.size()) || !(m.cell_size > 0) ||
      !std::isfinite(m.cell_size) || !std::isfinite(m.origin_x) || !std::isfinite(m.origin_y) ||
      !std::isfinite(m.robot_pose.x) || !std::isfinite(m.robot_pose.y) || !std::isfinite(m.robot_pose.theta)) {
    node_.reportError("rejected.tactical_map", "AGM_TACTICAL: " + std::to_string(m.width) + " x " +
                                                   std::to_string(m.height) + " cells of " + std::to_string(m.cell_size) +
                                                   " m, " + std::to_string(m.gp.size()) +
                                                   " Gp values, or a non-finite origin or robot_pose: dropped");
    return;
  }
  last_tactical_utime_ = m.utime;
  tactical_robot_pose_ = toPose(m.robot_pose);
  std::vector<geom::Vec2>& points = tactical_points_;
  points.clear();
  const int threshold = std::max(1, m.gp_threshold);
  // (A map whose `heard` is not one per cell records nothing: every cell is used.)
  const bool leave_unchecked = !cfg_.remembered_unchecked && m.heard.size() == m.gp.size();
  int64_t unchecked = 0;
  const auto keep = [&](int ix, int iy) {
    if (leave_unchecked && m.heard[static_cast<size_t>(iy) * static_cast<size_t>(m.width) + static_cast<size_t>(ix)] ==
                               grid_map_t::HEARD_UNCHECKED) {
      ++unchecked;
      return;
    }
    points.emplace_back(m.origin_x + (ix + 0.5) * m.cell_size, m.origin_y + (iy + 0.5) * m.cell_size);
  };
  for (int iy = 0; iy < m.height; ++iy) {
    const int32_t* const row = m.gp.data() + static_cast<size_t>(iy) * static_cast<size_t>(m.width);
    forEachAtLeast(row, static_cast<size_t>(m.width), threshold, [&](size_t ix) { keep(static_cast<int>(ix), iy); });
  }
  if (unchecked > 0) node_.count("remembered.unchecked_left_out", unchecked);
  setRemembered();
  node_.count("remembered.maps");
}

bool PilotStage::timeOk(int64_t utime, const char* channel) {
  const ClockCheck c = checkClock(node_, clock_, utime, channel);
  if (c != ClockCheck::Restarted) return c == ClockCheck::Ok;
  poses_.clear();
  odometry_outage_ = OdometryOutage{};
  laser_outage_.reset();
  sonar_outage_.reset();
  speed_ = 0;
  agm_ = AccumulativeGridMap(cfg_.agm);
  sector_map_ = SectorMap(cfg_.sector_map);
  placer_ = EchoPlacer(cfg_.placement);
  motion_confirmation_ = MotionConfirmation(cfg_.motion_confirmation);
  ring_groups_ = RingGroups{};
  scan_period_ = ScanPeriod{};
  movers_ = MoverPrediction(cfg_.mover_prediction);
  laser_memory_ = LaserMemory(laserMemoryParams(cfg_), laserMemoryHeardThrough(cfg_));
  last_tactical_utime_.reset();
  agm_lines_utime_.reset();
  agm_lines_.clear();
  tactical_points_.clear();
  last_scan_utime_.reset();
  last_complement_utime_.reset();
  last_agm_publish_.reset();
  last_map_utime_.reset();
  now_ = 0;
  return true;
}

void PilotStage::onOdometry(const odometry_t& m) {
  if (!timeOk(m.utime, channels::ODOMETRY)) return;
  const auto odo = acceptOdometry(node_, poses_, m);
  if (!odo) return;
  speed_ = odo->v;
  // No sensor made a map for too long: odometry does, so the ages (and stale flags) move on.
  const auto interval_us = secondsToUs(cfg_.map_max_interval_s);
  if (last_map_utime_ && odo->utime - *last_map_utime_ >= interval_us) {
    now_ = std::max(now_, odo->utime);
    node_.count("sector_map.on_odometry");
    publishSectorMap();
  }
}

void giveScanForShadow(SectorMap& sector_map, const complement::LaserScan& scan,
                       const std::vector<complement::ScanPoint>& placed, const geom::Pose2& robot,
                       std::vector<geom::Vec2>& xy, std::vector<uint8_t>& valid) {
  xy.resize(placed.size());
  valid.resize(placed.size());
  for (size_t i = 0; i < placed.size(); ++i) {
    xy[i] = placed[i].p;
    valid[i] = placed[i].valid ? 1 : 0;
  }
  sector_map.setLaserScan(xy, valid, complement::laserViewOf(scan, robot).sensor.position(), scan.full_circle);
}

void noReturnMask(const laser_scan_t& m, std::vector<uint8_t>& mask) {
  const size_t n = m.flags.size();
  mask.resize(n);
  // In the LaserScan's order: a clockwise scan's readings reversed (complement::laserScanFromMessage).
  const bool reversed = m.angle_increment < 0;
  for (size_t i = 0; i < n; ++i)
    mask[reversed ? n - 1 - i : i] = m.flags[i] == laser_scan_t::FLAG_NO_RETURN && i < m.offset_us.size() &&
                                     complement::input_limits::offsetInSweep(m.offset_us[i]);
}

void validReturns(const std::vector<complement::ScanPoint>& placed, const std::vector<complement::LaserReading>& readings,
                  std::vector<geom::Vec2>& points, std::vector<TimedPoint>* timed, int64_t& newest) {
  // Every element written and the count advanced by validity (no branch per reading); the
  // surplus cut off at the end. Through local pointers and a local maximum: the stores could
  // alias the vectors and newest, which would otherwise be reloaded and stored per reading.
  const size_t n = std::min(placed.size(), readings.size());
  points.resize(n);
  const complement::ScanPoint* in = placed.data();
  const complement::LaserReading* rd = readings.data();
  geom::Vec2* out = points.data();
  int64_t latest = newest;
  size_t k = 0;
  if (timed) {
    timed->resize(n);
    TimedPoint* tout = timed->data();
    for (size_t i = 0; i < n; ++i) {
      const int64_t t = rd[i].utime;
      latest = std::max(latest, t);
      const geom::Vec2 p = in[i].p;
      out[k] = p;
      tout[k].p = p;
      tout[k].utime = t;
      k += in[i].valid ? 1 : 0;
    }
    timed->resize(k);
  } else {
    for (size_t i = 0; i < n; ++i) {
      latest = std::max(latest, rd[i].utime);
      out[k] = in[i].p;
      k += in[i].valid ? 1 : 0;
    }
  }
  points.resize(k);
  newest = latest;
}

void takeOutMovers(const std::vector<TimedPoint>& scan, const std::vector<MoverPrediction::MovingRun>& runs,
                   std::vector<geom::Vec2>& points, std::vector<SectorMap::MovingPoint>& moving) {
  size_t kept = 0, next = 0;  // points[0 .. kept) are final; points[next ..] not looked at yet
  for (const MoverPrediction::MovingRun& r : runs) {
    if (r.vel.x() == 0 && r.vel.y() == 0) continue;
    std::copy(points.begin() + static_cast<std::ptrdiff_t>(next), points.begin() + static_cast<std::ptrdiff_t>(r.first),
              points.begin() + static_cast<std::ptrdiff_t>(kept));
    kept += r.first - next;
    for (size_t j = r.first; j <= r.last; ++j) moving.push_back({scan[j].p, r.vel, scan[j].utime});
    next = r.last + 1;
  }
  if (next == 0) return;  // nothing taken out
  std::copy(points.begin() + static_cast<std::ptrdiff_t>(next), points.end(), points.begin() + static_cast<std::ptrdiff_t>(kept));
  points.resize(kept + (points.size() - next));
}

void PilotStage::onLaserScan(const laser_scan_t& m) {
  if (!timeOk(m.utime, channels::LASER_SCAN)) return;
  node_.noteMessageTime(m.utime);
  if (!isNewer(node_, last_scan_utime_, m.utime, channels::LASER_SCAN, "laser")) return;
  std::vector<complement::InputProblem> problems;
  const std::optional<complement::LaserScan>& scan =
      placement_ ? placement_->scanFrom(m, problems) : complement::laserScanFromMessageInto(m, problems, own_scan_);
  reportProblems(node_, problems);
  if (!scan) return;
  last_scan_utime_ = m.utime;
  // What is said in scan periods follows the laser's own (a 2.5 Hz scanner's people move twice as
  // far between scans as a 5 Hz one's).
  scan_period_.scanned(m.utime);
  sector_map_.setLaserStaleS(scan_period_.scans(cfg_.laser_stale_scans, cfg_.sector_map.laser_stale_s));
  // A full-circle scanner sees everywhere: nothing to remember (LaserMemory would keep nothing)
  // but, with laser_memory_dark, where its readings came back empty.
  const bool remember =
      laser_memory_.enabled() && (!scan->full_circle || cfg_.laser_memory_dark) && !scan->readings.empty();
  bool mask_made = false;  // no_return_ holds this scan's empty readings
  if (remember && cfg_.laser_memory_dark) {
    noReturnMask(m, no_return_);
    mask_made = true;
  }
  if (!remember) laser_memory_.clear();

  int no_pose = 0;
  if (!placement_) complement::placeReadingsInto(*scan, poses_, own_placed_, &no_pose);
  const std::vector<complement::ScanPoint>& placed = placement_ ? placement_->place(*scan, poses_, &no_pose) : own_placed_;
  // The valid returns, in scan order (points[k] is timed_[k].p); in the storage the sector map
  // handed back from the previous scan.
  std::vector<geom::Vec2>& points = laser_points_;
  int64_t newest = m.utime;
  validReturns(placed, scan->readings, points, cfg_.predict_movers ? &timed_ : nullptr, newest);
  std::vector<SectorMap::MovingPoint> moving;
  // What the laser memory may keep: returns known to stand still (all of them without the
  // mover prediction).
  std::vector<geom::Vec2>& still = still_;  // (storage reused scan to scan)
  still.clear();
  still_cluster_.clear();  // per still return: of a still person-sized cluster
  if (cfg_.predict_movers) {
    // The robot at the middle of the scan (its readings span one revolution).
    const int64_t mid = m.utime + (newest - m.utime) / 2;
    const std::vector<MoverPrediction::MovingRun>& runs =
        movers_.track(timed_, poses_.at(mid).value_or(poses_.at(newest).value_or(geom::Pose2{})).position());
    if (remember) {
      still.reserve(timed_.size());
      for (size_t i = 0; i < timed_.size(); ++i)
        if (const uint8_t s = movers_.still()[i]; s != 0) {
          still.push_back(timed_[i].p);
          still_cluster_.push_back(s == MoverPrediction::kStillCluster);
        }
    }
    takeOutMovers(timed_, runs, points, moving);
    if (!moving.empty()) node_.count("laser.moving_returns", static_cast<int64_t>(moving.size()));
    if (cfg_.hold_unpassed.ring_cycles > 0) markNearMovers(agm_, moving, cfg_.hold_unpassed.mover_radius_m);
  } else if (remember) {
    still.assign(points.begin(), points.end());  // every return, before the dark continuation adds its points below
  }
  if (cfg_.dark_continuation.length > 0 && !mask_made) noReturnMask(m, no_return_);
  if (cfg_.dark_continuation.length > 0) {
    // Where a straight run of returns ends in readings that came back empty, its surface goes on
    // unseen (complement/dark_continuation.hpp). Not kept by the laser memory: it is the newest
    // scan's alone. The run's jump and fit rules are the Radar Map's (`complement.radar_map`).
    const size_t before = points.size();
    complement::darkContinuation(*scan, placed, no_return_, [this](int64_t t) { return poses_.at(t); },
                                 cfg_.scan_cut, cfg_.dark_continuation, points);
    if (points.size() > before) node_.count("laser.dark_continuation", static_cast<int64_t>(points.size() - before));
  }
  if (no_pose > 0) {
    node_.reportError("rejected.laser_no_odometry", "LASER_SCAN utime " + std::to_string(m.utime) +
                                                        ": no odometry for " + std::to_string(no_pose) +
                                                        " readings");
    // A scan none of whose returns could be placed says nothing: keep the previous one (it ages).
    if (points.empty() && moving.empty()) return;
  }
  // The view as the Radar Map takes it: the scanner's pose at the scan's last reading. Without
  // that pose nothing tells what the scan covered: nothing is remembered or recalled.
  if (const auto robot = poses_.at(newest); remember && robot) {
    const complement::LaserView view = complement::laserViewOf(*scan, *robot);
    // The newest scan decides where it looked and a reading came back; with laser_memory_dark,
    // where the reading nearest in bearing and both its neighbours came back empty, an earlier
    // return stays.
    std::optional<complement::DarkBearings> dark;
    if (cfg_.laser_memory_dark) dark.emplace(*scan, view, no_return_);
    // Where it looked: a robot turning against the sweep leaves a wedge at a full circle's seam
    // that no reading of this scan looked into; earlier returns stay there.
    const auto first = cfg_.laser_memory_seam ? poses_.at(complement::firstReadingTime(*scan)) : std::nullopt;
    const complement::LaserView looked = first ? complement::laserViewOf(*scan, *robot, *first) : view;
    laser_memory_.update(
        newest, robot->position(), still, moving,
        [&looked, &dark](const geom::Vec2& p) { return looked.covers(p) && !(dark && dark->at(p)); }, &still_cluster_);
    const std::vector<SectorMap::MovingPoint>& coasting = laser_memory_.coastingMovers();
    if (!coasting.empty()) {
      moving.insert(moving.end(), coasting.begin(), coasting.end());
      node_.count("laser.coasting_returns", static_cast<int64_t>(coasting.size()));
    }
    const std::vector<geom::Vec2>& remembered = laser_memory_.points();
    if (!remembered.empty()) {
      points.insert(points.end(), remembered.begin(), remembered.end());
      node_.count("laser.remembered_returns", static_cast<int64_t>(remembered.size()));
    }
  }
  laser_points_ = sector_map_.setLaserPoints(newest, std::move(points));
  // What this scan did not see free, for when it is the last one (every return, movers' too).
  if (cfg_.sector_map.stale_values == StaleValues::Frontier)
    if (const auto robot = poses_.at(newest))
      giveScanForShadow(sector_map_, *scan, placed, *robot, shadow_points_, shadow_valid_);
  sector_map_.setLaserMovers(std::move(moving),
                             scan_period_.scans(cfg_.mover_prediction.horizon_scans, cfg_.mover_prediction.horizon_s));
  now_ = std::max(now_, newest);
  publishSectorMap();
}

void PilotStage::onComplement(const complement_t& m) {
  if (!timeOk(m.utime, channels::SONAR_COMPLEMENT)) return;
  node_.noteMessageTime(m.utime);
  if (!isNewer(node_, last_complement_utime_, m.utime, channels::SONAR_COMPLEMENT, "complement")) return;
  last_complement_utime_ = m.utime;

  std::vector<complement::InputProblem> problems;
  const std::vector<complement::ComplementInput> readings = complement::complementFromMessage(m, problems);
  reportProblems(node_, problems);
  // An echo that lines an earlier scan saw explain where the newest does not look (SeenBefore,
  // complement/radar_map_memory.hpp) is left out where the laser's returns the sector map holds
  // (the newest scan's, the laser memory's) report its surface in its own sector, at its range
  // within the complement's tolerance (the message's): the echo adds nothing there. Elsewhere
  // it is the only report of that surface (the memory keeps only returns known to stand still)
  // and goes in.
  // Without the laser, what the sonar hears is the only report of what is near: a person who
  // walks up while the laser is lost is otherwise in no map (the held laser distances do not see
  // them), so a group without a recent Radar Map has its echoes in (stale_radar_map: echoes).
  std::vector<GroupReading> group = toGroupReadings(readings, m.utime, true, cfg_.stale_radar_map_echoes);
  const double tol = std::isfinite(m.tolerance) && m.tolerance >= 0 ? m.tolerance : 0.0;
  const double sector = 2 * geom::kPi / std::max(1, sector_map_.params().sectors);
  for (size_t i = 0; i < group.size() && i < readings.size(); ++i) {
    const complement::ComplementInput& r = readings[i];
    if (r.cls == complement::SonarClass::SeenBefore && group[i].echo && r.sensor_pose &&
        laserReportsEcho(sector_map_.laserPoints(), *r.sensor_pose, r.range, tol, sector)) {
      group[i].echo = false;
      node_.count("agm.seen_before_left_out");
    }
    // An outside-view echo the newest scan's lines explain (redundant by them: the message keeps
    // that hypothesis) came most likely from the surface the scan saw at the edge of its view:
    // on its axis, beyond the view, it lies in front of whatever the laser reports there (an
    // oblique wall passed). Left out where the sector map holds any laser return in its own
    // sector; where it holds none, it is the only report there and goes in.
    if (cfg_.outside_view_redundant_laser && r.cls == complement::SonarClass::OutsideView && group[i].echo &&
        r.sensor_pose && std::abs(r.range - r.hypothetical_range) <= tol &&
        laserInSector(sector_map_.laserPoints(), *r.sensor_pose, sector)) {
      group[i].echo = false;
      node_.count("agm.outside_view_redundant_left_out");
    }
    if (group[i].echo && r.unverified_echo) node_.count("agm.unverified_echoes");
  }
  // The AGM's memory in ring cycles: this group's firing counted, h_max follows the ring.
  ring_groups_.fired(m.group);
  agm_.setHMax(ring_groups_.hMax(cfg_.h_max_ring_cycles, cfg_.agm.h_max));
  // Where the group's sound went with nothing answering (operational/sound_passed.hpp).
  const bool memory_heard = laser_memory_.enabled() && cfg_.laser_memory_heard_through.clear_after > 0;
  std::vector<Sounding> soundings;
  if (cfg_.hold_unpassed.ring_cycles > 0 || memory_heard) {
    const double beam = geom::plausibleBeamWidth(m.beam_width) ? m.beam_width : cfg_.placement.params.beam_width;
    soundings = soundingsOf(readings, beam, true, true);
  }
  if (cfg_.hold_unpassed.ring_cycles > 0) {
    // The hold counts from the firings too; before the ring is counted, h_max's own length.
    agm_.setHoldUnpassed(ring_groups_.hMax(cfg_.hold_unpassed.ring_cycles, cfg_.agm.h_max));
    if (const int n = markSoundPassed(agm_, soundings, cfg_.hold_unpassed.core, cfg_.hold_unpassed.margin_m,
                                      cfg_.hold_unpassed.at_range);
        n > 0)
      node_.count("agm.cells_heard_through", n);
  }
  // A remembered round cluster the sound went through, looks in a row, is gone (from the next
  // scan's sector maps on: operational/laser_memory.hpp).
  if (memory_heard)
    if (const int n = laser_memory_.heardThrough(m.utime, soundings); n > 0)
      node_.count("laser.memory_heard_through", n);
  std::vector<geom::Vec2> hits = placer_.place(group, agm_);
  if (const int n = motion_confirmation_.apply(placer_.lastPlaced(), agm_, hits); n > 0)
    node_.count("agm.motion_confirmed", n);
  for (const GroupReading& r : group) motion_confirmation_.fired(r.sensor_id, m.utime);

  if (const auto pose = poses_.at(m.utime); pose && agm_.follow(pose->position(), speed_))
    node_.count("agm.recentred");
  const int inside = agm_.update(hits);
  node_.count("agm.cycles");
  node_.count("agm.hits", inside);
  if (inside < static_cast<int>(hits.size()))
    node_.count("agm.hits_outside_window", static_cast<int64_t>(hits.size()) - inside);

  sector_map_.setSonarTime(m.utime);
  now_ = std::max(now_, m.utime);
  publishSectorMap();
  const auto period_us = periodUs(cfg_.agm_publish_hz);
  if (!last_agm_publish_ || m.utime - *last_agm_publish_ >= period_us) publishAgm(m.utime);
}

void PilotStage::publishSectorMap() {
  const auto pose = poses_.at(now_);
  if (!pose) {
    node_.count("sector_map.no_odometry");
    odometry_outage_.missing(node_, poses_, now_, "SECTOR_MAP");
    return;
  }
  odometry_outage_.present(now_);
  const SectorMapState& s = sector_map_.update(now_, *pose, agm_);
  sector_map_t& msg = map_msg_;  // (kept: its arrays' storage is reused, map after map)
  msg.utime = s.utime;
  msg.robot_pose = {s.pose.x, s.pose.y, s.pose.theta};
  msg.robot_radius = static_cast<float>(cfg_.sector_map.robot_radius);
  msg.max_range = static_cast<float>(cfg_.sector_map.max_range);
  msg.distance = s.distance;
  msg.laser_distance = s.laser;
  msg.sonar_distance = s.sonar;
  msg.source.resize(s.source.size());
  for (size_t k = 0; k < s.source.size(); ++k) msg.source[k] = static_cast<int8_t>(s.source[k]);
  msg.laser_stale = s.laser_stale ? 1 : 0;
  msg.sonar_stale = s.sonar_stale ? 1 : 0;
  msg.laser_age_s = static_cast<float>(s.laser_age_s);
  msg.sonar_age_s = static_cast<float>(s.sonar_age_s);
  msg.remembered_distance = s.remembered;
  msg.remembered_stale = s.remembered_stale ? 1 : 0;
  msg.remembered_age_s = static_cast<float>(s.remembered_age_s);
  node_.publish(channels::SECTOR_MAP, msg);
  last_map_utime_ = s.utime;
  const auto newest = [&](double age_s) {
    return age_s >= 0 ? std::optional<int64_t>(s.utime - secondsToUs(age_s)) : std::nullopt;
  };
  const StaleValues rule = cfg_.sector_map.stale_values;
  const bool held = rule == StaleValues::HeldMin;
  laser_outage_.update(node_, s.utime, newest(s.laser_age_s), s.laser_stale, "laser.lost", channels::LASER_SCAN,
                       held ? "the sector map holds the laser's last distances, flagged laser_stale"
                       : rule == StaleValues::Frontier
                           ? "the sector map moves the laser's last scan, and where it did not see free, with "
                             "odometry, flagged laser_stale"
                           : "the sector map moves the laser's last scan with odometry, flagged laser_stale");
  sonar_outage_.update(node_, s.utime, newest(s.sonar_age_s), s.sonar_stale, "sonar.lost", channels::SONAR_COMPLEMENT,
                       held ? "the sector map holds the sonar's last distances, flagged sonar_stale"
                            : "the sector map moves the operational AGM with odometry, flagged sonar_stale");
}

void PilotStage::publishAgm(int64_t utime) {
  // Without the robot's pose at that time the grid would go out with a made-up one (the origin);
  // as the sector map, it waits for odometry (the AGM itself runs on: its hits are global).
  const auto pose = poses_.at(utime);
  if (!pose) {
    node_.count("agm.no_odometry");
    return;
  }
  gridMapMessageInto(agm_msg_, agm_, utime, *pose, cfg_.sector_map.gp_threshold);
  node_.publish(channels::AGM_OPERATIONAL, agm_msg_);
  last_agm_publish_ = utime;
}

}  // namespace lasonic
