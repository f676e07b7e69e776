// Line generation (Jörg 1995 sec. 3.4) on synthetic grids, and the Current Sensor Map.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tactical/current_sensor_map.hpp"
#include "tactical/line_generation.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

constexpr double kCell = 0.10;

LineGenerationParams params() {
  LineGenerationParams p;
  p.gp_threshold = 1;
  return p;
}

// Cells along a straight segment from a to b, one per `step` metres (cell centres).
std::vector<CandidateCell> along(Vec2 a, Vec2 b, double step = kCell, int64_t support = 1) {
  std::vector<CandidateCell> out;
  const int n = static_cast<int>(std::lround((b - a).norm() / step));
  for (int i = 0; i <= n; ++i) out.push_back({a + (b - a) * (double(i) / n), 10, support});
  return out;
}

std::vector<CandidateCell> join(std::vector<CandidateCell> a, const std::vector<CandidateCell>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

double angleOf(const AgmLine& l) { return std::atan2(l.seg.b.y() - l.seg.a.y(), l.seg.b.x() - l.seg.a.x()); }

// Distance of p from the infinite line through l.
double offLine(const AgmLine& l, const Vec2& p) {
  const Vec2 d = (l.seg.b - l.seg.a).normalized();
  const Vec2 q = p - l.seg.a;
  return std::abs(d.x() * q.y() - d.y() * q.x());
}

}  // namespace

TEST(LineGeneration, EmptyGridGivesNoLines) {
  EXPECT_TRUE(generateLines({}, {}, kCell, params()).empty());
  AccumulativeGridMap agm(AgmParams{});
  EXPECT_TRUE(candidateCells(agm, 1).empty());
  EXPECT_TRUE(splitAtGaps({}, 0.5).empty());
  EXPECT_TRUE(nearestPerAngle({}, 0.01, kCell).empty());
}

TEST(LineGeneration, StraightWallIsOneLineReachingTheOuterCellEdges) {
  // A wall 1 m in front of the robot (at the origin, facing +y), cells from x = -1 to 1.
  const auto lines = generateLines(along({-1, 1}, {1, 1}), {0, 0, geom::kPi / 2}, kCell, params());
  ASSERT_EQ(lines.size(), 1u);
  const AgmLine& l = lines[0];
  EXPECT_EQ(l.ncells, 21);
  EXPECT_NEAR(l.rms, 0.0, 1e-9);
  // Ends extended by half a cell beyond the outer cell centres.
  EXPECT_NEAR(std::min(l.seg.a.x(), l.seg.b.x()), -1.05, 1e-9);
  EXPECT_NEAR(std::max(l.seg.a.x(), l.seg.b.x()), 1.05, 1e-9);
  EXPECT_NEAR(l.seg.a.y(), 1.0, 1e-9);
  EXPECT_NEAR(l.seg.b.y(), 1.0, 1e-9);
}

TEST(LineGeneration, LCornerGivesTwoLinesMeetingAtTheCorner) {
  const auto cells = join(along({-1, 1}, {1, 1}), along({1, 0.9}, {1, -0.5}));
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, params());
  ASSERT_EQ(lines.size(), 2u);
  int horizontal = 0, vertical = 0;
  for (const auto& l : lines) {
    const double a = std::abs(std::sin(angleOf(l)));
    if (a < 0.05) {
      ++horizontal;
      EXPECT_LT(offLine(l, {0, 1}), 0.02);
    } else if (a > 0.99) {
      ++vertical;
      EXPECT_LT(offLine(l, {1, 0}), 0.02);
    }
    // Both lines reach the corner (within the half-cell extension).
    EXPECT_LT(std::min((l.seg.a - Vec2(1, 1)).norm(), (l.seg.b - Vec2(1, 1)).norm()), 0.08);
  }
  EXPECT_EQ(horizontal, 1);
  EXPECT_EQ(vertical, 1);
}

TEST(LineGeneration, GapBetweenTwoObstaclesNeverBecomesALine) {
  // Two obstacles at the same distance, 0.6 m apart (wider than max_gap 0.5): two lines, and
  // no line point in the gap.
  const auto cells = join(along({-1.5, 1}, {-0.3, 1}), along({0.3, 1}, {1.5, 1}));
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, params());
  ASSERT_EQ(lines.size(), 2u);
  for (const auto& l : lines) {
    const double lo = std::min(l.seg.a.x(), l.seg.b.x()), hi = std::max(l.seg.a.x(), l.seg.b.x());
    EXPECT_TRUE(hi <= -0.2 || lo >= 0.2) << lo << " .. " << hi;
  }
  // A missing cell or two on one surface (0.3 m) is bridged.
  auto holey = along({-1.5, 1}, {1.5, 1});
  holey.erase(holey.begin() + 14, holey.begin() + 16);
  EXPECT_EQ(generateLines(holey, {0, 0, 0}, kCell, params()).size(), 1u);
}

TEST(LineGeneration, DiagonalWallOfQuantisedCellsKeepsItsDirection) {
  // A 45 deg wall y = x + 1 as the cells of a 0.1 m grid hold it (centres, staircase).
  std::vector<CandidateCell> cells;
  for (int i = -15; i <= 5; ++i) {
    const double x = i * kCell + 0.05;
    const double y = std::floor((x + 1.0) / kCell) * kCell + 0.05;
    cells.push_back({{x, y}, 10, 1});
  }
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, params());
  ASSERT_EQ(lines.size(), 1u);
  const double a = angleOf(lines[0]);
  EXPECT_NEAR(std::abs(std::cos(a)), std::sqrt(0.5), 0.02);
  EXPECT_NEAR(std::abs(std::sin(a)), std::sqrt(0.5), 0.02);
  EXPECT_LT(offLine(lines[0], {-0.5, 0.5}), 0.06);
}

TEST(LineGeneration, TwoDeepBandSeenAtAnAngleIsOneStraightLine) {
  // A surface at y = 1 whose cells (evidence points) lie in two rows, 1 and 1.12, as the angle
  // order visits them when the band is seen at an angle: zigzagging between the rows.
  std::vector<PolarCell> run;
  for (int i = 0; i <= 20; ++i) run.push_back({{{1.0 + 0.1 * i, i % 3 == 0 ? 1.12 : 1.0}, 10, 1}, 0.0, 0.0});
  LineGenerationParams p = params();
  const auto merged = fitRun(run, p, kCell);
  ASSERT_EQ(merged.size(), 1u);
  EXPECT_LT(std::abs(std::sin(angleOf(merged[0]))), 0.03);
  EXPECT_EQ(merged[0].ncells, 21);
  p.merge = false;  // the end-point fit alone splits the band into slanted pieces
  EXPECT_GT(fitRun(run, p, kCell).size(), 1u);
}

TEST(LineGeneration, IsolatedNoiseCellsGiveNoLines) {
  // Cells scattered at least 0.6 m apart (crosstalk hits): each alone, below min_cells.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-4, 4);
  std::vector<CandidateCell> cells;
  while (cells.size() < 25) {
    const Vec2 p(u(rng), u(rng));
    bool far = p.norm() > 0.5;
    for (const auto& c : cells) far = far && (c.centre - p).norm() > 0.6;
    if (far) cells.push_back({p, 10, 1});
  }
  EXPECT_TRUE(generateLines(cells, {0, 0, 0}, kCell, params()).empty());
  // The same cells plus a real wall: only the wall.
  const auto lines = generateLines(join(cells, along({-0.4, -1.0}, {0.4, -1.0})), {0, 0, 0}, kCell, params());
  ASSERT_GE(lines.size(), 1u);
  for (const auto& l : lines) EXPECT_LT(offLine(l, {0, -1}), 0.02);
}

TEST(LineGeneration, OnlyTheNearestCellsPerAngleUnlessPerCluster) {
  // A near wall (y = 1) hides a far one (y = 3) behind it, at the same bearings.
  const auto cells = join(along({-0.5, 1}, {0.5, 1}), along({-0.5, 3}, {0.5, 3}));
  LineGenerationParams paper = params();
  paper.occlusion = LineGenerationParams::Occlusion::Global;
  paper.hidden_cells = LineGenerationParams::HiddenCells::Drop;
  const auto global = generateLines(cells, {0, 0, 0}, kCell, paper);
  ASSERT_EQ(global.size(), 1u);
  EXPECT_LT(offLine(global[0], {0, 1}), 0.02);
  LineGenerationParams p = params();
  p.occlusion = LineGenerationParams::Occlusion::PerCluster;
  p.hidden_cells = LineGenerationParams::HiddenCells::Drop;
  EXPECT_EQ(generateLines(cells, {0, 0, 0}, kCell, p).size(), 2u);
  // Peeled, the far wall gets its line also where one cluster (or global occlusion) hides it.
  paper.hidden_cells = LineGenerationParams::HiddenCells::Peel;
  EXPECT_EQ(generateLines(cells, {0, 0, 0}, kCell, paper).size(), 2u);
  // Two rows of one surface (quantisation): only the nearer row is a line candidate.
  const auto visible = nearestPerAngle(toPolar(join(along({-1, 1}, {1, 1}), along({-1, 1.1}, {1, 1.1})), {0, 0, 0}),
                                       geom::deg2rad(1.0), kCell);
  ASSERT_EQ(visible.size(), along({-1, 1}, {1, 1}).size());  // every cell of the nearer row
  for (const auto& c : visible) EXPECT_NEAR(c.cell.centre.y(), 1.0, 1e-9);
}

TEST(LineGeneration, BandRefitPutsTheLineInTheMiddleOfATwoDeepBand) {
  // A mesh at y = 1.05 heard from both sides: its cells fill the rows y = 1.0 and y = 1.1. Only
  // the nearer row is nearest per angle; the band refit uses both rows.
  const auto cells = join(along({-1, 1.0}, {1, 1.0}), along({-1, 1.1}, {1, 1.1}));
  LineGenerationParams run = params();
  run.refit_cells = LineGenerationParams::RefitCells::Run;
  const auto near_face = generateLines(cells, {0, 0, 0}, kCell, run);
  ASSERT_EQ(near_face.size(), 1u);
  EXPECT_LT(offLine(near_face[0], {0, 1.0}), 0.01);
  LineGenerationParams band = params();
  band.refit_cells = LineGenerationParams::RefitCells::Band;
  const auto middle = generateLines(cells, {0, 0, 0}, kCell, band);
  ASSERT_EQ(middle.size(), 1u);
  EXPECT_LT(offLine(middle[0], {0, 1.05}), 0.01);
  EXPECT_LT(std::abs(std::sin(angleOf(middle[0]))), 0.01);
  EXPECT_EQ(middle[0].ncells, 21);  // the cells the line was found on (the run)
}

TEST(LineGeneration, EchoWeightedRefitFollowsTheHeavyRowsNotStrayCells) {
  // A mesh at y = 1.05 heard from both sides many times (rows 1.0 and 1.1, G 50 each), and at
  // its left end five cells 0.1 m in front of it from one stray echo each (G 1; an edge's echoes
  // placed off the surface). They are nearest per angle there, so the run's line is tilted. Their
  // Gp is as large as the rows' (a 3 x 3 neighbourhood sum takes in the row beside them): the
  // weight is the cell's own G.
  std::vector<CandidateCell> cells = join(along({-1, 1.0}, {1, 1.0}), along({-1, 1.1}, {1, 1.1}));
  for (CandidateCell& c : cells) {
    c.g = 50;
    c.gp = 300;
  }
  for (CandidateCell c : along({-1, 0.9}, {-0.6, 0.9})) {
    c.g = 1;
    c.gp = 150;
    cells.push_back(c);
  }
  auto endsOff = [](const AgmLine& l) {  // the line's distance from the mesh at x = -1 and x = 1
    const double slope = (l.seg.b.y() - l.seg.a.y()) / (l.seg.b.x() - l.seg.a.x());
    const double y_at = l.seg.a.y() - slope * l.seg.a.x();
    return std::max(std::abs(y_at - slope - 1.05), std::abs(y_at + slope - 1.05));
  };
  LineGenerationParams cells_once = params();
  cells_once.refit_weights = LineGenerationParams::RefitWeights::Cells;
  cells_once.hidden_cells = LineGenerationParams::HiddenCells::Drop;  // the first layer's line only
  const auto tilted = generateLines(cells, {0, 0, 0}, kCell, cells_once);
  ASSERT_EQ(tilted.size(), 1u);
  EXPECT_GT(endsOff(tilted[0]), 0.03);  // each cell once: the stray cells tilt it
  LineGenerationParams echoes = params();
  echoes.refit_weights = LineGenerationParams::RefitWeights::Echoes;
  echoes.hidden_cells = LineGenerationParams::HiddenCells::Drop;
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, echoes);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_LT(endsOff(lines[0]), 0.01);  // the band chosen again around the heavy rows: the mesh
  EXPECT_LT(lines[0].rms, 0.06);
}

TEST(LineGeneration, BandRefitLeavesAnotherObstacleBehindAlone) {
  // A second wall 0.3 m behind the first (more than split_threshold): not part of the band, and
  // with per-cluster occlusion its own line (both walls are one cluster only within max_gap).
  const auto cells = join(along({-1, 1.0}, {1, 1.0}), along({-1, 1.3}, {1, 1.3}));
  LineGenerationParams p = params();
  p.refit_cells = LineGenerationParams::RefitCells::Band;
  p.occlusion = LineGenerationParams::Occlusion::Global;
  p.hidden_cells = LineGenerationParams::HiddenCells::Drop;
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, p);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_LT(offLine(lines[0], {0, 1.0}), 0.01);
  EXPECT_LT(std::abs(std::sin(angleOf(lines[0]))), 0.01);
  EXPECT_NEAR(lines[0].seg.length(), 2.1, 1e-6);  // band cells beyond the ends: none
}

TEST(LineGeneration, PeeledLayersGiveTheSurfaceBehindItsOwnLine) {
  // A pane at y = 1.0 and, 0.3 m behind it (one cluster: closer than max_gap), a wall at y = 1.3.
  const auto cells = join(along({-1, 1.0}, {1, 1.0}), along({-1, 1.3}, {1, 1.3}));
  LineGenerationParams drop = params();
  drop.hidden_cells = LineGenerationParams::HiddenCells::Drop;
  EXPECT_EQ(generateLines(cells, {0, 0, 0}, kCell, drop).size(), 1u);  // the paper: what the robot faces
  LineGenerationParams peel = params();
  peel.hidden_cells = LineGenerationParams::HiddenCells::Peel;
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, peel);
  ASSERT_EQ(lines.size(), 2u);
  std::vector<double> ys;
  for (const AgmLine& l : lines) {
    EXPECT_LT(std::abs(std::sin(angleOf(l))), 0.01);
    EXPECT_NEAR(l.seg.length(), 2.1, 1e-6);
    ys.push_back(0.5 * (l.seg.a.y() + l.seg.b.y()));
  }
  std::sort(ys.begin(), ys.end());
  EXPECT_NEAR(ys[0], 1.0, 0.01);
  EXPECT_NEAR(ys[1], 1.3, 0.01);
  const auto runs = lineRuns(cells, {0, 0, 0}, kCell, peel);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].layer, 0);
  EXPECT_EQ(runs[1].layer, 1);
}

TEST(LineGeneration, PeelingABandTwoCellsDeepGivesOneLine) {
  // The far row of a mesh heard from both sides is in the first line's band: no second line.
  const auto cells = join(along({-1, 1.0}, {1, 1.0}), along({-1, 1.1}, {1, 1.1}));
  LineGenerationParams peel = params();
  peel.hidden_cells = LineGenerationParams::HiddenCells::Peel;
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, peel);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_LT(offLine(lines[0], {0, 1.05}), 0.01);
}

TEST(LineGeneration, PeelingEndsOnADeepBlockOfCells) {
  // 40 rows of cells behind each other, 0.15 m apart (one cluster, and no row within the
  // split_threshold of another's line): the layers stop at kMaxLineLayers.
  std::vector<CandidateCell> cells;
  for (int row = 0; row < 40; ++row) cells = join(cells, along({-0.5, 1.0 + 0.15 * row}, {0.5, 1.0 + 0.15 * row}));
  LineGenerationParams peel = params();
  peel.hidden_cells = LineGenerationParams::HiddenCells::Peel;
  peel.refit_cells = LineGenerationParams::RefitCells::Run;  // one row per layer
  const auto runs = lineRuns(cells, {0, 0, 0}, kCell, peel);
  ASSERT_FALSE(runs.empty());
  int deepest = 0;
  for (const LineRun& r : runs) deepest = std::max(deepest, r.layer);
  EXPECT_EQ(deepest, kMaxLineLayers - 1);
}

TEST(LineGeneration, WallBehindTheRobotIsNotCutAtTheBearingSeam) {
  // The robot faces +x; a wall behind it spans bearings across +-pi.
  const auto lines = generateLines(along({-1, -1}, {-1, 1}), {0, 0, 0}, kCell, params());
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].ncells, 21);
}

TEST(LineGeneration, LineSupportIsItsNewestCell) {
  auto cells = along({-1, 1}, {1, 1}, kCell, 100);
  cells[7].support = 250;
  const auto lines = generateLines(cells, {0, 0, 0}, kCell, params());
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].support, 250);
}

TEST(LineGeneration, CandidatesComeFromTheGridAboveThreshold) {
  AgmParams ap;
  ap.g_threshold = 3;
  ap.hit_centroids = true;
  AccumulativeGridMap agm(ap);
  agm.centreOn({0, 0});
  // Three hits in one cell at (1.02, 1.03): Gp 3; a single hit elsewhere stays below G_T.
  for (int i = 0; i < 3; ++i) agm.update({{1.02, 1.03}});
  agm.update({{-2.05, 0.5}});
  const auto cells = candidateCells(agm, 3, [](int64_t cycle) { return cycle * 1000; });
  ASSERT_EQ(cells.size(), 1u);
  // The evidence point is where the hits landed, not the cell centre (1.05, 1.05).
  EXPECT_NEAR(cells[0].centre.x(), 1.02, 1e-6);
  EXPECT_NEAR(cells[0].centre.y(), 1.03, 1e-6);
  EXPECT_EQ(cells[0].gp, 3);
  EXPECT_EQ(cells[0].g, 3);
  EXPECT_EQ(cells[0].support, 3000);  // last hit in cycle 3
}

TEST(LineGeneration, ConfigKeysAndErrors) {
  const auto p = lineGenerationParams(Config::fromString(
      "lines: {gp_threshold: 7, angle_bin_deg: 2, max_gap: 0.3, split_threshold: 0.05, min_cells: 4, refit: false, "
      "occlusion: global, merge: false, min_length: 0.3, refit_cells: run, refit_weights: cells, "
      "hidden_cells: drop}").section("lines"));
  EXPECT_EQ(p.gp_threshold, 7);
  EXPECT_DOUBLE_EQ(p.angle_bin_deg, 2);
  EXPECT_DOUBLE_EQ(p.max_gap, 0.3);
  EXPECT_DOUBLE_EQ(p.split_threshold, 0.05);
  EXPECT_EQ(p.min_cells, 4);
  EXPECT_FALSE(p.refit);
  EXPECT_EQ(p.occlusion, LineGenerationParams::Occlusion::Global);
  EXPECT_EQ(p.refit_cells, LineGenerationParams::RefitCells::Run);
  EXPECT_EQ(p.refit_weights, LineGenerationParams::RefitWeights::Cells);
  EXPECT_EQ(p.hidden_cells, LineGenerationParams::HiddenCells::Drop);
  EXPECT_FALSE(p.merge);
  // The defaults are the shipped configuration's.
  const LineGenerationParams d;
  EXPECT_EQ(d.occlusion, LineGenerationParams::Occlusion::PerCluster);
  EXPECT_EQ(d.refit_cells, LineGenerationParams::RefitCells::Band);
  EXPECT_EQ(d.refit_weights, LineGenerationParams::RefitWeights::Echoes);
  EXPECT_EQ(d.hidden_cells, LineGenerationParams::HiddenCells::Peel);
  EXPECT_DOUBLE_EQ(p.min_length, 0.3);
  for (const char* bad : {"lines: {max_gap: 0}", "lines: {min_cells: 1}", "lines: {angle_bin_deg: -1}",
                          "lines: {occlusion: none}", "lines: {refit: maybe}", "lines: {refit_cells: all}", "lines: {refit_weights: gp}", "lines: {hidden_cells: keep}",
                          "lines: {colour: red}"})
    EXPECT_THROW(lineGenerationParams(Config::fromString(bad).section("lines")), ConfigError) << bad;
}

TEST(CurrentSensorMap, TagsEachLineWithItsSourceAndSupport) {
  CurrentSensorMap csm;
  csm.setRadarMap({{{{0, 0}, {1, 0}}, LineSource::Sonar, 12, 0.01, 0}, {{{1, 0}, {1, 1}}, LineSource::Laser, 8, 0.01, 400}},
                  500);
  AgmLine a;
  a.seg = {{2, 2}, {3, 2}};
  a.ncells = 5;
  a.support = 450;
  csm.setAgmLines({a});
  const auto lines = csm.lines();
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].source, LineSource::Laser);  // whatever the caller said: RM lines are laser lines
  EXPECT_EQ(lines[0].last_supported_utime, 500);  // none given: the map's time
  EXPECT_EQ(lines[1].last_supported_utime, 400);
  EXPECT_EQ(lines[2].source, LineSource::Sonar);
  EXPECT_EQ(lines[2].last_supported_utime, 450);
  EXPECT_EQ(lines[2].npoints, 5);
  EXPECT_EQ(csm.radarMapUtime(), 500);
  // A new Radar Map replaces the laser lines only; new AGM lines replace the sonar lines only.
  csm.setRadarMap({}, 700);
  EXPECT_EQ(csm.laserLines().size(), 0u);
  EXPECT_EQ(csm.sonarLines().size(), 1u);
  csm.setAgmLines({});
  EXPECT_TRUE(csm.lines().empty());
}

namespace {
// The lines (their mid-point y, sorted) of a tactical map (G_T = 5, t = 1, 0.1 m cells) holding
// `hits`, seen from the origin facing +y, with the given rule for hidden cells.
std::vector<double> hiddenSupportLines(const std::vector<Vec2>& hits, LineGenerationParams::HiddenSupport s,
                                       size_t* candidates_at_1_25 = nullptr) {
  AgmParams ap;
  ap.g_threshold = 5;
  ap.t = 1;
  ap.h_max = 1000;
  AccumulativeGridMap agm(ap);
  agm.centreOn({0, 0});
  agm.update(hits);
  const auto cells = candidateCells(agm, ap.g_threshold);
  if (candidates_at_1_25)
    *candidates_at_1_25 = static_cast<size_t>(std::count_if(
        cells.begin(), cells.end(), [](const CandidateCell& c) { return std::abs(c.centre.y() - 1.25) < 0.01; }));
  LineGenerationParams p;
  p.gp_threshold = ap.g_threshold;
  p.neighbourhood = ap.t;
  p.hidden_support = s;
  std::vector<double> ys;
  for (const AgmLine& l : generateLines(cells, {0, 0, geom::kPi / 2}, agm.cellSize(), p)) {
    EXPECT_LT(std::abs(std::sin(angleOf(l))), 0.05);
    ys.push_back(0.5 * (l.seg.a.y() + l.seg.b.y()));
  }
  std::sort(ys.begin(), ys.end());
  return ys;
}
}  // namespace

TEST(LineGeneration, AHiddenCellNeedsEchoesOfItsOwn) {
  // A wall heard 4 times per cell in a band two cells deep (y = 1.05 and 1.15: the surface at
  // 1.10) and single stray echoes in the row behind it (y = 1.25, 0.15 m off the surface: more
  // than split_threshold, so no wall line takes them).
  std::vector<Vec2> wall;
  for (double x = -0.95; x < 1.0; x += 0.1)
    for (int k = 0; k < 4; ++k) wall.insert(wall.end(), {{x, 1.05}, {x, 1.15}});
  std::vector<Vec2> strays = wall;
  for (double x : {-0.55, -0.35, -0.15, 0.05, 0.25}) strays.push_back({x, 1.25});
  // The strays are candidates by their Gp: the wall's echoes in their neighbourhood.
  size_t at_1_25 = 0;
  const auto shared = hiddenSupportLines(strays, LineGenerationParams::HiddenSupport::Shared, &at_1_25);
  EXPECT_EQ(at_1_25, 5u);
  // Shared: they make a second line behind the wall's (its band refit draws it towards the
  // wall's echoes, so it lies between the strays and the wall: a surface that is not there).
  ASSERT_EQ(shared.size(), 2u);
  EXPECT_NEAR(shared[0], 1.10, 0.02);
  EXPECT_GT(shared[1], 1.14);
  EXPECT_LT(shared[1], 1.26);
  // Own: their support was the wall's echoes, which located the wall.
  const auto own = hiddenSupportLines(strays, LineGenerationParams::HiddenSupport::Own);
  ASSERT_EQ(own.size(), 1u);
  EXPECT_NEAR(own[0], 1.10, 0.02);

  // A surface 0.5 m behind the wall heard by echoes of its own (3 per cell, two rows) keeps its
  // line under both rules.
  std::vector<Vec2> behind = wall;
  for (double x = -0.95; x < 1.0; x += 0.1)
    for (int k = 0; k < 3; ++k) behind.insert(behind.end(), {{x, 1.55}, {x, 1.65}});
  for (const auto s : {LineGenerationParams::HiddenSupport::Shared, LineGenerationParams::HiddenSupport::Own}) {
    const auto ys = hiddenSupportLines(behind, s);
    ASSERT_EQ(ys.size(), 2u);
    EXPECT_NEAR(ys[0], 1.10, 0.02);
    EXPECT_NEAR(ys[1], 1.60, 0.02);
  }
}

TEST(LineGeneration, HiddenSupportIsAConfigKey) {
  Config c = Config::fromString("hidden_support: shared");
  EXPECT_EQ(lineGenerationParams(c).hidden_support, LineGenerationParams::HiddenSupport::Shared);
  EXPECT_EQ(LineGenerationParams{}.hidden_support, LineGenerationParams::HiddenSupport::Own);
  EXPECT_THROW(lineGenerationParams(Config::fromString("hidden_support: maybe")), ConfigError);
}
