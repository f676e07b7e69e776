// Tactical level: line generation from a filled tactical AGM, and the navigator over a simulated
// run (one firing group through NavigatorStage, its 2 Hz publication included). Run:
// build/bench/bench_tactical.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "lcmio/eventlog.hpp"
#include "sim/drivers.hpp"
#include "stages/complement_stage.hpp"
#include "stages/navigator_stage.hpp"
#include "tactical/line_generation.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

// A tactical AGM (shipped parameters) after a few thousand firing groups of echoes on the walls of
// 3 m rooms tiling the window (2 cm noise), plus stray hits (crosstalk-like), every 8th.
AccumulativeGridMap filledAgm() {
  AccumulativeGridMap m(NavigatorConfig::tacticalAgmDefaults());
  m.centreOn({0.0, 0.0});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4.5, 4.5);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (int cycle = 0; cycle < 3000; ++cycle) {
    std::vector<Vec2> hits;
    for (int i = 0; i < 4; ++i) {
      Vec2 p(u(rng), u(rng));
      if ((cycle * 4 + i) % 8 != 0) {
        if (rng() % 2) p.x() = 3.0 * std::round(p.x() / 3.0);
        else p.y() = 3.0 * std::round(p.y() / 3.0);
      }
      hits.push_back(p + Vec2(noise(rng), noise(rng)));
    }
    m.update(hits);
  }
  return m;
}

void BM_LineGeneration(benchmark::State& state) {
  const AccumulativeGridMap agm = filledAgm();
  const LineGenerationParams p;
  size_t cells = 0, lines = 0;
  for (auto _ : state) {
    const auto c = candidateCells(agm, p.gp_threshold);
    const auto l = generateLines(c, {0.3, -0.2, 0.5}, agm.cellSize(), p);
    cells = c.size();
    lines = l.size();
    benchmark::DoNotOptimize(l.data());
  }
  state.counters["candidate_cells"] = static_cast<double>(cells);
  state.counters["lines"] = static_cast<double>(lines);
}
BENCHMARK(BM_LineGeneration)->Unit(benchmark::kMicrosecond);

// The navigator's input of a simulated fig7-like run (metal room, mesh fence, black box, a glass
// pane): ODOMETRY, LASER_SCAN (the laser glints), RADAR_MAP and SONAR_COMPLEMENT, as the drivers
// and the complement stage publish them.
struct Recorded {
  std::vector<std::pair<std::string, std::vector<uint8_t>>> events;
  int64_t groups = 0;
  void handleMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    events.emplace_back(channel, std::vector<uint8_t>(p, p + rbuf->data_size));
    if (channel == channels::SONAR_COMPLEMENT) ++groups;
  }
};

const Recorded& recordedRun() {
  static const Recorded rec = [] {
    const sim::Scenario sc = sim::parseScenario(Config::fromString(R"(
name: bench
duration_s: 30
seed: 3
obstacles:
  - {shape: polyline, material: metal, closed: true, points: [[0, 0], [8, 0], [8, 5], [0, 5]]}
  - {shape: segment, material: mesh, from: [2.0, 2.5], to: [3.5, 2.5]}
  - {shape: box, material: black_cardboard, center: [4.0, 0.35], size: [0.5, 0.3]}
  - {shape: segment, material: glass, from: [4.5, 2.5], to: [6.5, 2.5]}
robot: {radius: 0.35, path: [[1.0, 1.2], [7.0, 1.2], [7.0, 3.8], [1.0, 3.8]], speed: 0.3}
)"));
    auto lcm = std::make_shared<lcm::LCM>("memq://");
    Node node("c", lcm, Node::Options{false, false});
    ComplementStage stage(node, ComplementConfig{});
    Recorded r;
    lcm->subscribe(channels::RADAR_MAP, &Recorded::handleMessage, &r);
    lcm->subscribe(channels::SONAR_COMPLEMENT, &Recorded::handleMessage, &r);
    lcm->subscribe(channels::ODOMETRY, &Recorded::handleMessage, &r);
    lcm->subscribe(channels::LASER_SCAN, &Recorded::handleMessage, &r);
    sim::WorldCore world(sc, sim::OdometryConfig{});
    sim::LaserDriverCore laser(sc, sim::LaserConfig{}, sc.seed);
    sim::SonarDriverCore sonar(sc, sim::sonarConfig(Config{}), sc.seed);
    auto publish = [&](const char* ch, auto& msg) {
      std::vector<uint8_t> data = encodeMsg(msg);
      lcm->publish(ch, data.data(), static_cast<unsigned>(data.size()));
      while (lcm->handleTimeout(0) > 0) {
      }
    };
    for (int64_t t = world.startUtime(); !world.finished(t); t += world.periodUs()) {
      sim_state_t st = world.stateAt(t);
      odometry_t od = world.odometry();
      publish(channels::ODOMETRY, od);
      for (auto& o : laser.onSimState(st)) publish(channels::LASER_SCAN, o.scan);
      for (auto& o : sonar.onSimState(st)) publish(channels::SONAR_RING, o.ring);
    }
    return r;
  }();
  return rec;
}

// Per firing group: decode, next-scan verification, echo placement, AGM cycle; plus the share of
// the 2 Hz publication (AGM_TACTICAL export, line generation, AGM_LINES, CURRENT_SENSOR_MAP) and
// of the ODOMETRY / RADAR_MAP / LASER_SCAN handling (the scan's cut, scan matching and the laser
// glints) that falls on it.
void BM_NavigatorPerFiringGroup(benchmark::State& state) {
  const Recorded& rec = recordedRun();
  for (auto _ : state) {
    state.PauseTiming();
    auto lcm = std::make_shared<lcm::LCM>("memq://");
    auto node = std::make_unique<Node>("n", lcm, Node::Options{false, false});
    NavigatorConfig cfg;
    if (state.range(0) == 3) cfg.pass_through.core = 0;  // shipped but no pass-through
    if (state.range(0) == 4) cfg.pass_through.beyond_limit = cfg.pass_through.silence = false;  // echoes alone
    if (state.range(0) == 2 || state.range(0) == 0) cfg.scan_matching.enabled = false;
    if (state.range(0) == 0) cfg.laser_glints.max_incidence = 0;  // neither: LASER_SCAN not taken
    auto nav = std::make_unique<NavigatorStage>(*node, cfg);
    state.ResumeTiming();
    for (const auto& [ch, data] : rec.events) {
      lcm->publish(ch, data.data(), static_cast<unsigned>(data.size()));
      while (lcm->handleTimeout(0) > 0) {
      }
    }
    state.PauseTiming();
    nav.reset();
    node.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * rec.groups);
  state.counters["us_per_group"] = benchmark::Counter(static_cast<double>(state.iterations() * rec.groups),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["us_per_group"].flags = benchmark::Counter::kIsRate | benchmark::Counter::kInvert;
}
// Arg 1: the shipped configuration; 4: pass-through by echoes alone (not by silence); 3: without
// pass-through; 2: without scan matching; 0: without it and the laser glints.
BENCHMARK(BM_NavigatorPerFiringGroup)->Arg(1)->Arg(4)->Arg(3)->Arg(2)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace
