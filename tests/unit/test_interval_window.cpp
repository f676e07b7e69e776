#include "core/interval_window.hpp"

#include <gtest/gtest.h>

namespace lasonic {
namespace {

TEST(IntervalWindow, KeepsTheLatestPositiveIntervals) {
  IntervalWindow w(3);
  EXPECT_FALSE(w.stamp(1000));  // the first stamp has no interval
  EXPECT_EQ(w.median(), 0);
  EXPECT_TRUE(w.stamp(1100));
  EXPECT_FALSE(w.stamp(1100));  // a repeat
  EXPECT_FALSE(w.stamp(900));   // backwards: nothing kept, the latest stays 1100
  EXPECT_TRUE(w.stamp(1300));   // 200 since 1100, not 400 since 900
  EXPECT_TRUE(w.stamp(1330));
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w.median(), 100);  // {100, 200, 30}
  EXPECT_TRUE(w.stamp(1730));  // 400 replaces the oldest (100): {400, 200, 30}
  EXPECT_EQ(w.size(), 3u);
  EXPECT_EQ(w.median(), 200);
}

TEST(IntervalWindow, TheMedianPassesOverOneLostAndOneLateStamp) {
  IntervalWindow w(15);
  int64_t t = 0;
  w.stamp(t);
  for (int i = 0; i < 14; ++i) {
    t += (i == 5) ? 400000 : (i == 9 ? 230000 : (i == 10 ? 170000 : 200000));  // lost, late, early
    w.stamp(t);
  }
  EXPECT_EQ(w.median(), 200000);
}

TEST(ScanPeriod, TimesTheLaserFromItsScans) {
  ScanPeriod p;
  EXPECT_EQ(p.periodUs(), 0);
  EXPECT_DOUBLE_EQ(p.scans(1.5, 0.3), 0.3);  // not timed: the seconds
  // A 2 Hz scanner: timed once three intervals are kept.
  p.scanned(1'000'000);
  p.scanned(1'500'000);
  p.scanned(2'000'000);
  EXPECT_EQ(p.periodUs(), 0);
  p.scanned(2'500'000);
  EXPECT_EQ(p.periodUs(), 500'000);
  EXPECT_DOUBLE_EQ(p.scans(1.5, 0.3), 0.75);
  EXPECT_DOUBLE_EQ(p.scans(2.5, 0.5), 1.25);
  EXPECT_DOUBLE_EQ(p.scans(0, 0.3), 0.3);    // 0: the seconds always
  EXPECT_DOUBLE_EQ(p.scans(0.1, 0.3), 0.3);  // never below the seconds
  // A lost scan (one interval of 1 s), a late one (0.6 s, then 0.4 s), a repeated and an older
  // time: still 0.5 s.
  p.scanned(3'500'000);
  p.scanned(4'100'000);
  p.scanned(4'500'000);
  p.scanned(4'500'000);
  p.scanned(4'000'000);
  p.scanned(5'000'000);
  EXPECT_EQ(p.periodUs(), 500'000);
  // The scanner switched to 10 Hz: the median follows once most of the latest intervals are.
  for (int64_t t = 5'100'000; t <= 6'500'000; t += 100'000) p.scanned(t);
  EXPECT_EQ(p.periodUs(), 100'000);
  EXPECT_DOUBLE_EQ(p.scans(1.5, 0.3), 0.3);  // a fast laser keeps the seconds
}

}  // namespace
}  // namespace lasonic
