// PassThrough: a remembered cell that the sonar's sound has since passed, in the core of its beam
// and where it would have answered, is emptied after clear_after firing groups; a remembered
// line met obliquely, a cell beyond the reading, beside the core or hit again in between stays.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tactical/pass_through.hpp"

using namespace lasonic;
using geom::Pose2;
using geom::Vec2;

namespace {
const double kBeam = geom::deg2rad(30);

AgmParams smallAgm() {
  AgmParams p;
  p.size = 60;
  p.cell_size = 0.10;
  p.h_max = 1000;
  p.g_threshold = 3;
  p.hit_centroids = true;
  return p;
}

PassThroughParams on() { return PassThroughParams{}; }  // the shipped rule

int gAt(const AccumulativeGridMap& agm, const Vec2& q) {
  int ix = 0, iy = 0;
  return agm.cellAt(q, ix, iy) ? agm.g(ix, iy) : -1;
}

// A remembered blob (a person who stood there): a few hits at (1.55, 0.05).
AccumulativeGridMap withBlob() {
  AccumulativeGridMap agm(smallAgm());
  agm.centreOn({0, 0});
  for (int i = 0; i < 5; ++i) agm.update({{1.55, 0.05}});
  return agm;
}
}  // namespace

TEST(PassThrough, OffTouchesNothing) {
  AccumulativeGridMap agm = withBlob();
  PassThroughParams off;
  off.core = 0;
  PassThrough pt(off);
  EXPECT_FALSE(pt.params().enabled());
  EXPECT_TRUE(PassThrough(PassThroughParams{}).params().enabled());  // shipped
  for (int i = 0; i < 5; ++i) EXPECT_EQ(pt.apply({{Pose2{0, 0, 0}, 2.5, kBeam}}, agm), 0);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
}

TEST(PassThrough, ABlobHeardThroughTwiceIsEmptied) {
  AccumulativeGridMap agm = withBlob();
  PassThrough pt(on());
  const std::vector<Sounding> group = {{Pose2{0, 0, 0}, 2.5, kBeam}};
  EXPECT_EQ(pt.apply(group, agm), 0);  // one look may have missed a weak reflector
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
  EXPECT_EQ(pt.pending(), 1u);
  EXPECT_EQ(pt.apply(group, agm), 1);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 0);
  EXPECT_EQ(pt.pending(), 0u);
}

TEST(PassThrough, TwoTransducersOfOneGroupAreOneLook) {
  AccumulativeGridMap agm = withBlob();
  PassThrough pt(on());
  EXPECT_EQ(pt.apply({{Pose2{0, 0, 0}, 2.5, kBeam}, {Pose2{0, 0.1, -0.05}, 2.5, kBeam}}, agm), 0);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
}

TEST(PassThrough, AHitInBetweenStartsTheCountAfresh) {
  AccumulativeGridMap agm = withBlob();
  PassThrough pt(on());
  const std::vector<Sounding> group = {{Pose2{0, 0, 0}, 2.5, kBeam}};
  pt.apply(group, agm);
  agm.update({{1.55, 0.05}});  // heard again: it is there after all
  EXPECT_EQ(pt.apply(group, agm), 0);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 6);
  EXPECT_EQ(pt.apply(group, agm), 1);
}

TEST(PassThrough, OnlyWhatLiesMarginNearerThanTheReadingAndInTheCore) {
  PassThrough pt(on());
  // The reading ends at the blob (1.6 m, within the 0.25 m margin): it may be the blob's echo.
  {
    AccumulativeGridMap agm = withBlob();
    for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply({{Pose2{0, 0, 0}, 1.7, kBeam}}, agm), 0);
    EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
  }
  // The blob 10 deg off the axis: outside the core (+-7.5 deg of a 30 deg beam).
  {
    AccumulativeGridMap agm = withBlob();
    const double off = std::atan2(0.05, 1.55) + geom::deg2rad(10);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply({{Pose2{0, 0, off}, 2.5, kBeam}}, agm), 0);
    EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
  }
  // Behind the transducer, or nearer than the margin (blanking): nothing.
  {
    AccumulativeGridMap agm = withBlob();
    for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply({{Pose2{3.0, 0, 0}, 2.5, kBeam}}, agm), 0);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply({{Pose2{1.45, 0.05, 0}, 2.5, kBeam}}, agm), 0);
    EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
  }
}

TEST(PassThrough, ARememberedPaneMetObliquelyStays) {
  // A pane along x = 1.5 (cells from y = -0.3 to 0.3): a line whose normal is the x axis.
  AccumulativeGridMap agm(smallAgm());
  agm.centreOn({0, 0});
  for (int i = 0; i < 4; ++i)
    for (double y = -0.25; y <= 0.26; y += 0.1) agm.update({{1.55, y}});
  Vec2 n;
  int ix = 0, iy = 0;
  ASSERT_TRUE(agm.cellAt({1.55, 0.05}, ix, iy));
  ASSERT_TRUE(rememberedLineNormal(agm, ix, iy, on(), n));
  EXPECT_NEAR(std::abs(n.x()), 1.0, 1e-6);
  PassThrough pt(on());
  // Met at 40 deg from its normal: a plane is silent there, however far the reading.
  const Vec2 from = Vec2(1.55, 0.05) - 1.2 * geom::unitVector(geom::deg2rad(40));
  const std::vector<Sounding> oblique = {{Pose2{from.x(), from.y(), geom::deg2rad(40)}, 2.5, kBeam}};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(pt.apply(oblique, agm), 0);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 4);
  // Met face-on and heard through: it is gone.
  const std::vector<Sounding> face_on = {{Pose2{0, 0.05, 0}, 2.5, kBeam}};
  pt.apply(face_on, agm);
  EXPECT_GT(pt.apply(face_on, agm), 0);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 0);
}

// A line of remembered cells is a plane only if it was heard from near its normal (within a beam
// width: a plane answers transducers within the half beam of it, and an echo lands up to a half
// beam along its arc). A person's front heard from one side can line up three cells; heard from
// 40 deg off that line's normal by two echoes or more, it is a round reflector, and a beam from
// where it answered before passes it. From elsewhere, heard within a beam width of its normal,
// or heard there once (a rough pane's scatter), the line stays. (Off in the shipped config:
// a pane's end answers from off its normal too; tests/RESULTS.md "Round lines".)
TEST(PassThrough, ALineHeardFromOffItsNormalIsNoPlaneWhereItWasHeardFrom) {
  EXPECT_FALSE(on().line_heard_at_normal);  // shipped: every line a plane
  PassThroughParams p = on();
  p.line_heard_at_normal = true;
  const Vec2 mid(1.55, 0.05);
  // Cells along x = 1.55 (a line whose normal is the x axis), every hit heard from `from`.
  const auto heardFrom = [&](PassThrough& pt, const Vec2& from, int times = 4) {
    AccumulativeGridMap agm(smallAgm());
    agm.centreOn({0, 0});
    for (int i = 0; i < times; ++i)
      for (double y = -0.25; y <= 0.26; y += 0.1) {
        pt.noteHit({1.55, y}, from, agm);
        agm.update({{1.55, y}});
      }
    return agm;
  };
  const auto lookFrom = [&](double deg) {
    const Vec2 at = mid - 1.2 * geom::unitVector(geom::deg2rad(deg));
    return std::vector<Sounding>{{Pose2{at.x(), at.y(), geom::deg2rad(deg)}, 2.5, kBeam}};
  };
  // Heard from 40 deg off its normal, looked at from there: passed twice, gone.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = heardFrom(pt, mid - 1.2 * geom::unitVector(geom::deg2rad(40)));
    int ix = 0, iy = 0;
    Vec2 n;
    ASSERT_TRUE(agm.cellAt(mid, ix, iy));
    ASSERT_TRUE(rememberedLineNormal(agm, ix, iy, p, n));  // it is a line
    EXPECT_EQ(pt.apply(lookFrom(40), agm), 0);
    EXPECT_GT(pt.apply(lookFrom(40), agm), 0);
    EXPECT_EQ(gAt(agm, mid), 0);
  }
  // The same from the other side of the normal (where it was never heard): a plane's silence.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = heardFrom(pt, mid - 1.2 * geom::unitVector(geom::deg2rad(40)));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(pt.apply(lookFrom(-40), agm), 0);
    EXPECT_EQ(gAt(agm, mid), 4);
  }
  // Heard from 25 deg off its normal (within a beam width): a plane, met at 25 deg, stays.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = heardFrom(pt, mid - 1.2 * geom::unitVector(geom::deg2rad(25)));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(pt.apply(lookFrom(25), agm), 0);
    EXPECT_EQ(gAt(agm, mid), 4);
  }
  // Heard from 40 deg off its normal once: the line stays a plane.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = heardFrom(pt, mid - 1.2 * geom::unitVector(geom::deg2rad(40)), 1);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(pt.apply(lookFrom(40), agm), 0);
    EXPECT_EQ(gAt(agm, mid), 1);
  }
  // Every line a plane (line_heard_at_normal: false, shipped): the first case stays too.
  {
    PassThrough pt(on());
    AccumulativeGridMap agm = heardFrom(pt, mid - 1.2 * geom::unitVector(geom::deg2rad(40)));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(pt.apply(lookFrom(40), agm), 0);
    EXPECT_EQ(gAt(agm, mid), 4);
  }
}

// An unverifiable reading (nothing answered within the range limit) passes a cell only from where
// the cell was heard from (within the beam's half width, 15 deg): silence from elsewhere is what a
// plane met obliquely gives.
TEST(PassThrough, SilencePassesOnlyFromWhereTheCellWasHeard) {
  const PassThroughParams p = on();
  ASSERT_TRUE(p.silence && p.heard_from_gate);
  const Vec2 blob(1.55, 0.05);
  // Heard five times from the origin's side (the transducer at (0, 0.05)).
  const auto heard = [&](PassThrough& pt) {
    AccumulativeGridMap agm(smallAgm());
    agm.centreOn({0, 0});
    for (int i = 0; i < 5; ++i) {
      pt.noteHit(blob, {0, 0.05}, agm);
      agm.update({blob});
    }
    return agm;
  };
  // Silent from 60 deg round the blob: stays.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = heard(pt);
    const Vec2 from = blob - 1.3 * geom::unitVector(geom::deg2rad(60));
    const std::vector<Sounding> silent = {{Pose2{from.x(), from.y(), geom::deg2rad(60)}, 2.2, kBeam, true}};
    for (int i = 0; i < 4; ++i) EXPECT_EQ(pt.apply(silent, agm), 0);
    EXPECT_EQ(gAt(agm, blob), 5);
    // The same reading as an echo (from beyond the blob) passes it: every echo is evidence.
    const std::vector<Sounding> echo = {{Pose2{from.x(), from.y(), geom::deg2rad(60)}, 2.2, kBeam, false}};
    pt.apply(echo, agm);
    EXPECT_EQ(pt.apply(echo, agm), 1);
    EXPECT_EQ(pt.emptiedBySilence(), 0);
  }
  // Silent from where it was heard: it answered 5 times, so after four silent looks in a row
  // ((1 - 5/9)^4 <= 0.05; three: (1 - 5/8)^3 > 0.05) it is gone.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = heard(pt);
    const std::vector<Sounding> silent = {{Pose2{0, 0.05, 0}, 2.2, kBeam, true}};
    for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply(silent, agm), 0) << i;
    EXPECT_EQ(pt.apply(silent, agm), 1);
    EXPECT_EQ(pt.emptiedBySilence(), 1);
    EXPECT_EQ(gAt(agm, blob), 0);
  }
  // A weak reflector (a mesh) that answered every other look needs many more silent looks in a
  // row; a hit in between starts them afresh.
  {
    PassThrough pt(p);
    AccumulativeGridMap agm(smallAgm());
    agm.centreOn({0, 0});
    const auto hit = [&] {
      pt.noteHit(blob, {0, 0.05}, agm);
      agm.update({blob});
    };
    hit();
    const std::vector<Sounding> silent = {{Pose2{0, 0.05, 0}, 2.2, kBeam, true}};
    for (int round = 0; round < 10; ++round) {
      EXPECT_EQ(pt.apply(silent, agm), 0) << round;
      hit();
    }
    // 11 hits and 10 silent looks before: six in a row ((1 - 11/27)^6 <= 0.05), where one that
    // answered every time needs four.
    int looks = 0;
    while (gAt(agm, blob) > 0 && looks < 50) {
      pt.apply(silent, agm);
      ++looks;
    }
    EXPECT_EQ(looks, 6);
  }
  // Without the gate, silence from anywhere in the core passes it; without notes, nothing does.
  {
    PassThroughParams ungated = p;
    ungated.heard_from_gate = false;
    PassThrough pt(ungated);
    AccumulativeGridMap agm = heard(pt);
    const Vec2 from = blob - 1.3 * geom::unitVector(geom::deg2rad(60));
    const std::vector<Sounding> silent = {{Pose2{from.x(), from.y(), geom::deg2rad(60)}, 2.2, kBeam, true}};
    pt.apply(silent, agm);
    EXPECT_EQ(pt.apply(silent, agm), 1);
  }
  {
    PassThrough pt(p);
    AccumulativeGridMap agm = withBlob();  // never noted
    const std::vector<Sounding> silent = {{Pose2{0, 0.05, 0}, 2.2, kBeam, true}};
    for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply(silent, agm), 0);
  }
}

// What is kept per cell is swept once the cells are forgotten, not at every group: 5,000 cells
// heard once and forgotten by time leave nothing behind after the next sweep.
TEST(PassThrough, ForgottenCellsAreSwept) {
  AgmParams ap = smallAgm();
  ap.size = 100;
  ap.h_max = 3;
  AccumulativeGridMap agm(ap);
  agm.centreOn({0, 0});
  PassThrough pt(on());
  std::vector<Vec2> hits;
  for (int i = 0; i < 5000; ++i) hits.emplace_back(-4.95 + 0.1 * (i % 100), -4.95 + 0.1 * (i / 100));
  for (const Vec2& h : hits) pt.noteHit(h, {0, 0}, agm);
  agm.update(hits);
  EXPECT_EQ(pt.noted(), 5000u);
  for (int i = 0; i < 20; ++i) agm.update({});
  ASSERT_EQ(gAt(agm, hits.front()), 0);  // forgotten by time
  pt.apply({{Pose2{0, 0, 0}, 2.5, kBeam}}, agm);
  EXPECT_EQ(pt.noted(), 0u);
}

TEST(PassThrough, SilentLooksNeededFollowTheAnswerRate) {
  EXPECT_EQ(silentLooksNeeded(10, 1, 0.05), 2);   // p = 10/11: (1/11)^2 <= 0.05
  EXPECT_EQ(silentLooksNeeded(5, 4, 0.05), 4);    // p = 5/9: (4/9)^4 = 0.039, (4/9)^3 = 0.088
  EXPECT_EQ(silentLooksNeeded(1, 1, 0.05), 5);    // p = 1/2: 0.5^5 = 0.031
  EXPECT_EQ(silentLooksNeeded(1, 9, 0.05), 29);   // p = 0.1: 0.9^29 = 0.047
  EXPECT_EQ(silentLooksNeeded(0, 0, 0.05), 1);    // no silence yet: p = 1
  EXPECT_EQ(silentLooksNeeded(1, 100000, 0.05), 1000);  // capped
  EXPECT_EQ(silentLooksNeeded(1, 9, 0), 1);       // 0: off (clear_after decides)
  EXPECT_GT(silentLooksNeeded(3, 7, 0.01), silentLooksNeeded(3, 7, 0.05));
}

TEST(PassThrough, MalformedSoundingsAreIgnored) {
  AccumulativeGridMap agm = withBlob();
  PassThrough pt(on());
  const double nan = std::nan("");
  const std::vector<Sounding> bad = {{Pose2{nan, 0, 0}, 2.5, kBeam},     {Pose2{0, 0, nan}, 2.5, kBeam},
                                     {Pose2{0, 0, 0}, nan, kBeam},       {Pose2{0, 0, 0}, -1.0, kBeam},
                                     {Pose2{0, 0, 0}, 1e300, kBeam},     {Pose2{0, 0, 0}, 2.5, nan},
                                     {Pose2{0, 0, 0}, 2.5, -kBeam},      {Pose2{1e12, 0, 0}, 2.5, kBeam}};
  for (int i = 0; i < 3; ++i) EXPECT_EQ(pt.apply(bad, agm), 0);
  EXPECT_EQ(gAt(agm, {1.55, 0.05}), 5);
}

TEST(PassThrough, ConfigNamesTheKey) {
  EXPECT_THROW(passThroughParams(Config::fromString("core: 2")), ConfigError);
  EXPECT_THROW(passThroughParams(Config::fromString("clear_after: 0")), ConfigError);
  EXPECT_THROW(passThroughParams(Config::fromString("cores: 0.5")), ConfigError);
  EXPECT_THROW(passThroughParams(Config::fromString("silence: maybe")), ConfigError);
  EXPECT_FALSE(passThroughParams(Config::fromString("heard_from_gate: false")).heard_from_gate);
  EXPECT_THROW(passThroughParams(Config::fromString("silence_risk: 1.5")), ConfigError);
  EXPECT_DOUBLE_EQ(passThroughParams(Config::fromString("silence_risk: 0.2")).silence_risk, 0.2);
  EXPECT_TRUE(passThroughParams(Config::fromString("line_heard_at_normal: true")).line_heard_at_normal);
  EXPECT_THROW(passThroughParams(Config::fromString("line_heard_at_normal: 2")), ConfigError);
  const PassThroughParams p = passThroughParams(Config::fromString("core: 0.4\nclear_after: 3"));
  EXPECT_DOUBLE_EQ(p.core, 0.4);
  EXPECT_EQ(p.clear_after, 3);
}
