// AccumulativeGridMap against hand-computed grids and against a naive dense reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

#include "operational/agm.hpp"
#include "operational/sound_passed.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

// 10 x 10 cells of 1 m; window cell (ix, iy) = global cell (ix - 5, iy - 5) after centreOn(0.5, 0.5).
AgmParams small(int t = 1, int g_threshold = 2, int h_max = 3) {
  AgmParams p;
  p.size = 10;
  p.cell_size = 1.0;
  p.t = t;
  p.g_threshold = g_threshold;
  p.h_max = h_max;
  p.g_max = 5;
  p.recenter_max_cells = 2;
  p.recenter_min_cells = 0;
  p.recenter_lookahead_s = 1.0;
  return p;
}
// Centre of window cell (ix, iy) for a window centred on global cell (0, 0).
Vec2 at(int ix, int iy) { return {ix - 5 + 0.5, iy - 5 + 0.5}; }

}  // namespace

TEST(Agm, AccumulationIncrementsOneCellAndResetsH) {
  AccumulativeGridMap m(small());
  m.centreOn({0.5, 0.5});
  EXPECT_EQ(m.originX(), -5);
  EXPECT_EQ(m.update({at(5, 5)}), 1);
  EXPECT_EQ(m.g(5, 5), 1);
  EXPECT_EQ(m.h(5, 5), 0);
  EXPECT_EQ(m.update({}), 0);
  EXPECT_EQ(m.h(5, 5), 1);
  m.update({at(5, 5)});
  EXPECT_EQ(m.g(5, 5), 2);
  EXPECT_EQ(m.h(5, 5), 0);
  // Every other cell is untouched.
  for (int iy = 0; iy < 10; ++iy)
    for (int ix = 0; ix < 10; ++ix)
      if (ix != 5 || iy != 5) {
        EXPECT_EQ(m.g(ix, iy), 0) << ix << "," << iy;
      }
  // Hits outside the window are ignored.
  EXPECT_EQ(m.update({{100.0, 0.0}, {0.5, -5.5}}), 0);
}

TEST(Agm, HugeFiniteHitsAreOutsideAndLeaveTheGridAlone) {
  // 1e30 m is 1e30 cells: beyond int64, so the cell index must not be a plain conversion.
  AccumulativeGridMap m(small());
  m.centreOn({0.5, 0.5});
  EXPECT_EQ(m.update({at(5, 5)}), 1);
  EXPECT_EQ(m.update({{1e30, 0.5}, {0.5, -1e30}, {1e30, 1e30}, {-1e30, -1e30}, at(5, 5)}), 1);
  int ix = -1, iy = -1;
  EXPECT_FALSE(m.cellAt({1e30, 0.5}, ix, iy));
  EXPECT_FALSE(m.cellAt({-1e30, -1e30}, ix, iy));
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      EXPECT_EQ(m.g(x, y), x == 5 && y == 5 ? 2 : 0) << x << "," << y;
    }
  EXPECT_EQ(m.h(5, 5), 0);
  // And the window still follows the robot normally afterwards.
  m.centreOn({3.5, 0.5});
  EXPECT_EQ(m.originX(), -2);
}

TEST(Agm, WeightSaturatesAtCapButHitStillResetsH) {
  AccumulativeGridMap m(small());
  m.centreOn({0.5, 0.5});
  for (int i = 0; i < 8; ++i) m.update({at(5, 5)});
  EXPECT_EQ(m.g(5, 5), 5);  // g_max
  EXPECT_EQ(m.gu(5, 5), 5);
  m.update({});
  m.update({at(5, 5)});
  EXPECT_EQ(m.g(5, 5), 5);
  EXPECT_EQ(m.h(5, 5), 0);
}

TEST(Agm, RevisionAfterHmax) {
  AccumulativeGridMap m(small(1, 1, /*h_max=*/3));
  m.centreOn({0.5, 0.5});
  m.update({at(5, 5), at(5, 5), at(6, 5)});  // cycle 1: G(5,5) = 2, G(6,5) = 1
  m.update({at(6, 5)});                       // cycle 2: (6,5) hit again
  for (int h = 2; h <= 3; ++h) {              // cycles 3, 4: H(5,5) = 2, 3 <= Hmax: kept
    m.update({});
    EXPECT_EQ(m.h(5, 5), h);
    EXPECT_EQ(m.g(5, 5), 2);
  }
  m.update({});  // cycle 5: H(5,5) = 4 > 3 -> forgotten; H(6,5) = 3 kept
  EXPECT_EQ(m.g(5, 5), 0);
  EXPECT_EQ(m.h(5, 5), 0);
  EXPECT_EQ(m.gp(5, 5), 0);
  EXPECT_EQ(m.g(6, 5), 2);
  EXPECT_EQ(m.h(6, 5), 3);
  EXPECT_EQ(m.gu(6, 5), 2);  // the revised neighbour no longer counts
  EXPECT_EQ(m.gp(6, 5), 2);
  m.update({});
  EXPECT_EQ(m.g(6, 5), 0);
  EXPECT_EQ(m.gu(5, 5), 0);
}

TEST(Agm, RehitBeforeHmaxKeepsTheCell) {
  AccumulativeGridMap m(small(1, 1, 2));
  m.centreOn({0.5, 0.5});
  for (int i = 0; i < 20; ++i) m.update(i % 3 == 0 ? std::vector<Vec2>{at(2, 2)} : std::vector<Vec2>{});
  EXPECT_GT(m.g(2, 2), 0);  // hit every third cycle: H never exceeds 2
}

TEST(Agm, PropagationHandComputed) {
  // G:   (2,3)=1
  //      (2,2)=2 (3,2)=1          (5,5)=1 isolated
  AccumulativeGridMap m(small(/*t=*/1, /*G_T=*/3, /*h_max=*/50));
  m.centreOn({0.5, 0.5});
  m.update({at(2, 2), at(2, 2), at(3, 2), at(2, 3), at(5, 5)});
  EXPECT_EQ(m.gu(2, 2), 4);
  EXPECT_EQ(m.gp(2, 2), 4);
  EXPECT_EQ(m.gp(3, 2), 4);
  EXPECT_EQ(m.gp(2, 3), 4);
  EXPECT_EQ(m.gu(3, 3), 4);  // empty cell: Gu counts, Gp does not
  EXPECT_EQ(m.gp(3, 3), 0);
  EXPECT_EQ(m.gu(4, 3), 1);
  EXPECT_EQ(m.gu(5, 5), 1);
  EXPECT_EQ(m.gp(5, 5), 0);  // weak neighbourhood: suppressed
  // A hit next to the isolated cell lifts both over G_T.
  m.update({at(6, 6), at(6, 6)});
  EXPECT_EQ(m.gp(5, 5), 3);
  EXPECT_EQ(m.gp(6, 6), 3);
  EXPECT_EQ(m.gp(4, 4), 0);
}

TEST(Agm, ANewGThresholdAppliesToEveryCellAtOnce) {
  AccumulativeGridMap m(small(/*t=*/1, /*G_T=*/5, /*h_max=*/50));
  m.centreOn({0.5, 0.5});
  m.update({at(2, 2), at(2, 2), at(3, 2), at(2, 3), at(5, 5)});
  EXPECT_EQ(m.gp(2, 2), 0);  // Gu 4 < 5
  m.setGThreshold(3);
  EXPECT_EQ(m.params().g_threshold, 3);
  EXPECT_EQ(m.gp(2, 2), 4);  // as if G_T had been 3 all along (PropagationHandComputed)
  EXPECT_EQ(m.gp(3, 2), 4);
  EXPECT_EQ(m.gp(3, 3), 0);  // no weight of its own
  EXPECT_EQ(m.gp(5, 5), 0);
  m.update({at(6, 6), at(6, 6)});  // and on from there
  EXPECT_EQ(m.gp(5, 5), 3);
  m.setGThreshold(0);  // at least 1
  EXPECT_EQ(m.params().g_threshold, 1);
  EXPECT_EQ(m.gp(5, 5), 3);
  m.setGThreshold(4);
  EXPECT_EQ(m.gp(5, 5), 0);
  EXPECT_EQ(m.gp(2, 2), 4);
}

TEST(Agm, TheWalkerRuleGivesEachRingItsGThreshold) {
  // 0.3 m (3 x 3 cells of 0.1 m), people walking 0.8 m/s or faster: 0.375 s in the neighbourhood,
  // heard by the two transducers whose beams overlap there (MOBOT-IV, a Pioneer).
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 6 * 0.0305, 2), 5);   // MOBOT-IV: 6 groups of 30 ms, 4.1 echoes
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 8 * 0.0405, 2), 3);   // a Pioneer: 8 groups of 40 ms, 2.3 echoes
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 12 * 0.0305, 2), 3);  // 12 groups of 30 ms: 2.05 echoes
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 0.7, 2), 2);          // 1.07 echoes: G_T 2
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 10.0, 2), 1);
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 1e-12, 2), 1000001);  // capped
  // Beams that do not overlap (8 of 30 deg, 45 deg apart, 4 groups of 30 ms): one transducer,
  // 3.1 echoes, G_T 4 (the two-transducer count would give 7, above what a static surface
  // beside the path gives that one transducer); three overlapping beams: 6.1, G_T 7.
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 4 * 0.0305, 1), 4);
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 4 * 0.0305, 2), 7);
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 6 * 0.0305, 3), 7);
  for (const double bad : {0.0, -1.0, std::nan(""), static_cast<double>(INFINITY)}) {
    EXPECT_EQ(walkerGThreshold(bad, 0.8, 0.18, 2), -1);
    EXPECT_EQ(walkerGThreshold(0.3, bad, 0.18, 2), -1);
    EXPECT_EQ(walkerGThreshold(0.3, 0.8, bad, 2), -1);
  }
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 0.18, 0), -1);
  EXPECT_EQ(walkerGThreshold(0.3, 0.8, 0.18, -2), -1);
}

TEST(Agm, PropagationWiderNeighbourhood) {
  AccumulativeGridMap m(small(/*t=*/2, /*G_T=*/2, 50));
  m.centreOn({0.5, 0.5});
  m.update({at(2, 2), at(4, 4), at(5, 5)});
  EXPECT_EQ(m.gp(2, 2), 2);  // (4,4) is within 2 cells
  EXPECT_EQ(m.gp(4, 4), 3);
  EXPECT_EQ(m.gp(5, 5), 2);  // (2,2) is 3 cells away
}

TEST(Agm, NeighbourhoodDoesNotWrapAroundTheBuffer) {
  // Window columns 0 and 9 share neighbouring storage slots; they are 9 cells apart in the world.
  AccumulativeGridMap m(small(1, 2, 50));
  m.centreOn({0.5, 0.5});
  m.update({at(0, 5), at(9, 5), at(4, 0), at(4, 9)});
  EXPECT_EQ(m.gu(0, 5), 1);
  EXPECT_EQ(m.gu(9, 5), 1);
  EXPECT_EQ(m.gu(4, 0), 1);
  EXPECT_EQ(m.gu(4, 9), 1);
}

TEST(Agm, RecenterLimitShrinksWithSpeed) {
  AgmParams p;  // cell 0.1 m, k 5..1, lookahead 1 s
  AccumulativeGridMap m(p);
  EXPECT_EQ(m.recenterLimit(0.0), 5);
  EXPECT_EQ(m.recenterLimit(0.25), 3);
  EXPECT_EQ(m.recenterLimit(-0.25), 3);
  EXPECT_EQ(m.recenterLimit(0.5), 1);
  EXPECT_EQ(m.recenterLimit(3.0), 1);
}

TEST(Agm, FollowMovesInWholeCellsAndKeepsGlobalCoordinates) {
  AccumulativeGridMap m(small(1, 1, 1000));
  m.centreOn({0.5, 0.5});
  m.update({{2.5, 1.5}});  // global cell (2, 1) = window (7, 6)
  ASSERT_EQ(m.g(7, 6), 1);
  EXPECT_FALSE(m.follow({2.9, 2.9}, 0.0));  // 2 cells off centre: k = 2, stays
  EXPECT_TRUE(m.follow({3.2, 0.5}, 0.0));   // 3 cells: re-centred on global cell (3, 0)
  EXPECT_EQ(m.originX(), -2);
  EXPECT_EQ(m.originY(), -5);
  int ix, iy;
  ASSERT_TRUE(m.cellAt({2.5, 1.5}, ix, iy));
  EXPECT_EQ(ix, 4);
  EXPECT_EQ(iy, 6);
  EXPECT_EQ(m.g(ix, iy), 1);
  EXPECT_EQ(m.cellCorner(ix, iy), Vec2(2.0, 1.0));
  // At speed the robot may not drift as far: k(2 m/s) = 0.
  EXPECT_TRUE(m.follow({4.2, 0.5}, 2.0));
  EXPECT_EQ(m.originX(), -1);
}

TEST(Agm, CellsLeavingTheWindowAreForgotten) {
  AccumulativeGridMap m(small(1, 1, 1000));
  m.centreOn({0.5, 0.5});
  m.update({{-4.5, 0.5}, {-3.5, 0.5}});  // window columns 0 and 1
  m.centreOn({1.5, 0.5});                  // column 0 (global -5) leaves
  int ix, iy;
  EXPECT_FALSE(m.cellAt({-4.5, 0.5}, ix, iy));
  ASSERT_TRUE(m.cellAt({-3.5, 0.5}, ix, iy));
  EXPECT_EQ(ix, 0);
  EXPECT_EQ(m.g(0, iy), 1);
  EXPECT_EQ(m.gu(0, iy), 1);  // the forgotten neighbour's weight was withdrawn
  // The slot now holds global column 5 (entering, empty); its Gu sees no wrapped weight.
  EXPECT_EQ(m.g(9, iy), 0);
  EXPECT_EQ(m.gu(9, iy), 0);
  m.centreOn({0.5, 0.5});  // back: the forgotten cell stays forgotten
  ASSERT_TRUE(m.cellAt({-4.5, 0.5}, ix, iy));
  EXPECT_EQ(m.g(ix, iy), 0);
  EXPECT_EQ(m.gu(ix, iy), 1);  // entering cell counts its surviving neighbour
  m.centreOn({100.5, 0.5});    // jump beyond the window: nothing survives
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) EXPECT_EQ(m.gu(x, y), 0);
}

namespace {

// Naive dense reference: a map of global cells, batch revision and propagation every cycle.
class ReferenceAgm {
 public:
  explicit ReferenceAgm(const AgmParams& p) : ox_(-(p.size / 2)), oy_(-(p.size / 2)), p_(p) {}
  int64_t cell(double v) const { return static_cast<int64_t>(std::floor(v / p_.cell_size)); }
  void follow(const Vec2& r, double speed) {
    const int64_t rx = cell(r.x()), ry = cell(r.y());
    const double driven = std::abs(speed) * p_.recenter_lookahead_s / p_.cell_size;
    const int k = std::clamp(p_.recenter_max_cells - static_cast<int>(std::floor(driven)), p_.recenter_min_cells,
                             p_.recenter_max_cells);
    if (std::max(std::abs(rx - ox_ - p_.size / 2), std::abs(ry - oy_ - p_.size / 2)) <= k) return;
    ox_ = rx - p_.size / 2;
    oy_ = ry - p_.size / 2;
    for (auto it = cells_.begin(); it != cells_.end();)
      it = inWindow(it->first.first, it->first.second) ? std::next(it) : cells_.erase(it);
  }
  void update(const std::vector<Vec2>& hits) {
    ++cycle_;
    for (const auto& h : hits) {
      const int64_t x = cell(h.x()), y = cell(h.y());
      if (!inWindow(x, y)) continue;
      Cell& c = cells_[{x, y}];
      c.g = std::min(c.g + 1, p_.g_max);
      c.last = cycle_;
    }
    for (auto it = cells_.begin(); it != cells_.end();)
      it = (cycle_ - it->second.last > p_.h_max) ? cells_.erase(it) : std::next(it);
  }
  int g(int64_t x, int64_t y) const {
    auto it = cells_.find({x, y});
    return it == cells_.end() ? 0 : it->second.g;
  }
  int h(int64_t x, int64_t y) const {
    auto it = cells_.find({x, y});
    return it == cells_.end() ? 0 : static_cast<int>(cycle_ - it->second.last);
  }
  // The neighbourhood's weight inside the window, for every cell (an empty one too: it is what
  // the cell's Gp becomes when it is hit).
  int gu(int64_t x, int64_t y) const {
    int sum = 0;
    for (int64_t q = y - p_.t; q <= y + p_.t; ++q)
      for (int64_t pp = x - p_.t; pp <= x + p_.t; ++pp)
        if (inWindow(pp, q)) sum += g(pp, q);
    return sum;
  }
  int gp(int64_t x, int64_t y) const {
    if (g(x, y) == 0) return 0;
    const int sum = gu(x, y);
    return sum >= p_.g_threshold ? sum : 0;
  }
  bool inWindow(int64_t x, int64_t y) const {
    return x >= ox_ && x < ox_ + p_.size && y >= oy_ && y < oy_ + p_.size;
  }
  int64_t ox_, oy_;

 private:
  struct Cell {
    int g = 0;
    int64_t last = 0;
  };
  AgmParams p_;
  int64_t cycle_ = 0;
  std::map<std::pair<int64_t, int64_t>, Cell> cells_;
};

void compareOverRandomMotion(const AgmParams& p, uint32_t seed, int steps) {
  AccumulativeGridMap m(p);
  ReferenceAgm ref(p);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Fixed "obstacles" so weights accumulate, plus scattered noise hits.
  std::vector<Vec2> obstacles;
  for (int i = 0; i < 30; ++i) obstacles.emplace_back(8 * u(rng), 8 * u(rng));
  Vec2 robot(0, 0);
  int shifts = 0;
  for (int step = 0; step < steps; ++step) {
    const double speed = std::abs(u(rng));
    robot += Vec2(u(rng), u(rng)) * (3 * p.cell_size);
    if (step % 500 == 499) robot += Vec2(u(rng), u(rng)) * (2 * p.size * p.cell_size);  // teleport
    if (step % 50 == 0) robot *= 0.2;  // keep coming back over the obstacles
    const int64_t before = m.originX() * 1000003 + m.originY();
    m.follow(robot, speed);
    ref.follow(robot, speed);
    shifts += (m.originX() * 1000003 + m.originY()) != before;
    std::vector<Vec2> hits;
    const int nhits = static_cast<int>(rng() % 6);
    for (int i = 0; i < nhits; ++i) {
      const Vec2 o = obstacles[rng() % obstacles.size()];
      hits.push_back(rng() % 4 == 0 ? robot + Vec2(u(rng), u(rng)) * (0.7 * p.size * p.cell_size)
                                    : o + Vec2(u(rng), u(rng)) * p.cell_size);
    }
    m.update(hits);
    ref.update(hits);
    ASSERT_EQ(m.originX(), ref.ox_);
    ASSERT_EQ(m.originY(), ref.oy_);
    for (int iy = 0; iy < p.size; ++iy)
      for (int ix = 0; ix < p.size; ++ix) {
        const int64_t gx = ref.ox_ + ix, gy = ref.oy_ + iy;
        ASSERT_EQ(m.cellCorner(ix, iy), Vec2(static_cast<double>(gx) * p.cell_size, static_cast<double>(gy) * p.cell_size));
        ASSERT_EQ(m.g(ix, iy), ref.g(gx, gy)) << "step " << step << " cell " << ix << "," << iy;
        ASSERT_EQ(m.h(ix, iy), ref.h(gx, gy)) << "step " << step << " cell " << ix << "," << iy;
        ASSERT_EQ(m.gp(ix, iy), ref.gp(gx, gy)) << "step " << step << " cell " << ix << "," << iy;
        ASSERT_EQ(m.gu(ix, iy), ref.gu(gx, gy)) << "step " << step << " cell " << ix << "," << iy;
      }
  }
  EXPECT_GT(shifts, steps / 10);  // the test really exercised re-centring and wrap-around
}

}  // namespace

TEST(Agm, MatchesDenseReferenceOverRandomMotion) {
  AgmParams p;
  p.size = 20;
  p.cell_size = 0.5;
  p.h_max = 6;
  p.g_max = 4;
  p.recenter_max_cells = 3;
  p.recenter_min_cells = 0;
  p.recenter_lookahead_s = 2.0;
  for (int t : {0, 1, 2}) {
    p.t = t;
    p.g_threshold = 1 + t;
    compareOverRandomMotion(p, 17u + static_cast<uint32_t>(t), 3000);
  }
}

TEST(Agm, MatchesDenseReferenceOddSize) {
  AgmParams p;
  p.size = 15;
  p.cell_size = 0.3;
  p.h_max = 3;
  p.t = 1;
  p.g_threshold = 2;
  p.recenter_max_cells = 1;
  p.recenter_min_cells = 0;
  compareOverRandomMotion(p, 99u, 2000);
}

TEST(Agm, ExportIsRowMajorInWindowCoordinates) {
  AccumulativeGridMap m(small(1, 1, 50));
  m.centreOn({3.5, -2.5});  // a window whose origin is not a multiple of N
  m.update({{3.5, -2.5}, {3.5, -2.5}, {4.5, -2.5}});
  m.update({});
  std::vector<int16_t> g, h;
  std::vector<int32_t> gp;
  m.exportGrids(g, h, gp);
  ASSERT_EQ(g.size(), 100u);
  for (int iy = 0; iy < 10; ++iy)
    for (int ix = 0; ix < 10; ++ix) {
      const size_t i = static_cast<size_t>(iy * 10 + ix);
      EXPECT_EQ(g[i], m.g(ix, iy));
      EXPECT_EQ(h[i], m.h(ix, iy));
      EXPECT_EQ(gp[i], m.gp(ix, iy));
    }
  EXPECT_EQ(g[5 * 10 + 5], 2);
  EXPECT_EQ(h[5 * 10 + 5], 1);
  EXPECT_EQ(gp[5 * 10 + 6], 3);
}

TEST(Agm, ConfigErrorsNameTheKey) {
  const Config c = Config::fromString("agm: {size: 100, t: 60}");
  try {
    agmParams(c.section("agm"));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("agm.t"), std::string::npos) << e.what();
  }
  EXPECT_THROW(agmParams(Config::fromString("agm: {colour: 3}").section("agm")), ConfigError);
  const AgmParams p = agmParams(Config::fromString("agm: {h_max: 40, g_threshold: 6}").section("agm"));
  EXPECT_EQ(p.h_max, 40);
  EXPECT_EQ(p.g_threshold, 6);
  EXPECT_EQ(p.size, 100);
}

TEST(Agm, LastHitCycleAndHitCentroids) {
  AgmParams p = small();
  p.hit_centroids = true;
  AccumulativeGridMap m(p);
  m.centreOn({0.5, 0.5});
  m.update({{0.2, 0.3}});
  m.update({});
  m.update({{0.4, 0.5}});
  EXPECT_EQ(m.lastHitCycle(5, 5), 3);
  EXPECT_EQ(m.lastHitCycle(4, 4), 0);  // never hit
  // The mean of the two hits, not the cell centre (0.5, 0.5).
  EXPECT_NEAR(m.evidencePoint(5, 5).x(), 0.3, 1e-6);
  EXPECT_NEAR(m.evidencePoint(5, 5).y(), 0.4, 1e-6);
  EXPECT_NEAR(m.evidencePoint(4, 4).x(), -0.5, 1e-12);  // no weight: the centre
  // Revision forgets where the hits were: a new hit starts a new mean.
  for (int i = 0; i < 4; ++i) m.update({});
  EXPECT_EQ(m.g(5, 5), 0);
  m.update({{0.9, 0.9}});
  EXPECT_NEAR(m.evidencePoint(5, 5).x(), 0.9, 1e-6);
  // Without hit_centroids: always the centre.
  AccumulativeGridMap plain(small());
  plain.centreOn({0.5, 0.5});
  plain.update({{0.2, 0.3}});
  EXPECT_DOUBLE_EQ(plain.evidencePoint(5, 5).x(), 0.5);
}

TEST(Agm, DistanceRevisionForgetsAfterTheRobotDroveFar) {
  AgmParams p = small(1, 2, /*h_max=*/1000);
  p.h_max_m = 2.5;
  p.recenter_max_cells = 4;  // keep the window still while the robot moves 3 m
  AccumulativeGridMap m(p);
  m.centreOn({0.5, 0.5});
  m.follow({0.5, 0.5}, 0);
  m.update({at(6, 6)});
  // Standing still: never forgotten by distance (h_max is 1000 cycles).
  for (int i = 0; i < 50; ++i) m.update({});
  EXPECT_EQ(m.g(6, 6), 1);
  // Driving 1 m per cycle: forgotten once more than 2.5 m from where it was heard.
  for (int i = 1; i <= 2; ++i) {
    m.follow({0.5 + i, 0.5}, 0);
    m.update({});
    EXPECT_EQ(m.g(6, 6), 1) << i;
  }
  m.follow({3.5, 0.5}, 0);
  m.update({});
  EXPECT_DOUBLE_EQ(m.odometer(), 3.0);
  EXPECT_EQ(m.g(6, 6), 0);
  EXPECT_EQ(m.gp(6, 6), 0);
}

TEST(Agm, SubWindowExportIsTheWindowsMiddle) {
  AccumulativeGridMap m(small(1, 1, 50));
  m.centreOn({3.5, -2.5});  // origin not a multiple of N: the sub-window wraps the buffer
  m.update({{3.5, -2.5}, {4.5, -4.5}, {-1.5, -7.5}});
  std::vector<int16_t> g, h, sg, sh;
  std::vector<int32_t> gp, sgp;
  m.exportGrids(g, h, gp);
  m.exportGrids(3, 2, 4, sg, sh, sgp);
  ASSERT_EQ(sg.size(), 16u);
  int weighted = 0;
  for (int iy = 0; iy < 4; ++iy)
    for (int ix = 0; ix < 4; ++ix) {
      const size_t i = static_cast<size_t>(iy * 4 + ix), w = static_cast<size_t>((iy + 2) * 10 + ix + 3);
      EXPECT_EQ(sg[i], g[w]);
      EXPECT_EQ(sh[i], h[w]);
      EXPECT_EQ(sgp[i], gp[w]);
      weighted += sg[i] > 0;
    }
  EXPECT_EQ(weighted, 2);  // (3.5, -2.5) and (4.5, -4.5); (-1.5, -7.5) lies outside the sub-window
  EXPECT_THROW(m.exportGrids(7, 0, 4, sg, sh, sgp), std::invalid_argument);
  EXPECT_THROW(m.exportGrids(-1, 0, 4, sg, sh, sgp), std::invalid_argument);
}

// forget_sigma_m: the displacement variance since a hit is trans^2 * driven plus, for every
// heading error since, its variance times the distance driven after it squared.
TEST(Agm, OdometryErrorRevisionCountsTurnsByTheDistanceDrivenAfterThem) {
  AgmParams p = small(1, 1, /*h_max=*/100000);
  p.size = 400;  // 40 m: the robot never takes the window away from the cell
  p.cell_size = 0.1;
  const Vec2 cell{0.05, 0.55};
  auto weight = [&](const AccumulativeGridMap& m) {
    int ix = 0, iy = 0;
    return m.cellAt(cell, ix, iy) ? m.g(ix, iy) : -1;
  };
  p.odometry_trans_noise = 0.01;
  p.odometry_rot_noise = 0.005;
  p.odometry_drift_noise = 0.002;
  p.forget_sigma_m = 0.08;
  // Straight: trans^2 d + drift^2 d^3 / 3 = 0.08^2 at d = 15.4 m (the shipped h_max_m's bound).
  auto straight = [&](double step) {
    AccumulativeGridMap m(p);
    m.centreOn({0, 0});
    m.follow({0, 0}, 0, 0.0);
    m.update({cell});
    double x = 0;
    while (weight(m) > 0 && x < 100) {
      x += step;
      m.follow({x, 0}, 0, 0.0);
      m.update({});
    }
    return x;
  };
  EXPECT_NEAR(straight(0.01), 15.39, 0.03);
  EXPECT_NEAR(straight(0.1), 15.39, 0.15);  // a step's heading error counts from its end: a little later
  // A U-turn on the spot costs nothing at once, the way back after it does: 0.005^2 pi L^2.
  AccumulativeGridMap m(p);
  m.centreOn({0, 0});
  m.follow({0, 0}, 0, 0.0);
  m.update({cell});
  for (int k = 1; k <= 180; ++k) {  // turning on the spot, 1 degree at a time
    m.follow({0, 0}, 0, geom::normalizeAngle(k * geom::kPi / 180));
    m.update({});
  }
  EXPECT_EQ(weight(m), 1);
  double x = 0;
  while (weight(m) > 0 && x > -100) {
    x -= 0.01;
    m.follow({x, 0}, 0, geom::kPi);
    m.update({});
  }
  // 1e-4 L + 4e-6 L^3 / 3 + 7.854e-5 L^2 = 0.0064 at L = 7.9 m.
  EXPECT_NEAR(-x, 7.93, 0.03);
  // Off (forget_sigma_m 0): kept.
  p.forget_sigma_m = 0;
  AccumulativeGridMap off(p);
  off.centreOn({0, 0});
  off.follow({0, 0}, 0, 0.0);
  off.update({cell});
  off.follow({0, 0}, 0, geom::kPi);
  off.follow({-9.9, 0}, 0, geom::kPi);
  off.update({});
  EXPECT_EQ(weight(off), 1);
}

// forEachWeightedCell visits exactly the cells with G > 0 that forEachCell finds in the same
// rectangle (forEachPositiveCell: in forEachCell's order), each once, through hits, repeated hits of one cell in one cycle, revision and
// re-centring, whether it walks the revision queue (small rectangles) or the rectangle.
TEST(Agm, WeightedCellsAreExactlyTheCellsWithWeight) {
  AgmParams p;
  p.size = 40;
  p.cell_size = 0.1;
  p.h_max = 6;
  p.g_threshold = 2;
  AccumulativeGridMap m(p);
  m.centreOn({0.0, 0.0});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::uniform_int_distribution<int> corner(0, 39), side(1, 40);
  Vec2 robot(0.0, 0.0);
  int walked_queue = 0;
  for (int cycle = 0; cycle < 600; ++cycle) {
    std::vector<Vec2> hits;
    for (int i = 0; i < 4; ++i) hits.push_back(robot + Vec2(u(rng), u(rng)));
    if (cycle % 3 == 0) hits.push_back(hits.front());  // one cell twice in a cycle
    if (cycle % 50 == 0) robot += Vec2(0.35, -0.2);     // re-centring moves the window
    m.follow(robot, 0.0);
    m.update(hits);
    for (int r = 0; r < 3; ++r) {
      const int ix0 = corner(rng), iy0 = corner(rng);
      const int ix1 = ix0 + (r == 0 ? 39 : side(rng) % 12), iy1 = iy0 + (r == 0 ? 39 : side(rng) % 12);
      std::map<std::pair<int, int>, std::pair<int, int>> brute, fast;
      std::vector<std::array<int, 4>> in_order, positive;
      m.forEachCell(ix0, iy0, ix1, iy1, [&](int ix, int iy, int g, int gp) {
        if (g > 0) brute[{ix, iy}] = {g, gp};
        if (g > 0) in_order.push_back({ix, iy, g, gp});
      });
      // forEachPositiveCell: the same calls in the same order.
      m.forEachPositiveCell(ix0, iy0, ix1, iy1, [&](int ix, int iy, int g, int gp) { positive.push_back({ix, iy, g, gp}); });
      ASSERT_EQ(positive, in_order) << "cycle " << cycle << " rectangle " << ix0 << "," << iy0 << " - " << ix1 << "," << iy1;
      int visits = 0;
      m.forEachWeightedCell(ix0, iy0, ix1, iy1, [&](int ix, int iy, int g, int gp) {
        ++visits;
        fast[{ix, iy}] = {g, gp};
      });
      ASSERT_EQ(fast, brute) << "cycle " << cycle << " rectangle " << ix0 << "," << iy0 << " - " << ix1 << "," << iy1;
      ASSERT_EQ(visits, static_cast<int>(brute.size())) << "a cell visited twice, cycle " << cycle;
      // The queue walk is taken when the rectangle is larger than the queue.
      if (static_cast<size_t>(std::min(ix1, 39) - ix0 + 1) * static_cast<size_t>(std::min(iy1, 39) - iy0 + 1) > 40)
        ++walked_queue;
    }
  }
  EXPECT_GT(walked_queue, 100);
}

// hold_unpassed: a cell whose H passes h_max is kept, at most hold_unpassed cycles longer, until
// sound goes through it (markPassed before the cycle; a hit in that cycle outweighs it). Against
// a dense reference of G, last hit and last pass per cell, random hits and passes; and the
// weighted cells (the held ones too) against every cell with weight while the window moves.
TEST(Agm, HeldCellsGoOnceSoundPassesOrTheHoldEnds) {
  AgmParams p;
  p.size = 20;
  p.cell_size = 0.1;
  p.h_max = 4;
  p.g_max = 1000;
  p.hold_unpassed = 7;
  p.recenter_max_cells = 0;
  p.recenter_min_cells = 0;
  for (const bool moving : {false, true}) {
    AccumulativeGridMap m(p);
    m.centreOn({0.0, 0.0});
    std::vector<int> g(400, 0);
    std::vector<int64_t> last(400, 0), passed(400, 0);
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> cell(0, 19), chance(0, 9);
    Vec2 robot(0.0, 0.0);
    bool held_seen = false;
    for (int64_t cycle = 1; cycle <= 400; ++cycle) {
      std::vector<Vec2> hits;
      for (int i = 0; i < 2; ++i)
        if (chance(rng) < 3) {
          const int ix = cell(rng), iy = cell(rng);
          hits.push_back(m.cellCorner(ix, iy) + Vec2(0.05, 0.05));
          if (!moving) ++g[static_cast<size_t>(iy * 20 + ix)], last[static_cast<size_t>(iy * 20 + ix)] = cycle;
        }
      for (int i = 0; i < 3; ++i)
        if (chance(rng) < 2) {
          const int ix = cell(rng), iy = cell(rng);
          m.markPassed(ix, iy);
          if (!moving) passed[static_cast<size_t>(iy * 20 + ix)] = cycle;
        }
      if (moving && cycle % 37 == 0) robot += Vec2(0.3, 0.1);
      if (moving) m.follow(robot, 0.0);
      m.update(hits);
      held_seen = held_seen || m.held() > 0;
      std::map<std::pair<int, int>, int> brute, fast;
      m.forEachCell(0, 0, 19, 19, [&](int ix, int iy, int gv, int) {
        if (gv > 0) brute[{ix, iy}] = gv;
      });
      int visits = 0;
      m.forEachWeightedCell(0, 0, 19, 19, [&](int ix, int iy, int gv, int) { ++visits, fast[{ix, iy}] = gv; });
      ASSERT_EQ(fast, brute) << "cycle " << cycle << (moving ? " moving" : "");
      ASSERT_EQ(visits, static_cast<int>(brute.size())) << "cycle " << cycle;
      if (moving) continue;
      for (size_t i = 0; i < g.size(); ++i) {
        const int64_t h = cycle - last[i];
        if (g[i] > 0 && h > p.h_max && (passed[i] > last[i] || h > p.h_max + p.hold_unpassed)) g[i] = 0;
        const int ix = static_cast<int>(i % 20), iy = static_cast<int>(i / 20);
        ASSERT_EQ(m.g(ix, iy), g[i]) << "cycle " << cycle << " cell " << ix << "," << iy << " last hit " << last[i]
                                      << " passed " << passed[i];
        ASSERT_EQ(m.held(ix, iy), g[i] > 0 && h > p.h_max) << "cycle " << cycle;
      }
    }
    EXPECT_TRUE(held_seen);
  }
}

// markSoundPassed: the weighted cells within core x half the beam of the axis and margin_m nearer
// than the reach, no others (not behind the echo, not beside the beam, not within the margin of
// the transducer), whatever the window's place.
TEST(SoundPassed, MarksTheWeightedCellsTheBeamWentThrough) {
  AgmParams p;
  p.size = 60;
  p.cell_size = 0.1;
  p.h_max = 0;
  p.hold_unpassed = 100;
  AccumulativeGridMap m(p);
  m.centreOn({10.0, -3.0});
  const Vec2 o(9.0, -3.0);  // the transducer, facing +x, 30 deg beam, echo at 2.0 m
  const Sounding s{{o.x(), o.y(), 0.0}, 2.0, geom::deg2rad(30.0), false, 2.0};
  // Cell centres: on the axis at 1.0 (passed), 1.9 (within the margin of the echo: kept), 2.5
  // (behind it); 10 deg off the axis at 1.0 (inside the beam; outside its half core); 20 deg off
  // (outside the beam); 0.1 m ahead (the margin at the transducer).
  const auto centre = [&](double r, double deg) -> Vec2 {
    return o + r * geom::unitVector(geom::deg2rad(deg));
  };
  const std::vector<Vec2> cells = {centre(1.0, 0), centre(1.9, 0), centre(2.5, 0), centre(1.0, 10), centre(1.0, 20),
                                   centre(0.1, 0)};
  std::vector<Vec2> snapped;
  for (const Vec2& c : cells) {
    int ix = 0, iy = 0;
    ASSERT_TRUE(m.cellAt(c, ix, iy));
    snapped.push_back(m.cellCorner(ix, iy) + Vec2(0.05, 0.05));
  }
  const auto keptAfter = [&](double core, int marked) {
    AccumulativeGridMap a(p);
    a.centreOn({10.0, -3.0});
    a.update(snapped);  // each cell hit once
    EXPECT_EQ(markSoundPassed(a, {s}, core, 0.15), marked) << "core " << core;
    a.update({});  // H = 1 > h_max: each passed cell goes, the others are held
    std::vector<int> kept;
    for (const Vec2& c : snapped) {
      int ix = 0, iy = 0;
      a.cellAt(c, ix, iy);
      kept.push_back(a.g(ix, iy));
    }
    return kept;
  };
  // (snapped centres lie within 0.05 m of the points above: the angles and distances stay clear
  // of the limits.)
  EXPECT_EQ(keptAfter(1.0, 2), (std::vector<int>{0, 1, 1, 0, 1, 1}));
  EXPECT_EQ(keptAfter(0.5, 1), (std::vector<int>{0, 1, 1, 1, 1, 1}));
  EXPECT_EQ(keptAfter(0.0, 0), (std::vector<int>{1, 1, 1, 1, 1, 1}));  // off
  // A NaN pose or a reach within the margin marks nothing.
  AccumulativeGridMap a(p);
  a.centreOn({10.0, -3.0});
  a.update(snapped);
  EXPECT_EQ(markSoundPassed(a, {{{std::nan(""), o.y(), 0.0}, 2.0, 0.5, false}, {{o.x(), o.y(), 0.0}, 0.2, 0.5, false}},
                            1.0, 0.15),
            0);
}

// markNearMovers: the cells whose centres lie within the radius of a walking person's returns
// are forgotten after h_max (the paper's), the others kept; outside the window nothing happens.
TEST(SoundPassed, CellsNearAWalkingPersonAreNotKept) {
  AgmParams p;
  p.size = 40;
  p.cell_size = 0.1;
  p.h_max = 0;
  p.hold_unpassed = 100;
  AccumulativeGridMap m(p);
  m.centreOn({0.0, 0.0});
  const std::vector<Vec2> cells = {{0.05, 0.05}, {0.25, 0.05}, {0.45, 0.05}, {0.05, -0.35}};
  m.update(cells);
  // Centres 0.05, 0.15, 0.25 m off each axis within 0.3 m: 8 a quadrant.
  EXPECT_EQ(markNearMovers(m, {{0.0, 0.0}, {50.0, 50.0}}, 0.3), 32);
  EXPECT_EQ(markNearMovers(m, {{0.0, 0.0}}, 0.0), 0);
  m.update({});
  std::vector<int> kept;
  for (const Vec2& c : cells) {
    int ix = 0, iy = 0;
    ASSERT_TRUE(m.cellAt(c, ix, iy));
    kept.push_back(m.g(ix, iy));
  }
  // (0.05, 0.05): 0.07 m from the person; (0.25, 0.05): 0.25 m; (0.45, 0.05) 0.45 m; (0.05,
  // -0.35) 0.35 m.
  EXPECT_EQ(kept, (std::vector<int>{0, 0, 1, 1}));
}

// ArcCells (the arc's unit vectors turned step by step, the cell taken where the point is clearly
// inside it) gives the cell of the defining computation, cellAt(centre + range *
// unitVector(b)), for every sample: random arcs of 1-400 samples with both signs of step, the
// window moved far from the origin, samples constructed to land on cell edges (centre on a cell
// corner, range a multiple of the cell, bearings through the axes and the diagonals), arcs
// leaving the window, and a centre or range that is NaN, infinite or huge (the defining way).
TEST(Agm, ArcCellsAreTheCellsOfTheDefiningPoints) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0), coin(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  int64_t samples = 0, on_edges = 0;
  for (const double cell : {0.1, 0.05, 0.07}) {
    AgmParams p;
    p.size = 100;
    p.cell_size = cell;
    AccumulativeGridMap agm(p);
    for (int trial = 0; trial < 3000; ++trial) {
      if (trial % 500 == 0) agm.centreOn(Vec2(2000 * u(rng), 2000 * u(rng)));  // a window far out
      const Vec2 mid = agm.originMetres() + Vec2(0.5, 0.5) * (p.size * cell);
      Vec2 centre = mid + Vec2(3 * u(rng), 3 * u(rng));
      double range = 0.2 + 4 * coin(rng);
      double b0 = 3.2 * u(rng);
      if (trial % 4 == 0) {  // on a cell corner, the range a whole number of cells, through the axes
        centre = Vec2(std::round(centre.x() / cell) * cell, std::round(centre.y() / cell) * cell);
        range = cell * std::round(range / cell);
        b0 = -geom::kPi / 4 * std::round(4 * coin(rng));
      }
      if (trial % 97 == 0) centre.x() = trial % 2 ? nan : inf;
      if (trial % 89 == 0) range = trial % 2 ? 1e7 : nan;
      const int n = 1 + trial % 400;
      const double span = (coin(rng) < 0.5 ? -1 : 1) * (trial % 5 == 0 ? 2 * geom::kPi : 0.6 * coin(rng));
      const double step = span / n;
      AccumulativeGridMap::ArcCells arc(agm, centre, range, step);
      for (int q = 0; q <= n; ++q) {
        const double b = b0 + span * q / n;  // (as the callers round it)
        int ix = -1, iy = -1, jx = -1, jy = -1;
        const bool got = arc.cellAt(b, ix, iy);
        const Vec2 point = centre + range * geom::unitVector(b);
        const bool want = agm.cellAt(point, jx, jy);
        ASSERT_EQ(got, want) << "cell " << cell << " trial " << trial << " sample " << q;
        if (want) {
          ASSERT_EQ(ix, jx) << "cell " << cell << " trial " << trial << " sample " << q;
          ASSERT_EQ(iy, jy) << "cell " << cell << " trial " << trial << " sample " << q;
        }
        ++samples;
        const double fx = point.x() / cell, fy = point.y() / cell;
        on_edges += std::isfinite(fx) && (fx == std::floor(fx) || fy == std::floor(fy));
      }
    }
  }
  EXPECT_GT(samples, 1'000'000);
  EXPECT_GT(on_edges, 1000);  // (points exactly on an edge were among them)
}

// The robot's footprint (NavigatorConfig::clear_footprint): cells whose centre lies within r of
// the robot are emptied, with their propagated weight taken from their neighbours; the others stay,
// and the cleared cells count again from zero when hit later.
TEST(Agm, ClearDiscEmptiesTheCellsInsideAndOnlyThem) {
  AccumulativeGridMap m(small(1, 2, 10));
  m.centreOn({0.5, 0.5});
  m.update({at(5, 5), at(5, 5), at(6, 5), at(8, 5), at(8, 5)});
  ASSERT_EQ(m.g(5, 5), 2);
  ASSERT_EQ(m.gp(6, 5), 3);  // its own 1 and (5,5)'s 2
  EXPECT_EQ(m.clearDisc(at(5, 5), 0.6), 1);  // (6, 5)'s centre is 1 m away
  EXPECT_EQ(m.g(5, 5), 0);
  EXPECT_EQ(m.gp(5, 5), 0);
  EXPECT_EQ(m.g(6, 5), 1);
  EXPECT_EQ(m.gp(6, 5), 0);  // alone now: below G_T
  EXPECT_EQ(m.g(8, 5), 2);   // outside: untouched
  EXPECT_EQ(m.gp(8, 5), 2);
  EXPECT_EQ(m.clearDisc(at(5, 5), 1.01), 1);  // now (6, 5) too
  EXPECT_EQ(m.g(6, 5), 0);
  EXPECT_EQ(m.clearDisc(at(5, 5), 0), 0);
  EXPECT_EQ(m.clearDisc({std::nan(""), 0}, 1), 0);
  m.update({at(5, 5)});
  EXPECT_EQ(m.g(5, 5), 1);
  for (int i = 0; i < 12; ++i) m.update({});  // the old hits' revision finds nothing to undo
  EXPECT_EQ(m.g(5, 5), 0);
  EXPECT_EQ(m.g(8, 5), 0);
}
