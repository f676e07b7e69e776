// MoverPrediction: small clusters paired scan to scan; those that moved at walking speed give
// their returns a velocity, everything else stays put. SectorMap reports moving returns where
// they are at the map's time.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "operational/mover_prediction.hpp"
#include "operational/sector_map.hpp"

using namespace lasonic;
using geom::Vec2;

namespace {

constexpr int64_t kScanUs = 200'000;  // 5 Hz

// A person: returns on the near half of a circle (0.25 m) around c, seen from `from`.
void person(std::vector<TimedPoint>& scan, const Vec2& c, int64_t t, const Vec2& from = Vec2::Zero(),
            double radius = 0.25) {
  const double a0 = std::atan2(from.y() - c.y(), from.x() - c.x());
  for (int i = -6; i <= 6; ++i)
    scan.push_back({c + radius * geom::unitVector(a0 + i * 0.12), t});
}
// A wall from a to b, returns 2 cm apart.
void wall(std::vector<TimedPoint>& scan, const Vec2& a, const Vec2& b, int64_t t) {
  const int n = static_cast<int>((b - a).norm() / 0.02);
  for (int i = 0; i <= n; ++i) scan.push_back({a + (b - a) * (static_cast<double>(i) / n), t});
}

}  // namespace

TEST(MoverPrediction, AWalkingPersonGetsTheirVelocityAndTheWallNone) {
  // Three scans 0.2 s apart, the person walking at 1 m/s along +y past a wall.
  std::vector<std::vector<TimedPoint>> scans(3);
  for (int i = 0; i < 3; ++i) {
    wall(scans[i], {3, -2}, {3, 2}, i * kScanUs);
    person(scans[i], {1.5, -0.7 + 0.2 * i}, i * kScanUs);
  }
  MoverPrediction mp;
  for (const Vec2& v : mp.update(scans[0], Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());  // nothing before it
  // One pairing gives a velocity, but a single one could be jitter: not yet a mover.
  for (const Vec2& v : mp.update(scans[1], Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());
  const auto v2 = mp.update(scans[2], Vec2::Zero());
  const auto& s2 = scans[2];
  ASSERT_EQ(v2.size(), s2.size());
  int moving = 0;
  for (size_t i = 0; i < s2.size(); ++i) {
    const bool on_person = (s2[i].p - Vec2(1.5, -0.3)).norm() < 0.26;
    if (on_person) {
      // The visible half's centroid turns with the line of sight: within 0.2 m/s of the truth.
      EXPECT_NEAR(v2[i].x(), 0.0, 0.2);
      EXPECT_NEAR(v2[i].y(), 1.0, 0.2);
      ++moving;
    } else {
      EXPECT_EQ(v2[i], Vec2::Zero()) << i;
    }
  }
  EXPECT_EQ(moving, 13);
  EXPECT_EQ(mp.movers(), 1);
}

// still(): what the laser memory may keep. The wall always; a person-sized cluster only once it
// has been paired with the scan before and found slow -- never when first seen, nor while it
// walks (before it is a mover as after).
TEST(MoverPrediction, StillReturnsAreTheWallAndPairedSlowClustersOnly) {
  MoverPrediction mp;
  const auto on = [](const TimedPoint& r, const Vec2& c) { return (r.p - c).norm() < 0.26; };
  for (int i = 0; i < 4; ++i) {
    std::vector<TimedPoint> s;
    wall(s, {3, -2}, {3, 2}, i * kScanUs);
    person(s, {1.5, -0.7 + 0.2 * i}, i * kScanUs);  // walking at 1 m/s
    person(s, {1.0, 1.5}, i * kScanUs);               // standing
    mp.update(s, Vec2::Zero());
    ASSERT_EQ(mp.still().size(), s.size());
    for (size_t j = 0; j < s.size(); ++j) {
      const bool walking = on(s[j], {1.5, -0.7 + 0.2 * i}), standing = on(s[j], {1.0, 1.5});
      const bool expected = walking ? false : (standing ? i > 0 : true);
      EXPECT_EQ(mp.still()[j] != 0, expected) << "scan " << i << ", return " << j;
      // The standing person is a still cluster (kept less long by a laser memory that asks so);
      // the wall belongs to no cluster.
      if (expected) {
        EXPECT_EQ(mp.still()[j], standing ? MoverPrediction::kStillCluster : MoverPrediction::kStill)
            << "scan " << i << ", return " << j;
      }
    }
  }
}

TEST(MoverPrediction, AJitteringStaticClusterIsNoMover) {
  // A small cluster whose centroid jumps 0.1 m back and forth (an edge's mixed pixels, odometry
  // between two scans): 0.5 m/s each time, but never the same way twice.
  MoverPrediction mp;
  int movers = 0;
  for (int i = 0; i < 10; ++i) {
    std::vector<TimedPoint> s;
    person(s, {1.5, (i % 2) * 0.1}, i * kScanUs);
    mp.update(s, Vec2::Zero());
    movers += mp.movers();
  }
  EXPECT_EQ(movers, 0);
}

TEST(MoverPrediction, StandingStillTooFastOrTooFewReturnsIsNoMover) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);  // 1 cm range noise
  const auto jitter = [&](std::vector<TimedPoint> s) {
    for (auto& q : s) q.p += Vec2(noise(rng), noise(rng));
    return s;
  };
  {  // a person standing: only noise
    MoverPrediction mp;
    std::vector<TimedPoint> s1, s2;
    person(s1, {1.5, 0.5}, 0);
    person(s2, {1.5, 0.5}, kScanUs);
    mp.update(jitter(s1), Vec2::Zero());
    for (const Vec2& v : mp.update(jitter(s2), Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());
  }
  {  // 0.8 m in 0.2 s (4 m/s): not one thing moving, two things
    MoverPrediction mp;
    std::vector<TimedPoint> s1, s2;
    person(s1, {1.5, 0.5}, 0);
    person(s2, {1.5, 1.3}, kScanUs);
    mp.update(s1, Vec2::Zero());
    for (const Vec2& v : mp.update(s2, Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());
  }
  {  // two returns are no cluster
    MoverPrediction mp;
    mp.update({{{1, 0}, 0}, {{1, 0.01}, 0}}, Vec2::Zero());
    for (const Vec2& v : mp.update({{{1, 0.2}, kScanUs}, {{1, 0.21}, kScanUs}}, Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());
  }
  {  // time not advancing: no velocity
    MoverPrediction mp;
    std::vector<TimedPoint> s1, s2;
    person(s1, {1.5, 0.5}, kScanUs);
    person(s2, {1.5, 0.7}, kScanUs);
    mp.update(s1, Vec2::Zero());
    for (const Vec2& v : mp.update(s2, Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());
  }
  {  // a long wall that shifts (its visible part) is never a candidate
    MoverPrediction mp;
    std::vector<TimedPoint> s1, s2;
    wall(s1, {2, -1}, {2, 1}, 0);
    wall(s2, {2, -0.8}, {2, 1.2}, kScanUs);
    mp.update(s1, Vec2::Zero());
    for (const Vec2& v : mp.update(s2, Vec2::Zero())) EXPECT_EQ(v, Vec2::Zero());
  }
}

TEST(MoverPrediction, AStaticDrumPassedFastIsNoMover) {
  // A 0.8 m drum 0.8 m beside the path, passed at 1.2 m/s: the line of sight turns by 0.2 rad
  // between two scans and the visible half's centroid moves at ~0.4 m/s, steadily. The robot's
  // own motion explains that; told the robot stood still, the same returns would be taken for a
  // mover.
  const Vec2 drum(0, 1.2);
  std::vector<std::vector<TimedPoint>> scans(3);
  std::vector<Vec2> robot;
  for (int i = 0; i < 3; ++i) {
    robot.emplace_back(-0.24 + 0.24 * i, 0);
    person(scans[i], drum, i * kScanUs, robot.back(), 0.4);
  }
  MoverPrediction mp, fooled;
  for (int i = 0; i < 3; ++i) {
    for (const Vec2& v : mp.update(scans[i], robot[i])) EXPECT_EQ(v, Vec2::Zero()) << i;
    fooled.update(scans[i], Vec2::Zero());
  }
  EXPECT_EQ(fooled.movers(), 1);
}

TEST(MoverPrediction, TwoPeoplePassingArePairedEachWithTheirOwn) {
  MoverPrediction mp;
  std::vector<Vec2> v;
  for (int i = 0; i < 3; ++i) {
    std::vector<TimedPoint> s;
    person(s, {2.0, -1.24 + 0.24 * i}, i * kScanUs);  // +1.2 m/s
    person(s, {2.0, 1.2 - 0.2 * i}, i * kScanUs);     // -1.0 m/s
    v = mp.update(s, Vec2::Zero());
  }
  EXPECT_NEAR(v.front().y(), 1.2, 0.2);
  EXPECT_NEAR(v.back().y(), -1.0, 0.2);
  EXPECT_EQ(mp.movers(), 2);
}

// track(): the same result as runs -- one per mover, in scan order, each exactly that person's
// returns with their velocity (the wall between them in no run); update() gives each return its
// run's velocity and zero outside the runs.
TEST(MoverPrediction, TrackGivesEachMoversReturnsAsOneRun) {
  const auto scan = [](int i) {
    std::vector<TimedPoint> s;
    person(s, {2.0, -1.24 + 0.24 * i}, i * kScanUs);  // +1.2 m/s
    wall(s, {3, -0.5}, {3, 0.5}, i * kScanUs);       // 51 returns
    person(s, {2.0, 1.2 - 0.2 * i}, i * kScanUs);     // -1.0 m/s
    return s;
  };
  MoverPrediction by_runs, by_return;
  std::vector<MoverPrediction::MovingRun> runs;
  std::vector<Vec2> v;
  for (int i = 0; i < 3; ++i) {
    runs = by_runs.track(scan(i), Vec2::Zero());
    v = by_return.update(scan(i), Vec2::Zero());
  }
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].first, 0u);
  EXPECT_EQ(runs[0].last, 12u);
  EXPECT_EQ(runs[1].first, 13u + 51u);
  EXPECT_EQ(runs[1].last, 25u + 51u);
  EXPECT_NEAR(runs[0].vel.y(), 1.2, 0.2);
  EXPECT_NEAR(runs[1].vel.y(), -1.0, 0.2);
  ASSERT_EQ(v.size(), 26u + 51u);
  for (size_t j = 0; j < v.size(); ++j) {
    const MoverPrediction::MovingRun* in = nullptr;
    for (const auto& r : runs)
      if (r.first <= j && j <= r.last) in = &r;
    EXPECT_EQ(v[j], in ? in->vel : Vec2::Zero()) << j;
  }
}

// A flat face (a box's side, a piece of wall at grazing incidence) passed close by: the part in
// view moves along it as the robot drives, so its centroid slides at the robot's speed though
// the face stands. Only the motion across a flat face is seen.
TEST(MoverPrediction, AFlatFaceSlidingAlongItselfIsNoMoverButOneMovingAcrossItIs) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);  // the laser's range noise
  // The robot drives along +x at 0.8 m/s; the 0.5 m of a face at distance y_face beside it that
  // is in view is the part abreast of it.
  const auto face = [&](int i, double y_face) {
    std::vector<TimedPoint> s;
    const double x0 = 0.16 * i - 0.25;
    for (int k = 0; k <= 25; ++k) s.push_back({Vec2(x0 + 0.02 * k, y_face + noise(rng)), i * kScanUs});
    return s;
  };
  const auto robot = [](int i) { return Vec2(0.16 * i, 0); };
  MoverPrediction standing, centroid_only{[] {
    MoverPredictionParams p;
    p.flat_face_rms = 0;
    return p;
  }()};
  for (int i = 0; i < 4; ++i) {
    const std::vector<TimedPoint> s = face(i, 0.6);  // a box's side 0.6 m beside the path
    EXPECT_TRUE(standing.track(s, robot(i)).empty()) << "scan " << i;
    centroid_only.track(s, robot(i));
  }
  EXPECT_EQ(standing.movers(), 0);
  EXPECT_EQ(centroid_only.movers(), 1);  // the centroid alone: sliding at 0.8 m/s
  // The same face coming nearer at 0.5 m/s (a board carried towards the path): a mover, with
  // the velocity across it.
  MoverPrediction approaching;
  std::vector<MoverPrediction::MovingRun> runs;
  for (int i = 0; i < 4; ++i) runs = approaching.track(face(i, 1.0 - 0.1 * i), robot(i));
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_NEAR(runs[0].vel.x(), 0.0, 0.05);
  EXPECT_NEAR(runs[0].vel.y(), -0.5, 0.1);
}

TEST(MoverPrediction, BadParametersAreRejected) {
  MoverPredictionParams p;
  p.max_speed = p.min_speed;
  EXPECT_THROW(MoverPrediction{p}, std::invalid_argument);
  p = {};
  p.min_points = 1;
  EXPECT_THROW(MoverPrediction{p}, std::invalid_argument);
  p = {};
  p.agree_speed = 0;
  EXPECT_THROW(MoverPrediction{p}, std::invalid_argument);
  p = {};
  p.flat_face_rms = -0.01;
  EXPECT_THROW(MoverPrediction{p}, std::invalid_argument);
}

TEST(SectorMap, MovingReturnsAreReportedWhereTheyAreNowUpToTheHorizon) {
  AgmParams ap;
  ap.g_threshold = 2;
  AccumulativeGridMap agm(ap);
  SectorMap s({});
  const geom::Pose2 pose{0, 0, 0};
  // A return 1.5 m ahead at t = 0 moving towards the robot at 1 m/s; the map at t = 0.2 s.
  s.setLaserPoints(0, {});
  s.setLaserMovers({{{1.5, 0}, {-1, 0}, 0}}, 0.3);
  const int ahead = s.sectorOf(0.0);
  EXPECT_NEAR(s.update(200'000, pose, agm).laser[static_cast<size_t>(ahead)], 1.3 - 0.35, 1e-6);
  // At t = 0.5 s the extrapolation stops at the horizon (0.3 s): 1.2 m.
  EXPECT_NEAR(s.update(500'000, pose, agm).laser[static_cast<size_t>(ahead)], 1.2 - 0.35, 1e-6);
  // Crossing: a return at bearing +2 deg moving left at 1 m/s is two sectors over after 0.2 s.
  s.setLaserPoints(600'000, {});
  const Vec2 p = 1.5 * geom::unitVector(2 * geom::kPi / 180);
  s.setLaserMovers({{p, {0, 1}, 600'000}}, 0.3);
  const auto& m = s.update(800'000, pose, agm);
  const int now = s.sectorOf(std::atan2(p.y() + 0.2, p.x()));
  EXPECT_NE(now, s.sectorOf(2 * geom::kPi / 180));
  EXPECT_GE(m.laser[static_cast<size_t>(now)], 0.f);
  EXPECT_FLOAT_EQ(m.laser[static_cast<size_t>(s.sectorOf(2 * geom::kPi / 180))], -1.f);  // where it was: free now
  // A new scan clears the movers.
  s.setLaserPoints(900'000, {});
  for (const float d : s.update(900'000, pose, agm).laser) EXPECT_FLOAT_EQ(d, -1.f);
}
