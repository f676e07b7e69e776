#pragma once
// Dark continuation (beyond the paper, for the Sector Map's laser part, README "Method", step 5):
// a surface the scan sees up to a reading after which nothing comes back is taken to go on a
// little way into those empty readings.
//
// A reading with no return is not free space. A wall or a person in a room is seen up to 15 m;
// what returns nothing indoors is a surface too dark to be detected at that range and incidence
// (black cardboard, 3 % remission, is seen only up to 2.7 m head-on and less obliquely, README
// "Sensor models"). So where a straight run of returns ends in no-return readings, the surface
// usually goes on past its last return, unseen: a black box's face drops out where it turns
// away from the scanner. The paper's pilot reports, in the sectors those readings cross,
// whatever the laser sees farther on -- or nothing. Glass is not affected: the laser passes
// through it and returns from what lies behind, so those readings are returns, not gaps.
//
// The continuation is short: a return stands for its surface `length` around it (the 0.10 m the
// Sector Map already lets a scan point explain an AGM cell by), continued along the line its own
// run of returns fits, only into readings that came back empty and never at grazing incidence.
// A return among them that lies on that line is the same surface flickering near its detection
// limit, and the continuation goes on from it; any other return contradicts it and ends it. The
// Radar Map is untouched: its gaps stay gaps (radar_map.hpp), so the sonar's echoes there stay
// complementary.
#include <cstdint>
#include <vector>

#include "complement/radar_map.hpp"
#include "core/geometry.hpp"

namespace lasonic::complement {

struct DarkContinuationConfig {
  double length = 0;  // [m] how far past its last return a surface is continued; 0: off (the paper)
  // The run a continuation starts from: returns consecutive by the Radar Map's jump rule (empty
  // readings between them skipped: a dark face flickers), up to this far back from its last
  // return [m]. The last piece of the Radar Map's end-point fit (split_threshold) gives the line,
  // if it holds at least RadarMapConfig::min_points returns and is at least its min_length long
  // (what the Radar Map would call a segment).
  double fit_span = 0.30;
  // Readings meeting that line more obliquely than this from its normal [rad] are not continued
  // (the intersection runs away along the line): 80 deg.
  double max_incidence = 1.3962634015954636;
};

// Points (global frame) where the no-return readings next to the end of a straight run of
// returns cross that run's line, at most cfg.length past the run's last return (or past a later
// return on the line, within split_threshold of it). `placed` is the scan placed with `pose_at`
// (placeReadings); no_return[i] != 0 where reading i came back empty
// (FLAG_NO_RETURN; not a reading rejected as malformed, which says nothing). The rays of the
// empty readings use the pose at their own time; a reading without a pose ends a continuation.
// Appends to `out`.
void darkContinuation(const LaserScan& scan, const std::vector<ScanPoint>& placed,
                      const std::vector<uint8_t>& no_return, const PoseLookup& pose_at,
                      const RadarMapConfig& rm, const DarkContinuationConfig& cfg, std::vector<geom::Vec2>& out);

}  // namespace lasonic::complement
