// The simulated laser range scanner (MOBOT-IV: 720 readings per 360° scan, 2 scans per
// revolution), in two profiles (README "Sensor models"). Ideal: one ray per reading; transparent
// materials (glass, mesh) are passed through, absorbing ones (black cardboard) return nothing,
// thin objects fall between the rays. Physical: a beam with a footprint; what returns depends on
// the material's remission, the incidence and the range (dark surfaces drop out with range);
// glass returns the beam within a few degrees of normal incidence; edges give mixed pixels.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/pose_msg.hpp"
#include "core/utime.hpp"
#include "sim/drivers.hpp"

namespace lasonic::sim {

namespace {

LaserConfig laserKeys(const Config& c, LaserConfig base) {
  c.allowOnly({"profile", "scan_rate_hz", "readings", "fov_deg", "range_max", "range_min", "noise_std", "mount",
               "range_10pct_m", "dropout_db", "beam_divergence_deg", "beam_diameter_m", "footprint_rays", "merge_range_m",
               "clock_offset_s", "sweep"});
  base.profile = c.getChoice("profile", base.profile, {{"physical", SensorProfile::Physical}, {"ideal", SensorProfile::Ideal}});
  base.scan_rate_hz = c.get("scan_rate_hz", base.scan_rate_hz, Range::between(0.1, 100));
  base.readings = c.get("readings", base.readings, Range::between(2, 100000));
  base.fov_deg = c.get("fov_deg", base.fov_deg, Range::between(1, 360));
  base.range_min = c.get("range_min", base.range_min, Range::nonNegative());
  base.range_max = c.get("range_max", base.range_max, Range::positive());
  base.noise_std = c.get("noise_std", base.noise_std, Range::nonNegative());
  base.clockwise = c.getChoice("sweep", base.clockwise, {{"counterclockwise", false}, {"clockwise", true}});
  if (c.has("mount")) {
    const Config m = c.section("mount");
    m.allowOnly({"x", "y", "yaw_deg"});
    // On the robot's body (bounds::kMaxBodyRadius).
    const Range on_body = Range::between(-bounds::kMaxBodyRadius, bounds::kMaxBodyRadius);
    base.mount.x = m.get("x", base.mount.x, on_body);
    base.mount.y = m.get("y", base.mount.y, on_body);
    base.mount.theta = geom::deg2rad(m.get("yaw_deg", geom::rad2deg(base.mount.theta), Range::between(-180, 180)));
  }
  base.range_10pct = c.get("range_10pct_m", base.range_10pct, Range::positive());
  base.dropout_db = c.get("dropout_db", base.dropout_db, Range::positive());
  base.beam_divergence =
      geom::deg2rad(c.get("beam_divergence_deg", geom::rad2deg(base.beam_divergence), Range::between(0, 10)));
  base.beam_diameter = c.get("beam_diameter_m", base.beam_diameter, Range::between(0, 0.5));
  base.footprint_rays = c.get("footprint_rays", base.footprint_rays, Range::between(1, 100));
  base.merge_range = c.get("merge_range_m", base.merge_range, Range::nonNegative());
  // (an hour either way: beyond that no clock is merely unsynchronised)
  base.clock_offset_s = c.get("clock_offset_s", base.clock_offset_s, Range::between(-3600, 3600));
  return base;
}

}  // namespace

void checkLaserKeys(const Config& c) { laserKeys(c, {}); }

LaserConfig laserConfig(const Config& c, LaserConfig base) {
  base = laserKeys(c, base);
  if (base.range_max <= base.range_min)
    c.fail(c.has("range_max") ? "range_max" : "range_min",
           "range_max (" + showNumber(base.range_max) + ") must be > range_min (" + showNumber(base.range_min) + ")");
  return base;
}

LaserDriverCore::LaserDriverCore(const Scenario& s, const LaserConfig& c, uint64_t seed)
    : scenario_(std::make_unique<const Scenario>(s)),
      world_(*scenario_),
      cfg_(c),
      period_us_(periodUs(c.scan_rate_hz)),
      rng_(deriveSeed(seed, "laser")) {
  const double fov = geom::deg2rad(c.fov_deg);
  const bool full_circle = c.fov_deg >= 360.0 - 1e-9;
  // A full circle must not read the same direction twice; a partial fov includes both edges.
  angle_increment_ = full_circle ? fov / c.readings : fov / (c.readings - 1);
  angle_min_ = -0.5 * fov;
  if (c.clockwise) {  // the same directions, swept the other way: from +fov/2 down
    angle_min_ = -angle_min_;
    angle_increment_ = -angle_increment_;
  }
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
  robot = geom::interpolate(toPose(sa.robot_pose), toPose(sb.robot_pose), f);
  movers.clear();
  for (const mover_state_t& ma : sa.movers) {
    geom::Vec2 p(ma.x, ma.y);
    for (const mover_state_t& mb : sb.movers)
      if (mb.id == ma.id) p += f * (geom::Vec2(mb.x, mb.y) - p);
    movers.push_back({ma.id, p, ma.radius});
  }
}

void LaserDriverCore::binStatics(const geom::Vec2& from, double motion) {
  bins_.assign(kBins, {});
  const double bin = 2 * geom::kPi / kBins;
  const auto& prims = world_.primitives();
  auto binOf = [&](double a) {
    double f = std::fmod(a + geom::kPi, 2 * geom::kPi);
    if (f < 0) f += 2 * geom::kPi;
    return std::min(kBins - 1, static_cast<int>(f / bin));
  };
  for (size_t i = 0; i < world_.staticCount(); ++i) {
    const Primitive& p = prims[i];
    double lo = 0, span = 2 * geom::kPi, dist;
    if (p.kind == Primitive::Kind::Segment) {
      dist = geom::distance(p.segment, from);
      const geom::Vec2 da = p.segment.a - from, db = p.segment.b - from;
      const double aa = std::atan2(da.y(), da.x()), ab = std::atan2(db.y(), db.x());
      double ccw = std::fmod(ab - aa, 2 * geom::kPi);
      if (ccw < 0) ccw += 2 * geom::kPi;
      lo = ccw <= geom::kPi ? aa : ab;
      span = ccw <= geom::kPi ? ccw : 2 * geom::kPi - ccw;
    } else {
      const geom::Vec2 d = p.circle.center - from;
      dist = d.norm() - p.circle.radius;
      const double half = d.norm() > p.circle.radius ? std::asin(p.circle.radius / d.norm()) : geom::kPi;
      lo = std::atan2(d.y(), d.x()) - half;
      span = 2 * half;
    }
    // Widen by what the sensor's motion during the scan, the beam's width and a bin can shift it.
    const double reach = motion + cfg_.beam_diameter + 0.02;
    if (dist <= reach + 1e-3) {
      lo = 0;
      span = 2 * geom::kPi;
    } else {
      const double m = std::asin(std::min(1.0, reach / dist)) + 0.5 * cfg_.beam_divergence + bin;
      lo -= m;
      span += 2 * m;
    }
    const int n = std::min(kBins, static_cast<int>(std::ceil(span / bin)) + 1);
    const int first = binOf(lo);
    for (int k = 0; k < n; ++k) bins_[static_cast<size_t>((first + k) % kBins)].push_back(static_cast<uint32_t>(i));
  }
}

std::pair<double, int> LaserDriverCore::physicalReading(const geom::Vec2& origin, double angle) {
  // The beam's footprint, sampled by footprint_rays sub-rays spread over the exit aperture and
  // the divergence. Each sub-ray passes transparent surfaces, except that one met within its
  // specular cone (glass, near normal incidence) sends the beam straight back; other surfaces
  // return rho cos(beta) / r² of it (Lambert).
  struct Part {
    double range, power;
    int obstacle;
  };
  // Fresnel reflection of a pane (~4 % per face) comes straight back into the receiver: far
  // stronger than any diffuse return, whose power spreads over the half-space.
  constexpr double kSpecularRemission = 10.0;
  const int n = cfg_.footprint_rays;
  Part parts[100];
  int nparts = 0;
  double total = 0;
  double f = std::fmod(angle + geom::kPi, 2 * geom::kPi);
  if (f < 0) f += 2 * geom::kPi;
  const std::vector<uint32_t>& candidates = bins_[static_cast<size_t>(std::min(kBins - 1, static_cast<int>(f / (2 * geom::kPi / kBins))))];
  const geom::Vec2 axis = geom::unitVector(angle);
  const geom::Vec2 across(-axis.y(), axis.x());
  for (int j = 0; j < n; ++j) {
    const double fj = n == 1 ? 0.0 : static_cast<double>(j) / (n - 1) - 0.5;
    const double da = fj * cfg_.beam_divergence;  // small: first order is exact to 1e-6
    const geom::Vec2 dir = (axis + da * across).normalized();
    geom::Vec2 o = origin + fj * cfg_.beam_diameter * across;
    double travelled = 0;
    for (int k = 0; k < 8; ++k) {
      const std::optional<Hit> h = world_.castRayAmong({o, dir}, cfg_.range_max - travelled, candidates);
      if (!h) break;
      const Material& m = *h->primitive->material;
      const double r = travelled + h->range;
      const double cos_beta = std::abs(dir.dot(h->normal));
      if (m.laser == LaserBehaviour::Transparent && (m.laser_specular <= 0 || cos_beta < std::cos(m.laser_specular))) {
        travelled = r;
        o = h->point + 1e-6 * dir;  // through the pane (or the mesh) to what lies behind
        continue;
      }
      const double rho = m.laser == LaserBehaviour::Transparent ? kSpecularRemission : m.laser_remission * cos_beta;
      const double power = rho / std::max(r * r, 1e-6) / n;
      if (power > 0) {
        parts[nparts++] = {r, power, h->obstacle};
        total += power;
      }
      break;
    }
  }
  // One draw per reading, returned or not, so the random stream does not depend on the world.
  const double u = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  if (total <= 0) return {-1.0, -1};
  // Returns closer together in range than merge_range overlap in the receiver and are measured
  // as one, at their power-weighted mean range: a mixed pixel where the footprint straddles an
  // edge (Hebert & Krotkov 1992). The nearest such group whose power passes the detection
  // threshold (a 10 % target at range_10pct; near it, receiver noise decides) is the reading; a
  // thin object is seen when it covers enough of the footprint, else the beam's rest is read.
  std::sort(parts, parts + nparts, [](const Part& a, const Part& b) { return a.range < b.range; });
  const double threshold = 0.1 / (cfg_.range_10pct * cfg_.range_10pct);
  for (int first = 0; first < nparts;) {
    int end = first + 1;
    while (end < nparts && parts[end].range - parts[first].range <= cfg_.merge_range) ++end;
    double power = 0, range = 0;
    for (int i = first; i < end; ++i) {
      power += parts[i].power;
      range += parts[i].range * parts[i].power;
    }
    range /= power;
    const double margin_db = 10.0 * std::log10(power / threshold);
    if (u < 1.0 / (1.0 + std::pow(10.0, -margin_db / cfg_.dropout_db))) {
      // LASER_TRUTH: the surface that returned most of the power, if the reading lies within
      // 5 cm of it; otherwise a mixed pixel, no one surface's reading (-1).
      int obstacle = -1;
      double best = 0, best_range = 0;
      for (int i = first; i < end; ++i) {
        double p = 0, r = 0;
        for (int j = first; j < end; ++j)
          if (parts[j].obstacle == parts[i].obstacle) {
            p += parts[j].power;
            r += parts[j].range * parts[j].power;
          }
        if (p > best) {
          best = p;
          best_range = r / p;
          obstacle = parts[i].obstacle;
        }
      }
      if (std::abs(range - best_range) > 0.05) obstacle = -1;
      return {range, obstacle};
    }
    first = end;
  }
  return {-1.0, -1};
}
LaserDriverCore::Output LaserDriverCore::makeScan(int64_t start_utime) {
  Output out;
  laser_scan_t& scan = out.scan;
  scan.utime = start_utime + secondsToUs(cfg_.clock_offset_s);  // the scanner host's clock
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
  out.truth.utime = scan.utime;
  out.truth.seq = scan.seq;
  out.truth.obstacle.assign(offset_us_.size(), -1);

  const auto transparent = [](const Material& m) { return m.laser == LaserBehaviour::Transparent; };
  geom::Pose2 robot;
  std::vector<MoverPose> movers;
  if (cfg_.profile == SensorProfile::Physical) {
    geom::Pose2 end;
    truthAt(start_utime, robot, movers);
    truthAt(start_utime + offset_us_.back(), end, movers);
    const geom::Vec2 p0 = robot.compose(cfg_.mount).position(), p1 = end.compose(cfg_.mount).position();
    binStatics(p0, (p1 - p0).norm() + std::hypot(cfg_.mount.x, cfg_.mount.y) * std::abs(geom::angleDiff(end.theta, robot.theta)));
  }
  for (size_t i = 0; i < offset_us_.size(); ++i) {
    truthAt(start_utime + offset_us_[i], robot, movers);
    if (!movers.empty()) world_.setMovers(movers);
    const geom::Pose2 sensor = robot.compose(cfg_.mount);
    const double angle = sensor.theta + angle_min_ + static_cast<double>(i) * angle_increment_;
    double r = 0;
    int obstacle = -1;
    bool ok = false;
    if (cfg_.profile == SensorProfile::Ideal) {
      const std::optional<Hit> hit =
          world_.castRay({sensor.position(), geom::unitVector(angle)}, cfg_.range_max, transparent);
      // One draw per reading, hit or not, so the noise stream does not depend on the world.
      const double noise = cfg_.noise_std * gauss_(rng_);
      r = hit ? hit->range + noise : 0.0;
      ok = hit && hit->primitive->material->laser != LaserBehaviour::Absorb && r >= cfg_.range_min &&
           r <= cfg_.range_max;
      if (ok) obstacle = hit->obstacle;
    } else {
      const auto [range, who] = physicalReading(sensor.position(), angle);
      const double noise = cfg_.noise_std * gauss_(rng_);
      r = range + noise;
      ok = range >= 0 && r >= cfg_.range_min && r <= cfg_.range_max;
      if (ok) obstacle = who;
    }
    scan.ranges[i] = ok ? static_cast<float>(r) : 0.0f;
    scan.flags[i] = ok ? int8_t{laser_scan_t::FLAG_OK} : int8_t{laser_scan_t::FLAG_NO_RETURN};
    out.truth.obstacle[i] = obstacle;
  }
  out.truth.nranges = static_cast<int32_t>(out.truth.obstacle.size());
  return out;
}

std::vector<LaserDriverCore::Output> LaserDriverCore::onSimState(const sim_state_t& st) {
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

  std::vector<Output> out;
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
