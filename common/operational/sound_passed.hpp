#pragma once
// Where a firing group's sound went with nothing answering (README "Method, as implemented",
// step 4, "Forgetting only what the sonar could have heard").
//
// A sonar's first echo comes from the nearest reflector anywhere in its beam, so a reading of
// range r says that nothing answering stood nearer than r in the beam's middle, where the
// transducer's gain is near its peak (at the beam's edge a weak reflector may stay silent). A
// grid cell there, clearly nearer than r, was heard through. The paper's AGM forgets a cell
// h_max update cycles after its last hit whatever the sonar could hear; with
// AgmParams::hold_unpassed a cell no sound went through since its last hit is kept longer
// (agm.hpp), and these are the cells some sound went through.
#include <vector>

#include "core/geometry.hpp"
#include "operational/agm.hpp"

namespace lasonic {

// One reading's sound: from the transducer (global pose, axis) out to `reach` [m] (its range, or
// the hypothesis where that is shorter; for an unverifiable reading the hypothesis, at most the
// range limit), in a beam of full width `beam_width` [rad].
struct Sounding {
  geom::Pose2 sensor;
  double reach = 0;
  double beam_width = 0;
  bool unverifiable = false;  // nothing answered within the range limit: an echo beyond it, or none
};

// Marks (AccumulativeGridMap::markPassed) every weighted cell whose centre lies within `core` of
// a sounding's beam half width of its axis and at least `margin_m` nearer than its reach (and at
// least margin_m from the transducer: the blanking). Call before the group's own hits go in.
// Returns how many cells were marked (a cell passed by two soundings counts twice).
int markSoundPassed(AccumulativeGridMap& agm, const std::vector<Sounding>& group, double core, double margin_m);

}  // namespace lasonic
