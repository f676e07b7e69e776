#pragma once
// Poles for the complement extraction (beyond the paper; Jörg 1995 sec. 3.1 predicts the ideal
// sonar from the Radar Map's lines only; a reading at a pole's distance is that pole's echo:
// complement/hypothetical_scan.hpp, poleEcho). A pipe, a post or a table leg gives the laser a few points
// but no line, so the paper's hypothesis predicts nothing there, and every sonar echo from it
// is "complementary": it goes into both AGMs as if the laser had missed it, at the sonar's
// bearing (up to half a beam off), next to the laser's own points of it.
//
// A cluster of the scan that gives no segment (RadarMap::pole_candidates) is of two kinds:
// - a pole: a small object, at the same place in the odometry frame whatever the robot's pose;
// - a glint: glass returns the laser only near normal incidence, so a pane shows a few points
//   at the foot of the perpendicular from the scanner, a foot that slides along the pane as the
//   robot moves along it. The sonar's echo from the pane face-on is exactly what the memory of
//   the pane (the tactical AGM) is built from, so a glint must not explain it.
// A candidate is a pole when a candidate of an earlier scan had its centroid within `match` of
// this one's, the robot having moved at least `baseline` across the line of sight to it since:
// a glint has then moved along the pane with the robot. Motion along the line of sight (driving
// straight at a pane) moves neither, so it decides nothing. A pole once found stays one while the
// scans see a candidate within `match` of where it was found (keep_confirmed; unseen for
// memory_s, it is forgotten): a robot that stops, or turns on the spot, moves across no line of
// sight, yet the pipe it found is still there (a glint was never found: it moved along the pane
// while the robot moved).
#include <cstdint>
#include <deque>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic::complement {

struct PoleConfig {
  // A candidate needs this many points (RadarMapConfig::pole_min_points); 0: no poles (the
  // paper). 1: a 2 cm pipe 2.5 m away falls on one of the laser's 0.5 deg rays.
  int min_points = 1;
  double match = 0.03;     // [m] centroids of one pole from two scans: the laser's 1 cm noise (2 sigma
                           // of a difference of one-point centroids) plus a post's visible face moving
                           // as the robot goes round it (5 mm for a 10 cm post seen from 1 m)
  double baseline = 0.10;  // [m] the robot's motion across the line of sight between the two scans:
                           // a glint moves as far along the pane, several times `match`
  double memory_s = 2.0;   // [s] earlier scans kept: at a cautious 0.1 m/s the robot has moved 0.2 m
  // A pole found stays one while scans see it there (none for memory_s: forgotten); false: every
  // scan needs its own baseline within memory_s.
  bool keep_confirmed = true;
};

class PoleTracker {
 public:
  explicit PoleTracker(const PoleConfig& cfg) : cfg_(cfg) {}
  // One scan: its time, the robot's position (odometry frame) and its candidate clusters (global
  // points). Returns the points of the candidates that are poles. A scan older than the newest
  // one seen (a clock that went back) starts afresh.
  std::vector<geom::Vec2> update(int64_t utime, const geom::Vec2& robot,
                                 const std::vector<std::vector<geom::Vec2>>& candidates);
  void reset() {
    history_.clear();
    found_.clear();
  }

 private:
  struct Seen {
    int64_t utime = 0;
    geom::Vec2 robot = geom::Vec2::Zero();
    std::vector<geom::Vec2> centroids;
  };
  struct Found {
    geom::Vec2 centroid = geom::Vec2::Zero();
    int64_t utime = 0;  // last seen
  };
  PoleConfig cfg_;
  std::deque<Seen> history_;
  std::vector<Found> found_;  // poles found, by centroid x
};

}  // namespace lasonic::complement
