#include "stages/complement_stage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "complement/messages.hpp"
#include "core/physics.hpp"
#include "stages/inputs.hpp"
#include "core/utime.hpp"

namespace lasonic {

namespace cp = complement;

ComplementStage::ComplementStage(Node& node, const ComplementConfig& cfg)
    : node_(node),
      cfg_(cfg),
      poles_(cfg.poles),
      rm_memory_(cfg.radar_map_memory_s, cfg.radar_map_memory_max_incidence, cfg.radar_map_memory_min_length),
      rm_max_age_base_us_(cfg.params.max_rm_age_us) {
  node_.subscribe<odometry_t>(channels::ODOMETRY, [this](const odometry_t& m) { onOdometry(m); });
  node_.subscribe<laser_scan_t>(channels::LASER_SCAN, [this](const laser_scan_t& m) { onLaserScan(m); });
  node_.subscribe<sonar_ring_t>(channels::SONAR_RING, [this](const sonar_ring_t& m) { onSonarRing(m); });
}

bool ComplementStage::timeOk(int64_t utime, const char* channel) {
  const ClockCheck c = checkClock(node_, clock_, utime, channel);
  if (c == ClockCheck::Restarted) {
    poses_.clear();
    radar_map_.reset();
    poles_.reset();
    rm_memory_.clear();
    last_scan_utime_.reset();
    last_ring_utime_.reset();
    overlapping_reported_.clear();  // a restarted driver may fire another ring
    pings_.clear();
    laser_stamps_.reset();
    sonar_stamps_.reset();
    scan_period_ = ScanPeriod{};
    cfg_.params.max_rm_age_us = rm_max_age_base_us_;
    laser_outage_.reset();
  }
  return c == ClockCheck::Ok || c == ClockCheck::Restarted;
}

void ComplementStage::onOdometry(const odometry_t& m) {
  if (!timeOk(m.utime, channels::ODOMETRY)) return;
  if (!acceptOdometry(node_, poses_, m)) return;
  laser_stamps_.noteOdometry(m.utime);
  sonar_stamps_.noteOdometry(m.utime);
}

namespace {
// "class." + className(c), made once per class (a counter per reading).
const std::string& classCounter(cp::SonarClass c) {
  constexpr size_t kClasses = static_cast<size_t>(cp::SonarClass::SeenBefore) + 1;  // (the last of SonarClass's values)
  static const std::array<std::string, kClasses> names = [] {
    std::array<std::string, kClasses> n;
    for (size_t k = 0; k < kClasses; ++k) n[k] = std::string("class.") + cp::className(static_cast<cp::SonarClass>(k));
    return n;
  }();
  const auto i = static_cast<size_t>(c);
  return names[i < kClasses ? i : static_cast<size_t>(cp::SonarClass::Invalid)];  // (className's "invalid")
}
// A datum of `channel` measured at `utime`, against the newest odometry (none yet: nothing to
// compare); `listening_us`: how long after `utime` its driver can send at the earliest.
void checkStamps(Node& node, StampAgreement& stamps, const PoseHistory& poses, int64_t utime, const char* channel,
                 const char* counter_ahead, const char* counter_behind, int64_t listening_us = 0) {
  if (poses.empty()) return;
  if (const auto f = stamps.check(utime, poses.newestTime(), listening_us))
    node.reportError(f->ahead ? counter_ahead : counter_behind, stamps.describe(*f, channel));
}
}  // namespace

void ComplementStage::onLaserScan(const laser_scan_t& m) {
  if (!timeOk(m.utime, channels::LASER_SCAN)) return;
  node_.noteMessageTime(m.utime);
  if (!isNewer(node_, last_scan_utime_, m.utime, channels::LASER_SCAN, "laser")) return;
  std::vector<cp::InputProblem> problems;
  const std::optional<cp::LaserScan>& scan =
      placement_ ? placement_->scanFrom(m, problems) : cp::laserScanFromMessageInto(m, problems, own_scan_);
  reportProblems(node_, problems);
  if (!scan) return;
  last_scan_utime_ = m.utime;
  // A 1 Hz scanner's newest Radar Map is up to a second old at every firing: its age limit in
  // its own scan periods, as the pilot's staleness (2.5 of 5 Hz: the configured 0.5 s).
  scan_period_.scanned(m.utime);
  cfg_.params.max_rm_age_us = secondsToUs(std::min(
      ComplementConfig::kMaxRmAgeS,
      scan_period_.scans(cfg_.rm_max_age_scans, static_cast<double>(rm_max_age_base_us_) * 1e-6)));

  int returns = 0, no_pose = 0;
  for (const auto& r : scan->readings) returns += r.valid ? 1 : 0;
  // Every reading malformed (each reported above) is a broken scan, not an empty room: an empty
  // Radar Map would make every echo complementary. (Gaps and readings inside the scanner's
  // blind zone are readings, and an empty map from them is right.)
  if (returns == 0 && !scan->readings.empty() && problems.size() >= scan->readings.size()) {
    node_.reportError("rejected.laser_scan", "LASER_SCAN utime " + std::to_string(m.utime) +
                                                 ": every reading malformed; previous Radar Map kept");
    return;
  }
  cp::RadarMap rm = placement_ ? cp::radarMapFromPlaced(*scan, placement_->place(*scan, poses_, &no_pose), poses_,
                                                         cfg_.radar_map)
                               : cp::extractRadarMap(*scan, poses_, cfg_.radar_map, &no_pose);
  // The map is seen from the robot's pose at the scan's last reading (its view, the pole
  // tracker's motion across the line of sight); without that pose it would be seen from the
  // odometry origin.
  const bool seen_from_known_pose = poses_.at(rm.utime).has_value();
  if (no_pose > 0 || !seen_from_known_pose) {
    node_.reportError("rejected.laser_no_odometry",
                      "LASER_SCAN utime " + std::to_string(m.utime) + ": no odometry for " +
                          std::to_string(no_pose) + " of " + std::to_string(returns) + " readings" +
                          (seen_from_known_pose ? "" : " nor at its last reading; previous Radar Map kept"));
    // Without any placed reading, or without the pose it is seen from, the scan says nothing;
    // keep the previous Radar Map (it ages).
    if (no_pose == returns || !seen_from_known_pose) return;
  }
  // (rm.utime: the scan's last reading, the newest pose the scan needed)
  checkStamps(node_, laser_stamps_, poses_, rm.utime, channels::LASER_SCAN, "time.laser_ahead_of_odometry",
              "time.laser_behind_odometry");
  rm.poles = poles_.update(rm.utime, rm.robot_pose.position(), rm.pole_candidates);
  line_map_t out = cp::radarMapToMessage(rm);
  node_.publish(channels::RADAR_MAP, out);
  rm_memory_.update(rm);
  radar_map_ = std::move(rm);
}

void ComplementStage::onSonarRing(const sonar_ring_t& m) {
  if (!timeOk(m.utime, channels::SONAR_RING)) return;
  node_.noteMessageTime(m.utime);
  // A repeated or out-of-order group would be classified and published again, and the ping
  // history (late echoes, crosstalk) assumes firings in time order.
  if (!isNewer(node_, last_ring_utime_, m.utime, channels::SONAR_RING, "sonar")) return;
  last_ring_utime_ = m.utime;
  std::vector<cp::InputProblem> problems;
  const cp::SonarGroup group = cp::sonarGroupFromMessage(m, problems);
  reportProblems(node_, problems);
  for (const cp::BeamOverlap& o : cp::overlappingBeams(group, cfg_.params.model.beam_width)) {
    if (!overlapping_reported_.insert({o.a, o.b}).second) continue;
    const auto deg = [](double rad) { return std::to_string(std::lround(geom::rad2deg(rad))); };
    node_.reportError("ring.overlapping_beams",
                      "SONAR_RING group " + std::to_string(m.group) + ": sensors " + std::to_string(o.a) + " and " +
                          std::to_string(o.b) + " fire together and hear each other's pings (axes " + deg(o.apart) +
                          " deg apart, beams " + deg(o.width_a) + " and " + deg(o.width_b) +
                          " deg: no farther apart than the sum of the openings); that crosstalk reads short and "
                          "passes as complementary: fire them in different groups");
  }

  // (A ring is sent once its echoes could have come back from range_max: a malformed range_max
  // only makes that allowance 0 or at most a second.)
  const double flight_s = std::isfinite(m.range_max) ? std::clamp(timeOfFlight(m.range_max), 0.0, 1.0) : 0.0;
  checkStamps(node_, sonar_stamps_, poses_, m.utime, channels::SONAR_RING, "time.sonar_ahead_of_odometry",
              "time.sonar_behind_odometry", secondsToUs(flight_s));
  const auto robot = poses_.at(m.utime);
  if (!robot)
    node_.reportError("rejected.sonar_no_odometry", "SONAR_RING utime " + std::to_string(m.utime) +
                                                        ": no odometry at the firing time; group " +
                                                        std::to_string(m.group) + " classified invalid");
  const cp::GroupComplement result = cp::extractComplement(group, robot, radar_map_ ? &*radar_map_ : nullptr, cfg_.params,
                                                           pings_.before(m.utime, cfg_.params.late_echo_window_us),
                                                           rm_memory_.enabled() ? &rm_memory_ : nullptr);
  pings_.add(result);
  laser_outage_.update(node_, m.utime, radar_map_ ? std::optional<int64_t>(radar_map_->utime) : std::nullopt,
                       result.radar_map_stale, "laser.lost", channels::LASER_SCAN,
                       "every sonar reading is unverifiable (no Radar Map recent enough to verify it)");
  for (const auto& r : result.readings) {
    node_.count(classCounter(r.cls));
    if (result.radar_map_stale && r.cls == cp::SonarClass::Unverifiable) node_.count("unverifiable.stale_radar_map");
    if (r.by_pole && r.cls == cp::SonarClass::Redundant) node_.count("redundant.pole");  // (not if outside_view)
    if (r.by_crosstalk) node_.count("redundant.crosstalk");
    if (r.by_late_echo) node_.count("redundant.late_echo");
  }
  cp::hypothesisToMessageInto(hyp_msg_, result, cfg_.params);
  node_.publish(hypothesis_channel_, hyp_msg_);
  cp::complementToMessageInto(comp_msg_, result, cfg_.params);
  node_.publish(complement_channel_, comp_msg_);
}

}  // namespace lasonic
