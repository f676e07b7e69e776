// The simulated laser range scanner (MOBOT-IV: 720 readings per 360° scan, 2 scans per
// revolution). Materials decide what it sees: transparent ones (glass, mesh) are passed through,
// absorbing ones (black cardboard) return nothing; thin objects fall between the rays.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/drivers.hpp"

namespace lasonic::sim {

LaserConfig laserConfig(const Config& c, LaserConfig base) {
  c.allowOnly({"scan_rate_hz", "readings", "fov_deg", "range_max", "range_min", "noise_std", "mount"});
  base.scan_rate_hz = c.get("scan_rate_hz", base.scan_rate_hz, Range::between(0.1, 100));
  base.readings = c.get("readings", base.readings, Range::between(2, 100000));
  base.fov_deg = c.get("fov_deg", base.fov_deg, Range::between(1, 360));
  base.range_min = c.get("range_min", base.range_min, Range::nonNegative());
  base.range_max = c.get("range_max", base.range_max, Range::positive());
  if (base.range_max <= base.range_min)
    c.fail(c.has("range_max") ? "range_max" : "range_min", "range_max must be > range_min");
  base.noise_std = c.get("noise_std", base.noise_std, Range::nonNegative());
  if (c.has("mount")) {
    const Config m = c.section("mount");
    m.allowOnly({"x", "y", "yaw_deg"});
    base.mount.x = m.get("x", base.mount.x, Range::any());
    base.mount.y = m.get("y", base.mount.y, Range::any());
    base.mount.theta = geom::deg2rad(m.get("yaw_deg", geom::rad2deg(base.mount.theta), Range::between(-180, 180)));
  }
  return base;
}

LaserDriverCore::LaserDriverCore(const Scenario& s, const LaserConfig& c, uint64_t seed)
    : scenario_(std::make_unique<const Scenario>(s)),
      world_(*scenario_),
      cfg_(c),
      period_us_(std::llround(1e6 / c.scan_rate_hz)),
      rng_(deriveSeed(seed, "laser")) {
  const double fov = geom::deg2rad(c.fov_deg);
  const bool full_circle = c.fov_deg >= 360.0 - 1e-9;
  // A full circle must not read the same direction twice; a partial fov includes both edges.
  angle_increment_ = full_circle ? fov / c.readings : fov / (c.readings - 1);
  angle_min_ = -0.5 * fov;
  offset_us_.resize(static_cast<size_t>(c.readings));
  for (int i = 0; i < c.readings; ++i)
    offset_us_[static_cast<size_t>(i)] =
        static_cast<int32_t>(static_cast<int64_t>(i) * period_us_ / c.readings);
}

void LaserDriverCore::truthAt(int64_t utime, geom::Pose2& robot, std::vector<MoverPose>& movers) const {
  // states_ brackets every reading of the scan being made (see onSimState).
  size_t b = 1;
  while (b + 1 < states_.size() && states_[b].utime < utime) ++b;
  const sim_state_t& sa = states_[b - 1];
  const sim_state_t& sb = states_[b];
  const double f = std::clamp(static_cast<double>(utime - sa.utime) / static_cast<double>(sb.utime - sa.utime), 0.0, 1.0);
  robot = geom::interpolate({sa.robot_pose.x, sa.robot_pose.y, sa.robot_pose.theta},
                            {sb.robot_pose.x, sb.robot_pose.y, sb.robot_pose.theta}, f);
  movers.clear();
  for (const mover_state_t& ma : sa.movers) {
    geom::Vec2 p(ma.x, ma.y);
    for (const mover_state_t& mb : sb.movers)
      if (mb.id == ma.id) p += f * (geom::Vec2(mb.x, mb.y) - p);
    movers.push_back({ma.id, p, ma.radius});
  }
}

laser_scan_t LaserDriverCore::makeScan(int64_t start_utime) {
  laser_scan_t scan;
  scan.utime = start_utime;
  scan.seq = seq_++;
  scan.mount.x = cfg_.mount.x;
  scan.mount.y = cfg_.mount.y;
  scan.mount.theta = cfg_.mount.theta;
  scan.angle_min = angle_min_;
  scan.angle_increment = angle_increment_;
  scan.range_min = static_cast<float>(cfg_.range_min);
  scan.range_max = static_cast<float>(cfg_.range_max);
  scan.nranges = cfg_.readings;
  scan.ranges.resize(offset_us_.size());
  scan.flags.resize(offset_us_.size());
  scan.offset_us = offset_us_;

  const auto transparent = [](const Material& m) { return m.laser == LaserBehaviour::Transparent; };
  geom::Pose2 robot;
  std::vector<MoverPose> movers;
  for (size_t i = 0; i < offset_us_.size(); ++i) {
    truthAt(start_utime + offset_us_[i], robot, movers);
    if (!movers.empty()) world_.setMovers(movers);
    const geom::Pose2 sensor = robot.compose(cfg_.mount);
    const double angle = sensor.theta + angle_min_ + static_cast<double>(i) * angle_increment_;
    const std::optional<Hit> hit =
        world_.castRay({sensor.position(), geom::unitVector(angle)}, cfg_.range_max, transparent);
    // One draw per reading, hit or not, so the noise stream does not depend on the world.
    const double noise = cfg_.noise_std * gauss_(rng_);
    const double r = hit ? hit->range + noise : 0.0;
    const bool ok = hit && hit->primitive->material->laser != LaserBehaviour::Absorb && r >= cfg_.range_min &&
                    r <= cfg_.range_max;
    scan.ranges[i] = ok ? static_cast<float>(r) : 0.0f;
    scan.flags[i] = ok ? int8_t{laser_scan_t::FLAG_OK} : int8_t{laser_scan_t::FLAG_NO_RETURN};
  }
  return scan;
}

std::vector<laser_scan_t> LaserDriverCore::onSimState(const sim_state_t& st) {
  if (!std::isfinite(st.robot_pose.x) || !std::isfinite(st.robot_pose.y) || !std::isfinite(st.robot_pose.theta))
    throw std::invalid_argument("SIM_STATE seq " + std::to_string(st.seq) + ": non-finite robot pose");
  if (!states_.empty() && st.utime <= states_.back().utime)
    throw std::invalid_argument("SIM_STATE utime " + std::to_string(st.utime) + " is not after the previous " +
                                std::to_string(states_.back().utime));
  // After a gap longer than a scan (the world paused or restarted its clock forward),
  // interpolating across it would invent motion: start scanning afresh from this state.
  if (!states_.empty() && st.utime - states_.back().utime > period_us_) states_.clear();
  if (states_.empty()) next_scan_utime_ = st.utime;
  states_.push_back(st);

  std::vector<laser_scan_t> out;
  // A scan is complete once the truth is known up to its last reading.
  while (states_.size() >= 2 && states_.back().utime >= next_scan_utime_ + offset_us_.back()) {
    out.push_back(makeScan(next_scan_utime_));
    next_scan_utime_ += period_us_;
  }
  // Keep only the states from the last one at or before the next scan's start.
  while (states_.size() >= 2 && states_[1].utime <= next_scan_utime_) states_.pop_front();
  return out;
}

}  // namespace lasonic::sim
