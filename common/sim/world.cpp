// The simulated robot's motion (ground truth), the movers, and drifting odometry.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/pose_msg.hpp"
#include "core/utime.hpp"
#include "sim/drivers.hpp"
#include "sim/path_follower.hpp"

namespace lasonic::sim {

uint64_t deriveSeed(uint64_t seed, const char* stream) {
  // FNV-1a of the stream name, mixed with the seed by splitmix64: fixed arithmetic, so a seed
  // gives the same streams on every platform and standard library.
  uint64_t h = 1469598103934665603ULL;
  for (const char* p = stream; *p; ++p) h = (h ^ static_cast<unsigned char>(*p)) * 1099511628211ULL;
  uint64_t z = seed ^ h;
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// ---------------------------------------------------------------- PathFollower

PathFollower::PathFollower(const std::vector<geom::Vec2>& path, PathMode mode, double speed,
                           double turn_rate, double start_delay_s)
    : mode_(mode), speed_(speed), turn_rate_(turn_rate), delay_(start_delay_s) {
  if (path.size() < 2) throw std::invalid_argument("PathFollower: a path needs at least 2 waypoints");
  std::vector<geom::Vec2> w = path;
  if (mode == PathMode::Loop && (w.back() - w.front()).norm() > 1e-9) w.push_back(w.front());
  if (mode == PathMode::PingPong)
    for (size_t i = path.size() - 1; i-- > 0;) w.push_back(path[i]);

  auto heading = [](const geom::Vec2& a, const geom::Vec2& b) { return std::atan2(b.y() - a.y(), b.x() - a.x()); };
  const double start_heading = heading(w[0], w[1]);
  geom::Pose2 at{w[0].x(), w[0].y(), start_heading};
  double t = 0;
  auto turnTo = [&](double h) {
    const double d = std::abs(geom::angleDiff(h, at.theta));
    const geom::Pose2 to{at.x, at.y, h};
    if (d > 1e-12 && std::isfinite(turn_rate_)) {
      phases_.push_back({t, d / turn_rate_, at, to, true});
      t += d / turn_rate_;
    }
    at = to;
  };
  for (size_t i = 0; i + 1 < w.size(); ++i) {
    if ((w[i + 1] - w[i]).norm() < 1e-9) continue;
    turnTo(heading(w[i], w[i + 1]));
    const geom::Pose2 to{w[i + 1].x(), w[i + 1].y(), at.theta};
    const double len = (w[i + 1] - w[i]).norm();
    phases_.push_back({t, len / speed_, at, to, false});
    t += len / speed_;
    at = to;
  }
  // A repeating path ends each cycle where it began, facing the same way.
  if (mode != PathMode::Once) turnTo(start_heading);
  if (phases_.empty()) throw std::invalid_argument("PathFollower: the path has no length");
  cycle_ = t;
}

PathFollower::State PathFollower::at(double t) const {
  t -= delay_;
  State s;
  s.pose = phases_.front().from;
  if (t <= 0) return s;
  if (mode_ == PathMode::Once) {
    if (t >= cycle_) {
      s.pose = phases_.back().to;
      return s;
    }
  } else {
    t = std::fmod(t, cycle_);
  }
  // Last phase starting at or before t.
  size_t lo = 0, hi = phases_.size();
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    (phases_[mid].t0 <= t ? lo : hi) = mid;
  }
  const Phase& p = phases_[lo];
  const double f = std::clamp((t - p.t0) / p.duration, 0.0, 1.0);
  s.pose = geom::interpolate(p.from, p.to, f);
  if (p.turn) {
    s.omega = std::copysign(turn_rate_, geom::angleDiff(p.to.theta, p.from.theta));
  } else {
    s.v = speed_;
  }
  return s;
}

// ---------------------------------------------------------------- odometry config

namespace {

OdometryConfig odometryKeys(const Config& c, OdometryConfig base) {
  c.allowOnly({"rate_hz", "publish_hz", "trans_noise", "rot_noise", "drift_noise", "scale_error", "turn_scale_error",
               "curvature_error"});
  base.rate_hz = c.get("rate_hz", base.rate_hz, Range::between(1, 1000));
  base.publish_hz = c.get("publish_hz", base.publish_hz, Range::between(0, 1000));
  // An odometry whose error after one metre driven (one radian turned) is a metre (a radian) is
  // no odometry: wheels spinning on ice do better.
  base.trans_noise = c.get("trans_noise", base.trans_noise, Range::between(0, 1));
  base.rot_noise = c.get("rot_noise", base.rot_noise, Range::between(0, 1));
  base.drift_noise = c.get("drift_noise", base.drift_noise, Range::between(0, 1));
  base.scale_error = c.get("scale_error", base.scale_error, Range::between(-0.5, 0.5));
  base.turn_scale_error = c.get("turn_scale_error", base.turn_scale_error, Range::between(-0.5, 0.5));
  base.curvature_error = c.get("curvature_error", base.curvature_error, Range::between(-1, 1));
  return base;
}

}  // namespace

void checkOdometryKeys(const Config& c) { odometryKeys(c, {}); }

OdometryConfig odometryConfig(const Config& c, OdometryConfig base) {
  base = odometryKeys(c, base);
  if (base.publish_hz > base.rate_hz) {
    std::ostringstream os;
    os << "must be <= rate_hz (" << base.rate_hz << "): ODOMETRY is published with a state";
    c.fail("publish_hz", os.str());
  }
  return base;
}

// ---------------------------------------------------------------- WorldCore

WorldCore::WorldCore(const Scenario& s, const OdometryConfig& c)
    : cfg_(c),
      scenario_(s),
      robot_(s.robot.path, s.robot.mode, s.robot.speed, s.robot.turn_rate),
      end_utime_(kStartUtime + secondsToUs(s.duration_s)),
      rng_(deriveSeed(s.seed, "odometry")) {
  // (parseScenario and the tools' --duration keep it so; a longer one would overflow end_utime_)
  if (!(s.duration_s > 0 && s.duration_s <= bounds::kMaxDurationS))
    throw std::invalid_argument("WorldCore: duration_s must be in (0, " + std::to_string(bounds::kMaxDurationS) + "] s");
  for (const MoverSpec& m : s.movers)
    movers_.emplace_back(m.path, m.mode, m.speed, std::numeric_limits<double>::infinity(), m.start_delay_s);
  waited_.assign(movers_.size(), 0.0);
  waiting_.assign(movers_.size(), 0.0);
  stepped_.assign(movers_.size(), geom::Vec2::Zero());
}

geom::Vec2 WorldCore::moverAt(size_t i, double t) const {
  return movers_[i].at(t - waited_[i]).pose.position() + stepped_[i];
}

bool WorldCore::moveFree(const geom::Vec2& from, const geom::Vec2& to, double radius) const {
  const geom::Segment way{from, to};
  for (const Primitive& p : scenario_.statics) {
    const double along = clearance(p, way);
    // (1e-9 m: rounding, for a body that already stood that near and walks along the wall)
    if (along < radius && along < clearance(p, from) - 1e-9) return false;
  }
  return true;
}

// A person does not walk into a robot, and steps out of the way of one that comes at them.
// Each step of the world: the mover waits (its path time stands still) if its own step would
// take it nearer than keep_clear_m to the robot's body — for at most kPatienceS, then it walks
// on round the robot; if the robot has come nearer than that, the mover steps back from it to
// that distance — straight back, else half or fully aside (to the side it is on), where no
// static obstacle stands (if none is free it stays: nowhere to go); with the robot gone, it
// walks back to its path. A mover that never comes near the robot keeps exactly its path.
//
// Off its path, the mover's place is its path's point plus the offset it stepped aside by, and
// the path's point walks on: that place, and the way to it, must be free of static obstacles
// too, or the body is carried into a wall. Where they are not, the mover stands where it was,
// its path time standing still as when it waits (README "Simulator": a body never overlaps a
// static obstacle). On its path it is where the scenario puts it.
void WorldCore::keepClear(size_t i, double t, double dt, const geom::Pose2& robot) {
  const geom::Vec2 from = moverAt(i, t - dt);
  const double waited = waited_[i];
  const geom::Vec2 stepped = stepped_[i];
  giveWay(i, t, dt, robot, from);
  if (stepped.isZero() && stepped_[i].isZero()) return;
  if (moveFree(from, moverAt(i, t), scenario_.movers[i].radius)) return;
  waited_[i] = waited + dt;
  stepped_[i] = stepped;
}

void WorldCore::giveWay(size_t i, double t, double dt, const geom::Pose2& robot, const geom::Vec2& before) {
  const MoverSpec& spec = scenario_.movers[i];
  const geom::Vec2 r = robot.position();
  const double keep = scenario_.robot.radius + spec.radius + spec.keep_clear_m;
  const geom::Vec2 walked = moverAt(i, t);
  const double d_walked = (walked - r).norm();
  const bool blocked = d_walked < keep && d_walked < (before - r).norm();
  waiting_[i] = blocked ? waiting_[i] + dt : 0.0;
  if (blocked && waiting_[i] <= kPatienceS) waited_[i] += dt;  // stand still this step
  const geom::Vec2 p = moverAt(i, t);
  const geom::Vec2 rel = p - r;
  const double d = rel.norm();
  if (d < keep) {
    const geom::Vec2 heading(std::cos(robot.theta), std::sin(robot.theta));
    geom::Vec2 away = d > 1e-9 ? geom::Vec2(rel / d) : heading;
    // Head-on: the robot ahead of the mover, its centre within kHeadOnM of the line the mover
    // walks, and standing or coming the other way along it. Straight back is then (nearly)
    // against the walk, so stepping back barely carries the mover round the robot — on the very
    // line not at all: it would be held in front of the robot for ever. A person steps back and
    // aside there, kSideStepRad off straight back, to the side they are on (on the line, their
    // right). (A robot that drives across their way they wait for, or step back from, as before.)
    const double walk = movers_[i].at(t - waited_[i]).pose.theta;
    const geom::Vec2 dir(std::cos(walk), std::sin(walk));
    const double lateral = dir.x() * rel.y() - dir.y() * rel.x();  // > 0: left of the robot, seen along the walk
    const bool oncoming = std::abs(robot_.at(t).v) < kStandingMps || heading.dot(dir) < -std::cos(geom::kPi / 4);
    if (oncoming && dir.dot(away) < 0 && std::abs(lateral) < kHeadOnM) {
      const double a = lateral > 1e-3 ? -kSideStepRad : kSideStepRad;  // (away points back along the walk)
      const double c = std::cos(a), s = std::sin(a);
      away = geom::Vec2(c * away.x() - s * away.y(), s * away.x() + c * away.y());
    }
    const double side = heading.x() * rel.y() - heading.y() * rel.x() >= 0 ? 1.0 : -1.0;
    for (const double turn : {0.0, 0.25 * side, -0.25 * side, 0.5 * side, -0.5 * side}) {
      const double c = std::cos(turn * geom::kPi), s = std::sin(turn * geom::kPi);
      const geom::Vec2 u(c * away.x() - s * away.y(), s * away.x() + c * away.y());
      // How far along u until the keep distance: |rel + k u| = keep.
      const double b = u.dot(rel);
      const double k = -b + std::sqrt(std::max(0.0, b * b - (d * d - keep * keep)));
      if (moveFree(before, p + u * k, spec.radius)) {
        stepped_[i] += u * k;
        return;
      }
    }
    return;
  }
  // Clear of the robot: back towards the path at walking speed, as far as stays clear.
  const double off = stepped_[i].norm();
  if (off > 0) {
    const double step = std::min(off, spec.speed * dt);
    const geom::Vec2 back_on = stepped_[i] * ((off - step) / off);
    const geom::Vec2 q = p - stepped_[i] + back_on;
    if ((q - r).norm() >= keep && moveFree(before, q, spec.radius)) stepped_[i] = back_on;
  }
}

int64_t WorldCore::periodUs() const { return ::lasonic::periodUs(cfg_.rate_hz); }

bool WorldCore::odometryDue(int64_t utime) const {
  if (!(cfg_.publish_hz > 0) || cfg_.publish_hz >= cfg_.rate_hz) return true;
  const int64_t every = ::lasonic::periodUs(cfg_.publish_hz);
  return (utime - kStartUtime) % every < periodUs();
}

bool WorldCore::finished(int64_t utime) const { return utime > end_utime_; }

sim_state_t WorldCore::stateAt(int64_t utime) {
  if (started_ && utime < last_utime_)
    throw std::invalid_argument("WorldCore::stateAt: time went backwards");
  const double t = static_cast<double>(utime - kStartUtime) * 1e-6;
  const PathFollower::State r = robot_.at(t);

  sim_state_t st;
  st.utime = utime;
  st.seq = seq_++;
  st.robot_pose = toPoseMsg(r.pose);
  st.v = r.v;
  st.omega = r.omega;
  const double dt = started_ ? static_cast<double>(utime - last_utime_) * 1e-6 : 0.0;
  for (size_t i = 0; i < movers_.size(); ++i) {
    if (started_ && scenario_.movers[i].avoid_robot) keepClear(i, t, dt, r.pose);
    const geom::Vec2 p = moverAt(i, t);
    mover_state_t m;
    m.id = static_cast<int32_t>(i);
    m.x = p.x();
    m.y = p.y();
    m.radius = scenario_.movers[i].radius;
    st.movers.push_back(m);
  }
  st.nmovers = static_cast<int32_t>(st.movers.size());

  // Odometry: the true motion increment in the robot frame, corrupted like wheel encoders do —
  // distance error and heading error growing with the square root of what was driven and
  // turned, plus the systematic errors (0 by default) growing with it. Three draws every step,
  // so the stream never depends on the path taken.
  const double n_trans = gauss_(rng_), n_rot = gauss_(rng_), n_drift = gauss_(rng_);
  if (!started_) {
    odom_.pose = toPoseMsg(r.pose);
  } else {
    const geom::Pose2 delta = last_true_.inverse().compose(r.pose);
    const double d = std::hypot(delta.x, delta.y);
    // What the encoders read before noise: the systematic errors. (A factor 1 is exact and the
    // curvature term is added only where set, so a log without them stays bit for bit what it was.)
    const double read_d = d * (1 + cfg_.scale_error);
    double read_dtheta = delta.theta * (1 + cfg_.turn_scale_error);
    if (cfg_.curvature_error != 0) read_dtheta += cfg_.curvature_error * d;
    const double measured_d = read_d + cfg_.trans_noise * std::sqrt(d) * n_trans;
    const double scale = d > 1e-12 ? measured_d / d : 0.0;
    const double measured_dtheta = read_dtheta + cfg_.rot_noise * std::sqrt(std::abs(delta.theta)) * n_rot +
                                   cfg_.drift_noise * std::sqrt(d) * n_drift;
    const geom::Pose2 odom = toPose(odom_.pose);
    odom_.pose = toPoseMsg(odom.compose({delta.x * scale, delta.y * scale, measured_dtheta}));
    if (dt > 0) {
      odom_.v = measured_d / dt;
      odom_.omega = measured_dtheta / dt;
    }
  }
  odom_.utime = utime;
  started_ = true;
  last_utime_ = utime;
  last_true_ = r.pose;
  return st;
}

odometry_t WorldCore::odometry() const { return odom_; }

}  // namespace lasonic::sim
