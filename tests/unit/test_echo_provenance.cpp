// EchoProvenance: each tactical cell says whether echoes the laser could check made it, echoes it
// could not, or both, since it was last empty; the window export matches cell by cell; the
// record sheds the cells that were emptied as it grows.
#include <gtest/gtest.h>

#include <vector>

#include "tactical/echo_provenance.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {
AgmParams smallAgm(int size = 60) {
  AgmParams p;
  p.size = size;
  p.cell_size = 0.10;
  p.h_max = 1000;
  p.g_threshold = 1;
  return p;
}

int8_t at(const EchoProvenance& e, const AccumulativeGridMap& agm, const Vec2& q) {
  int ix = 0, iy = 0;
  EXPECT_TRUE(agm.cellAt(q, ix, iy));
  return e.at(agm, ix, iy);
}

// Notes each hit, then puts them into the map (as the navigator does, before update()).
void hit(EchoProvenance& e, AccumulativeGridMap& agm, const std::vector<std::pair<Vec2, bool>>& hits) {
  std::vector<Vec2> points;
  for (const auto& [p, checked] : hits) {
    e.note(p, checked, agm);
    points.push_back(p);
  }
  agm.update(points);
}
}  // namespace

TEST(EchoProvenance, EachCellSaysWhichEchoesMadeIt) {
  AccumulativeGridMap agm(smallAgm());
  agm.centreOn({0, 0});
  EchoProvenance e;
  const Vec2 a{1.05, 0.05}, b{-1.05, 0.55}, c{0.55, -1.25}, d{1.55, 1.55}, empty{-2.05, -2.05};
  hit(e, agm, {{a, true}, {b, false}, {c, false}});
  hit(e, agm, {{a, true}, {b, false}, {c, true}});
  agm.update({d});  // weight no note recorded: unknown
  EXPECT_EQ(at(e, agm, a), EchoProvenance::kChecked);
  EXPECT_EQ(at(e, agm, b), EchoProvenance::kUnchecked);
  EXPECT_EQ(at(e, agm, c), EchoProvenance::kBoth);
  EXPECT_EQ(at(e, agm, d), EchoProvenance::kUnknown);
  EXPECT_EQ(at(e, agm, empty), EchoProvenance::kUnknown);
  // A point outside the window is no cell's.
  e.note({50, 50}, false, agm);
  EXPECT_EQ(e.size(), 3u);
}

TEST(EchoProvenance, ACellEmptiedStartsAfresh) {
  AccumulativeGridMap agm(smallAgm());
  agm.centreOn({0, 0});
  EchoProvenance e;
  const Vec2 a{1.05, 0.05};
  hit(e, agm, {{a, false}});
  EXPECT_EQ(at(e, agm, a), EchoProvenance::kUnchecked);
  ASSERT_GT(agm.clearDisc(a, 0.2), 0);
  EXPECT_EQ(at(e, agm, a), EchoProvenance::kUnknown);  // empty: nothing made it
  hit(e, agm, {{a, true}});
  EXPECT_EQ(at(e, agm, a), EchoProvenance::kChecked);  // not both: the unchecked echo's weight is gone
}

TEST(EchoProvenance, TheWindowExportIsRowMajorCellByCell) {
  AccumulativeGridMap agm(smallAgm());
  agm.centreOn({0.3, -0.2});
  EchoProvenance e;
  hit(e, agm, {{{1.05, 0.05}, true}, {{-1.05, 0.55}, false}, {{0.55, -1.25}, false}, {{0.15, 0.25}, true}});
  hit(e, agm, {{{0.55, -1.25}, true}, {{2.85, 2.85}, false}});
  const int ix0 = 10, iy0 = 15, w = 30;
  std::vector<int8_t> out(3, 7);
  e.exportWindow(agm, ix0, iy0, w, out);
  ASSERT_EQ(out.size(), static_cast<size_t>(w * w));
  int recorded = 0;
  for (int jy = 0; jy < w; ++jy)
    for (int jx = 0; jx < w; ++jx) {
      const int8_t v = out[static_cast<size_t>(jy * w + jx)];
      EXPECT_EQ(v, e.at(agm, ix0 + jx, iy0 + jy)) << jx << ", " << jy;
      recorded += v != EchoProvenance::kUnknown;
    }
  EXPECT_EQ(recorded, 4);  // (2.85, 2.85) lies outside the exported window
}

TEST(EchoProvenance, TheRecordShedsEmptiedCellsAsItGrows) {
  AccumulativeGridMap agm(smallAgm(200));
  agm.centreOn({0, 0});
  EchoProvenance e;
  const auto block = [](double x0, int cols) {
    std::vector<std::pair<Vec2, bool>> cells;
    for (int i = 0; i < cols; ++i)
      for (int j = 0; j < 60; ++j) cells.push_back({{x0 + 0.1 * i, -2.95 + 0.1 * j}, false});
    return cells;
  };
  hit(e, agm, block(-6.95, 50));  // 3,000 cells
  const Vec2 kept{8.05, 8.05};
  hit(e, agm, {{kept, true}});
  ASSERT_EQ(e.size(), 3001u);
  ASSERT_EQ(agm.clearDisc({-4.5, 0}, 4.0), 3000);  // the block emptied; `kept` stays
  // 1,200 new cells in one cycle: past 4,096 entries the emptied ones are swept, not this
  // cycle's, whose weight is yet to come.
  const auto more = block(2.05, 20);
  hit(e, agm, more);
  EXPECT_EQ(e.size(), 1201u);
  EXPECT_EQ(at(e, agm, kept), EchoProvenance::kChecked);
  for (const auto& [p, checked] : more) ASSERT_EQ(at(e, agm, p), EchoProvenance::kUnchecked) << p.transpose();
}

// Two echoes of one cycle in a cell that was empty: both are what made it.
TEST(EchoProvenance, TwoEchoesOfOneCycleInAnEmptyCellMakeItTogether) {
  AccumulativeGridMap agm(smallAgm());
  agm.centreOn({0, 0});
  EchoProvenance e;
  hit(e, agm, {{{1.05, 0.05}, true}, {{1.06, 0.04}, false}});
  EXPECT_EQ(at(e, agm, {1.05, 0.05}), EchoProvenance::kBoth);
}
