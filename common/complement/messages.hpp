#pragma once
// The thin layer between LCM messages (used as plain data here, no transport) and the
// algorithms' structs: input validation that names the offending field, and output filling.
// Bad input is never fatal: a bad reading becomes a gap (laser) or Invalid (sonar), a message
// that cannot be used at all is refused; every problem is returned for the caller to report.
#include <optional>
#include <string>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/sonar_ring_t.hpp>

#include "complement/complement.hpp"
#include "complement/radar_map.hpp"

namespace lasonic::complement {

struct InputProblem {
  std::string counter;  // e.g. "rejected.sonar_range"
  std::string message;  // e.g. "SONAR_RING.range[2] = nan"
};

// nullopt when the scan as a whole is unusable (arrays of different length, no readings, bad
// angles, range limits or mount).
std::optional<LaserScan> laserScanFromMessage(const laser_scan_t& m, std::vector<InputProblem>& problems);
SonarGroup sonarGroupFromMessage(const sonar_ring_t& m, std::vector<InputProblem>& problems);

line_map_t radarMapToMessage(const RadarMap& rm);
hypothetical_scan_t hypothesisToMessage(const GroupComplement& g, const ComplementParams& p);
complement_t complementToMessage(const GroupComplement& g, const ComplementParams& p);

}  // namespace lasonic::complement
