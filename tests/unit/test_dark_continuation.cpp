// darkContinuation: a straight run of returns continued into the no-return readings beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "complement/dark_continuation.hpp"
#include "complement/radar_map.hpp"

using namespace lasonic;
using namespace lasonic::complement;
using geom::Vec2;

namespace {

constexpr double kStep = 0.5 * geom::kPi / 180.0;  // 0.5 deg between readings

// What a reading at `angle` (from the sensor at the origin, facing +x) sees: a range, or nothing.
struct Ray {
  bool returned = false;
  bool rejected = false;  // malformed: neither a return nor FLAG_NO_RETURN
  double range = 0;
};

struct Scan {
  LaserScan scan;
  std::vector<uint8_t> no_return;
};

// n readings from angle_min, each given by what(angle).
template <typename F>
Scan makeScan(double angle_min, int n, F&& what, bool full_circle = false) {
  Scan s;
  s.scan.full_circle = full_circle;
  for (int i = 0; i < n; ++i) {
    const double a = angle_min + i * kStep;
    const Ray r = what(a);
    s.scan.readings.push_back({1000 + i, a, r.range, r.returned});
    s.no_return.push_back(!r.returned && !r.rejected ? 1 : 0);
  }
  return s;
}

// The robot stands at the origin facing +x.
std::optional<geom::Pose2> atOrigin(int64_t) { return geom::Pose2{}; }

std::vector<Vec2> continued(const Scan& s, double length, const PoseLookup& pose_at = atOrigin,
                            double max_incidence_deg = 80) {
  const std::vector<ScanPoint> placed = placeReadings(s.scan, pose_at);
  DarkContinuationConfig cfg;
  cfg.length = length;
  cfg.max_incidence = geom::deg2rad(max_incidence_deg);
  std::vector<Vec2> out;
  darkContinuation(s.scan, placed, s.no_return, pose_at, RadarMapConfig{}, cfg, out);
  return out;
}

// A wall along y = 1 seen for x <= x_end; beyond it the face is dark (nothing comes back), or
// (behind_m > 0) transparent, with a wall behind_m farther.
Ray wallThenDark(double a, double x_end, double behind_m = 0) {
  const double range = 1.0 / std::sin(a);
  if (range * std::cos(a) <= x_end) return {true, false, range};
  if (behind_m > 0) return {true, false, (1.0 + behind_m) / std::sin(a)};
  return {};
}

}  // namespace

// The face seen from x = -0.5 to 0.3 goes on unseen: points on its line, past its last return,
// at most `length` beyond it, one per empty reading.
TEST(DarkContinuation, AStraightRunGoesOnIntoTheEmptyReadings) {
  // Readings from 60 deg to 120 deg: the face seen where x <= 0.3 (a >= 73.3 deg), dark below.
  const Scan s = makeScan(geom::deg2rad(60), 121, [](double a) { return wallThenDark(a, 0.3); });
  const std::vector<Vec2> pts = continued(s, 0.10);
  ASSERT_FALSE(pts.empty());
  double last_seen = -1e9;
  for (const auto& r : s.scan.readings)
    if (r.valid) last_seen = std::max(last_seen, r.range * std::cos(r.angle));
  for (const Vec2& p : pts) {
    EXPECT_NEAR(p.y(), 1.0, 1e-9) << "on the face's line";
    EXPECT_GT(p.x(), last_seen) << "past its last return";
    EXPECT_LE(p.x(), last_seen + 0.10 + 1e-9) << "at most 0.10 m past it";
  }
  // At 1 m a reading every 0.5 deg meets the line about every 9 mm: 0.10 m holds 10 or 11.
  EXPECT_GE(pts.size(), 10u);
  EXPECT_LE(pts.size(), 12u);
  // Longer: more of the face.
  EXPECT_GT(continued(s, 0.30).size(), pts.size() + 15);
}

TEST(DarkContinuation, OffByDefault) {
  const Scan s = makeScan(geom::deg2rad(60), 121, [](double a) { return wallThenDark(a, 0.3); });
  EXPECT_TRUE(continued(s, 0.0).empty());
  EXPECT_EQ(DarkContinuationConfig{}.length, 0.0);
}

// Glass: the laser passes through and returns from the wall behind. Those are returns, not
// gaps, and nothing is continued (the Sector Map's sonar and memory are for glass).
TEST(DarkContinuation, AReturnFromBehindIsNotAGap) {
  const Scan s = makeScan(geom::deg2rad(60), 121, [](double a) { return wallThenDark(a, 0.3, 2.0); });
  EXPECT_TRUE(continued(s, 0.10).empty());
}

// A reading rejected as malformed says nothing about the world: it is not a gap.
TEST(DarkContinuation, ARejectedReadingIsNotAGap) {
  const Scan s = makeScan(geom::deg2rad(60), 121, [](double a) {
    Ray r = wallThenDark(a, 0.3);
    if (!r.returned) r.rejected = true;
    return r;
  });
  EXPECT_TRUE(continued(s, 0.10).empty());
}

// The gap ends where a reading returns again: the continuation stops there, and the far side's
// run is continued back into the gap too.
TEST(DarkContinuation, BothSidesOfAGapAreContinuedAndAReturnEndsIt) {
  // Face along y = 1 seen for x <= 0.3 and x >= 0.36, dark in between.
  const Scan s = makeScan(geom::deg2rad(40), 201, [](double a) {
    const double range = 1.0 / std::sin(a), x = range * std::cos(a);
    return x <= 0.3 || x >= 0.36 ? Ray{true, false, range} : Ray{};
  });
  const std::vector<Vec2> pts = continued(s, 0.10);
  ASSERT_FALSE(pts.empty());
  bool from_left = false, from_right = false;
  for (const Vec2& p : pts) {
    EXPECT_NEAR(p.y(), 1.0, 1e-9);
    EXPECT_GT(p.x(), 0.29);
    EXPECT_LT(p.x(), 0.37) << "only the empty readings";
    from_left = from_left || p.x() < 0.31;
    from_right = from_right || p.x() > 0.35;
  }
  EXPECT_TRUE(from_left);
  EXPECT_TRUE(from_right);
}

// Near its detection limit a dark face flickers: a return here and there among the empty
// readings. A return on the continued line is the same surface: the continuation goes on past it,
// up to `length` beyond it; a return off the line ends it.
TEST(DarkContinuation, AFlickerOnTheLineCarriesItOn) {
  // The face along y = 1, seen for x <= 0.3, then dark except one return at x = 0.35.
  const auto flicker = [](double off_line) {
    return makeScan(geom::deg2rad(50), 141, [off_line](double a) {
      const double range = 1.0 / std::sin(a), x = range * std::cos(a);
      if (x <= 0.3) return Ray{true, false, range};
      if (std::abs(x - 0.35) < 0.0045) return Ray{true, false, range + off_line};
      return Ray{};
    });
  };
  double farthest = -1e9;
  const std::vector<Vec2> on_line = continued(flicker(0.0), 0.10);
  for (const Vec2& p : on_line) {
    EXPECT_NEAR(p.y(), 1.0, 1e-9);
    farthest = std::max(farthest, p.x());
  }
  EXPECT_GT(farthest, 0.40) << "beyond 0.10 m past the first run";
  EXPECT_LE(farthest, 0.35 + 0.10 + 0.01) << "at most 0.10 m past the flicker";
  // The same return 0.3 m behind the face's line: something else; the gap ends there.
  farthest = -1e9;
  for (const Vec2& p : continued(flicker(0.3), 0.10)) farthest = std::max(farthest, p.x());
  EXPECT_LT(farthest, 0.351);
}

// The same flicker within the run: a face that returns only two readings in three is still one
// straight run of returns, and is continued.
TEST(DarkContinuation, AFlickeringRunIsStillARun) {
  int k = 0;
  const Scan s = makeScan(geom::deg2rad(60), 121, [&k](double a) {
    const Ray r = wallThenDark(a, 0.3);
    return r.returned && ++k % 3 == 0 ? Ray{} : r;
  });
  const std::vector<Vec2> pts = continued(s, 0.10);
  ASSERT_FALSE(pts.empty());
  double last_seen = -1e9;
  for (const auto& r : s.scan.readings)
    if (r.valid) last_seen = std::max(last_seen, r.range * std::cos(r.angle));
  int past = 0;
  for (const Vec2& p : pts) {
    EXPECT_NEAR(p.y(), 1.0, 1e-9);
    past += p.x() > last_seen ? 1 : 0;
  }
  EXPECT_GE(past, 8) << "past the face's last return";
}

// What the Radar Map would not call a segment is not continued: too few returns (a thin
// object's glint), or too short a face.
TEST(DarkContinuation, OnlyARunOfEnoughReturns) {
  // Five returns around 90 deg, then dark: fewer than the Radar Map's six.
  const Scan few = makeScan(geom::deg2rad(80), 41, [](double a) {
    return std::abs(a - geom::kPi / 2) <= 2.1 * kStep ? Ray{true, false, 1.0 / std::sin(a)} : Ray{};
  });
  EXPECT_TRUE(continued(few, 0.10).empty());
  // Eleven returns, 0.09 m of a face: enough returns, but shorter than the Radar Map's 0.15 m.
  const Scan short_run = makeScan(geom::deg2rad(80), 41, [](double a) {
    return std::abs(a - geom::kPi / 2) <= 5.5 * kStep ? Ray{true, false, 1.0 / std::sin(a)} : Ray{};
  });
  EXPECT_TRUE(continued(short_run, 0.10).empty());
}

// A corner shortly before the last return: the surface goes on the way its last straight piece
// (the Radar Map's end-point fit) runs, not along a line through the corner.
TEST(DarkContinuation, ACornerTurnsTheContinuation) {
  // Along y = 1 up to x = 0.1, then towards the robot along y = 1.1 - x (45 deg), seen to
  // x = 0.3 (0.28 m of it), dark beyond.
  const Scan bent = makeScan(geom::deg2rad(60), 121, [](double a) {
    const double c = std::cos(a), s = std::sin(a);
    double range = 1.0 / s;
    if (range * c > 0.1) range = 1.1 / (s + c);
    if (range * c > 0.3) return Ray{};
    return Ray{true, false, range};
  });
  const std::vector<Vec2> pts = continued(bent, 0.10);
  ASSERT_FALSE(pts.empty());
  for (const Vec2& p : pts) {
    EXPECT_NEAR(p.x() + p.y(), 1.1, 0.01) << "on the last piece's line (its fit may hold the corner's reading)";
    EXPECT_GT(p.x(), 0.29);
    EXPECT_LT(p.x(), 0.3 + 0.10 / std::sqrt(2.0) + 0.01);
  }
}

// A face met nearly edge-on: its line and the empty readings meet more obliquely than 80 deg
// from the normal, where an intersection says little; nothing is continued.
TEST(DarkContinuation, NotAtGrazingIncidence) {
  // The face along y = 0.1 for x in [0.4, 0.9] (seen at 6-14 deg: 76-84 deg from its normal),
  // dark beyond x = 0.9 (the readings below 6.3 deg meet it beyond 83.7 deg); a far wall above.
  const Scan s = makeScan(geom::deg2rad(1), 40, [](double a) {
    const double range = 0.1 / std::sin(a), x = range * std::cos(a);
    if (x < 0.4) return Ray{true, false, 5.0};
    if (x > 0.9) return Ray{};
    return Ray{true, false, range};
  });
  EXPECT_TRUE(continued(s, 0.10).empty());
  EXPECT_FALSE(continued(s, 0.10, atOrigin, 89.0).empty()) << "the same face, allowed up to 89 deg";
}

// The empty readings' rays are cast from where the sensor was at their own time.
TEST(DarkContinuation, RaysUseThePoseAtTheirOwnTime) {
  // The empty readings (the scan's first, below 73 deg) taken with the robot 0.05 m further
  // along -y than at the returns': their rays meet the face's line elsewhere than from the
  // origin, and still on it.
  const Scan s = makeScan(geom::deg2rad(60), 121, [](double a) { return wallThenDark(a, 0.3); });
  const int64_t first_return = [&] {
    for (const auto& r : s.scan.readings)
      if (r.valid) return r.utime;
    return int64_t{0};
  }();
  ASSERT_GT(first_return, s.scan.readings.front().utime);
  const auto moved = [first_return](int64_t t) -> std::optional<geom::Pose2> {
    return geom::Pose2{0.0, t < first_return ? -0.05 : 0.0, 0.0};
  };
  const std::vector<Vec2> from_origin = continued(s, 0.10), from_moved = continued(s, 0.10, moved);
  ASSERT_FALSE(from_moved.empty());
  for (const Vec2& p : from_moved) EXPECT_NEAR(p.y(), 1.0, 1e-9);
  EXPECT_GT(std::abs(from_moved.front().x() - from_origin.front().x()), 1e-3);
  // Without a pose for the empty readings nothing is continued.
  const auto none = [first_return](int64_t t) -> std::optional<geom::Pose2> {
    if (t < first_return) return std::nullopt;
    return geom::Pose2{};
  };
  EXPECT_TRUE(continued(s, 0.10, none).empty());
}

// A 360 deg scanner: the last reading neighbours the first.
TEST(DarkContinuation, AFullCircleWrapsAtTheSeam) {
  // 720 readings from -180 deg. A face along x = -1 (behind the robot), seen for y > 0.001 (the
  // last readings, up to +179.5 deg) and for y < -0.3, dark in between (the first readings after
  // the seam); a far wall elsewhere.
  const Scan s = makeScan(
      -geom::kPi, 720,
      [](double a) {
        const double c = std::cos(a);
        if (c > -0.5) return Ray{true, false, 5.0};
        const double range = -1.0 / c, y = range * std::sin(a);
        return y > 0.001 || y < -0.3 ? Ray{true, false, range} : Ray{};
      },
      true);
  const auto across_the_seam = [](const std::vector<Vec2>& pts) {
    int n = 0;
    for (const Vec2& p : pts) {
      EXPECT_NEAR(p.x(), -1.0, 1e-9);
      n += p.y() > -0.15 ? 1 : 0;  // continued from the seen part above y = 0
    }
    return n;
  };
  const std::vector<Vec2> pts = continued(s, 0.10);
  EXPECT_GT(across_the_seam(pts), 5);
  for (const Vec2& p : pts) EXPECT_GE(p.y(), -0.3 - 1e-9);
  Scan open = s;
  open.scan.full_circle = false;
  const std::vector<Vec2> open_pts = continued(open, 0.10);
  EXPECT_FALSE(open_pts.empty()) << "the part below y = -0.3 is continued up into the gap";
  EXPECT_EQ(across_the_seam(open_pts), 0) << "no neighbour across the ends of a partial scan";
}

// Mismatched inputs give nothing (and do not read out of bounds).
TEST(DarkContinuation, MismatchedSizesGiveNothing) {
  Scan s = makeScan(geom::deg2rad(60), 121, [](double a) { return wallThenDark(a, 0.3); });
  s.no_return.pop_back();
  EXPECT_TRUE(continued(s, 0.10).empty());
}
