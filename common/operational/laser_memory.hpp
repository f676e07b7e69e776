#pragma once
// LaserMemory (beyond the paper, for the Sector Map's laser part, Jörg 1995 sec. 3.4; README
// "Method", step 5): what a scanner of less than a full turn saw where it no longer looks.
//
// The paper's pilot takes the laser's obstacles from the newest scan only, right for MOBOT-IV's
// 360 deg scanner. A 270 deg scanner (the Pioneer's; most robots' are 180-270 deg) is blind in a
// wedge behind the robot, and there the sector map would have only the rear sonars, which miss
// much of what is there (a 25 deg beam gives one echo, from the nearest point; an oblique wall
// often none). But everything in that wedge was in the scanner's view a moment earlier, as the
// robot drove or turned past it. So the memory keeps each scan's static returns (the moving ones,
// operational/mover_prediction.hpp, are where a person was, not where they are) and, after each
// new scan, drops those the new scan's view covers (there the newest scan decides, as in the
// paper), those older than memory_s (cluster_s for a still person-sized cluster's, when set: a
// person who stood may walk off unseen), and those beyond reach of the robot. What is left lies
// where the scanner does not look now: the sector map takes it as laser values.
//
// A full-circle scanner covers everything, so the memory stays empty and the map is the paper's,
// unless the caller's view leaves out the bearings whose readings came back empty (the pilot's
// laser_memory_dark, complement::DarkBearings): an empty reading is no free space.
// The points are in the odometry frame: their error grows with the distance driven since they
// were seen (the odometry's drift). A driving robot leaves them beyond reach first (the sector
// map's 3.35 m: ~2 cm of drift); memory_s bounds what a robot that creeps, waits or turns on
// the spot keeps: a still return that goes away unseen stays a ghost that long
// (deploy/config/lasonic.yaml). Within that bound, sound can tell (LaserMemoryHeardThrough): a
// remembered person-sized round cluster that the sonar's beams have since gone through, nothing
// answering there, is gone.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry.hpp"
#include "operational/sector_map.hpp"
#include "operational/sound_passed.hpp"
#include "core/utime.hpp"

namespace lasonic {

struct LaserMemoryParams {
  double memory_s = 0;  // [s] 0: off (the paper: the newest scan only)
  double reach = 0;     // [m] from the robot centre; farther points are dropped (0: no limit)
  // [s] a mover (a person the laser saw walking) that walked on where the scanner does not look
  // is reported where it would be by now, for this long after the laser last saw it (0: off).
  double coast_s = 0;
  // [s] returns of a still person-sized cluster (MoverPrediction::kStillCluster: a person who
  // stands, or a bin) are kept only this long: a person may walk off unseen (0: memory_s).
  double cluster_s = 0;
};

// Sound heard through a remembered still person-sized cluster (beyond the paper): a person who
// stood where the scanner does not look and walked off unseen leaves the memory's returns there
// for memory_s. But a round reflector -- a person, a post, a bin -- answers a beam that holds the
// direction to it from any side (its surface faces every direction), so when the sound of
// clear_after looks in a row went through it (the direction to the cluster's centroid within
// `core` of a reading's half beam, the reading at least margin_m longer than the centroid's
// distance, and that beyond margin_m: Sounding), it is gone, and its returns are dropped. A look
// that answered at the cluster's distance (within margin_m) starts the count again: a person
// misses a ping now and then. Round means the returns lie on a circle of min_radius to
// max_radius, within fit_rms; a flat cluster (a box's side, a piece of wall at grazing incidence)
// or a box's corner sends oblique sound away, and a thin pipe answers too weakly: their silence
// says nothing, they are never dropped so. Returns of no cluster are the memory's as above.
// clear_after 0: off.
struct LaserMemoryHeardThrough {
  int clear_after = 0;
  double core = 1.0;
  double margin_m = 0.25;
  double min_radius = 0.1;  // [m] the circle the returns lie on: a post's, a bin's, a person's
  double max_radius = 0.5;  // [m]
  double fit_rms = 0.02;    // [m] the returns within this (rms) of it
  double cluster_gap = 0.20;  // [m] returns of one cluster lie nearer than this to the next
};

class LaserMemory {
 public:
  explicit LaserMemory(const LaserMemoryParams& p = {}, const LaserMemoryHeardThrough& h = {}) : p_(p), h_(h) {}
  const LaserMemoryParams& params() const { return p_; }
  bool enabled() const { return p_.memory_s > 0; }

  // The newest scan: the time of its newest reading, the robot's position then, its static
  // returns (global frame) and its view: covers(p) is true where the new scan could have seen p.
  // Earlier scans' returns that the new view covers, that are older than memory_s (by utime) or
  // farther than reach from `robot` are dropped; this scan's returns are kept for the next.
  template <typename Covers>
  void update(int64_t utime, const geom::Vec2& robot, const std::vector<geom::Vec2>& points, Covers&& covers) {
    update(utime, robot, points, {}, covers);
  }
  // The same with the scan's movers (SectorMap::MovingPoint: where and when the laser saw them,
  // and their velocity): the earlier scans' movers, moved on by their velocity to `utime`, are
  // kept while that is outside the new view, within reach and within coast_s of when the laser
  // last saw them (coastingMovers()).
  // `cluster` (if given, one flag per point): nonzero for the returns of a still person-sized
  // cluster, kept for cluster_s only.
  template <typename Covers>
  void update(int64_t utime, const geom::Vec2& robot, const std::vector<geom::Vec2>& points,
              const std::vector<SectorMap::MovingPoint>& movers, Covers&& covers,
              const std::vector<uint8_t>* cluster = nullptr) {
    if (!enabled()) return;
    const auto max_age_us = secondsToUs(p_.memory_s);
    const auto cluster_age_us = p_.cluster_s > 0 ? secondsToUs(p_.cluster_s) : max_age_us;
    const double reach2 = p_.reach * p_.reach;
    const auto keep = [&](const Remembered& r) {
      return utime - r.utime <= (r.cluster ? cluster_age_us : max_age_us) &&
             (p_.reach <= 0 || (r.p - robot).squaredNorm() <= reach2) && !covers(r.p);
    };
    std::vector<Remembered>& kept = kept_;  // (scratch, swapped with remembered_ below)
    kept.clear();
    for (const Remembered& r : remembered_)
      if (keep(r)) kept.push_back(r);
    for (const Remembered& r : last_)
      if (keep(r)) kept.push_back(r);
    std::swap(remembered_, kept);
    points_.clear();
    points_.reserve(remembered_.size());
    for (const Remembered& r : remembered_) points_.push_back(r.p);
    last_.clear();  // (storage reused scan to scan)
    const bool flags = cluster && cluster->size() == points.size();
    for (size_t i = 0; i < points.size(); ++i) last_.push_back({points[i], utime, flags && (*cluster)[i] != 0});
    if (h_.clear_after > 0) groupClusters(utime);

    std::vector<Coasting> coasting;
    const auto coast_us = secondsToUs(p_.coast_s);
    const auto coast = [&](const Coasting& c) {
      if (utime - c.seen > coast_us) return;
      Coasting n = c;
      n.m.p = c.m.p + c.m.v * (static_cast<double>(utime - c.m.utime) * 1e-6);
      n.m.utime = utime;
      if ((p_.reach > 0 && (n.m.p - robot).squaredNorm() > reach2) || covers(n.m.p)) return;
      coasting.push_back(n);
    };
    if (p_.coast_s > 0) {
      for (const Coasting& c : coasting_) coast(c);
      for (const SectorMap::MovingPoint& m : last_movers_) coast({m, m.utime});
      last_movers_ = movers;
    }
    coasting_ = std::move(coasting);
    coasting_points_.clear();
    for (const Coasting& c : coasting_) coasting_points_.push_back(c.m);
  }
  // A firing group's sound at `utime` (LaserMemoryHeardThrough): a look at each round cluster seen
  // before utime, remembered or of the newest scan (which the next one may not cover); drops the
  // returns of those heard through clear_after times in a row. Returns how many returns were
  // dropped; points() follows.
  int heardThrough(int64_t utime, const std::vector<Sounding>& group);

  // Earlier scans' movers that walked on where the newest scan does not look, moved on to its
  // time (each keeps its velocity).
  const std::vector<SectorMap::MovingPoint>& coastingMovers() const { return coasting_points_; }

  // Forgets everything (a scanner that sees everywhere leaves nothing to remember).
  void clear() { *this = LaserMemory(p_, h_); }

  // Earlier scans' returns outside the newest scan's view (global frame), oldest scans first.
  const std::vector<geom::Vec2>& points() const { return points_; }

 private:
  struct Remembered {
    geom::Vec2 p;
    int64_t utime = 0;     // the scan's newest reading
    bool cluster = false;  // of a still person-sized cluster (cluster_s)
    uint32_t round = 0;    // LaserMemoryHeardThrough: the round cluster it belongs to (0: none)
  };
  struct Round {
    uint32_t id = 0;
    int64_t utime = 0;
    geom::Vec2 centroid = geom::Vec2::Zero();
    int silent = 0;  // looks in a row that went through it
  };
  // Splits the newest scan's cluster returns into clusters (cluster_gap), gives the round ones an
  // id, and forgets the clusters none of whose returns are left.
  void groupClusters(int64_t utime);
  // If last_[first, end) lie on a circle (LaserMemoryHeardThrough): their centroid.
  std::optional<geom::Vec2> roundCluster(size_t first, size_t end) const;
  std::vector<Round> rounds_;
  uint32_t next_round_ = 1;
  LaserMemoryParams p_;
  LaserMemoryHeardThrough h_;
  std::vector<Remembered> remembered_, kept_;
  std::vector<geom::Vec2> points_;
  std::vector<Remembered> last_;  // the newest scan's returns (in its own view: not remembered yet)
  struct Coasting {
    SectorMap::MovingPoint m;
    int64_t seen = 0;  // when the laser last saw it
  };
  std::vector<Coasting> coasting_;
  std::vector<SectorMap::MovingPoint> coasting_points_, last_movers_;
};

}  // namespace lasonic
