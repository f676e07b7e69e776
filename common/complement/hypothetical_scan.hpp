#pragma once
// Hypothetical sonar scan (Jörg 1995, sec. 3.1; README "Method", step 2): what an ideal sonar would read
// on the Radar Map. The ideal beam is a circular sector (opening 30 deg, radius 2.20 m): all of it
// is empty except for the nearest obstacle, so the hypothetical range is the exact distance from
// the sensor to the nearest point of any RM segment inside the sector; no segment -> the limit.
#include <optional>
#include <vector>

#include "complement/radar_map.hpp"
#include "core/geometry.hpp"

namespace lasonic::complement {

struct IdealSonarModel {
  double beam_width = geom::deg2rad(30.0);  // [rad] full opening
  double range_limit = 2.20;                // [m]
};

// One sensor: its global pose at firing time (acoustic axis along theta).
double hypotheticalRange(const geom::Pose2& sensor, const std::vector<RmSegment>& rm,
                         const IdealSonarModel& model);
// The same with the beam's edge directions given (geom::SectorEdges of the beam: apex at the
// sensor, heading sensor.theta, opening model.beam_width), for a caller that needs them too.
double hypotheticalRange(const geom::Pose2& sensor, const geom::SectorEdges& edges, const std::vector<RmSegment>& rm,
                         const IdealSonarModel& model);
// The Radar Map's poles (RadarMap::poles) for a reading at `range`: the distance of the pole point
// inside the beam nearest to that range, if one lies within tol of it (the echo is that pole's).
// A pole is a weak reflector, heard in the transducer's main lobe only, so one that the reading
// does not match says nothing: unlike a line it never makes a longer reading false.
std::optional<double> poleEcho(const geom::Pose2& sensor, const std::vector<geom::Vec2>& poles, double range,
                               double tol, const IdealSonarModel& model);

// A firing group (or the whole ring): one range per sensor pose.
std::vector<double> hypotheticalScan(const std::vector<geom::Pose2>& sensors,
                                     const std::vector<RmSegment>& rm, const IdealSonarModel& model);

}  // namespace lasonic::complement
