// Operational level: one AGM update cycle (accumulate + revise + propagate), one re-centring
// step, one Sector Map update. Run: build/bench/bench_operational.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "operational/agm.hpp"
#include "operational/evidence_placement.hpp"
#include "operational/remembered_on_lines.hpp"
#include "operational/sector_map.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

// Points on the walls of rooms tiling the window (3 m x 3 m rooms), as sonar echoes would land
// on them, with 2 cm of noise; every 8th hit is a stray (crosstalk-like) anywhere in the window.
std::vector<std::vector<Vec2>> firingGroups(double half_width, int groups, int hits_per_group, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half_width, half_width);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<std::vector<Vec2>> out(static_cast<size_t>(groups));
  int n = 0;
  for (auto& g : out) {
    for (int i = 0; i < hits_per_group; ++i, ++n) {
      Vec2 p(u(rng), u(rng));
      if (n % 8 != 0) {  // snap to the nearest room wall
        if (rng() % 2) p.x() = 3.0 * std::round(p.x() / 3.0);
        else p.y() = 3.0 * std::round(p.y() / 3.0);
      }
      g.push_back(p + Vec2(noise(rng), noise(rng)));
    }
  }
  return out;
}

int occupied(const AccumulativeGridMap& m) {
  std::vector<int16_t> g, h;
  std::vector<int32_t> gp;
  m.exportGrids(g, h, gp);
  int n = 0;
  for (auto v : g) n += v > 0;
  return n;
}

// Args: N, h_max, hits per cycle. Operational: 4 hits (one firing group), h_max 12.
// Tactical-like: h_max 1000 keeps thousands of cells occupied.
void BM_AgmCycle(benchmark::State& state) {
  AgmParams p;
  p.size = static_cast<int>(state.range(0));
  p.h_max = static_cast<int>(state.range(1));
  const int hits = static_cast<int>(state.range(2));
  AccumulativeGridMap m(p);
  m.centreOn({0.0, 0.0});
  const double half = 0.5 * p.size * p.cell_size;
  const auto groups = firingGroups(half, 4096, hits, 7);
  for (int i = 0; i < 3 * p.h_max + 100; ++i) m.update(groups[static_cast<size_t>(i) % groups.size()]);  // steady state
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.update(groups[i]));
    if (++i == groups.size()) i = 0;
  }
  state.counters["occupied_cells"] = occupied(m);
}
BENCHMARK(BM_AgmCycle)
    ->ArgNames({"N", "h_max", "hits"})
    ->Args({100, 12, 4})
    ->Args({100, 1000, 4})
    ->Args({1000, 12, 4})
    ->Args({1000, 1000, 24})
    ->Unit(benchmark::kNanosecond);

// Re-centring by one cell (the robot crossing a cell boundary): only one column leaves.
void BM_AgmRecentreOneCell(benchmark::State& state) {
  AgmParams p;
  p.size = static_cast<int>(state.range(0));
  p.h_max = 1000;
  p.recenter_max_cells = 0;
  p.recenter_min_cells = 0;
  AccumulativeGridMap m(p);
  m.centreOn({0.0, 0.0});
  const auto groups = firingGroups(0.5 * p.size * p.cell_size, 2000, 24, 3);
  for (const auto& g : groups) m.update(g);
  double x = 0.05;
  for (auto _ : state) {
    x += p.cell_size;
    benchmark::DoNotOptimize(m.follow({x, 0.05}, 0.0));
  }
}
BENCHMARK(BM_AgmRecentreOneCell)->ArgName("N")->Arg(100)->Arg(1000)->Unit(benchmark::kNanosecond);

// One Sector Map: 720 laser points and the operational AGM in a 6 m x 4 m room.
// Arg 0: the paper's rules; 1: as shipped (laser_explains_radius 0.10, copy unless confirmed).
// Arg new_scan 1: a new scan before every map (the explained cells are rebuilt: the cost a
// map pays once per scan, at 5 Hz); 0: maps between scans (~7 of every 8).
SectorMapParams benchParams(bool shipped) {
  SectorMapParams p;
  if (shipped) {
    p.laser_explains_radius = 0.10;
    p.copy_rule = CopyRule::UnlessLaserConfirmed;
    p.sonar_cell_point = CellPoint::Centre;
  }
  return p;
}
void BM_SectorMapUpdate(benchmark::State& state) {
  AccumulativeGridMap agm{AgmParams{}};
  agm.centreOn({0.0, 0.0});
  for (const auto& g : firingGroups(5.0, 200, 4, 11)) agm.update(g);
  std::vector<Vec2> points;
  for (int i = 0; i < 720; ++i) {
    const double a = i * 2 * geom::kPi / 720;
    const Vec2 d = geom::unitVector(a);
    const double r = std::min(3.0 / std::max(std::abs(d.x()), 1e-9), 2.0 / std::max(std::abs(d.y()), 1e-9));
    points.push_back(d * r);
  }
  SectorMap s{benchParams(state.range(0) != 0)};
  const bool new_scan = state.range(1) != 0;
  s.setLaserPoints(0, points);
  s.setSonarTime(0);
  int64_t t = 0;
  for (auto _ : state) {
    t += 1000;
    if (new_scan) s.setLaserPoints(t, points);
    benchmark::DoNotOptimize(s.update(t, {0.2, -0.1, 0.3}, agm).distance.data());
  }
}
BENCHMARK(BM_SectorMapUpdate)
    ->ArgNames({"shipped", "new_scan"})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kNanosecond);

// Evidence placement of one echo at 1.5 m on the paper's +-15 deg arc (the widest) in an AGM
// holding a room's worth of weight.
void BM_EvidenceBearing(benchmark::State& state) {
  AccumulativeGridMap agm{AgmParams{}};
  agm.centreOn({0.0, 0.0});
  for (const auto& g : firingGroups(5.0, 200, 4, 11)) agm.update(g);
  const BearingEstimate est{0.7, geom::deg2rad(15.0)};
  for (auto _ : state) benchmark::DoNotOptimize(evidenceBearing(agm, {0.3, 0.2}, 1.5, est));
}
BENCHMARK(BM_EvidenceBearing)->Unit(benchmark::kNanosecond);

// The pilot's remembered cells moved onto the navigator's lines, once per AGM_TACTICAL (2 Hz):
// the occupied cells of a 10 m window of 3 m rooms (two cells deep along every wall, as a
// tactical band) and one line per wall piece of the window (24, each 3 m).
void BM_MoveOntoLines(benchmark::State& state) {
  std::vector<Vec2> cells;
  std::vector<geom::Segment> lines;
  for (int w = -1; w <= 2; ++w) {
    const double c = 3.0 * w - 1.5;  // walls at -4.5, -1.5, 1.5, 4.5
    for (int piece = 0; piece < 3; ++piece) {
      const double a = -4.5 + 3.0 * piece, b = a + 3.0;
      lines.push_back({{c, a}, {c, b}});
      lines.push_back({{a, c}, {b, c}});
      for (double t = a; t < b; t += 0.1)
        for (double d : {-0.05, 0.05}) {
          cells.emplace_back(c + d, t);
          cells.emplace_back(t, c + d);
        }
    }
  }
  for (auto _ : state) {
    std::vector<Vec2> p = cells;
    moveOntoLines(p, lines, 0.15);
    benchmark::DoNotOptimize(p.data());
  }
  state.counters["cells"] = static_cast<double>(cells.size());
  state.counters["lines"] = static_cast<double>(lines.size());
}
BENCHMARK(BM_MoveOntoLines)->Unit(benchmark::kMicrosecond);

// The lines remembered between their cells, after BM_MoveOntoLines' move: the same window and
// lines, but a band cell only every 0.3 m along each wall (a surface heard at a few places), so
// every line has gaps of 0.2 m to fill at the shipped 0.05 m.
void BM_FillBetweenOnLines(benchmark::State& state) {
  std::vector<Vec2> cells;
  std::vector<geom::Segment> lines;
  for (int w = -1; w <= 2; ++w) {
    const double c = 3.0 * w - 1.5;
    for (int piece = 0; piece < 3; ++piece) {
      const double a = -4.5 + 3.0 * piece, b = a + 3.0;
      lines.push_back({{c, a}, {c, b}});
      lines.push_back({{a, c}, {b, c}});
      for (double t = a + 0.05; t < b; t += 0.3) {
        cells.emplace_back(c + 0.05, t);
        cells.emplace_back(t, c - 0.05);
      }
    }
  }
  const std::vector<int> taken_by = moveOntoLines(cells, lines, 0.15);
  size_t filled = 0;
  for (auto _ : state) {
    const std::vector<Vec2> fill = fillBetweenOnLines(cells, taken_by, lines, 0.05, 0.7);
    filled = fill.size();
    benchmark::DoNotOptimize(fill.data());
  }
  state.counters["cells"] = static_cast<double>(cells.size());
  state.counters["filled"] = static_cast<double>(filled);
}
BENCHMARK(BM_FillBetweenOnLines)->Unit(benchmark::kMicrosecond);

}  // namespace
