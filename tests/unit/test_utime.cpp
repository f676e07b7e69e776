// Durations in microseconds (core/utime.hpp): rounded to the nearest, never truncated, so a
// configured or computed duration is exactly itself on the messages' clock.
#include <gtest/gtest.h>

#include "core/utime.hpp"

using namespace lasonic;

TEST(Utime, SecondsRoundToTheNearestMicrosecond) {
  EXPECT_EQ(secondsToUs(0.4), 400'000);
  EXPECT_EQ(secondsToUs(0.0), 0);
  EXPECT_EQ(secondsToUs(-0.5), -500'000);
  // 4.1 * 1e6 is 4099999.9999999995 in double: a truncating cast made it 1 µs short.
  EXPECT_EQ(secondsToUs(4.1), 4'100'000);
  // Two and a half periods of a 15 Hz scanner: 166666.67 µs, the nearest is 166667.
  EXPECT_EQ(secondsToUs(2.5 / 15.0), 166'667);
  EXPECT_EQ(secondsToUs(1e6), 1'000'000'000'000);  // the longest duration the configuration allows
}

TEST(Utime, PeriodOfARate) {
  EXPECT_EQ(periodUs(2.0), 500'000);
  EXPECT_EQ(periodUs(10.0), 100'000);
  EXPECT_EQ(periodUs(15.0), 66'667);  // 66666.67
  EXPECT_EQ(periodUs(3.0), 333'333);  // 333333.33
}
