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
//
// Between two cells that one line took, the line is the surface too: the memory holds a cell
// where an echo was placed, not every cell the surface spans (one echo answers from a patch a few
// centimetres wide), so a pane heard at a few places leaves gaps of a cell or two in the grid, and
// the sector map reports what lies behind them (through glass: the laser's far wall). The line
// says the cells on either side are one surface (the navigator splits a line at every gap the
// robot fits through), so the gap between them is filled along the line.
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

// Moves each point within `radius` (> 0) of a segment onto its foot on the nearest such segment;
// a point whose foot lies beyond a segment's ends is not taken by that segment. Zero-length
// segments take nothing. radius <= 0: nothing moves. Returns, per point, the index of the segment
// that took it, or -1.
std::vector<int> moveOntoLines(std::vector<geom::Vec2>& points, const std::vector<geom::Segment>& lines,
                               double radius);

// Points every `step` (> 0) along each segment between consecutive feet it took (`taken_by` as
// moveOntoLines returns it for `points`) that lie more than `step` and less than `max_gap` apart
// (a gap the robot could drive through is a gap: pass the robot's width); not beyond the first and
// last foot. step <= 0: none.
std::vector<geom::Vec2> fillBetweenOnLines(const std::vector<geom::Vec2>& points, const std::vector<int>& taken_by,
                                           const std::vector<geom::Segment>& lines, double step, double max_gap);

}  // namespace lasonic
