#pragma once
// Input checks shared by the stages that consume the same channels (the pilot and the navigator
// both read ODOMETRY and SONAR_COMPLEMENT): one place, one set of counter names, one limit per
// quantity. Every problem is reported on the node (counted, named field, rate-limited log) and
// never stops the stage.
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/odometry_t.hpp>

#include "core/pose_history.hpp"
#include "lcmio/node.hpp"
#include "operational/echo_placer.hpp"

namespace lasonic {

// No sonar hears this far: a complementary range beyond it is a malformed reading.
inline constexpr double kMaxEchoRange = 100.0;  // [m]

// Adds a finite ODOMETRY pose to `poses`. Non-finite fields (rejected.odometry_nan) and poses
// older than the newest (rejected.odometry_backwards) are dropped; an equal time is counted as
// odometry_duplicates. Returns true if the pose was added.
bool acceptOdometry(Node& node, PoseHistory& poses, const odometry_t& m);

// The readings of one SONAR_COMPLEMENT message as the AGM sees them. A reading with an unknown
// class (rejected.complement_class) is skipped entirely; a complementary one with a non-finite
// range or end point (rejected.complement_nan) or a range outside [0, kMaxEchoRange]
// (rejected.complement_range) stays in the group without an echo.
std::vector<GroupReading> complementGroup(Node& node, const complement_t& m);

}  // namespace lasonic
