// LookWeight: an echo counts for max(1, v / v_ref) hits (and, with a low speed, v / v_low below
// it), dithered deterministically.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "tactical/look_weight.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {
std::vector<Vec2> points(int n) {
  std::vector<Vec2> v;
  for (int i = 0; i < n; ++i) v.emplace_back(0.1 * i, 1.0);
  return v;
}
}  // namespace

TEST(LookWeight, AtOrBelowTheReferenceSpeedEveryEchoIsOneHit) {
  LookWeight w(0.4);
  for (const double v : {0.0, 0.1, 0.4, -0.3}) {
    auto hits = points(7);
    EXPECT_EQ(w.apply(hits, v), 0) << v;
    EXPECT_EQ(hits, points(7)) << v;
  }
  // Off (the paper): one hit whatever the speed.
  LookWeight off(0);
  auto hits = points(5);
  EXPECT_EQ(off.apply(hits, 3.0), 0);
  EXPECT_EQ(hits.size(), 5u);
}

TEST(LookWeight, TwiceTheReferenceSpeedCountsEveryEchoTwiceInOrder) {
  LookWeight w(0.4);
  auto hits = points(3);
  EXPECT_EQ(w.apply(hits, 0.8), 3);
  ASSERT_EQ(hits.size(), 6u);
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(hits[i], points(3)[i / 2]) << i;
  // Backwards driving counts the same.
  auto back = points(3);
  EXPECT_EQ(LookWeight(0.4).apply(back, -0.8), 3);
}

TEST(LookWeight, FractionalWeightsAverageOutAndRepeatExactly) {
  // 0.6 m/s against 0.4: 1.5 hits per echo over many echoes, the same sequence every time.
  LookWeight a(0.4), b(0.4);
  int total = 0;
  std::vector<size_t> sizes_a, sizes_b;
  for (int g = 0; g < 100; ++g) {
    auto ha = points(2), hb = points(2);
    a.apply(ha, 0.6);
    b.apply(hb, 0.6);
    total += static_cast<int>(ha.size());
    sizes_a.push_back(ha.size());
    sizes_b.push_back(hb.size());
  }
  EXPECT_EQ(sizes_a, sizes_b);
  EXPECT_NEAR(total, 300, 1);
}

TEST(LookWeight, BadSpeedsCountOneAndHugeOnesAreCapped) {
  LookWeight w(0.4);
  EXPECT_DOUBLE_EQ(w.weight(std::numeric_limits<double>::quiet_NaN()), 1.0);
  EXPECT_DOUBLE_EQ(w.weight(std::numeric_limits<double>::infinity()), 1.0);
  auto hits = points(1);
  EXPECT_EQ(w.apply(hits, 1e9), 9);  // capped at 10 x the reference
  EXPECT_EQ(LookWeight::meanSpeed({0, 0}, {1, 0}, 0.0), -1);
  EXPECT_EQ(LookWeight::meanSpeed({0, 0}, {std::numeric_limits<double>::quiet_NaN(), 0}, 1.0), -1);
  EXPECT_DOUBLE_EQ(LookWeight::meanSpeed({0, 0}, {0.3, 0.4}, 0.5), 1.0);
}

TEST(LookWeight, BelowTheLowSpeedEchoesCountLessAndStandingAddsNone) {
  // Standing (and turning on the spot): no hit at all.
  LookWeight w(0.4, 0.2);
  auto standing = points(6);
  EXPECT_EQ(w.apply(standing, 0.0), -6);
  EXPECT_TRUE(standing.empty());
  // Half the low speed: every other echo, in order, the same every time.
  LookWeight a(0.4, 0.2), b(0.4, 0.2);
  auto ha = points(6), hb = points(6);
  EXPECT_EQ(a.apply(ha, 0.1), -3);
  b.apply(hb, -0.1);  // backwards the same
  EXPECT_EQ(ha, hb);
  ASSERT_EQ(ha.size(), 3u);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(ha[i], points(6)[2 * i + 1]) << i;
  // Between the two speeds one echo is one hit; above the reference more.
  EXPECT_DOUBLE_EQ(w.weight(0.2), 1.0);
  EXPECT_DOUBLE_EQ(w.weight(0.3), 1.0);
  EXPECT_DOUBLE_EQ(w.weight(0.8), 2.0);
  // The low speed alone, without the reference.
  EXPECT_DOUBLE_EQ(LookWeight(0, 0.2).weight(0.05), 0.25);
  EXPECT_DOUBLE_EQ(LookWeight(0, 0.2).weight(3.0), 1.0);
  EXPECT_TRUE(LookWeight(0, 0.2).enabled());
  EXPECT_FALSE(LookWeight(0, 0).enabled());
  EXPECT_DOUBLE_EQ(w.weight(std::numeric_limits<double>::quiet_NaN()), 1.0);
}
