// moveOntoLines: the tactical map's cells taken at their foot on the line they belong to;
// fillBetweenOnLines: the line remembered between two cells it took.
#include <gtest/gtest.h>

#include <vector>

#include "operational/remembered_on_lines.hpp"

using namespace lasonic;
using geom::Segment;
using geom::Vec2;

namespace {

// A wall along y = 1 from x = 0 to x = 2.
const std::vector<Segment> kWall = {{{0.0, 1.0}, {2.0, 1.0}}};

TEST(RememberedOnLines, BandCellsMoveOntoTheirLine) {
  // A band two cells deep: centres 0.05 m in front of and behind the surface, and one 0.12 m in
  // front (a cell of the band whose echoes landed at its far edge).
  std::vector<Vec2> p = {{0.55, 0.95}, {0.65, 1.05}, {1.25, 0.88}};
  moveOntoLines(p, kWall, 0.15);
  EXPECT_DOUBLE_EQ(p[0].x(), 0.55);
  EXPECT_DOUBLE_EQ(p[0].y(), 1.0);
  EXPECT_DOUBLE_EQ(p[1].x(), 0.65);
  EXPECT_DOUBLE_EQ(p[1].y(), 1.0);
  EXPECT_DOUBLE_EQ(p[2].x(), 1.25);
  EXPECT_DOUBLE_EQ(p[2].y(), 1.0);
}

TEST(RememberedOnLines, CellsFarFromOrBeyondALineStay) {
  std::vector<Vec2> p = {{1.0, 0.80}, {-0.05, 1.0}, {2.1, 1.02}, {5.0, 5.0}};
  const std::vector<Vec2> before = p;
  moveOntoLines(p, kWall, 0.15);
  for (size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p[i], before[i]) << i;
}

TEST(RememberedOnLines, TheNearestLineTakesTheCell) {
  // Two parallel lines 0.2 m apart (a mesh heard from both sides would be one; two surfaces are
  // two): a cell between them goes to the nearer.
  const std::vector<Segment> two = {{{0.0, 1.0}, {2.0, 1.0}}, {{0.0, 1.2}, {2.0, 1.2}}};
  std::vector<Vec2> p = {{1.0, 1.06}, {1.0, 1.14}, {1.0, 1.6}};
  EXPECT_EQ(moveOntoLines(p, two, 0.15), (std::vector<int>{0, 1, -1}));
  EXPECT_DOUBLE_EQ(p[0].y(), 1.0);
  EXPECT_DOUBLE_EQ(p[1].y(), 1.2);
}

TEST(RememberedOnLines, ADiagonalLineTakesItsFoot) {
  const std::vector<Segment> diag = {{{0.0, 0.0}, {1.0, 1.0}}};
  std::vector<Vec2> p = {{0.6, 0.4}};  // 0.141 m from the line, foot (0.5, 0.5)
  moveOntoLines(p, diag, 0.15);
  EXPECT_NEAR(p[0].x(), 0.5, 1e-12);
  EXPECT_NEAR(p[0].y(), 0.5, 1e-12);
  std::vector<Vec2> q = {{0.7, 0.3}};  // 0.283 m: stays
  moveOntoLines(q, diag, 0.15);
  EXPECT_DOUBLE_EQ(q[0].x(), 0.7);
}

TEST(RememberedOnLines, NoRadiusNoLinesOrADegenerateLineMoveNothing) {
  const std::vector<Vec2> before = {{1.0, 0.95}};
  std::vector<Vec2> p = before;
  moveOntoLines(p, kWall, 0.0);
  EXPECT_EQ(p[0], before[0]);
  moveOntoLines(p, {}, 0.15);
  EXPECT_EQ(p[0], before[0]);
  moveOntoLines(p, {{{1.0, 1.0}, {1.0, 1.0}}}, 0.15);
  EXPECT_EQ(p[0], before[0]);
}

TEST(RememberedOnLines, TheGapBetweenTwoFeetOfALineIsFilled) {
  // Three cells of a pane along y = 1: feet at x = 0.2, 0.5 and 0.55 (the last two closer than
  // a step: nothing between them), and one cell no line takes.
  std::vector<Vec2> p = {{0.5, 0.95}, {0.2, 1.05}, {0.55, 1.0}, {1.5, 1.5}};
  const std::vector<int> taken_by = moveOntoLines(p, kWall, 0.15);
  ASSERT_EQ(taken_by, (std::vector<int>{0, 0, 0, -1}));
  const std::vector<Vec2> fill = fillBetweenOnLines(p, taken_by, kWall, 0.05, 0.7);
  // 0.2 .. 0.5: 0.3 m in 6 steps of 0.05 m, the 5 points between the feet.
  ASSERT_EQ(fill.size(), 5u);
  for (size_t i = 0; i < fill.size(); ++i) {
    EXPECT_NEAR(fill[i].x(), 0.25 + 0.05 * static_cast<double>(i), 1e-12) << i;
    EXPECT_DOUBLE_EQ(fill[i].y(), 1.0) << i;
  }
}

TEST(RememberedOnLines, NothingIsFilledBeyondTheFeetAcrossLinesOrWithoutAStep) {
  // One foot per line: no gap to fill (a line's ends are not remembered beyond its cells).
  const std::vector<Segment> two = {{{0.0, 1.0}, {2.0, 1.0}}, {{0.0, 2.0}, {2.0, 2.0}}};
  std::vector<Vec2> p = {{0.2, 1.0}, {1.8, 2.0}};
  const std::vector<int> taken_by = moveOntoLines(p, two, 0.15);
  ASSERT_EQ(taken_by, (std::vector<int>{0, 1}));
  EXPECT_TRUE(fillBetweenOnLines(p, taken_by, two, 0.05, 0.7).empty());
  // Two feet on one line 1.6 m apart: a gap a 0.7 m robot drives through stays a gap; with a
  // wider bound it is filled; no step, or indices that do not match the points: nothing.
  std::vector<Vec2> q = {{0.2, 1.0}, {1.8, 1.0}};
  const std::vector<int> on_one = moveOntoLines(q, kWall, 0.15);
  EXPECT_TRUE(fillBetweenOnLines(q, on_one, kWall, 0.05, 0.7).empty());
  EXPECT_EQ(fillBetweenOnLines(q, on_one, kWall, 0.05, 2.0).size(), 31u);
  EXPECT_TRUE(fillBetweenOnLines(q, on_one, kWall, 0.0, 2.0).empty());
  EXPECT_TRUE(fillBetweenOnLines(q, {0}, kWall, 0.05, 2.0).empty());
  EXPECT_TRUE(fillBetweenOnLines(q, {0, 5}, kWall, 0.05, 2.0).empty());
}

TEST(RememberedOnLines, ADiagonalGapIsFilledAlongItsLine) {
  const std::vector<Segment> diag = {{{0.0, 0.0}, {1.0, 1.0}}};
  std::vector<Vec2> p = {{0.1, 0.1}, {0.5, 0.5}};
  const std::vector<int> taken_by = moveOntoLines(p, diag, 0.15);
  const std::vector<Vec2> fill = fillBetweenOnLines(p, taken_by, diag, 0.05, 0.7);
  // 0.566 m between the feet: 12 steps of 0.047 m, 11 points, each on the line.
  ASSERT_EQ(fill.size(), 11u);
  for (const Vec2& f : fill) {
    EXPECT_NEAR(f.x(), f.y(), 1e-12);
    EXPECT_GT(f.x(), 0.1);
    EXPECT_LT(f.x(), 0.5);
  }
}

}  // namespace
