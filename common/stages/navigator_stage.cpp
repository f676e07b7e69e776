#include "stages/navigator_stage.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <spdlog/spdlog.h>

#include "complement/complement_config.hpp"
#include "stages/inputs.hpp"
#include "stages/pilot_stage.hpp"
#include "stages/stage_messages.hpp"
#include "core/utime.hpp"

namespace lasonic {

static_assert(EchoProvenance::kUnknown == grid_map_t::HEARD_UNKNOWN && EchoProvenance::kChecked == grid_map_t::HEARD_CHECKED &&
              EchoProvenance::kUnchecked == grid_map_t::HEARD_UNCHECKED && EchoProvenance::kBoth == grid_map_t::HEARD_BOTH);

AgmParams NavigatorConfig::tacticalAgmDefaults() {
  AgmParams p;
  p.size = 200;
  p.cell_size = 0.10;
  p.h_max = 10000;
  p.h_max_m = 0;
  p.forget_sigma_m = 0.08;
  p.t = 1;
  p.g_threshold = 5;
  p.hit_centroids = true;
  p.arc_vote_tau = 100;
  return p;
}

EchoPlacementConfig NavigatorConfig::tacticalPlacementDefaults() {
  EchoPlacementConfig p;
  p.placement = AgmPlacement::ArcVotes;
  p.arc_require_votes = true;
  p.arc_wait_cycles = 100;
  return p;
}

NavigatorConfig navigatorConfigFromRoot(const Config& root) {
  NavigatorConfig cfg = navigatorConfig(root.section("navigator"));
  cfg.scan_cut = complement::radarMapConfig(root.section("complement").section("radar_map"));
  cfg.robot_radius = pilotConfig(root.section("pilot")).sector_map.robot_radius;
  // The window must hold every complementary echo wherever re-centring lets the robot be (as the
  // pilot's holds the sector map's reach): else the tactical map stays empty without a word.
  const double reach = cfg.robot_radius + complement::complementConfig(root.section("complement")).params.model.range_limit;
  const double view = cfg.agm.guaranteedView();
  if (view < reach) {
    std::ostringstream msg;
    msg << (cfg.agm.size / 2 - cfg.agm.recenter_max_cells - 1) << " cells of " << cfg.agm.cell_size
        << " m ((size/2 - recenter_max_cells - 1) * cell_size = " << view
        << " m) do not hold the sonar's reach, pilot.robot_radius + complement.range_limit = " << reach << " m";
    root.section("navigator").section("agm").fail("cell_size", msg.str());
  }
  return cfg;
}

NavigatorConfig navigatorConfig(const Config& c) {
  std::vector<std::string> keys = {"agm", "lines", "publish_hz", "verify_with_next_scan", "verify_max_wait_s", "verify_max_wait_scans",
                                   "hit_weight_speed", "hit_weight_low_speed", "published_size", "laser_join", "laser_join_min_line_m",
                                   "laser_glints", "scan_matching", "clear_footprint", "look_weight_votes",
                                   "pass_through", "g_threshold_walking_speed"};
  for (const auto& k : echoPlacementKeys()) keys.push_back(k);
  c.allowOnly(keys);
  NavigatorConfig p;
  p.agm = agmParams(c.section("agm"), p.agm);
  p.placement = echoPlacementConfig(c, p.placement);
  // Every propagated cell is a line candidate unless configured otherwise.
  LineGenerationParams lines = p.lines;
  lines.gp_threshold = p.agm.g_threshold;
  lines.neighbourhood = p.agm.t;  // the sums Gp is made of (one source: the AGM's t)
  p.lines = lineGenerationParams(c.section("lines"), lines);
  p.lines_follow_g_threshold = !c.section("lines").has("gp_threshold");
  if (const double most = p.agm.maxGp(); p.lines.gp_threshold > most)
    c.section("lines").fail("gp_threshold", std::to_string(p.lines.gp_threshold) + " is never reached: Gp is at most " +
                                                std::to_string(most) + " ((2 agm.t + 1)^2 * agm.g_max)");
  p.g_threshold_fixed = c.section("agm").has("g_threshold");
  p.g_threshold_walking_speed = c.get("g_threshold_walking_speed", p.g_threshold_walking_speed, Range::between(0, 10));
  // (Bounded: its period in µs must fit an int64; below one per 100 s the tactical maps say nothing.)
  p.publish_hz = c.get("publish_hz", p.publish_hz, Range::between(0.01, 1000));
  p.verify_with_next_scan = c.get<bool>("verify_with_next_scan", p.verify_with_next_scan);
  p.verify_max_wait_s = c.get("verify_max_wait_s", p.verify_max_wait_s, Range::duration());
  p.verify_max_wait_scans = c.get("verify_max_wait_scans", p.verify_max_wait_scans, Range::between(0, 100));
  p.hit_weight_speed = c.get("hit_weight_speed", p.hit_weight_speed, Range::between(0, 10));
  p.hit_weight_low_speed = c.get("hit_weight_low_speed", p.hit_weight_low_speed, Range::between(0, 10));
  p.clear_footprint = c.get<bool>("clear_footprint", p.clear_footprint);
  p.look_weight_votes = c.get<bool>("look_weight_votes", p.look_weight_votes);
  p.laser_join = c.get<bool>("laser_join", p.laser_join);
  p.laser_join_min_line_m = c.get("laser_join_min_line_m", p.laser_join_min_line_m, Range::nonNegative());
  p.laser_glints = laserGlintParams(c.section("laser_glints"), p.laser_glints);
  p.pass_through = passThroughParams(c.section("pass_through"), p.pass_through);
  p.scan_matching = scanMatchParams(c.section("scan_matching"), p.scan_matching);
  p.published_size = c.get("published_size", p.published_size, Range::between(0, 1e6));
  if (p.published_size > p.agm.size)
    c.fail("published_size", std::to_string(p.published_size) + " cells, more than the tactical AGM's size (agm.size " +
                                 std::to_string(p.agm.size) + ")");
  return p;
}

AgmParams NavigatorConfig::effectiveAgm() const {
  AgmParams a = agm;
  if (scan_matching.enabled) {
    a.odometry_trans_noise = scan_matching.pose_noise.trans;
    a.odometry_rot_noise = scan_matching.pose_noise.rot;
    a.odometry_drift_noise = scan_matching.pose_noise.drift;
  }
  return a;
}

NavigatorStage::NavigatorStage(Node& node, const NavigatorConfig& cfg)
    : node_(node),
      cfg_(cfg),
      lines_(cfg.lines),
      agm_(cfg.effectiveAgm()),
      placer_(cfg.placement),
      look_weight_(cfg.hit_weight_speed, cfg.hit_weight_low_speed),
      pass_through_(cfg.pass_through),
      glints_(cfg.laser_glints),
      matcher_(cfg.scan_matching),
      cycle_utime_(static_cast<size_t>(cfg.agm.h_max) + 2, 0) {
  node_.subscribe<odometry_t>(channels::ODOMETRY, [this](const odometry_t& m) { onOdometry(m); });
  node_.subscribe<line_map_t>(channels::RADAR_MAP, [this](const line_map_t& m) { onRadarMap(m); });
  node_.subscribe<complement_t>(channels::SONAR_COMPLEMENT, [this](const complement_t& m) { onComplement(m); });
  // The glints are the scan's shortest segments, which the Radar Map drops (its min_length is
  // the sonar's lateral resolution), and scan matching needs the readings themselves: the
  // navigator cuts the scan itself, with the Radar Map's jump and fit rules (the shipped
  // `complement.radar_map` values are the code defaults).
  if (cfg_.laser_glints.enabled() || cfg_.scan_matching.enabled)
    node_.subscribe<laser_scan_t>(channels::LASER_SCAN, [this](const laser_scan_t& m) { onLaserScan(m); });
}

void NavigatorStage::onLaserScan(const laser_scan_t& m) {
  if (!timeOk(m.utime, channels::LASER_SCAN)) return;
  node_.noteMessageTime(m.utime);
  if (!isNewer(node_, last_scan_utime_, m.utime, channels::LASER_SCAN, "laser")) return;
  // A scan still waiting for its odometry goes in with what there is.
  if (scan_waiting_) processScan();
  std::vector<complement::InputProblem> problems;
  const std::optional<complement::LaserScan>& scan = complement::laserScanFromMessageInto(m, problems, own_scan_);
  reportProblems(node_, problems);
  if (!scan) return;
  last_scan_utime_ = m.utime;
  scan_period_.scanned(m.utime);
  // Placed once the odometry has passed its last reading (or the next scan comes): so its
  // readings' poses are interpolated, never held, whatever reached the navigator first.
  scan_waiting_ = true;
  if (newest_odometry_utime_ && *newest_odometry_utime_ >= complement::lastReadingTime(*scan)) processScan();
}

void NavigatorStage::processScan() {
  scan_waiting_ = false;
  if (!own_scan_) return;
  const complement::LaserScan* scan = &*own_scan_;
  // Seen from the scanner at the scan's last reading; without that pose, from nowhere known.
  const int64_t last = complement::lastReadingTime(*scan);
  const auto robot = poses_.at(last);
  int no_pose = 0;
  if (robot) complement::placeReadingsInto(*scan, poses_, placed_, &no_pose);
  if (!robot || no_pose > 0) {
    node_.count("glints.no_odometry");
    if (!robot) return;
  }
  complement::RadarMapConfig cut = cfg_.scan_cut;
  cut.min_points = cfg_.laser_glints.min_points;
  cut.min_length = 0;
  segments_.clear();
  complement::appendScanSegments(placed_, scan->full_circle, cut, segments_);
  const geom::Vec2 scanner = robot->compose(scan->mount).position();
  if (cfg_.scan_matching.enabled) {
    const ScanMatcher::Result r = matcher_.update(placed_, segments_, *robot, scanner);
    node_.count(r.matched ? "scan_match.matched" : "scan_match.unmatched");
    if (r.matched && !r.constrained) node_.count("scan_match.unconstrained");
    if (r.new_keyframe) node_.count("scan_match.keyframes");
    corrections_.push_back({last, matcher_.correction(), r.constrained});
    // Inputs wait at most verify_max_wait_s for the next scan: 5 s of corrections is plenty.
    while (corrections_.size() > 2 && corrections_[1].utime < last - 5'000'000) corrections_.pop_front();
  }
  if (!cfg_.laser_glints.enabled()) return;
  geom::Vec2 viewpoint = scanner;
  if (cfg_.scan_matching.enabled) {
    const geom::PoseTransform c(correctionAt(last));
    for (complement::RmSegment& s : segments_) s.seg = c(s.seg);
    viewpoint = c(scanner);
  }
  const std::vector<complement::RmSegment> glints = glints_.update(last, viewpoint, segments_);
  if (glints.empty()) return;
  const std::vector<geom::Vec2> hits = glintHits(glints);
  glint_hits_.insert(glint_hits_.end(), hits.begin(), hits.end());
  node_.count("agm.laser_glints", static_cast<int64_t>(glints.size()));
}

bool NavigatorStage::timeOk(int64_t utime, const char* channel) {
  const ClockCheck c = checkClock(node_, clock_, utime, channel);
  if (c != ClockCheck::Restarted) return c == ClockCheck::Ok;
  poses_.clear();
  odometry_outage_ = OdometryOutage{};
  speed_ = 0;
  agm_ = AccumulativeGridMap(cfg_.effectiveAgm());
  heard_.clear();
  lines_ = cfg_.lines;
  ring_groups_ = RingGroups{};
  scan_period_ = ScanPeriod{};
  beams_.clear();
  beam_overlap_ = 0;
  placer_ = EchoPlacer(cfg_.placement);
  look_weight_ = LookWeight(cfg_.hit_weight_speed, cfg_.hit_weight_low_speed);
  pass_through_.clear();
  last_integrated_utime_.reset();
  csm_ = CurrentSensorMap();
  std::fill(cycle_utime_.begin(), cycle_utime_.end(), 0);
  pending_.clear();
  rm_.clear();
  rm_source_utime_.reset();
  glints_.clear();
  matcher_.clear();
  corrections_.clear();
  scan_waiting_ = false;
  newest_odometry_utime_.reset();
  glint_hits_.clear();
  last_scan_utime_.reset();
  last_complement_utime_.reset();
  last_rm_utime_.reset();
  last_publish_.reset();
  now_ = 0;
  return true;
}

void NavigatorStage::onOdometry(const odometry_t& m) {
  if (!timeOk(m.utime, channels::ODOMETRY)) return;
  if (const auto odo = acceptOdometry(node_, poses_, m)) {
    speed_ = odo->v;
    newest_odometry_utime_ = m.utime;
    if (scan_waiting_ && own_scan_ && m.utime >= complement::lastReadingTime(*own_scan_)) processScan();
  }
}

void NavigatorStage::onRadarMap(const line_map_t& m) {
  if (!timeOk(m.utime, channels::RADAR_MAP)) return;
  node_.noteMessageTime(m.utime);
  if (!isNewer(node_, last_rm_utime_, m.utime, channels::RADAR_MAP, "radar_map")) return;
  last_rm_utime_ = m.utime;
  const geom::Pose2 c = correctionAt(m.utime);
  std::vector<CsmLine> lines;
  lines.reserve(m.segments.size());
  for (size_t i = 0; i < m.segments.size(); ++i) {
    const line_segment_t& s = m.segments[i];
    constexpr double kMax = complement::input_limits::kMaxCoordinate;
    if (!(std::abs(s.x0) <= kMax && std::abs(s.y0) <= kMax && std::abs(s.x1) <= kMax && std::abs(s.y1) <= kMax)) {
      node_.reportError("rejected.radar_map_segment", "RADAR_MAP.segments[" + std::to_string(i) +
                                                          "] has an end point that is not finite or farther than " +
                                                          std::to_string(kMax) + " m: skipped");
      continue;
    }
    // The fit's quality goes on into CURRENT_SENSOR_MAP: an RMS distance is finite and >= 0, a
    // point count >= 0.
    if (!(std::isfinite(s.rms) && s.rms >= 0) || s.npoints < 0) {
      node_.reportError("rejected.radar_map_segment", "RADAR_MAP.segments[" + std::to_string(i) + "] has rms " +
                                                          std::to_string(s.rms) + " m, npoints " +
                                                          std::to_string(s.npoints) + ": skipped");
      continue;
    }
    const int64_t support = s.last_supported_utime > 0 ? std::min(s.last_supported_utime, m.utime) : m.utime;
    geom::Segment seg{{s.x0, s.y0}, {s.x1, s.y1}};
    if (cfg_.scan_matching.enabled) seg = {c.transform(seg.a), c.transform(seg.b)};
    lines.push_back({seg, LineSource::Laser, s.npoints, s.rms, support});
  }
  csm_.setRadarMap(lines, m.utime);
  rm_.clear();
  for (const CsmLine& l : lines) rm_.push_back({l.seg, l.npoints, l.rms});
  rm_source_utime_ = m.source_utime;
  flushPending();
  advance(m.utime);
}

void NavigatorStage::onComplement(const complement_t& m) {
  if (!timeOk(m.utime, channels::SONAR_COMPLEMENT)) return;
  node_.noteMessageTime(m.utime);
  if (!isNewer(node_, last_complement_utime_, m.utime, channels::SONAR_COMPLEMENT, "complement")) return;
  last_complement_utime_ = m.utime;
  ring_groups_.fired(m.group, m.utime);

  std::vector<complement::InputProblem> problems;
  const auto readings = complement::complementFromMessage(m, problems);
  reportProblems(node_, problems);
  learnBeams(readings, m.utime);
  followRing();
  // (an echo the lines of an earlier scan explain where the newest does not look is what the
  // laser does not see now: the tactical memory keeps it)
  std::vector<GroupReading> group = toGroupReadings(readings, m.utime, true);
  std::vector<Sounding> soundings;
  if (cfg_.pass_through.enabled())
    soundings = soundingsOf(readings, geom::plausibleBeamWidth(m.beam_width) ? m.beam_width : cfg_.placement.params.beam_width,
                            cfg_.pass_through.beyond_limit, cfg_.pass_through.silence);
  if (!cfg_.verify_with_next_scan) {
    toNavigatorFrame(group, m.utime);
    toNavigatorFrame(soundings, m.utime);
    integrate(std::move(group), soundings, m.utime);
  } else {
    PendingGroup p;
    p.utime = m.utime;
    p.soundings = std::move(soundings);
    p.readings = std::move(group);
    // A later scan cannot vouch for what lies beyond its view either: such echoes are kept.
    for (const auto& r : readings) p.outside_view.push_back(r.cls == complement::SonarClass::OutsideView ||
                                                          r.cls == complement::SonarClass::SeenBefore);
    // The hypothesis model the complement stage used (a malformed one: the paper's).
    if (geom::plausibleBeamWidth(m.beam_width)) p.model.beam_width = m.beam_width;
    else node_.reportError("rejected.complement_model", "SONAR_COMPLEMENT.beam_width = " + std::to_string(m.beam_width) +
                                                             ": the paper's 30 deg used");
    if (std::isfinite(m.range_limit) && m.range_limit > 0) p.model.range_limit = m.range_limit;
    else node_.reportError("rejected.complement_model", "SONAR_COMPLEMENT.range_limit = " + std::to_string(m.range_limit) +
                                                             ": the paper's 2.20 m used");
    if (std::isfinite(m.tolerance) && m.tolerance >= 0) p.tolerance = m.tolerance;
    else node_.reportError("rejected.complement_model", "SONAR_COMPLEMENT.tolerance = " + std::to_string(m.tolerance) +
                                                             ": 0.10 m used");
    if (!(std::isfinite(m.tolerance) && m.tolerance >= 0)) p.tolerance = 0.10;
    pending_.push_back(std::move(p));
    flushPending();
  }
  advance(m.utime);
}

void NavigatorStage::flushPending() {
  const double wait_s = std::max(cfg_.verify_max_wait_s,
                                 std::min(kMaxScanWaitS, scan_period_.scans(cfg_.verify_max_wait_scans, 0.0)));
  const auto wait_us = secondsToUs(wait_s);
  const int64_t newest = std::max({now_, last_complement_utime_.value_or(0), last_rm_utime_.value_or(0)});
  while (!pending_.empty()) {
    PendingGroup& g = pending_.front();
    if (rm_source_utime_ && *rm_source_utime_ >= g.utime) {
      toNavigatorFrame(g.readings, g.utime);
      toNavigatorFrame(g.soundings, g.utime);
      for (size_t i = 0; i < g.readings.size(); ++i) {
        GroupReading& r = g.readings[i];
        if (!r.echo || (i < g.outside_view.size() && g.outside_view[i])) continue;
        complement::IdealSonarModel model = g.model;  // with the reading's own beam, as the complement used
        if (r.e.beam_width > 0) model.beam_width = r.e.beam_width;
        const double h = complement::hypotheticalRange(r.e.sensor, rm_, model);
        r.hit = r.e.range < h - g.tolerance;
        node_.count(r.hit ? "verify.kept" : "verify.explained");
      }
    } else if (newest - g.utime > wait_us) {
      toNavigatorFrame(g.readings, g.utime);
      toNavigatorFrame(g.soundings, g.utime);
      node_.count("verify.timed_out");
    } else {
      break;
    }
    integrate(std::move(g.readings), g.soundings, g.utime);
    pending_.pop_front();
  }
}

void NavigatorStage::integrate(std::vector<GroupReading> group, const std::vector<Sounding>& soundings, int64_t utime) {
  // What the sound has passed since the memory last heard something there (before this group's
  // own echoes go in: a cell hit now starts counting afresh).
  if (const int n = pass_through_.apply(soundings, agm_); n > 0) {
    node_.count("agm.passed_through", n);
    if (pass_through_.emptiedBySilence() > 0) node_.count("agm.passed_through_silence", pass_through_.emptiedBySilence());
  }
  // The robot's mean speed since the previous group (its newest odometry speed when there is
  // none within a second): how fast it drove past what this group heard.
  double v = speed_;
  if (look_weight_.enabled() && last_integrated_utime_ && utime > *last_integrated_utime_ &&
      utime - *last_integrated_utime_ <= 1000000)
    if (const auto before = poses_.at(*last_integrated_utime_), now = poses_.at(utime); before && now)
      if (const double m = LookWeight::meanSpeed(before->position(), now->position(),
                                                 static_cast<double>(utime - *last_integrated_utime_) * 1e-6);
          m >= 0)
        v = m;
  if (cfg_.look_weight_votes && look_weight_.enabled()) placer_.setVoteWeight(std::min(1.0, look_weight_.weight(v)));
  std::vector<geom::Vec2> hits = placer_.place(group, agm_);
  if (cfg_.laser_join) joinToLaserLines(hits);
  const auto pose = poseAt(utime);
  if (look_weight_.enabled()) {
    if (const int added = look_weight_.apply(hits, v); added > 0)
      node_.count("agm.look_weight_hits", added);
    else if (added < 0)
      node_.count("agm.look_weight_dropped", -added);
  }
  last_integrated_utime_ = utime;
  // The glints since the previous group, one hit per return (not weighed by speed: the scanner
  // sees a glint at its own rate, however fast the robot drives).
  const size_t glints = glint_hits_.size();  // hits' last ones (noted with the placed echoes, after follow())
  if (!glint_hits_.empty()) {
    node_.count("agm.laser_glint_hits", static_cast<int64_t>(glint_hits_.size()));
    if (pose && pass_through_.notesHits())
      for (const geom::Vec2& g : glint_hits_) pass_through_.noteHit(g, pose->position(), agm_);
    hits.insert(hits.end(), glint_hits_.begin(), glint_hits_.end());
    glint_hits_.clear();
  }
  if (cfg_.scan_matching.enabled) {
    // The pose's error from here on: the matched pose's where the walls fixed it.
    const Correction* c = correctionEntryAt(utime);
    const AgmParams& a = cfg_.agm;
    agm_.setOdometryNoise(c && c->constrained ? cfg_.scan_matching.pose_noise
                                              : OdometryNoise{a.odometry_trans_noise, a.odometry_rot_noise,
                                                              a.odometry_drift_noise});
  }
  if (pose && agm_.follow(pose->position(), speed_, pose->theta)) node_.count("agm.recentred");
  if (pass_through_.notesHits())
    for (const PlacedEcho& e : placer_.lastPlaced()) pass_through_.noteHit(e.point, e.sensor.position(), agm_);
  // Which echoes made each cell, for the pilot (AGM_TACTICAL's `heard`): the placed echoes and the
  // glints (the laser saw them). Cells only the surface fill or the laser join add stay unknown;
  // an echo the look weight drops still counts where its cell has weight (it was heard there).
  for (const PlacedEcho& e : placer_.lastPlaced()) heard_.note(e.point, e.checked, agm_);
  for (size_t k = hits.size() - glints; k < hits.size(); ++k) heard_.note(hits[k], true, agm_);
  const int inside = agm_.update(hits);
  if (cfg_.clear_footprint && pose)
    if (const int n = agm_.clearDisc(pose->position(), cfg_.robot_radius - agm_.cellSize() * std::sqrt(0.5)); n > 0)
      node_.count("agm.footprint_cleared", n);
  cycle_utime_[static_cast<size_t>(agm_.cycle()) % cycle_utime_.size()] = utime;
  node_.count("agm.cycles");
  node_.count("agm.hits", inside);
  if (inside < static_cast<int>(hits.size()))
    node_.count("agm.hits_outside_window", static_cast<int64_t>(hits.size()) - inside);
}

void NavigatorStage::joinToLaserLines(std::vector<geom::Vec2>& hits) {
  if (rm_.empty() || placer_.lastPlaced().empty()) return;
  std::vector<geom::Segment> lines;
  lines.reserve(rm_.size());
  for (const auto& s : rm_) lines.push_back(s.seg);
  const LaserJoinParams jp{agm_.cellSize(), cfg_.laser_join_min_line_m};
  const size_t before = hits.size();
  std::vector<std::pair<int, int>> cells;  // one hit per cell and echo; not the echo's own cell again
  for (const PlacedEcho& e : placer_.lastPlaced()) {
    const double beam = geom::plausibleBeamWidth(e.beam_width) ? e.beam_width : cfg_.placement.params.beam_width;
    const auto join = laserJoinPoints(e.sensor, e.range, beam, lines, jp);
    if (join.empty()) continue;
    cells.clear();
    int fx = 0, fy = 0;
    if (agm_.cellAt(e.point, fx, fy)) cells.emplace_back(fx, fy);
    for (const geom::Vec2& q : join) {
      int ix = 0, iy = 0;
      if (!agm_.cellAt(q, ix, iy) || std::find(cells.begin(), cells.end(), std::make_pair(ix, iy)) != cells.end())
        continue;
      cells.emplace_back(ix, iy);
      hits.push_back(q);
    }
  }
  if (hits.size() > before) node_.count("agm.laser_join_hits", static_cast<int64_t>(hits.size() - before));
}

int64_t NavigatorStage::cycleUtime(int64_t cycle) const {
  // Cells with G > 0 were hit within the last h_max cycles, all still in the ring.
  if (cycle <= 0 || agm_.cycle() - cycle >= static_cast<int64_t>(cycle_utime_.size())) return 0;
  return cycle_utime_[static_cast<size_t>(cycle) % cycle_utime_.size()];
}

void NavigatorStage::advance(int64_t utime) {
  now_ = std::max(now_, utime);
  const auto period_us = periodUs(cfg_.publish_hz);
  if (!last_publish_ || now_ - *last_publish_ >= period_us) publish();
}

const NavigatorStage::Correction* NavigatorStage::correctionEntryAt(int64_t utime) const {
  for (auto it = corrections_.rbegin(); it != corrections_.rend(); ++it)
    if (it->utime <= utime - kCorrectionDelayUs) return &*it;
  return nullptr;
}

geom::Pose2 NavigatorStage::correctionAt(int64_t utime) const {
  const Correction* c = correctionEntryAt(utime);
  return c ? c->c : geom::Pose2{};
}

void NavigatorStage::toNavigatorFrame(std::vector<GroupReading>& group, int64_t utime) const {
  if (!cfg_.scan_matching.enabled) return;
  const geom::PoseTransform c(correctionAt(utime));
  for (GroupReading& r : group) {
    if (!r.echo) continue;
    r.e.sensor = c(r.e.sensor);
    r.axis_end = c(r.axis_end);
  }
}

void NavigatorStage::toNavigatorFrame(std::vector<Sounding>& soundings, int64_t utime) const {
  if (!cfg_.scan_matching.enabled) return;
  const geom::Pose2 c = correctionAt(utime);
  for (Sounding& s : soundings) s.sensor = c.compose(s.sensor);
}

std::optional<geom::Pose2> NavigatorStage::poseAt(int64_t utime) const {
  const auto p = poses_.at(utime);
  if (!p || !cfg_.scan_matching.enabled) return p;
  return correctionAt(utime).compose(*p);
}

void NavigatorStage::learnBeams(const std::vector<complement::ComplementInput>& readings, int64_t utime) {
  if (cfg_.g_threshold_fixed || !(cfg_.g_threshold_walking_speed > 0)) return;
  // Interpolated, as the complement stage placed the sensor (not extrapolated past the newest
  // odometry, which a turning robot would put off by up to a degree).
  if (poses_.empty() || poses_.newestTime() < utime) return;
  std::optional<geom::Pose2> robot;
  bool added = false;
  for (const auto& r : readings) {
    if (r.cls == complement::SonarClass::Invalid || !r.sensor_pose) continue;
    if (!robot && !(robot = poses_.at(utime))) return;
    const double beam = geom::plausibleBeamWidth(r.beam_width) ? r.beam_width : cfg_.placement.params.beam_width;
    const BeamAxis b{geom::normalizeAngle(r.sensor_pose->theta - robot->theta), beam};
    if (const auto known = beams_.find(r.sensor_id); known != beams_.end()) {
      const BeamAxis& k = known->second;
      if (std::abs(geom::angleDiff(b.axis, k.axis)) <= geom::deg2rad(kRingChangeDeg) &&
          std::abs(b.beam - k.beam) <= geom::deg2rad(kRingChangeDeg))
        continue;
      // Another ring under the same ids (a driver restarted with another ring, or recalibrated):
      // its beams are learnt afresh, and G_T follows them. (Logged the 1st, 2nd, 4th, ... time: a
      // stream whose poses keep jumping must not flood the log.)
      node_.count("ring.relearnt");
      const int64_t n = node_.counter("ring.relearnt");
      if ((n & (n - 1)) == 0)
        spdlog::warn("{}: sonar {}'s axis {:.1f} -> {:.1f} deg, beam {:.1f} -> {:.1f} deg: another ring; its beams "
                     "learnt afresh [ring.relearnt so far: {}]",
                     node_.name(), r.sensor_id, geom::rad2deg(k.axis), geom::rad2deg(b.axis), geom::rad2deg(k.beam),
                     geom::rad2deg(b.beam), n);
      beams_.clear();
    }
    // (a message naming thousands of sensors must not make the count below quadratic in them)
    if (beams_.size() >= kMaxRingSensors) {
      node_.count("ring.sensors_ignored");
      continue;
    }
    beams_[r.sensor_id] = b;
    added = true;
  }
  if (!added) return;
  std::vector<BeamAxis> all;
  all.reserve(beams_.size());
  for (const auto& [id, b] : beams_) all.push_back(b);
  beam_overlap_ = maxBeamOverlap(all, geom::deg2rad(kBeamOverlapMarginDeg));
}

void NavigatorStage::followRing() {
  if (cfg_.g_threshold_fixed || !(cfg_.g_threshold_walking_speed > 0) || beam_overlap_ < 1) return;
  const int gt = walkerGThreshold((2 * agm_.params().t + 1) * agm_.cellSize(), cfg_.g_threshold_walking_speed,
                                  ring_groups_.shortestCycleS(), beam_overlap_);
  if (gt < 1 || gt == agm_.params().g_threshold) return;
  agm_.setGThreshold(gt);
  if (cfg_.lines_follow_g_threshold) lines_.gp_threshold = gt;
  node_.count("agm.g_threshold_changes");
  spdlog::info("{}: tactical G_T {} (a ring cycle of {} firing groups, {:.3f} s at its quickest; at most {} of {} "
               "beams over one bearing; people walking {} m/s)",
               node_.name(), gt, ring_groups_.perCycle(), ring_groups_.shortestCycleS(), beam_overlap_, beams_.size(),
               cfg_.g_threshold_walking_speed);
}

void NavigatorStage::publish() {
  const auto pose = poseAt(now_);
  if (!pose) {
    node_.count("publish.no_odometry");
    odometry_outage_.missing(node_, poses_, now_, "AGM_TACTICAL, AGM_LINES or CURRENT_SENSOR_MAP");
    return;
  }
  odometry_outage_.present(now_);
  last_publish_ = now_;
  gridMapMessageInto(grid_msg_, agm_, now_, *pose, lines_.gp_threshold, cfg_.published_size);
  const int o = publishedOffset(agm_, cfg_.published_size);
  heard_.exportWindow(agm_, o, o, grid_msg_.width, grid_msg_.heard);
  node_.publish(channels::AGM_TACTICAL, grid_msg_);

  const auto cells = candidateCells(agm_, lines_.gp_threshold, o, o, grid_msg_.width,
                                    [this](int64_t c) { return cycleUtime(c); });
  csm_.setAgmLines(generateLines(cells, *pose, agm_.cellSize(), lines_));
  const int64_t agm_utime = last_complement_utime_.value_or(0);
  line_map_t agm_lines = lineMapMessage(csm_.sonarLines(), now_, agm_utime, *pose);
  node_.publish(channels::AGM_LINES, agm_lines);
  line_map_t csm = lineMapMessage(csm_.lines(), now_, csm_.radarMapUtime(), *pose);
  node_.publish(channels::CURRENT_SENSOR_MAP, csm);
  node_.count("lines.published", static_cast<int64_t>(csm_.sonarLines().size()));
}

}  // namespace lasonic
