#include "complement/hypothetical_scan.hpp"

#include <algorithm>
#include <cmath>

namespace lasonic::complement {

double hypotheticalRange(const geom::Pose2& sensor, const std::vector<RmSegment>& rm,
                         const IdealSonarModel& model) {
  const geom::Sector beam{sensor.position(), sensor.theta, model.beam_width, model.range_limit};
  return hypotheticalRange(sensor, geom::SectorEdges(beam), rm, model);  // once per sensor, not per segment
}

double hypotheticalRange(const geom::Pose2& sensor, const geom::SectorEdges& edges, const std::vector<RmSegment>& rm,
                         const IdealSonarModel& model) {
  const geom::Sector beam{sensor.position(), sensor.theta, model.beam_width, model.range_limit};
  double best = model.range_limit;
  for (const RmSegment& s : rm) {
    // Cheap reject before the exact wedge clip: a segment wholly beyond the best range so far
    // cannot hold a nearer point.
    if (geom::distance(s.seg, beam.apex) >= best) continue;
    if (const auto d = geom::nearestInSector(beam, edges, s.seg)) best = std::min(best, *d);
  }
  return best;
}

std::optional<double> poleEcho(const geom::Pose2& sensor, const std::vector<geom::Vec2>& poles, double range,
                               double tol, const IdealSonarModel& model) {
  if (poles.empty() || !(range >= 0)) return std::nullopt;
  const geom::Sector beam{sensor.position(), sensor.theta, model.beam_width, model.range_limit};
  std::optional<double> best;
  for (const geom::Vec2& p : poles) {
    const double d = (p - beam.apex).norm();
    if (!(std::abs(d - range) <= tol) || (best && std::abs(d - range) >= std::abs(*best - range))) continue;
    if (beam.contains(p)) best = d;
  }
  return best;
}

std::vector<double> hypotheticalScan(const std::vector<geom::Pose2>& sensors,
                                     const std::vector<RmSegment>& rm, const IdealSonarModel& model) {
  std::vector<double> out;
  out.reserve(sensors.size());
  for (const geom::Pose2& s : sensors) out.push_back(hypotheticalRange(s, rm, model));
  return out;
}

}  // namespace lasonic::complement
