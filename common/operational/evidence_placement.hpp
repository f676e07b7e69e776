#pragma once
// Evidence placement: which ONE cell a complementary echo increments (operational AGM's sensor
// model, README "Method", step 4; beyond the paper, off with pilot.agm_placement: estimate).
//
// The trivial sensor model increments one cell at the estimated bearing, although the echo's
// true bearing may lie anywhere within +-halfwidth of it (BearingEstimate). A point obstacle
// (a 2 cm pipe) seen by two overlapping beams is put on their bisector, up to 7.5 deg (18 cm at
// 1.35 m) beside itself, in a different place from every robot pose: the AGM holds a smear, and
// its cells fall into the pipe's neighbour sectors (false alarms, copied on by the copy rule).
// Every reading's true point lies on its range arc, and so does the true obstacle: so the cell
// incremented is the one on the arc, within the bearing's uncertainty, that already holds the
// most weight G (the readings before it, from other poses, agree there), if that is at least
// min_g; otherwise the estimate's cell. Still one cell per reading, still no free-space
// clearing; what changes is the choice of the cell, by evidence the AGM holds anyway.
#include "core/geometry.hpp"
#include "operational/agm.hpp"
#include "operational/sonar_bearing.hpp"

namespace lasonic {

// Sonar-echo placements into the operational AGM.
enum class AgmPlacement { Estimate, Evidence, ArcVotes };

// The bearing (global frame) of the point to increment for an echo at `range` from `sensor`:
// the bearing in [est.bearing - est.halfwidth, est.bearing + est.halfwidth] whose arc point lies
// in the window cell of greatest G (the arc sampled at most half a cell apart; ties: the sample
// nearest to est.bearing), if that G is at least min_g (2: a cell two readings agree on; a
// single hit may be crosstalk, and would attract the next echoes); otherwise, or when
// halfwidth is 0, range not positive, or the arc longer than the window, exactly est.bearing.
double evidenceBearing(const AccumulativeGridMap& agm, const geom::Vec2& sensor, double range,
                       const BearingEstimate& est, int min_g = 2);

}  // namespace lasonic
