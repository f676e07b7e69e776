#pragma once
// Laser join (beyond the paper; Jörg 1995 sec. 3.4 builds the tactical map from complementary
// echoes alone): where a laser-invisible surface continues a Radar Map line -- a glass door in a
// wall, a window, a pane held by the wall it continues -- its last stretch before the line's end
// is never heard as complementary, and the echoes of the rest are not placed at their feet.
//
// Why: the hypothetical scan (sec. 3.1) takes the nearest Radar Map point inside the ideal beam.
// A transducer facing the pane at range r has the wall's end inside its beam whenever its foot on
// the pane is within r tan(beam/2) of that end, and the wall is then as near as the pane: the echo
// is redundant, rightly (the sonar cannot tell the two apart there). And a complementary echo of
// the pane goes into the grid where crossing arcs put it, which on a plane heard along a path is
// towards the middle of what was heard. So the pane's cells stop short of the wall at both ends of
// a door, on every pass, and the tactical map keeps a gap the surface does not have.
//
// The rule: a complementary echo whose range is the transducer's perpendicular distance to the
// line through a Radar Map segment (within half a cell), with that perpendicular inside the beam
// (a plane answers from where the beam meets it face-on) and its foot beyond one of the segment's
// ends by at most r tan(beam/2) plus one cell, is the echo of a plane that continues the laser's
// line from the foot to that end: those points get the echo's hit too. A gap wider than the beam's
// footprint (a doorway beside a glass wall) is never bridged, and nothing is added alongside the
// segment itself (the laser's own business). Only segments of at least min_line_length are planes:
// the laser sees a person or a pillar as chords shorter than that.
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

struct LaserJoinParams {
  double cell_size = 0.10;  // [m] the grid's cell: the join's resolution, range tolerance (half) and margin
  // [m] the shortest Radar Map segment a plane may continue: a wall, not the chord of a person or a
  // pillar, which is never longer than they are across.
  double min_line_length = 0.5;
};

// The points (the foot, then every half cell up to the segment's end inclusive) that join the
// echo at `range` of the transducer `sensor` (position and acoustic axis; beam of full opening
// `beam_width` [rad]) to the nearest end of a Radar Map segment (`radar_map`, the same frame)
// whose plane it continues; empty when there is none. Non-finite input gives nothing.
std::vector<geom::Vec2> laserJoinPoints(const geom::Pose2& sensor, double range, double beam_width,
                                        const std::vector<geom::Segment>& radar_map, const LaserJoinParams& p);

}  // namespace lasonic
