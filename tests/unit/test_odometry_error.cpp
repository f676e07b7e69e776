// OdometryError against the closed forms of its random-walk model.
#include <gtest/gtest.h>

#include <cmath>

#include "core/odometry_error.hpp"

using namespace lasonic;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST(OdometryError, StraightDriveGivesDistanceAndDriftTerms) {
  const OdometryNoise n{0.01, 0.005, 0.002};
  OdometryError e(n);
  const OdometryError::Mark start = e.now();
  for (int i = 0; i < 10000; ++i) e.advance(0.001, 0);  // 10 m in 1 mm steps
  // trans^2 d + drift^2 d^3 / 3: the heading error grows along the way, its lever shrinks.
  EXPECT_NEAR(e.varianceSince(start), 1e-4 * 10 + 4e-6 * 1000 / 3, 1e-6);
  EXPECT_DOUBLE_EQ(e.varianceSince(e.now()), 0.0);
}

TEST(OdometryError, ATurnCostsOnlyByTheDistanceDrivenAfterIt) {
  const OdometryNoise n{0.0, 0.005, 0.0};  // turning only
  OdometryError e(n);
  const OdometryError::Mark before = e.now();
  e.advance(0, kPi);  // a U-turn on the spot
  EXPECT_DOUBLE_EQ(e.varianceSince(before), 0.0);  // nothing displaced yet
  const OdometryError::Mark after_turn = e.now();
  e.advance(4.0, 0);
  EXPECT_NEAR(e.varianceSince(before), 0.005 * 0.005 * kPi * 16, 1e-12);  // rot^2 |turn| L^2
  EXPECT_NEAR(e.varianceSince(after_turn), 0.0, 1e-15);  // seen after the turn: no lever
  // The same from stored marks; the sign of a turn does not matter.
  OdometryError f(n);
  const OdometryError::Mark a = f.now();
  f.advance(0, -kPi);
  f.advance(4.0, 0);
  EXPECT_NEAR(f.varianceBetween(a, f.now()), e.varianceSince(before), 1e-15);
}

TEST(OdometryError, VarianceGrowsWithTimeForEveryEarlierMark) {
  OdometryError e;
  std::vector<OdometryError::Mark> marks;
  std::vector<double> last(50, 0.0);
  for (int i = 0; i < 50; ++i) {
    marks.push_back(e.now());
    e.advance(0.1 * (i % 3), 0.05 * (i % 5));
    for (size_t k = 0; k < marks.size(); ++k) {
      const double v = e.varianceSince(marks[k]);
      EXPECT_GE(v, last[k] - 1e-15) << i << " " << k;
      if (k > 0) {
        EXPECT_LE(v, e.varianceSince(marks[k - 1]) + 1e-15);  // an older mark: farther
      }
      last[k] = v;
    }
  }
}

TEST(OdometryError, ANewModelCountsFromWhereItIsSet) {
  // 5 m with the odometry's model, then 5 m with a matched pose's (a tenth of each noise): the
  // variance is the first part's, carried by the 5 m after it, plus the second part's own.
  const OdometryNoise odo{0.01, 0.005, 0.002}, matched{0.001, 0.0005, 0.0002};
  OdometryError e(odo);
  const OdometryError::Mark start = e.now();
  for (int i = 0; i < 5000; ++i) e.advance(0.001, 0);
  const OdometryError::Mark half = e.now();
  e.setNoise(matched);
  for (int i = 0; i < 5000; ++i) e.advance(0.001, 0);
  // Heading error made in the first 5 m (drift^2 per metre) moves by the distance after it:
  // integral over s in [0, 5] of drift^2 (10 - s)^2 ds = drift^2 (1000 - 125) / 3.
  const double first = 1e-4 * 5 + 4e-6 * (1000.0 - 125.0) / 3;
  const double second = 1e-6 * 5 + 4e-8 * 125.0 / 3;
  EXPECT_NEAR(e.varianceSince(start), first + second, 1e-6);
  EXPECT_NEAR(e.varianceSince(half), second, 1e-9);
  // The whole drive with the matched model would be far less.
  EXPECT_LT(1e-6 * 10 + 4e-8 * 1000 / 3, 0.1 * (first + second));
}
