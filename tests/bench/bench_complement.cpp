// Complement extraction timings: Radar Map from one 720-reading scan (pose interpolated per
// reading), one hypothetical scan of 24 sonars against 50 RM segments, and the pole tracker's
// update for one scan.
#include <benchmark/benchmark.h>

#include <cmath>

#include "complement/dark_continuation.hpp"
#include "complement/hypothetical_scan.hpp"
#include "complement/messages.hpp"
#include "complement/pole_tracker.hpp"
#include "complement/radar_map.hpp"
#include "complement_fixture.hpp"
#include "core/pose_history.hpp"

using namespace lasonic;
using namespace lasonic::complement;

namespace {

// An office-like room: outer walls with a few doorways and boxes inside (28 visible walls).
fixture::World office() {
  fixture::World w;
  auto wall = [&](double x0, double y0, double x1, double y1) { w.laser_visible.push_back({{x0, y0}, {x1, y1}}); };
  wall(0, 0, 8, 0);
  wall(8, 0, 8, 6);
  wall(8, 6, 0, 6);
  wall(0, 6, 0, 0);
  for (int i = 0; i < 6; ++i) {  // boxes
    const double cx = 1.0 + 1.2 * i, cy = (i % 2) ? 1.2 : 4.8, h = 0.25;
    wall(cx - h, cy - h, cx + h, cy - h);
    wall(cx + h, cy - h, cx + h, cy + h);
    wall(cx + h, cy + h, cx - h, cy + h);
    wall(cx - h, cy + h, cx - h, cy - h);
  }
  return w;
}

void BM_RadarMap720(benchmark::State& state) {
  const auto traj = fixture::moving({4.0, 3.0, 0.0}, 0, 0.5, 0.1, 0.3);
  std::vector<InputProblem> problems;
  const LaserScan scan = *laserScanFromMessage(fixture::simulateScan(office(), traj, 0, 100'000), problems);
  PoseHistory odo;
  for (int64_t t = -100'000; t <= 300'000; t += 20'000) odo.add(t, traj(t));
  size_t segments = 0;
  for (auto _ : state) {
    const RadarMap rm = extractRadarMap(scan, odo, {});  // as the complement stage calls it
    segments = rm.segments.size();
    benchmark::DoNotOptimize(segments);
  }
  state.counters["segments"] = static_cast<double>(segments);
}
BENCHMARK(BM_RadarMap720)->Unit(benchmark::kMicrosecond);

// The pilot's dark continuation on the same scan with twelve dark stretches: every 30 deg the
// readings of a 5 deg window come back empty (a dark face between lit ones), so 24 runs are
// continued at the shipped 0.10 m.
void BM_DarkContinuation720(benchmark::State& state) {
  const auto traj = fixture::moving({4.0, 3.0, 0.0}, 0, 0.5, 0.1, 0.3);
  std::vector<InputProblem> problems;
  LaserScan scan = *laserScanFromMessage(fixture::simulateScan(office(), traj, 0, 100'000), problems);
  std::vector<uint8_t> no_return(scan.readings.size(), 0);
  for (size_t i = 0; i < scan.readings.size(); ++i)
    if (i % 60 < 10) {
      scan.readings[i].valid = false;
      no_return[i] = 1;
    }
  PoseHistory odo;
  for (int64_t t = -100'000; t <= 300'000; t += 20'000) odo.add(t, traj(t));
  const std::vector<ScanPoint> placed = placeReadings(scan, odo);
  const PoseLookup pose_at = [&odo](int64_t t) { return odo.at(t); };
  DarkContinuationConfig cfg;
  cfg.length = 0.10;
  std::vector<geom::Vec2> out;
  for (auto _ : state) {
    out.clear();
    darkContinuation(scan, placed, no_return, pose_at, RadarMapConfig{}, cfg, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["points"] = static_cast<double>(out.size());
}
BENCHMARK(BM_DarkContinuation720)->Unit(benchmark::kMicrosecond);

void BM_HypotheticalScan24x50(benchmark::State& state) {
  // 50 segments around the robot: a ring of short walls at 0.8..2.5 m.
  std::vector<RmSegment> rm;
  for (int i = 0; i < 50; ++i) {
    const double a = 2.0 * geom::kPi * i / 50, r = 0.8 + 0.034 * i;
    const geom::Vec2 c(r * std::cos(a), r * std::sin(a)), t(-std::sin(a), std::cos(a));
    rm.push_back({{c - 0.15 * t, c + 0.15 * t}, 20, 0.0});
  }
  const auto mounts = fixture::ringMounts(24);
  const IdealSonarModel model;
  for (auto _ : state) benchmark::DoNotOptimize(hypotheticalScan(mounts, rm, model));
}
BENCHMARK(BM_HypotheticalScan24x50)->Unit(benchmark::kMicrosecond);

// The pole tracker's update for one scan (README "Method", step 3, Poles), in its steady state:
// N posts in a 8 x 6 m hall (one-point clusters, the laser's 1 cm noise), the robot driving
// past at 0.4 m/s with a 5 Hz laser, so the 2 s memory holds 10 scans and every post is a pole
// found. 16 is a cluttered room; 4096 one-point clusters per scan are rain on the window or a
// driver's garbage, which must stay cheap (each lookup is a band of 2 * match around x).
void BM_PoleTracker(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  constexpr int kScans = 64;
  constexpr int64_t kPeriod = 200'000;  // [us] 5 Hz
  std::vector<geom::Vec2> posts;
  for (int i = 0; i < n; ++i)  // a low-discrepancy fill of the hall
    posts.emplace_back(8.0 * std::fmod(0.5 + 0.618034 * i, 1.0), 6.0 * std::fmod(0.5 + 0.754878 * i, 1.0));
  std::vector<geom::Vec2> robot;
  std::vector<std::vector<std::vector<geom::Vec2>>> scans;
  for (int k = 0; k < kScans; ++k) {
    robot.emplace_back(1.0 + 0.08 * k, 3.0);  // 0.4 m/s x 0.2 s
    std::vector<std::vector<geom::Vec2>> cands;
    for (int i = 0; i < n; ++i) {
      const double e = 0.01 * std::sin(12.9898 * (i + 1) + 78.233 * (k + 1));  // deterministic 1 cm noise
      cands.push_back({posts[static_cast<size_t>(i)] + geom::Vec2(e, -e)});
    }
    scans.push_back(std::move(cands));
  }
  PoleTracker tracker{PoleConfig{}};
  int64_t t = 0;
  int k = 0;
  size_t poles = 0;
  for (int warm = 0; warm < kScans; ++warm, t += kPeriod, k = (k + 1) % kScans)
    tracker.update(t, robot[static_cast<size_t>(k)], scans[static_cast<size_t>(k)]);
  for (auto _ : state) {
    const auto out = tracker.update(t, robot[static_cast<size_t>(k)], scans[static_cast<size_t>(k)]);
    poles = out.size();
    benchmark::DoNotOptimize(poles);
    t += kPeriod;
    k = (k + 1) % kScans;
  }
  state.counters["poles"] = static_cast<double>(poles);
}
BENCHMARK(BM_PoleTracker)->Arg(16)->Arg(256)->Arg(4096)->Unit(benchmark::kMicrosecond);

}  // namespace
