// The simulated sonar ring: config, beam model (sonar_model.hpp) and firing schedule (drivers.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "core/pose_msg.hpp"
#include "core/utime.hpp"
#include "lcmio/lengths.hpp"
#include "sim/drivers.hpp"
#include "sim/sonar_model.hpp"
#include "sim/sonar_physical.hpp"

namespace lasonic::sim {

namespace {

// Uniform in [0, 1) from 53 random bits: the same numbers on every standard library.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

SonarSensor parseSensor(const Config& s) {
  s.allowOnly({"x", "y", "theta_deg", "beam_deg", "group"});
  SonarSensor out;
  // On the robot's body (bounds::kMaxBodyRadius).
  const Range on_body = Range::between(-bounds::kMaxBodyRadius, bounds::kMaxBodyRadius);
  out.mount.x = s.requireNum("x", on_body);
  out.mount.y = s.requireNum("y", on_body);
  out.mount.theta = geom::normalizeAngle(geom::deg2rad(s.requireNum("theta_deg", Range::any())));
  out.beam_width = geom::deg2rad(s.get("beam_deg", 30.0, Range{0, 180, true}));
  if (!s.has("group")) s.fail("group", "is required");
  out.group = s.get("group", 0, Range::between(0, 1000));
  return out;
}

std::vector<SonarSensor> parseRing(const Config& r) {
  r.allowOnly({"count", "radius", "beam_deg", "groups", "offset_deg"});
  const int count = r.get("count", 24, Range::between(1, 1000));
  const double radius = r.get("radius", 0.35, Range::between(0, bounds::kMaxBodyRadius));  // on the robot's body
  const double beam = geom::deg2rad(r.get("beam_deg", 30.0, Range{0, 180, true}));
  const int groups = r.get("groups", 6, Range::between(1, 1000));
  if (groups > count) r.fail("groups", "must be <= count (" + std::to_string(count) + ")");
  const double offset = geom::deg2rad(r.get("offset_deg", 0.0, Range::any()));
  return ringSensors(count, radius, beam, groups, offset);
}

// Nearest hit among rays, with the hit that made it.
struct Candidate {
  double range = -1;
  const Hit* hit = nullptr;
  void offer(double r, const Hit& h) {
    if (range < 0 || r < range) {
      range = r;
      hit = &h;
    }
  }
};

}  // namespace

std::vector<SonarSensor> ringSensors(int count, double radius, double beam_width, int groups,
                                     double offset) {
  std::vector<SonarSensor> out;
  for (int i = 0; i < count; ++i) {
    const double bearing = geom::normalizeAngle(offset + 2.0 * geom::kPi * i / count);
    out.push_back({{radius * std::cos(bearing), radius * std::sin(bearing), bearing}, beam_width, i % groups});
  }
  return out;
}

std::vector<std::vector<int>> firingGroups(const std::vector<SonarSensor>& sensors) {
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < sensors.size(); ++i) {
    const size_t g = static_cast<size_t>(sensors[i].group);
    if (groups.size() <= g) groups.resize(g + 1);
    groups[g].push_back(static_cast<int>(i));
  }
  return groups;
}

namespace {

// A SONAR_RING carries at most limits::kSonarReadings readings (one firing group), and its
// sensor ids are int16: a ring of more transducers than that (real ones have 8 to 48) could not
// be sent.
constexpr int64_t kMaxSensors = limits::kSonarReadings;

SonarConfig sonarKeys(const Config& c, SonarConfig base) {
  c.allowOnly({"profile", "ring", "sensors", "range_max", "range_min", "group_period_s", "group_jitter_s", "beam_scale", "report_scaled_beam", "rays_per_beam",
               "noise_std", "noise_rel", "multipath_prob", "multipath_bounces", "crosstalk", "crosstalk_prob",
               "foreign_prob", "frequency_hz", "transducer_radius_m", "pulse_cycles", "side_lobes", "plane_range_m",
               "tvg_range_m", "air_absorption_db_per_m", "ray_step_deg", "ideal_beam_deg", "ideal_range",
               "clock_offset_s", "send_delay_s"});
  SonarConfig o = base;
  o.profile = c.getChoice("profile", o.profile, {{"physical", SensorProfile::Physical}, {"ideal", SensorProfile::Ideal}});
  if (c.has("ring") && c.has("sensors")) c.fail("sensors", "give either ring or sensors, not both");
  if (c.has("ring")) o.sensors = parseRing(c.section("ring"));
  if (c.has("sensors")) {
    o.sensors.clear();
    const std::vector<Config> sensors = c.list("sensors");
    if (static_cast<int64_t>(sensors.size()) > kMaxSensors)
      c.fail("sensors", "has " + std::to_string(sensors.size()) + " sensors: at most " + std::to_string(kMaxSensors) +
                            " (what one SONAR_RING carries)");
    for (const Config& s : sensors) o.sensors.push_back(parseSensor(s));
    if (o.sensors.empty()) c.fail("sensors", "needs at least one sensor");
    const auto groups = firingGroups(o.sensors);
    for (size_t g = 0; g < groups.size(); ++g)
      if (groups[g].empty())
        c.fail("sensors", "firing group " + std::to_string(g) +
                              " has no sensor (groups are numbered 0..n-1 and fired in that order)");
  }
  if (o.sensors.empty()) o.sensors = ringSensors(24, 0.35, geom::deg2rad(30), 6);

  o.range_max = c.get("range_max", o.range_max, Range::positive());
  o.range_min = c.get("range_min", o.range_min, Range::nonNegative());
  // A minute between groups: no ranging sensor is that slow (and the schedule, in int64
  // microseconds, stays exact).
  o.group_period_s = c.get("group_period_s", o.group_period_s, Range{0, 60, true});
  o.group_jitter_s = c.get("group_jitter_s", o.group_jitter_s, Range::between(0, 1));
  o.clock_offset_s = c.get("clock_offset_s", o.clock_offset_s, Range::between(-3600, 3600));
  if (c.has("send_delay_s")) o.send_delay_s = c.requireNum("send_delay_s", Range::between(0, 10));
  o.beam_scale = c.get("beam_scale", o.beam_scale, Range{0, 5, true});
  o.report_scaled_beam = c.get<bool>("report_scaled_beam", o.report_scaled_beam);
  o.rays_per_beam = c.get("rays_per_beam", o.rays_per_beam, Range::between(1, 10000));
  o.noise_std = c.get("noise_std", o.noise_std, Range::nonNegative());
  o.noise_rel = c.get("noise_rel", o.noise_rel, Range::nonNegative());
  o.multipath_prob = c.get("multipath_prob", o.multipath_prob, Range::probability());
  o.multipath_bounces = c.get("multipath_bounces", o.multipath_bounces, Range::between(0, 10));
  o.crosstalk = c.getChoice("crosstalk", o.crosstalk,
                            {{"geometric", CrosstalkModel::Geometric}, {"random", CrosstalkModel::Random}});
  o.crosstalk_prob = c.get("crosstalk_prob", o.crosstalk_prob, Range::probability());
  o.foreign_prob = c.get("foreign_prob", o.foreign_prob, Range::probability());
  o.frequency_hz = c.get("frequency_hz", o.frequency_hz, Range::between(1e3, 1e6));
  o.transducer_radius = c.get("transducer_radius_m", o.transducer_radius, Range{0, 1, true});
  o.pulse_cycles = c.get("pulse_cycles", o.pulse_cycles, Range::between(1, 10000));
  o.side_lobes = c.get<bool>("side_lobes", o.side_lobes);
  o.plane_range = c.get("plane_range_m", o.plane_range, Range::positive());
  o.tvg_range = c.get("tvg_range_m", o.tvg_range, Range::nonNegative());
  if (c.has("air_absorption_db_per_m"))
    o.air_absorption = c.requireNum("air_absorption_db_per_m", Range::between(0, 100));
  o.ray_step = geom::deg2rad(c.get("ray_step_deg", geom::rad2deg(o.ray_step), Range::between(0.01, 5)));
  o.ideal_beam_width =
      geom::deg2rad(c.get("ideal_beam_deg", geom::rad2deg(o.ideal_beam_width), Range{0, 180, true}));
  o.ideal_range = c.get("ideal_range", o.ideal_range, Range::positive());
  return o;
}

}  // namespace

void checkSonarKeys(const Config& c) { sonarKeys(c, {}); }

SonarConfig sonarConfig(const Config& c, SonarConfig base) {
  SonarConfig o = sonarKeys(c, base);
  // Cross-key checks name a key this section sets and give both values: with layered files the
  // merged section holds both keys, and the values show which one was changed.
  auto key = [&c](const char* a, const char* b) { return c.has(a) ? a : b; };
  if (o.range_min >= o.range_max)
    c.fail(key("range_min", "range_max"),
           "range_min (" + showNumber(o.range_min) + ") must be < range_max (" + showNumber(o.range_max) + ")");
  if (o.group_period_s < timeOfFlight(o.range_max))
    c.fail(key("group_period_s", "range_max"),
           "group_period_s (" + showNumber(o.group_period_s) +
               ") must be >= the echo time of flight 2*range_max/343 m/s = " +
               std::to_string(timeOfFlight(o.range_max)) + " s, else a group's echoes reach the next");
  if (o.crosstalk_prob + o.foreign_prob > 1.0)
    c.fail(key("crosstalk_prob", "foreign_prob"), "crosstalk_prob (" + showNumber(o.crosstalk_prob) +
                                                      ") + foreign_prob (" + showNumber(o.foreign_prob) + ") must be <= 1");
  if (o.plane_range <= o.range_max)
    c.fail(key("plane_range_m", "range_max"), "plane_range_m (" + showNumber(o.plane_range) +
                                                  ", the range a flat wall is still heard at) must be > range_max (" +
                                                  showNumber(o.range_max) + ")");
  return o;
}

double nearestLaserVisible(const std::vector<Primitive>& prims, const geom::Sector& sector) {
  double best = -1;
  for (const Primitive& p : prims) {
    if (p.material->laser != LaserBehaviour::Reflect) continue;
    const std::optional<double> d = p.kind == Primitive::Kind::Segment
                                        ? geom::nearestInSector(sector, p.segment)
                                        : geom::nearestInSector(sector, p.circle);
    if (d && (best < 0 || *d < best)) best = *d;
  }
  return best;
}

SonarReading fireSensor(const WorldGeometry& world, const geom::Pose2& sensor, double beam_width,
                        const SonarConfig& c, std::mt19937_64& rng) {
  const int n = c.rays_per_beam;
  std::vector<Hit> first_hits;
  first_hits.reserve(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double a = n == 1 ? 0.0 : -0.5 * beam_width + beam_width * i / (n - 1);
    if (auto h = world.castRay({sensor.position(), geom::unitVector(sensor.theta + a)}, c.range_max))
      first_hits.push_back(*h);
  }

  // One echo_prob draw per obstacle and reading (lazily, in ray order: deterministic).
  std::map<int, bool> heard;
  auto echoes = [&](const Hit& h, const geom::Vec2& dir) {
    const Material& m = *h.primitive->material;
    if (geom::incidenceAngle(dir, h.normal) > m.sonar_echo_angle) return false;
    auto [it, fresh] = heard.try_emplace(h.obstacle, false);
    if (fresh) it->second = uniform01(rng) < m.sonar_echo_prob;
    return it->second;
  };

  SonarReading out;
  out.truth.obstacle = -1;
  out.truth.true_range = -1;
  out.truth.cause = sonar_cause_t::CAUSE_NO_ECHO;

  Candidate direct;
  std::vector<const Hit*> mirrors;  // first hits at specular (too oblique) incidence
  for (const Hit& h : first_hits) {
    const geom::Vec2 dir = (h.point - sensor.position()).normalized();
    if (echoes(h, dir)) direct.offer(h.range, h);
    else if (geom::incidenceAngle(dir, h.normal) > h.primitive->material->sonar_echo_angle)
      mirrors.push_back(&h);
  }

  double reading = -1;  // noise-free
  const Hit* cause_hit = nullptr;
  if (direct.hit) {
    reading = direct.range;
    cause_hit = direct.hit;
    out.truth.cause = sonar_cause_t::CAUSE_DIRECT;
    out.truth.true_range = static_cast<float>(reading);
  } else if (!mirrors.empty() && uniform01(rng) < c.multipath_prob) {
    // Follow each mirrored ray through up to multipath_bounces specular reflections. The
    // reading is time of flight * 343 m/s / 2, so the shortest arrival wins (the first echo).
    // Each ray stands for the slice of the beam between it and its neighbours (`tube` wide).
    const double tube = n == 1 ? beam_width : beam_width / (n - 1);
    Candidate multipath;  // shortest reading, with the first mirror that made it
    for (const Hit* m : mirrors) {
      geom::Vec2 at = m->point;
      geom::Vec2 dir = mirror((m->point - sensor.position()).normalized(), m->normal);
      double path = m->range;  // sensor -> first mirror -> ... -> `at`
      for (int bounce = 1; bounce <= c.multipath_bounces && path < 2 * c.range_max; ++bounce) {
        // Start just off the mirror so the ray does not meet it again.
        const auto h = world.castRay({at + 1e-6 * dir, dir}, 2 * c.range_max - path);
        // (a) After two or more reflections (a corner) the sound may come back to the transducer
        // itself: its ray tube covers the sensor, it arrives within the beam, nothing in between.
        // Reading: half the closed loop. (One flat reflection cannot return off the normal.)
        const geom::Vec2 to_sensor = sensor.position() - at;
        const double t = to_sensor.dot(dir);
        if (bounce >= 2 && t > 0 && (!h || h->range > t) && path + t <= 2 * c.range_max &&
            std::abs(dir.x() * to_sensor.y() - dir.y() * to_sensor.x()) <= 0.5 * tube * (path + t) &&
            std::abs(geom::angleDiff(std::atan2(-dir.y(), -dir.x()), sensor.theta)) <= 0.5 * beam_width) {
          multipath.offer(0.5 * (path + t), *m);
          break;
        }
        if (!h) break;
        // (b) A surface met within its echo angle echoes back along the incoming ray, and the
        // echo retraces the whole path: the reading is the one-way path d1 + d2 + ... + dk.
        if (geom::incidenceAngle(dir, h->normal) <= h->primitive->material->sonar_echo_angle) {
          if (path + h->range <= c.range_max && echoes(*h, dir)) multipath.offer(path + h->range, *m);
          break;  // beyond range_max, or not heard (echo_prob): no echo along this ray
        }
        // (c) Oblique again: the sound mirrors once more.
        path += h->range;
        at = h->point;
        dir = mirror(dir, h->normal);
      }
    }
    if (multipath.hit) {
      reading = multipath.range;
      cause_hit = multipath.hit;
      out.truth.cause = sonar_cause_t::CAUSE_SPECULAR_LONG;
    }
  }
  if (direct.hit) {
    out.truth.hit_x = direct.hit->point.x();
    out.truth.hit_y = direct.hit->point.y();
    out.truth.reflector = direct.hit->primitive->kind == Primitive::Kind::Circle
                              ? sonar_cause_t::REFLECTOR_CYLINDER
                              : sonar_cause_t::REFLECTOR_PLANE;
  }
  if (cause_hit) {
    out.truth.obstacle = cause_hit->obstacle;
    out.truth.laser_visible = cause_hit->primitive->material->laser == LaserBehaviour::Reflect;
    // Scaled standard normal: a zero spread (noise-free config) is allowed.
    const double noise = (c.noise_std + c.noise_rel * reading) * std::normal_distribution<double>()(rng);
    out.range = static_cast<float>(std::clamp(reading + noise, c.range_min, c.range_max));
    out.no_echo = false;
  } else {
    out.range = static_cast<float>(c.range_max);
  }

  // Too-short misreadings replace whatever the sensor would have heard.
  const double u = uniform01(rng);
  if (u < c.crosstalk_prob + c.foreign_prob) {
    const double upper = out.no_echo ? c.range_max : out.range;
    out.range = static_cast<float>(c.range_min + uniform01(rng) * std::max(0.0, upper - c.range_min));
    out.no_echo = false;
    if (u < c.crosstalk_prob) out.truth.cause = sonar_cause_t::CAUSE_CROSSTALK;
    else out.truth.cause = sonar_cause_t::CAUSE_FOREIGN;
  }

  const geom::Sector ideal{sensor.position(), sensor.theta, c.ideal_beam_width, c.ideal_range};
  out.truth.nearest_laser_visible = static_cast<float>(nearestLaserVisible(world.primitives(), ideal));
  return out;
}

// ---------------------------------------------------------------- SonarDriverCore

namespace {

bool finite(const sim_state_t& st) {
  bool ok = std::isfinite(st.robot_pose.x) && std::isfinite(st.robot_pose.y) &&
            std::isfinite(st.robot_pose.theta) && std::isfinite(st.v) && std::isfinite(st.omega);
  for (const mover_state_t& m : st.movers)
    ok = ok && std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.radius);
  return ok;
}

// The beam SONAR_RING and SONAR_GEOMETRY publish: the nominal one, whatever the simulated
// transducer does (beam_scale), unless the driver is calibrated to its transducer.
float reportedBeam(const SonarConfig& c, const SonarSensor& s) {
  return static_cast<float>(c.report_scaled_beam ? s.beam_width * c.beam_scale : s.beam_width);
}


// Truth at utime in [a.utime, b.utime]: robot pose and movers linear in between.
sim_state_t interpolateState(const sim_state_t& a, const sim_state_t& b, int64_t utime) {
  const double s = b.utime > a.utime ? static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime) : 1.0;
  sim_state_t out = b;
  out.utime = utime;
  out.robot_pose = toPoseMsg(geom::interpolate(toPose(a.robot_pose), toPose(b.robot_pose), s));
  for (mover_state_t& m : out.movers)
    for (const mover_state_t& ma : a.movers)
      if (ma.id == m.id) {
        m.x = ma.x + s * (m.x - ma.x);
        m.y = ma.y + s * (m.y - ma.y);
      }
  return out;
}

// Firings lost in a longer gap of SIM_STATE are not caught up (nor interpolated over):
// the schedule restarts at the new state, as a sonar controller waiting for its pose would.
constexpr int64_t kMaxGapUs = 1'000'000;

}  // namespace

SonarDriverCore::SonarDriverCore(const Scenario& s, const SonarConfig& c, uint64_t seed)
    : scenario_(std::make_unique<Scenario>(s)),
      config_(c),
      world_(*scenario_),
      rng_(deriveSeed(seed, "sonar")),
      groups_(firingGroups(c.sensors)),
      period_us_(std::max<int64_t>(1, secondsToUs(c.group_period_s))),
      schedule_rng_(deriveSeed(seed, "sonar-schedule")) {
  if (groups_.empty()) throw std::invalid_argument("SonarDriverCore: no sonar sensors configured");
  if (c.profile == SensorProfile::Physical) physical_ = std::make_unique<PhysicalSonar>(*scenario_, c, seed);
  mover_velocity_.assign(scenario_->movers.size(), geom::Vec2::Zero());
}

SonarDriverCore::~SonarDriverCore() = default;
SonarDriverCore::SonarDriverCore(SonarDriverCore&&) noexcept = default;
SonarDriverCore& SonarDriverCore::operator=(SonarDriverCore&&) noexcept = default;

std::vector<SonarDriverCore::Output> SonarDriverCore::onSimState(const sim_state_t& st) {
  if (last_ && st.utime <= last_->utime)
    throw std::invalid_argument("SIM_STATE utime " + std::to_string(st.utime) +
                                " is not after the previous one (" + std::to_string(last_->utime) + ")");
  if (!finite(st)) throw std::invalid_argument("SIM_STATE has non-finite values");
  for (const mover_state_t& m : st.movers)
    if (m.id < 0 || static_cast<size_t>(m.id) >= scenario_->movers.size())
      throw std::invalid_argument("SIM_STATE mover id " + std::to_string(m.id) + " is not in the scenario");

  if (!last_ || st.utime - last_->utime > kMaxGapUs) {
    last_ = st;
    next_fire_utime_ = st.utime;
  }
  // The movers' true velocities over this interval (a person's aspect in the physical model).
  if (st.utime > last_->utime)
    for (const mover_state_t& m : st.movers)
      for (const mover_state_t& ma : last_->movers)
        if (ma.id == m.id)
          mover_velocity_[static_cast<size_t>(m.id)] =
              geom::Vec2(m.x - ma.x, m.y - ma.y) / (static_cast<double>(st.utime - last_->utime) * 1e-6);
  const auto jitter_us = secondsToUs(config_.group_jitter_s);
  const auto delay_us = secondsToUs(config_.sendDelay());
  for (; next_fire_utime_ <= st.utime;) {
    pending_.emplace_back(next_fire_utime_ + delay_us, fire(next_fire_utime_, interpolateState(*last_, st, next_fire_utime_)));
    next_fire_utime_ += period_us_;
    if (jitter_us > 0) next_fire_utime_ += static_cast<int64_t>(schedule_rng_() % static_cast<uint64_t>(jitter_us + 1));
  }
  last_ = st;
  // Sent in firing order once due (the delay is the same for every group, so the due times rise).
  std::vector<Output> out;
  size_t sent = 0;
  for (; sent < pending_.size() && pending_[sent].first <= st.utime; ++sent) out.push_back(std::move(pending_[sent].second));
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(sent));
  return out;
}

SonarDriverCore::Output SonarDriverCore::fire(int64_t utime, const sim_state_t& truth) {
  std::vector<MoverPose> movers;
  for (const mover_state_t& m : truth.movers) movers.push_back({m.id, {m.x, m.y}, m.radius});
  world_.setMovers(movers);
  const geom::Pose2 robot = toPose(truth.robot_pose);

  Output o;
  const int group = static_cast<int>(seq_ % static_cast<int32_t>(groups_.size()));
  o.ring.utime = o.truth.utime = utime + secondsToUs(config_.clock_offset_s);  // the sonar host's clock
  o.ring.seq = o.truth.seq = seq_++;
  o.ring.group = o.truth.group = static_cast<int16_t>(group);
  o.ring.num_sensors = static_cast<int16_t>(config_.sensors.size());
  o.ring.range_max = static_cast<float>(config_.range_max);
  const std::vector<int>& ids = groups_[static_cast<size_t>(group)];
  std::vector<SonarReading> readings;
  if (physical_) {
    std::vector<geom::Pose2> poses;
    for (int id : ids) poses.push_back(robot.compose(config_.sensors[static_cast<size_t>(id)].mount));
    readings = physical_->fireGroup(world_, utime, ids, poses, mover_velocity_, rng_);
  } else {
    for (int id : ids) {
      const SonarSensor& s = config_.sensors[static_cast<size_t>(id)];
      readings.push_back(fireSensor(world_, robot.compose(s.mount), s.beam_width * config_.beam_scale, config_, rng_));
    }
  }
  for (size_t k = 0; k < ids.size(); ++k) {
    const int id = ids[k];
    const SonarSensor& s = config_.sensors[static_cast<size_t>(id)];
    SonarReading& r = readings[k];
    r.truth.sensor_id = static_cast<int16_t>(id);
    o.ring.sensor_id.push_back(static_cast<int16_t>(id));
    o.ring.range.push_back(r.range);
    o.ring.no_echo.push_back(r.no_echo ? 1 : 0);
    o.ring.mount.push_back(toPoseMsg(s.mount));
    o.ring.beam_width.push_back(reportedBeam(config_, s));
    o.truth.causes.push_back(r.truth);
  }
  o.ring.nreadings = o.truth.nreadings = static_cast<int32_t>(o.ring.sensor_id.size());
  return o;
}

sonar_geometry_t SonarDriverCore::geometry(int64_t utime) const {
  sonar_geometry_t g;
  g.utime = utime + secondsToUs(config_.clock_offset_s);
  for (const SonarSensor& s : config_.sensors) {
    g.mount.push_back(toPoseMsg(s.mount));
    g.beam_width.push_back(reportedBeam(config_, s));
    g.group_of.push_back(static_cast<int16_t>(s.group));
  }
  g.num_sensors = static_cast<int32_t>(config_.sensors.size());
  g.num_groups = static_cast<int32_t>(groups_.size());
  g.range_max = static_cast<float>(config_.range_max);
  g.group_period_s = static_cast<float>(config_.group_period_s);
  return g;
}

}  // namespace lasonic::sim
