#pragma once
// Hand-built worlds, laser scans and sonar readings for the complement tests, the integration
// fixture publisher and the benchmarks. Noise-free: every expected value can be worked out by hand.
#include <cmath>
#include <functional>
#include <optional>
#include <vector>

#include <lasonic/laser_scan_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>

#include "core/geometry.hpp"

namespace lasonic::fixture {

using geom::Circle;
using geom::Pose2;
using geom::Segment;
using geom::Vec2;

struct World {
  std::vector<Segment> laser_visible;            // walls: both sensors see them
  std::vector<Segment> laser_invisible;          // glass: only the sonar sees it
  std::vector<Circle> laser_invisible_circles;   // e.g. a black round obstacle
};

// Robot pose over time (true = odometry in these tests).
using Trajectory = std::function<Pose2(int64_t utime)>;

inline Trajectory still(const Pose2& p) {
  return [p](int64_t) { return p; };
}
// Constant velocity in the global frame and constant turn rate (exact under linear interpolation).
inline Trajectory moving(const Pose2& p0, int64_t t0, double vx, double vy, double omega) {
  return [=](int64_t t) {
    const double s = static_cast<double>(t - t0) * 1e-6;
    return Pose2{p0.x + vx * s, p0.y + vy * s, geom::normalizeAngle(p0.theta + omega * s)};
  };
}

// The paper's Fig. 4: a closed room with a closed glass door and one round obstacle that the
// laser cannot see. Room [0,4]x[0,3.6]; door in the top wall, x in [1.4,2.6].
inline World fig4Room() {
  World w;
  w.laser_visible = {{{0, 0}, {4, 0}},     {{4, 0}, {4, 3.6}}, {{4, 3.6}, {2.6, 3.6}},
                     {{1.4, 3.6}, {0, 3.6}}, {{0, 3.6}, {0, 0}}};
  w.laser_invisible = {{{2.6, 3.6}, {1.4, 3.6}}};
  w.laser_invisible_circles = {{{3.0, 0.9}, 0.2}};
  return w;
}
inline Pose2 fig4RobotPose() { return {2.0, 1.8, 0.0}; }

// A 360 deg scan with 720 readings spread evenly over duration_us; each ray is cast from the
// robot pose at its own time (the laser sits at the robot centre). Transparent things are missed.
inline laser_scan_t simulateScan(const World& w, const Trajectory& traj, int64_t t0, int64_t duration_us,
                                 int n = 720, double angle_min = -geom::kPi, double range_max = 15.0) {
  laser_scan_t s{};
  s.utime = t0;
  s.mount = {};
  s.angle_min = angle_min;
  s.angle_increment = 2.0 * geom::kPi / n;
  s.range_min = 0.05f;
  s.range_max = static_cast<float>(range_max);
  for (int i = 0; i < n; ++i) {
    const auto off = static_cast<int32_t>(duration_us * i / n);
    const Pose2 p = traj(t0 + off);
    const geom::Ray ray{p.position(), geom::unitVector(p.theta + angle_min + i * s.angle_increment)};
    std::optional<double> best;
    for (const Segment& seg : w.laser_visible)
      if (auto d = geom::intersect(ray, seg); d && (!best || *d < *best)) best = d;
    const bool hit = best && *best <= range_max;
    const int8_t flag = hit ? laser_scan_t::FLAG_OK : laser_scan_t::FLAG_NO_RETURN;
    s.ranges.push_back(hit ? static_cast<float>(*best) : 0.f);
    s.flags.push_back(flag);
    s.offset_us.push_back(off);
  }
  s.nranges = n;
  return s;
}

// What an ideal sonar would read on the TRUE world (every surface echoes): the nearest point of
// any surface inside the beam, or nullopt (no echo).
inline std::optional<double> trueSonar(const World& w, const Pose2& sensor, double beam_width = geom::deg2rad(30),
                                       double range_max = 3.0) {
  const geom::Sector sec{sensor.position(), sensor.theta, beam_width, range_max};
  std::optional<double> best;
  auto take = [&](std::optional<double> d) {
    if (d && (!best || *d < *best)) best = d;
  };
  for (const Segment& s : w.laser_visible) take(geom::nearestInSector(sec, s));
  for (const Segment& s : w.laser_invisible) take(geom::nearestInSector(sec, s));
  for (const Circle& c : w.laser_invisible_circles) take(geom::nearestInSector(sec, c));
  return best;
}

// MOBOT-IV-like ring: n sensors 360/n deg apart at `radius` from the centre, facing outwards.
inline std::vector<Pose2> ringMounts(int n = 24, double radius = 0.3) {
  std::vector<Pose2> m;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * geom::kPi * k / n;
    m.push_back({radius * std::cos(a), radius * std::sin(a), geom::normalizeAngle(a)});
  }
  return m;
}

// One firing group holding the given sensors; a negative range means no echo (NaN stays an echo:
// bad input for the tests).
inline sonar_ring_t sonarGroup(int64_t utime, int group, const std::vector<int>& ids,
                               const std::vector<double>& ranges, int num_sensors = 24) {
  const auto mounts = ringMounts(num_sensors);
  sonar_ring_t g{};
  g.utime = utime;
  g.seq = group;
  g.group = static_cast<int16_t>(group);
  g.num_sensors = static_cast<int16_t>(num_sensors);
  g.range_max = 3.0f;
  for (size_t i = 0; i < ids.size(); ++i) {
    g.sensor_id.push_back(static_cast<int16_t>(ids[i]));
    const bool echo = !(ranges[i] < 0);
    g.range.push_back(echo ? static_cast<float>(ranges[i]) : 0.f);
    g.no_echo.push_back(echo ? 0 : 1);
    const Pose2& m = mounts[static_cast<size_t>(ids[i]) % mounts.size()];
    g.mount.push_back({m.x, m.y, m.theta});
    g.beam_width.push_back(static_cast<float>(geom::deg2rad(30)));
  }
  g.nreadings = static_cast<int32_t>(ids.size());
  return g;
}

// The whole ring firing at once with the true ideal readings of a world (-1: no echo).
inline std::vector<double> trueRing(const World& w, const Pose2& robot, int num_sensors = 24) {
  std::vector<double> r;
  for (const Pose2& m : ringMounts(num_sensors)) r.push_back(trueSonar(w, robot.compose(m)).value_or(-1.0));
  return r;
}

inline odometry_t odometryAt(const Trajectory& traj, int64_t t) {
  odometry_t o{};
  o.utime = t;
  const Pose2 p = traj(t);
  o.pose = {p.x, p.y, p.theta};
  return o;
}

}  // namespace lasonic::fixture
