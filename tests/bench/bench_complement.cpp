// Complement extraction timings: Radar Map from one 720-reading scan (pose interpolated per
// reading), and one hypothetical scan of 24 sonars against 50 RM segments.
#include <benchmark/benchmark.h>

#include <cmath>

#include "complement/dark_continuation.hpp"
#include "complement/hypothetical_scan.hpp"
#include "complement/messages.hpp"
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

}  // namespace
