#include "stages/inputs.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>

namespace lasonic {

void reportProblems(Node& node, const std::vector<complement::InputProblem>& problems) {
  for (const auto& p : problems) node.reportError(p.counter, p.message);
}

std::optional<complement::OdometryInput> acceptOdometry(Node& node, PoseHistory& poses, const odometry_t& m) {
  node.noteMessageTime(m.utime);
  std::vector<complement::InputProblem> problems;
  const auto odo = complement::odometryFromMessage(m, problems);
  reportProblems(node, problems);
  if (!odo) return std::nullopt;
  switch (poses.add(odo->utime, odo->pose)) {
    case PoseHistory::AddResult::Ok: return odo;
    case PoseHistory::AddResult::Duplicate: node.count("odometry_duplicates"); break;
    case PoseHistory::AddResult::WentBackwards:
      node.reportError("rejected.odometry_backwards", "ODOMETRY.utime = " + std::to_string(m.utime) +
                                                          " is older than the newest (" +
                                                          std::to_string(poses.newestTime()) + "): dropped");
      break;
  }
  return std::nullopt;
}

void OdometryOutage::missing(Node& node, const PoseHistory& poses, int64_t utime, const char* what) {
  ++missed_;
  if (since_ || poses.empty() || utime - poses.newestTime() <= kLostUs) return;
  since_ = poses.newestTime();
  node.reportError("odometry.lost", "no ODOMETRY since utime " + std::to_string(*since_) + " (" +
                                        std::to_string((utime - *since_) / 1000) + " ms before " +
                                        std::to_string(utime) + "): no " + what + " until it returns");
}

void OdometryOutage::present(int64_t utime) {
  if (since_)
    spdlog::warn("ODOMETRY back after {:.3f} s without: {} maps not made", static_cast<double>(utime - *since_) * 1e-6,
                 missed_);
  since_.reset();
  missed_ = 0;
}

void SensorOutage::update(Node& node, int64_t utime, std::optional<int64_t> newest, bool stale, const char* counter,
                          const char* channel, const char* meanwhile) {
  if (!newest) return;
  if (!seen_ || *newest > *seen_) {
    if (seen_ && !since_) interval_us_ = *newest - *seen_;  // (not the outage's own gap)
    seen_ = newest;
  }
  if (stale) {
    if (since_ || interval_us_ <= 0 || utime - *newest <= 2 * interval_us_) return;
    since_ = *newest;
    node.reportError(counter, std::string("no ") + channel + " since utime " + std::to_string(*newest) + " (" +
                                  std::to_string((utime - *newest) / 1000) + " ms before " + std::to_string(utime) +
                                  "): " + meanwhile + " until it returns");
  } else if (since_ && *newest > *since_) {
    spdlog::warn("{} back after {:.3f} s without", channel, static_cast<double>(*newest - *since_) * 1e-6);
    since_.reset();
  }
}

bool isNewer(Node& node, const std::optional<int64_t>& last, int64_t utime, const char* channel, const char* what) {
  if (last && utime <= *last) {
    node.reportError(std::string("rejected.") + what + "_backwards",
                     std::string(channel) + ".utime = " + std::to_string(utime) +
                         " is not newer than the previous one (" + std::to_string(*last) + "): dropped");
    return false;
  }
  return true;
}

ClockCheck checkClock(Node& node, TimeReset& clock, int64_t utime, const char* channel) {
  if (!plausibleUtime(utime)) {
    node.reportError("rejected.time", std::string(channel) + ".utime = " + std::to_string(utime) +
                                          " us is not a time (outside [0, " + std::to_string(kMaxUtime) + "]): dropped");
    return ClockCheck::Bad;
  }
  const TimeReset::Admission a = clock.admit(channel, utime);
  const auto seconds = [](int64_t us) {
    char s[32];
    std::snprintf(s, sizeof s, "%.3f", static_cast<double>(us) * 1e-6);
    return std::string(s);
  };
  if (a.stray)
    node.reportError("rejected.time_ahead",
                     std::string(channel) + ".utime = " + std::to_string(*a.stray) + " was " +
                         seconds(*a.stray - a.stray_reference) + " s ahead of every input and the next " + channel +
                         " (" + std::to_string(utime) +
                         ") is back: a stray time (a clock stepped on one computer, or a second source on the "
                         "channel), dropped");
  if (a.stepped_from) {
    node.count("time.steps_forward");
    spdlog::warn("{}.utime = {} goes on {} s ahead of the other inputs: its clock stepped forward; its first "
                 "message at the new time was held back and dropped [time.steps_forward: {}]",
                 channel, utime, seconds(utime - *a.stepped_from), node.counter("time.steps_forward"));
  }
  switch (a.kind) {
    case TimeReset::Admission::HeldAhead:
      node.count(std::string("time.held_ahead.") + channel);
      return ClockCheck::HeldAhead;
    case TimeReset::Admission::Restarted:
      node.count("time_resets");
      spdlog::warn("{}.utime = {} jumps back by more than {} s: the clock restarted; starting afresh [time_resets: {}]",
                   channel, utime, TimeReset::kJumpUs / 1e6, node.counter("time_resets"));
      return ClockCheck::Restarted;
    case TimeReset::Admission::Ok: break;
  }
  return ClockCheck::Ok;
}

bool laserReportsEcho(const std::vector<geom::Vec2>& laser, const geom::Pose2& sensor, double range, double tolerance,
                      double sector_width) {
  if (!(range >= 0) || !(sector_width > 0)) return false;
  const geom::Sector cone{sensor.position(), sensor.theta, sector_width, range + tolerance};
  const double near = std::max(0.0, range - tolerance);
  return std::any_of(laser.begin(), laser.end(), [&](const geom::Vec2& p) {
    return (p - cone.apex).squaredNorm() >= near * near && cone.contains(p);
  });
}

bool laserInSector(const std::vector<geom::Vec2>& laser, const geom::Pose2& sensor, double sector_width) {
  if (!(sector_width > 0)) return false;
  const geom::Sector cone{sensor.position(), sensor.theta, sector_width, std::numeric_limits<double>::infinity()};
  return std::any_of(laser.begin(), laser.end(), [&](const geom::Vec2& p) { return cone.contains(p); });
}

std::vector<GroupReading> toGroupReadings(const std::vector<complement::ComplementInput>& readings, int64_t utime,
                                          bool seen_before, bool unverified) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<GroupReading> group;
  group.reserve(readings.size());
  for (const complement::ComplementInput& r : readings) {
    GroupReading g;
    g.sensor_id = r.sensor_id;
    g.utime = utime;
    // An echo from beyond the laser's view is used as a complementary one (complement.hpp).
    g.echo = ((r.cls == complement::SonarClass::Complementary || r.cls == complement::SonarClass::OutsideView ||
               (seen_before && r.cls == complement::SonarClass::SeenBefore)) &&
              r.usable) ||
             (unverified && r.unverified_echo);
    if (g.echo) {
      g.e = SonarEcho{utime, r.range, r.sensor_pose.value_or(geom::Pose2{kNaN, kNaN, kNaN}), r.beam_width};
      g.axis_end = r.end;
      g.checked = r.cls == complement::SonarClass::Complementary;
    }
    group.push_back(g);
  }
  return group;
}

std::vector<Sounding> soundingsOf(const std::vector<complement::ComplementInput>& readings, double beam_width,
                                  bool beyond_limit, bool silence) {
  std::vector<Sounding> out;
  for (const complement::ComplementInput& r : readings) {
    if (!r.usable || !r.sensor_pose) continue;
    double reach = r.range;
    if (r.cls == complement::SonarClass::False) reach = std::min(reach, r.hypothetical_range);
    const bool unverifiable = r.cls == complement::SonarClass::Unverifiable;
    if (unverifiable) {
      if (!(r.echo ? beyond_limit : silence)) continue;
      reach = r.hypothetical_range;
    }
    out.push_back({*r.sensor_pose, reach, r.beam_width > 0 ? r.beam_width : beam_width, unverifiable,
                   unverifiable ? reach : r.range});
  }
  return out;
}

}  // namespace lasonic
