// LaserMemory: earlier scans' returns are kept only where the newest scan does not look, for
// memory_s and within reach; a full-circle scanner (or memory_s 0) leaves nothing to remember.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "operational/laser_memory.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

constexpr int64_t kScanUs = 100'000;  // 10 Hz

// A 270 deg scanner at `at` facing `heading`: blind within 45 deg of straight behind.
struct View270 {
  Vec2 at = Vec2::Zero();
  double heading = 0;
  bool operator()(const Vec2& p) const {
    double a = std::atan2(p.y() - at.y(), p.x() - at.x()) - heading;
    a = std::remainder(a, 2 * geom::kPi);
    return std::abs(a) <= geom::deg2rad(135.0);
  }
};
const auto kFullCircle = [](const Vec2&) { return true; };

LaserMemory memory(double memory_s, double reach = 0) { return LaserMemory({memory_s, reach}); }

}  // namespace

TEST(LaserMemory, KeepsWhatTheNewestScanNoLongerSees) {
  LaserMemory m = memory(3.0);
  // Scan 1 (facing +x) sees a wall point to the left and one ahead.
  const std::vector<Vec2> first = {{0.0, 1.0}, {2.0, 0.0}};
  m.update(0, Vec2::Zero(), first, View270{});
  EXPECT_TRUE(m.points().empty());  // the newest scan's own returns are the sector map's anyway
  // Scan 2: the robot has turned to face -y: the left point is now straight behind (blind), the
  // point ahead is at its left (seen again, so the newest scan decides there).
  m.update(kScanUs, Vec2::Zero(), {}, View270{Vec2::Zero(), -geom::kPi / 2});
  ASSERT_EQ(m.points().size(), 1u);
  EXPECT_EQ(m.points()[0], Vec2(0.0, 1.0));
  // Scan 3 faces +y: the remembered point is in view again and is dropped, whatever the scan saw.
  m.update(2 * kScanUs, Vec2::Zero(), {}, View270{Vec2::Zero(), geom::kPi / 2});
  EXPECT_TRUE(m.points().empty());
}

TEST(LaserMemory, ForgetsAfterMemorySAndBeyondReach) {
  LaserMemory m = memory(1.0, 2.0);
  const View270 facing_minus_y{Vec2::Zero(), -geom::kPi / 2};
  m.update(0, Vec2::Zero(), {{0.0, 1.0}, {0.0, 1.9}}, View270{});
  m.update(kScanUs, Vec2::Zero(), {}, facing_minus_y);
  EXPECT_EQ(m.points().size(), 2u);
  // The robot backs away along -y: the point 1.9 m ahead of where it was is now 2.2 m off.
  m.update(2 * kScanUs, {0.0, -0.3}, {}, View270{{0.0, -0.3}, -geom::kPi / 2});
  ASSERT_EQ(m.points().size(), 1u);
  EXPECT_EQ(m.points()[0], Vec2(0.0, 1.0));
  // Exactly memory_s after the scan that saw it: still kept; one microsecond later: gone.
  m.update(1'000'000, {0.0, -0.3}, {}, View270{{0.0, -0.3}, -geom::kPi / 2});
  EXPECT_EQ(m.points().size(), 1u);
  m.update(1'000'001, {0.0, -0.3}, {}, View270{{0.0, -0.3}, -geom::kPi / 2});
  EXPECT_TRUE(m.points().empty());
}

// A memory_s whose product with 1e6 lies just below the integer (4.1 s: 4099999.9999999995 µs)
// still keeps a return exactly that old: the age in microseconds is rounded, not truncated.
TEST(LaserMemory, AMemoryOf4point1SKeepsAReturnExactlyThatOld) {
  LaserMemory m = memory(4.1);
  const View270 facing_minus_y{Vec2::Zero(), -geom::kPi / 2};
  m.update(0, Vec2::Zero(), {{0.0, 1.0}}, View270{});
  m.update(4'100'000, Vec2::Zero(), {}, facing_minus_y);
  EXPECT_EQ(m.points().size(), 1u);
  m.update(4'100'001, Vec2::Zero(), {}, facing_minus_y);
  EXPECT_TRUE(m.points().empty());
}

// A still person-sized cluster's returns (flagged by the caller) are kept cluster_s, the rest
// memory_s; without cluster_s (0) or without flags, every return memory_s.
TEST(LaserMemory, AStillClusterIsKeptForClusterSOnly) {
  const View270 facing_minus_y{Vec2::Zero(), -geom::kPi / 2};
  const std::vector<Vec2> seen = {{0.0, 1.0}, {0.2, 1.5}};  // a wall point, a standing person's
  const std::vector<uint8_t> cluster = {0, 1};
  const auto none = std::vector<SectorMap::MovingPoint>{};
  for (const double cluster_s : {0.0, 1.0}) {
    LaserMemory m({30.0, 0.0, 0.0, cluster_s});
    m.update(0, Vec2::Zero(), seen, none, View270{}, &cluster);
    m.update(kScanUs, Vec2::Zero(), {}, none, facing_minus_y);
    EXPECT_EQ(m.points().size(), 2u) << "cluster_s " << cluster_s;
    m.update(1'000'001, Vec2::Zero(), {}, none, facing_minus_y);  // 1 s and 1 us after the first scan
    ASSERT_EQ(m.points().size(), cluster_s > 0 ? 1u : 2u) << "cluster_s " << cluster_s;
    EXPECT_EQ(m.points()[0], Vec2(0.0, 1.0));
    m.update(30'000'001, Vec2::Zero(), {}, none, facing_minus_y);
    EXPECT_TRUE(m.points().empty()) << "cluster_s " << cluster_s;
  }
  // Flags of another length than the points (a caller's mistake) flag nothing.
  LaserMemory m({30.0, 0.0, 0.0, 1.0});
  const std::vector<uint8_t> wrong = {1};
  m.update(0, Vec2::Zero(), seen, none, View270{}, &wrong);
  m.update(2'000'000, Vec2::Zero(), {}, none, facing_minus_y);
  EXPECT_EQ(m.points().size(), 2u);
}

TEST(LaserMemory, AFullCircleScannerOrMemoryOffRemembersNothing) {
  for (const double memory_s : {0.0, 3.0}) {
    LaserMemory m = memory(memory_s);
    for (int i = 0; i < 5; ++i) {
      const double heading = i * 1.3;
      const std::vector<Vec2> scan = {{std::cos(heading), std::sin(heading)}, {-1.0, 0.5}};
      if (memory_s > 0)
        m.update(i * kScanUs, Vec2::Zero(), scan, kFullCircle);
      else
        m.update(i * kScanUs, Vec2::Zero(), scan, View270{Vec2::Zero(), heading});
      EXPECT_TRUE(m.points().empty()) << "memory_s " << memory_s << ", scan " << i;
    }
  }
}

TEST(LaserMemory, PointsAccumulateOverScansOldestFirst) {
  // Driving along +x past a wall at y = 1 while facing +x: each scan's point abeam falls into
  // the blind wedge behind as the robot moves on.
  LaserMemory m = memory(3.0);
  for (int i = 0; i < 6; ++i) {
    const Vec2 robot(0.5 * i, 0.0);
    m.update(i * kScanUs, robot, {{robot.x() - 0.9, 1.0}}, View270{robot, 0.0});
  }
  // Scan i's point (0.5 i - 0.9, 1) is 0.4 m ahead of abeam when seen; from the next scan on it
  // lies 144.5 deg or more off the heading, in the blind wedge. Scan 5's own point is not
  // remembered yet.
  ASSERT_EQ(m.points().size(), 5u);
  for (size_t i = 0; i < 5; ++i) EXPECT_NEAR(m.points()[i].x(), 0.5 * static_cast<double>(i) - 0.9, 1e-12) << i;
}

// A person the laser saw walking at 1 m/s along -x, who walks on into the blind wedge behind a
// 270 deg scanner facing +x: reported where they would be by now, until coast_s after the laser
// last saw them; and dropped as soon as a scan's view covers where they would be.
TEST(LaserMemory, AMoverThatWalksOnWhereTheScannerDoesNotLookCoasts) {
  LaserMemory m({3.0, 0.0, 1.0});
  const Vec2 v(-1.0, 0.0);
  const SectorMap::MovingPoint seen{{-0.6, 0.5}, v, 0};  // 140 deg: already outside the view
  m.update(0, Vec2::Zero(), {}, {seen}, View270{});
  EXPECT_TRUE(m.coastingMovers().empty());  // the newest scan's own movers are the sector map's
  m.update(kScanUs, Vec2::Zero(), {}, {}, View270{});
  ASSERT_EQ(m.coastingMovers().size(), 1u);
  EXPECT_NEAR(m.coastingMovers()[0].p.x(), -0.7, 1e-12);  // moved on by 0.1 s at 1 m/s
  EXPECT_EQ(m.coastingMovers()[0].utime, kScanUs);
  EXPECT_EQ(m.coastingMovers()[0].v, v);
  m.update(1'000'000, Vec2::Zero(), {}, {}, View270{});  // 1 s after it was seen: still
  ASSERT_EQ(m.coastingMovers().size(), 1u);
  EXPECT_NEAR(m.coastingMovers()[0].p.x(), -1.6, 1e-12);
  m.update(1'000'001, Vec2::Zero(), {}, {}, View270{});
  EXPECT_TRUE(m.coastingMovers().empty());

  // Seen again at 0 s; at 0.1 s the robot has turned round (facing -x): the scanner looks where
  // the person would be, so the newest scan decides, whether it saw them or not.
  LaserMemory n({3.0, 0.0, 1.0});
  n.update(0, Vec2::Zero(), {}, {seen}, View270{});
  n.update(kScanUs, Vec2::Zero(), {}, {}, View270{Vec2::Zero(), geom::kPi});
  EXPECT_TRUE(n.coastingMovers().empty());

  // coast_s 0: nothing coasts.
  LaserMemory off({3.0, 0.0, 0.0});
  off.update(0, Vec2::Zero(), {}, {seen}, View270{});
  off.update(kScanUs, Vec2::Zero(), {}, {}, View270{});
  EXPECT_TRUE(off.coastingMovers().empty());
}

namespace {
// A transducer at the origin whose axis points at `at`, its reading `range` [m], 30 deg.
Sounding soundingAt(const Vec2& at, double range, double off_deg = 0) {
  return {{0.0, 0.0, std::atan2(at.y(), at.x()) + geom::deg2rad(off_deg)}, range, geom::deg2rad(30.0), false, range};
}
Vec2 centroidOf(const std::vector<Vec2>& p) {
  Vec2 c = Vec2::Zero();
  for (const Vec2& q : p) c += q;
  return c / static_cast<double>(p.size());
}
}  // namespace

TEST(LaserMemory, ARoundClusterTheSoundWentThroughThreeTimesInARowIsGone) {
  // Behind the robot once it faces -y: a standing person's visible half (0.25 m radius, round),
  // a box's side (flat, 0.57 m) and a wall return of no cluster.
  std::vector<Vec2> person, box;
  const Vec2 c(0.5, 1.8);
  const double toward = std::atan2(-c.y(), -c.x());
  for (int i = -7; i <= 7; ++i) person.push_back(c + 0.25 * geom::unitVector(toward + geom::deg2rad(10.0 * i)));
  for (int i = 0; i < 15; ++i) box.push_back(Vec2(-0.6, 1.5) + (i / 14.0) * Vec2(0.4, 0.4));
  std::vector<Vec2> seen = {{0.0, 1.0}};
  std::vector<uint8_t> cluster = {0};
  for (const auto* part : {&person, &box})
    for (const Vec2& p : *part) seen.push_back(p), cluster.push_back(1);
  const auto none = std::vector<SectorMap::MovingPoint>{};
  LaserMemoryHeardThrough h;
  h.clear_after = 3;
  LaserMemory m({30.0}, h);
  m.update(0, Vec2::Zero(), seen, none, View270{}, &cluster);
  m.update(kScanUs, Vec2::Zero(), {}, none, View270{Vec2::Zero(), -geom::kPi / 2});
  ASSERT_EQ(m.points().size(), seen.size());

  const Vec2 pc = centroidOf(person), bc = centroidOf(box);
  const double d = pc.norm();
  const std::vector<Sounding> through = {soundingAt(pc, 3.0), soundingAt(bc, 3.0), soundingAt({0.0, 1.0}, 3.0)};
  // Sound before the scan that saw them says nothing about them.
  EXPECT_EQ(m.heardThrough(0, through), 0);
  // Two looks through, then one that answered at the person's distance: the count starts again.
  int64_t t = 2 * kScanUs;
  EXPECT_EQ(m.heardThrough(t += 30'000, through), 0);
  EXPECT_EQ(m.heardThrough(t += 30'000, through), 0);
  EXPECT_EQ(m.heardThrough(t += 30'000, {soundingAt(pc, d - 0.05)}), 0);
  // Looks that tell nothing leave the count as it is: the beam beside it (the centroid 16 deg
  // off the axis), sound that ended well before it (something nearer answered), or no sounding.
  EXPECT_EQ(m.heardThrough(t += 30'000, through), 0);
  EXPECT_EQ(m.heardThrough(t += 30'000, {soundingAt(pc, 3.0, 16.0)}), 0);
  EXPECT_EQ(m.heardThrough(t += 30'000, {soundingAt(pc, d - 0.5)}), 0);
  EXPECT_EQ(m.heardThrough(t += 30'000, {}), 0);
  EXPECT_EQ(m.heardThrough(t += 30'000, through), 0);
  // The third look through in a row: the person is gone; the box's side (its silence is a
  // mirror's) and the wall return stay.
  EXPECT_EQ(m.heardThrough(t += 30'000, through), static_cast<int>(person.size()));
  ASSERT_EQ(m.points().size(), 1 + box.size());
  EXPECT_EQ(m.points()[0], Vec2(0.0, 1.0));
  for (const Vec2& p : m.points()) EXPECT_GT((p - pc).norm(), 0.3);
  EXPECT_EQ(m.heardThrough(t += 30'000, through), 0);
  // The memory goes on as before for the returns left.
  m.update(t, Vec2::Zero(), {}, none, View270{Vec2::Zero(), -geom::kPi / 2});
  EXPECT_EQ(m.points().size(), 1 + box.size());

  // clear_after 0 (the default): kept whatever the sound did.
  LaserMemory off({30.0});
  off.update(0, Vec2::Zero(), seen, none, View270{}, &cluster);
  off.update(kScanUs, Vec2::Zero(), {}, none, View270{Vec2::Zero(), -geom::kPi / 2});
  for (int i = 0; i < 5; ++i) EXPECT_EQ(off.heardThrough(2 * kScanUs + i * 30'000, through), 0);
  EXPECT_EQ(off.points().size(), seen.size());
}

namespace {
// The returns of a standing person (0.25 m radius) centred at `c` that a scanner at the origin
// sees (its visible half, every 10 deg), each flagged as a still person-sized cluster's.
struct SeenPerson {
  std::vector<Vec2> returns;
  std::vector<uint8_t> cluster;
  explicit SeenPerson(const Vec2& c) {
    const double toward = std::atan2(-c.y(), -c.x());
    for (int i = -7; i <= 7; ++i) returns.push_back(c + 0.25 * geom::unitVector(toward + geom::deg2rad(10.0 * i)));
    cluster.assign(returns.size(), 1);
  }
  int size() const { return static_cast<int>(returns.size()); }
};
// A memory with the shipped three looks, the person in its newest scan (at time 0).
LaserMemory memoryThatSaw(const SeenPerson& person) {
  LaserMemoryHeardThrough h;
  h.clear_after = 3;
  LaserMemory m({30.0}, h);
  m.update(0, Vec2::Zero(), person.returns, {}, View270{}, &person.cluster);
  return m;
}
}  // namespace

TEST(LaserMemory, AClusterOfTheNewestScanCanBeHeardThroughBeforeItIsRemembered) {
  // A person the robot looks away from just after the scan: its returns are the newest scan's
  // (not remembered yet) when the sound goes through; the next scan, not covering them, does not
  // bring them back.
  const SeenPerson person({0.0, 1.5});
  LaserMemory m = memoryThatSaw(person);
  const std::vector<Sounding> through = {soundingAt(centroidOf(person.returns), 3.0)};
  EXPECT_EQ(m.heardThrough(10'000, through), 0);
  EXPECT_EQ(m.heardThrough(40'000, through), 0);
  EXPECT_EQ(m.heardThrough(70'000, through), person.size());
  m.update(kScanUs, Vec2::Zero(), {}, {}, View270{Vec2::Zero(), -geom::kPi / 2});
  EXPECT_TRUE(m.points().empty());
}

TEST(LaserMemory, SilenceAtTheRangeLimitIsNoAnswer) {
  // A person's returns ~1.55 m away; the transducer's range limit (where the hypothesis stops
  // listening) 0.1 m beyond them: silence there neither answers nor went through them.
  const SeenPerson person({0.0, 1.75});
  const Vec2 pc = centroidOf(person.returns);
  Sounding silent = soundingAt(pc, pc.norm() + 0.1);
  silent.unverifiable = true;
  const std::vector<Sounding> through = {soundingAt(pc, 3.0)};
  LaserMemory m = memoryThatSaw(person);
  EXPECT_EQ(m.heardThrough(10'000, through), 0);
  EXPECT_EQ(m.heardThrough(40'000, through), 0);
  EXPECT_EQ(m.heardThrough(70'000, {silent}), 0);  // an echo there would have restarted the count
  EXPECT_EQ(m.heardThrough(100'000, through), person.size());
  // The same reading as an echo at that range is an answer.
  LaserMemory n = memoryThatSaw(person);
  silent.unverifiable = false;
  EXPECT_EQ(n.heardThrough(10'000, through), 0);
  EXPECT_EQ(n.heardThrough(40'000, through), 0);
  EXPECT_EQ(n.heardThrough(70'000, {silent}), 0);
  EXPECT_EQ(n.heardThrough(100'000, through), 0);
  EXPECT_EQ(n.heardThrough(130'000, through), 0);
  EXPECT_EQ(n.heardThrough(160'000, through), person.size());
}
