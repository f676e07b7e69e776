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
  // Surface fill (beyond the paper; false: one cell per echo). A placed echo whose arc and an
  // earlier placed echo's arc (within the last arc_wait_cycles, at least 1) are tangent to one
  // line -- bearings parallel within surface_max_angle, both points within half a cell of the line
  // across them, and the foot moved along that line as far as the sensor did (on a plane it does;
  // a pole's or two poles' echoes stay put while the robot drives on), no farther apart than the
  // beam's footprint on the line (2 r tan(beam/2)) nor surface_max_gap_m -- is one plane heard
  // from two poses: the empty cells (G = 0) between the two feet get one hit each, and so do
  // those up to surface_spread_m beyond this foot, away from the earlier one. Needs
  // surface_min_agree such earlier feet. Only empty cells, at most one hit per cell and cycle, so
  // a cell gains at most one hit from the fill until it is revised.
  bool surface_fill = false;
  double surface_spread_m = 0;                    // [m]
  double surface_max_angle = geom::deg2rad(7.5);  // [rad]
  int surface_min_agree = 2;
  double surface_max_gap_m = 0.3;                 // [m]
  SonarBearingParams params;
};

// Reads the placement keys of a level's config section over `base`: agm_bearing (axis |
// neighbours), agm_placement (estimate | evidence | arc_votes), evidence_min_g, arc_halfwidth_deg,
// arc_min_votes, arc_require_votes, arc_wait_cycles, surface_fill, surface_spread_m,
// surface_max_angle_deg, surface_min_agree, surface_max_gap_m, neighbour_bearing {beam_deg, similar, max_age_s}. The caller's allowOnly() lists them. Throws ConfigError naming the key.
EchoPlacementConfig echoPlacementConfig(const Config& section, EchoPlacementConfig base = {});
// The keys echoPlacementConfig reads, for the caller's allowOnly().
std::vector<std::string> echoPlacementKeys();

// One reading of a firing group, as far as the AGM is concerned.
struct GroupReading {
  int sensor_id = 0;
  int64_t utime = 0;         // the group's firing time (also without an echo: e.utime then unset)
  bool echo = false;         // a usable complementary echo (finite, plausible range and end point)
  SonarEcho e;               // valid if echo: firing time, range, sensor pose (global frame)
  geom::Vec2 axis_end = geom::Vec2::Zero();  // the reading's end point on the acoustic axis
  // false: the echo still tells its neighbours where the nearest surface is (bearing), but
  // increments no cell (e.g. the tactical level found it explained by a later laser scan).
  bool hit = true;
  // false: the laser could not check the echo when it was heard (its arc beyond the scanner's
  // view, explained only by an earlier scan, or no recent scan at all): passed on to PlacedEcho.
  bool checked = true;
};

// An echo place() put into the grid: its point and what heard it (global frame).
struct PlacedEcho {
  geom::Vec2 point = geom::Vec2::Zero();
  geom::Pose2 sensor;     // the transducer: position and acoustic axis
  double range = 0;       // [m]
  double beam_width = 0;  // [rad] the transducer's full opening (0: the config's)
  int sensor_id = -1;
  int64_t utime = 0;      // firing time
  bool checked = true;    // GroupReading::checked
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
  // The echoes the last place() put in (waiting ones first, as in its result), each with its
  // sensor: not the surface fill's extra points, nor echoes without a finite sensor pose.
  const std::vector<PlacedEcho>& lastPlaced() const { return last_placed_; }
  // ArcVotes: how many votes each arc of the next place() adds (1 until set; 0: none). A caller
  // that knows the robot stood or turned on the spot since the previous group gives less: an arc
  // heard from where the robot already was nearly coincides with the earlier ones and crosses
  // none, so its votes would only confirm whatever cell along it the placement picked.
  void setVoteWeight(double w) { vote_weight_ = w; }

 private:
  struct Waiting {
    SonarEcho echo;
    int sensor_id = -1;
    double estimate = 0;   // [rad] its bearing estimate
    double halfwidth = 0;  // [rad] the estimate's uncertainty: where later arcs may place it
    int64_t cycle = 0;    // the AGM cycle it arrived in
    bool checked = true;
  };
  EchoPlacementConfig cfg_;
  SonarBearingTracker tracker_;
  std::vector<Waiting> waiting_;
  struct Placed {
    geom::Vec2 p;
    geom::Vec2 normal;  // unit, from the sensor to the point
    geom::Vec2 sensor;
    int64_t cycle = 0;
  };
  std::vector<Placed> placed_;  // surface fill: recently placed echoes
  double vote_weight_ = 1.0;
  std::vector<PlacedEcho> last_placed_;
  struct Latest {
    int id = 0;
    int64_t utime = 0;  // its firing
    std::optional<SonarEcho> echo;
  };
  std::vector<Latest> latest_;  // (place's scratch: each sensor's latest reading)
  // Surface fill: the extra points for the echo placed at p, heard from `sensor`, appended to `hits`.
  void spread(const geom::Vec2& sensor, double range, double beam_width, const geom::Vec2& p,
              AccumulativeGridMap& agm, std::vector<geom::Vec2>& hits);
};

}  // namespace lasonic
