// evidenceBearing: the one cell an echo increments, chosen by the AGM's weight on its range arc
// within the bearing's uncertainty; and what that does to a pipe seen while driving past it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "operational/evidence_placement.hpp"

using namespace lasonic;
using geom::deg2rad;
using geom::Vec2;

namespace {

// 100 x 100 cells of 0.1 m centred on the origin (window cell (50, 50) holds the origin).
AgmParams operational() {
  AgmParams p;
  p.size = 100;
  p.cell_size = 0.1;
  p.t = 1;
  p.g_threshold = 2;
  p.h_max = 1000;
  p.g_max = 1000;
  return p;
}

AccumulativeGridMap emptyAgm() {
  AccumulativeGridMap m(operational());
  m.centreOn({0.05, 0.05});
  return m;
}

void addWeight(AccumulativeGridMap& m, const Vec2& p, int g) {
  for (int i = 0; i < g; ++i) m.update({p});
}

const Vec2 kSensor{0.0, 0.0};
constexpr double kRange = 1.5;
Vec2 onArc(double deg) { return kSensor + kRange * geom::unitVector(deg2rad(deg)); }

}  // namespace

TEST(EvidenceBearing, NoWeightIsExactlyTheEstimate) {
  const AccumulativeGridMap m = emptyAgm();
  const BearingEstimate est{deg2rad(37.5), deg2rad(7.5)};
  EXPECT_EQ(evidenceBearing(m, kSensor, kRange, est), est.bearing);
}

TEST(EvidenceBearing, GoesToTheWeightedCellWithinTheUncertainty) {
  AccumulativeGridMap m = emptyAgm();
  addWeight(m, onArc(33.0), 2);
  const BearingEstimate est{deg2rad(37.5), deg2rad(7.5)};
  const double b = evidenceBearing(m, kSensor, kRange, est);
  int ix = 0, iy = 0, jx = 0, jy = 0;
  ASSERT_TRUE(m.cellAt(kSensor + kRange * geom::unitVector(b), ix, iy));
  ASSERT_TRUE(m.cellAt(onArc(33.0), jx, jy));
  EXPECT_EQ(ix, jx);
  EXPECT_EQ(iy, jy);
  EXPECT_LE(std::abs(b - est.bearing), est.halfwidth + 1e-12);
}

TEST(EvidenceBearing, IgnoresWeightOutsideTheUncertaintyOrOffTheArc) {
  AccumulativeGridMap m = emptyAgm();
  addWeight(m, onArc(28.0), 5);                                 // 9.5 deg away: outside +-7.5
  addWeight(m, 1.8 * geom::unitVector(deg2rad(37.5)), 5);       // on the bearing, 0.3 m farther
  const BearingEstimate est{deg2rad(37.5), deg2rad(7.5)};
  EXPECT_EQ(evidenceBearing(m, kSensor, kRange, est), est.bearing);
  // A beam-edge estimate is exact (halfwidth 0): weight beside it changes nothing.
  addWeight(m, onArc(36.0), 5);
  EXPECT_EQ(evidenceBearing(m, kSensor, kRange, {deg2rad(37.5), 0.0}), deg2rad(37.5));
  EXPECT_EQ(evidenceBearing(m, kSensor, 0.0, est), est.bearing);
  // Malformed ranges: the estimate, at once.
  EXPECT_EQ(evidenceBearing(m, kSensor, 1e30, est), est.bearing);
  EXPECT_EQ(evidenceBearing(m, kSensor, std::numeric_limits<double>::infinity(), est), est.bearing);
  EXPECT_EQ(evidenceBearing(m, kSensor, std::numeric_limits<double>::quiet_NaN(), est), est.bearing);
}

TEST(EvidenceBearing, ASingleHitAttractsOnlyWithMinGOne) {
  AccumulativeGridMap m = emptyAgm();
  addWeight(m, onArc(33.0), 1);  // one reading (it might be crosstalk)
  const BearingEstimate est{deg2rad(37.5), deg2rad(7.5)};
  EXPECT_EQ(evidenceBearing(m, kSensor, kRange, est), est.bearing);  // min_g 2 (default)
  int ix = 0, iy = 0, jx = 0, jy = 0;
  ASSERT_TRUE(m.cellAt(kSensor + kRange * geom::unitVector(evidenceBearing(m, kSensor, kRange, est, 1)), ix, iy));
  ASSERT_TRUE(m.cellAt(onArc(33.0), jx, jy));
  EXPECT_EQ(std::make_pair(ix, iy), std::make_pair(jx, jy));
}

TEST(EvidenceBearing, GreatestWeightWinsThenNearestToTheEstimate) {
  AccumulativeGridMap m = emptyAgm();
  addWeight(m, onArc(31.0), 3);
  addWeight(m, onArc(43.0), 2);
  const BearingEstimate est{deg2rad(37.5), deg2rad(7.5)};
  int ix = 0, iy = 0, jx = 0, jy = 0;
  ASSERT_TRUE(m.cellAt(kSensor + kRange * geom::unitVector(evidenceBearing(m, kSensor, kRange, est)), ix, iy));
  ASSERT_TRUE(m.cellAt(onArc(31.0), jx, jy));
  EXPECT_EQ(std::make_pair(ix, iy), std::make_pair(jx, jy));
  addWeight(m, onArc(43.0), 1);  // now 3 each: 43 deg is 5.5 deg from the estimate, 31 deg 6.5
  ASSERT_TRUE(m.cellAt(kSensor + kRange * geom::unitVector(evidenceBearing(m, kSensor, kRange, est)), ix, iy));
  ASSERT_TRUE(m.cellAt(onArc(43.0), jx, jy));
  EXPECT_EQ(std::make_pair(ix, iy), std::make_pair(jx, jy));
}

namespace {
struct Spread {
  int cells = 0;          // cells holding weight
  double max_dist = 0;    // [m] farthest weighted cell centre from the pipe
  double mean_dist = 0;   // [m] weight-averaged distance of the cell centres from the pipe
};
// Drives a 24-sensor ring (radius 0.35 m, 30 deg beams) past a 2 cm pipe along y = 0,
// accumulating the ideal echoes' cells (every echo is the pipe's).
Spread pipeSpread(bool evidence) {
  const SonarBearingParams bp{};
  const geom::Circle pipe{{0.23, 1.31}, 0.01};
  AccumulativeGridMap m = emptyAgm();
  for (double x = -1.5; x <= 1.5 + 1e-9; x += 0.05) {
    std::vector<SonarEcho> echoes;
    for (int k = 0; k < 24; ++k) {
      const double a = deg2rad(15.0 * k);
      const geom::Pose2 s{x + 0.35 * std::cos(a), 0.35 * std::sin(a), a};
      if (const auto r = geom::nearestInSector(geom::Sector{s.position(), s.theta, bp.beam_width, 3.0}, pipe))
        echoes.push_back({0, *r, s});
    }
    std::vector<Vec2> hits;
    for (size_t i = 0; i < echoes.size(); ++i) {
      std::vector<SonarEcho> others;
      for (size_t j = 0; j < echoes.size(); ++j)
        if (j != i) others.push_back(echoes[j]);
      const SonarEcho& e = echoes[i];
      const BearingEstimate est = echoBearingEstimate(e, others, bp);
      const double b = evidence ? evidenceBearing(m, e.sensor.position(), e.range, est) : est.bearing;
      hits.push_back(e.sensor.position() + e.range * geom::unitVector(b));
    }
    m.update(hits);
  }
  Spread s;
  double total = 0;
  m.forEachCell(0, 0, m.size() - 1, m.size() - 1, [&](int ix, int iy, int g, int) {
    if (g == 0) return;
    const double d = (m.cellCorner(ix, iy) + Vec2(0.05, 0.05) - pipe.center).norm();
    ++s.cells;
    s.max_dist = std::max(s.max_dist, d);
    s.mean_dist += g * d;
    total += g;
  });
  if (total > 0) s.mean_dist /= total;
  return s;
}
}  // namespace

TEST(EvidenceBearing, DrivingPastAPipeConcentratesItsWeight) {
  const Spread est = pipeSpread(false), ev = pipeSpread(true);
  std::printf("pipe weight: estimate %d cells, mean %.3f m, max %.3f m; evidence %d cells, mean %.3f m, max %.3f m\n",
              est.cells, est.mean_dist, est.max_dist, ev.cells, ev.mean_dist, ev.max_dist);
  EXPECT_LT(ev.cells, est.cells);
  EXPECT_LT(ev.mean_dist, est.mean_dist);
}
