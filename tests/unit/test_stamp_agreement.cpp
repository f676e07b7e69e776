// StampAgreement: a sensor's message times against the odometry's (README "Clocks").
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "core/stamp_agreement.hpp"

using namespace lasonic;

namespace {

// Odometry every 20 ms and a sensor datum every 200 ms for `seconds`; the datum stamped
// `offset_us` later by the sensor's clock than by the odometry's and handled `latency_us` after
// it was measured, when the newest odometry is the last one at or before that. Returns the
// findings.
std::vector<StampAgreement::Finding> run(StampAgreement& s, int64_t offset_us, int64_t latency_us, double seconds,
                                         int64_t t0 = 1'000'000, int64_t listening_us = 0) {
  std::vector<StampAgreement::Finding> out;
  const int64_t end = t0 + static_cast<int64_t>(seconds * 1e6);
  int64_t odo = t0;
  s.noteOdometry(odo);
  for (int64_t t = t0 + 200'000; t < end; t += 200'000) {
    while (odo + 20'000 <= t + latency_us) s.noteOdometry(odo += 20'000);
    if (const auto f = s.check(t + offset_us, odo, listening_us)) out.push_back(*f);
  }
  return out;
}

}  // namespace

TEST(StampAgreement, OneClockWithTheUsualLatencyGivesNoFinding) {
  StampAgreement s;
  EXPECT_TRUE(run(s, 0, 0, 30).empty());                // handled at once: odometry up to a period older
  EXPECT_TRUE(run(s, 0, 10'000, 30, 40'000'000).empty());  // transport
}

TEST(StampAgreement, AClockAheadIsFoundAtOnceAndThenOncePerWindow) {
  StampAgreement s;
  const auto f = run(s, 80'000, 5'000, 12);  // data from 1.2 s: windows begin at 1.2, 6.2 and 11.2 s
  ASSERT_EQ(f.size(), 3u);
  for (const auto& x : f) {
    EXPECT_TRUE(x.ahead);
    EXPECT_EQ(x.offset_us, 80'000);
    EXPECT_EQ(x.odometry_period_us, 20'000);
  }
  // Within one odometry period plus the margin: nothing.
  StampAgreement t;
  EXPECT_TRUE(run(t, 35'000, 0, 12).empty());
}

TEST(StampAgreement, SlowOdometryAllowsDataAheadOfItByAPeriod) {
  // 10 Hz odometry (a Pioneer's): a scan 60 ms after the newest odometry is on time ...
  StampAgreement slow, fast;
  int found_slow = 0, found_fast = 0;
  for (int64_t odo = 0; odo < 3'000'000; odo += 100'000) {
    slow.noteOdometry(odo);
    found_slow += slow.check(odo + 60'000, odo).has_value();
  }
  // ... but 40 ms beyond the period of 50 Hz odometry it is not.
  for (int64_t odo = 0; odo < 3'000'000; odo += 20'000) {
    fast.noteOdometry(odo);
    if (odo % 100'000 == 0) found_fast += fast.check(odo + 60'000, odo).has_value();
  }
  EXPECT_EQ(found_slow, 0);
  EXPECT_EQ(found_fast, 1);
}

TEST(StampAgreement, AClockBehindIsTheWindowsSmallestLag) {
  StampAgreement s;
  const auto f = run(s, -80'000, 3'000, 12);
  ASSERT_EQ(f.size(), 2u);  // at the end of the windows that began at 1.2 and 6.2 s
  for (const auto& x : f) {
    EXPECT_FALSE(x.ahead);
    EXPECT_EQ(x.offset_us, 80'000);
  }
  // One late message among prompt ones is a delay, not a clock: the window's smallest lag is small.
  StampAgreement t;
  std::vector<StampAgreement::Finding> late;
  for (int64_t k = 0; k < 60; ++k) {
    const int64_t at = 1'000'000 + k * 200'000;
    if (const auto x = t.check(at, at + (k == 10 ? 400'000 : 2'000))) late.push_back(*x);
  }
  EXPECT_TRUE(late.empty());
  // A few late messages are no stream: two of them 5 s apart say nothing about a clock.
  StampAgreement u;
  EXPECT_FALSE(u.check(1'000'000, 1'100'000).has_value());
  EXPECT_FALSE(u.check(6'000'000, 6'100'000).has_value());
}

TEST(StampAgreement, ASonarsListeningTimeIsNoLag) {
  StampAgreement a, b;
  EXPECT_EQ(run(a, 0, 45'000, 12).size(), 2u);                  // 40 ms late: behind, or a slow link
  EXPECT_TRUE(run(b, 0, 45'000, 12, 1'000'000, 30'000).empty());  // 30 ms of it the echoes' flight
}

TEST(StampAgreement, OdometryTimeGoingBackStartsAWindowAfresh) {
  StampAgreement s;
  EXPECT_TRUE(run(s, -80'000, 0, 4).empty());          // one window, not yet ended
  EXPECT_TRUE(run(s, -80'000, 0, 4, 500'000).empty());  // back in time: a new window
  EXPECT_EQ(run(s, -80'000, 0, 6, 500'000).size(), 1u);
  s.reset();
  EXPECT_TRUE(run(s, -80'000, 0, 4).empty());
}

TEST(StampAgreement, DescribesTheChannelTheSignAndTheOffset) {
  const StampAgreement s;
  const std::string a = s.describe({true, 75'000, 20'000}, "LASER_SCAN");
  EXPECT_NE(a.find("LASER_SCAN stamped 75 ms later than the newest ODOMETRY (which comes every 20 ms)"),
            std::string::npos) << a;
  EXPECT_NE(a.find("ahead"), std::string::npos);
  const std::string b = s.describe({false, 83'000, 20'000}, "SONAR_RING");
  EXPECT_NE(b.find("SONAR_RING at least 83 ms older"), std::string::npos) << b;
  EXPECT_NE(b.find("for 5 s"), std::string::npos);
  EXPECT_NE(b.find("behind"), std::string::npos);
}
