// The last scan's shadow edges (README "Method", step 5, *A laser lost on the move*). A scan says
// that the space in front of each return is free and says nothing about what lies behind it. Seen
// from where the scanner stood, the boundary of what it saw free runs from return to return; where
// two neighbouring returns lie apart (a person in front of a wall, a wall's end), the line between
// them bounds a shadow no reading looked into, and where a return's neighbour came back empty, the
// ray beyond the return does. While the laser is lost and the robot moves on, it looks into those
// shadows from elsewhere: a sector map that takes the last scan's returns alone (moved with
// odometry) then reports the wall behind the person, or nothing, where it never saw free space.
// laserShadow() returns points along those edges, so that the sector map can report the nearest
// place the last scan did not see free. Pure: no state, no I/O.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

struct LaserShadowParams {
  // [m] points along an edge at most this far apart: a sector of 7.5 deg is 5 cm wide where it
  // begins at a robot boundary of 0.35 m, so no edge slips between two points unseen.
  double spacing = 0.05;
  // [m] no point farther than this from the scanner: the robot must drive that far, less the
  // sector map's own reach, before a point could count; the sector map takes twice its reach
  // (boundary radius + max_range).
  double reach = 6.7;
};

// Points (global frame) along the shadow edges of one scan: `points[i]` is reading i's return
// (global frame; its value does not matter where valid[i] is 0: no return), in scan order,
// `origin` the scanner's position. Between two neighbouring returns more than `spacing` apart:
// points along the segment joining them (between two returns of one surface that segment lies
// on it, and the points add nothing new); beside a reading without a return: points along the
// return's ray beyond it (an empty reading claims nothing, so that shadow is bounded by the ray).
// The last reading neighbours the first only for a full circle (a partial scanner's edges are
// where it did not look, which it never reports on). Appends to `out`.
void laserShadow(const std::vector<geom::Vec2>& points, const std::vector<uint8_t>& valid, const geom::Vec2& origin,
                 bool full_circle, const LaserShadowParams& p, std::vector<geom::Vec2>& out);

}  // namespace lasonic
