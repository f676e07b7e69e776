#pragma once
// Where a firing group's sound went with nothing answering (README "Method, as implemented",
// step 4, "Forgetting only what the sonar could have heard").
//
// A sonar's first echo comes from the nearest reflector anywhere in its beam, so a reading of
// range r says that nothing answering stood nearer than r in its beam (within `core` of the half
// width: 1, the whole beam, where a reflector could answer at all). A grid cell there, clearly
// nearer than r, was heard through. The paper's AGM forgets a cell h_max update cycles after its
// last hit whatever the sonar heard; with AgmParams::hold_unpassed a cell no sound went through
// since its last hit is kept longer (agm.hpp): one the beam still hears at about its range (a
// surface passed by a moving robot answers from a new point, on a new cell, each firing), or one
// no beam reached. These functions mark the cells sound went through, and those a person the
// laser sees walking may have made (their echoes' cells are the paper's to forget).
#include <vector>

#include "core/geometry.hpp"
#include "operational/agm.hpp"
#include "operational/sector_map.hpp"

namespace lasonic {

// One reading's sound: from the transducer (global pose, axis) out to `reach` [m] (its range, or
// the hypothesis where that is shorter; for an unverifiable reading the hypothesis, at most the
// range limit), in a beam of full width `beam_width` [rad].
struct Sounding {
  geom::Pose2 sensor;
  double reach = 0;
  double beam_width = 0;
  bool unverifiable = false;  // nothing answered within the range limit: an echo beyond it, or none
  // The reading's own range (an unverifiable one's: its reach): where something answered,
  // whatever the laser's surfaces say about mirrors (LaserMemory::heardThrough).
  double range = 0;
};

// Marks (AccumulativeGridMap::markPassed) every weighted cell whose centre lies within `core` of
// a sounding's beam half width of its axis and at least `margin_m` nearer than its reach (and at
// least margin_m from the transducer: the blanking). Call before the group's own hits go in.
// Returns how many cells were marked (a cell passed by two soundings counts twice).
// at_range: cells up to margin_m beyond the reach too (the range the reading answered from: a
// reflector in such a cell would have answered about then, so the beam reached it, whatever did
// answer; only cells no beam reached -- between beams, behind a nearer echo -- stay unmarked).
int markSoundPassed(AccumulativeGridMap& agm, const std::vector<Sounding>& group, double core, double margin_m,
                    bool at_range = false);

// Marks every window cell whose centre lies within `radius` of one of `points` (the laser's
// returns of a person it sees walking): an echo that made such a cell may have been that person,
// so the cell is forgotten after h_max as the paper's, not kept. Returns how many were marked.
int markNearMovers(AccumulativeGridMap& agm, const std::vector<geom::Vec2>& points, double radius);
// The same for the returns the mover prediction took out of a scan (their positions).
int markNearMovers(AccumulativeGridMap& agm, const std::vector<SectorMap::MovingPoint>& movers, double radius);

}  // namespace lasonic
