#pragma once
// RememberedOnLines (beyond the paper, for the Sector Map's remembered part, Jörg 1995 sec. 3.4):
// the tactical map's occupied cells moved onto the tactical lines they belong to.
//
// A line of AGM_LINES is where the echoes of one surface agree: the navigator fits it to the band
// of cells along the surface (two cells deep, since echoes land within half a cell either side of
// it), each cell weighted by its echoes. A cell of that band, taken at its centre, stands up to a
// cell in front of the surface (or behind it); the sector map then reports the surface 0.1-0.2 m
// nearer than it is, a false alarm by the 0.10 m rule. So a cell centre within `radius` of a line
// -- its perpendicular foot on the segment -- is replaced by that foot (the nearest line's); the
// cells no line takes (too few for a line, a pole) stay where they are.
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

// Moves each point within `radius` (> 0) of a segment onto its foot on the nearest such segment;
// a point whose foot lies beyond a segment's ends is not taken by that segment. Zero-length
// segments take nothing. radius <= 0: nothing moves.
void moveOntoLines(std::vector<geom::Vec2>& points, const std::vector<geom::Segment>& lines, double radius);

}  // namespace lasonic
