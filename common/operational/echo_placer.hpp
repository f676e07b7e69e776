#pragma once
// EchoPlacer: the ONE cell each complementary echo of a firing group increments (the trivial
// sensor model of the Accumulative Grid Map, Jörg 1995 sec. 3.2, with this project's bearing and
// placement refinements). Shared by the operational (pilot) and tactical (navigator) AGMs, so
// both levels put the same echo in the same place, each against its own grid's evidence.
//
// Per firing group: every usable complementary echo gets one point, at its range along
//  - Axis: the acoustic axis (the paper), or Neighbours: the bearing its overlapping neighbours'
//    latest echoes suggest (operational/sonar_bearing.hpp);
//  - Estimate: exactly that bearing, or Evidence: the bearing within its uncertainty whose arc
//    cell already holds the most weight G (operational/evidence_placement.hpp), or ArcVotes:
//    the bearing within arc_halfwidth of the axis whose cell the most recent echo arcs crossed
//    (at least arc_min_votes of them; AgmParams::arc_vote_tau), else the estimate. A real
//    transducer hears a strong near reflector beyond its nominal beam (side lobes) and a weak
//    one only near its axis, so no fixed sector says where the echo came from; but the arcs of
//    one surface or one pole, heard from several poses, cross where it is. Each echo then adds
//    its own arc's votes (after the whole group).
// Then every reading of the group becomes its sensor's latest (an echo, or none), after the whole
// group: the sensors of a group fire together and their beams never overlap, so the result does
// not depend on the readings' order.
#include <optional>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/geometry.hpp"
#include "operational/agm.hpp"
#include "operational/evidence_placement.hpp"
#include "operational/sonar_bearing.hpp"

namespace lasonic {

struct EchoPlacementConfig {
  AgmBearing bearing = AgmBearing::Neighbours;
  AgmPlacement placement = AgmPlacement::Evidence;
  int evidence_min_g = 2;  // Evidence: the least G of a cell that attracts an echo
  double arc_halfwidth = geom::deg2rad(22.5);  // [rad] ArcVotes: bearings searched and voted, +- the axis
  double arc_min_votes = 2.0;  // ArcVotes: the least (faded) votes of a cell that attracts an echo
  // ArcVotes, no cell with arc_min_votes on the echo's arc: false = the estimate's cell; true = no
  // cell at all (the echo still votes): a level that is not in a hurry waits for a second arc.
  bool arc_require_votes = false;
  // ArcVotes with arc_require_votes: how many update cycles an echo whose arc crossed no voted
  // cell waits for later arcs (retried every group, placed once a cell on its arc has
  // arc_min_votes). 0: it is dropped at once. The first echoes of a surface are as good as the
  // later ones; only their crossing arcs come later.
  int arc_wait_cycles = 0;
  SonarBearingParams params;
};

// Reads the placement keys of a level's config section over `base`: agm_bearing (axis |
// neighbours), agm_placement (estimate | evidence | arc_votes), evidence_min_g, arc_halfwidth_deg,
// arc_min_votes, arc_require_votes, arc_wait_cycles, neighbour_bearing {beam_deg, similar, max_age_s}. The caller's allowOnly() lists them. Throws ConfigError naming the key.
EchoPlacementConfig echoPlacementConfig(const Config& section, EchoPlacementConfig base = {});
// The keys echoPlacementConfig reads, for the caller's allowOnly().
std::vector<std::string> echoPlacementKeys();

// One reading of a firing group, as far as the AGM is concerned.
struct GroupReading {
  int sensor_id = 0;
  bool echo = false;         // a usable complementary echo (finite, plausible range and end point)
  SonarEcho e;               // valid if echo: firing time, range, sensor pose (global frame)
  geom::Vec2 axis_end = geom::Vec2::Zero();  // the reading's end point on the acoustic axis
  // false: the echo still tells its neighbours where the nearest surface is (bearing), but
  // increments no cell (e.g. the tactical level found it explained by a later laser scan).
  bool hit = true;
};

class EchoPlacer {
 public:
  explicit EchoPlacer(const EchoPlacementConfig& c) : cfg_(c), tracker_(c.params) {}
  const EchoPlacementConfig& config() const { return cfg_; }
  // One point per echo of the group that is a hit (global frame), in the group's order, then records the group's readings as their
  // sensors' latest. With arc_wait_cycles, first the points of waiting echoes of earlier groups
  // that later arcs now place (oldest first); agm.cycle() is the clock. An echo whose sensor pose is not finite is put at its axis end point and is
  // no neighbour to others.
  std::vector<geom::Vec2> place(const std::vector<GroupReading>& group, AccumulativeGridMap& agm);

 private:
  struct Waiting {
    SonarEcho echo;
    double estimate = 0;   // [rad] its bearing estimate
    double halfwidth = 0;  // [rad] the estimate's uncertainty: where later arcs may place it
    int64_t cycle = 0;    // the AGM cycle it arrived in
  };
  EchoPlacementConfig cfg_;
  SonarBearingTracker tracker_;
  std::vector<Waiting> waiting_;
};

}  // namespace lasonic
