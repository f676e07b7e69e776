#include "complement/complement.hpp"
#include "complement/radar_map_memory.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace lasonic::complement {

const char* className(SonarClass c) {
  switch (c) {
    case SonarClass::Complementary: return "complementary";
    case SonarClass::Redundant: return "redundant";
    case SonarClass::False: return "false";
    case SonarClass::Unverifiable: return "unverifiable";
    case SonarClass::Invalid: return "invalid";
    case SonarClass::OutsideView: return "outside_view";
    case SonarClass::SeenBefore: return "seen_before";
  }
  return "invalid";
}

SonarClass classify(double real, bool no_echo, double hyp, double tol, double limit) {
  if (no_echo || real > limit) return SonarClass::Unverifiable;
  if (real < hyp - tol) return SonarClass::Complementary;
  if (real > hyp + tol) return SonarClass::False;
  return SonarClass::Redundant;
}

bool arcSeen(const geom::Pose2& sensor, double range, double beam_width, const LaserView& view) {
  if (view.full_circle) return true;
  // The echo's arc within the beam, every 1/8 of its width (3 deg of a 25 deg beam).
  constexpr int kSteps = 8;
  for (int i = 0; i <= kSteps; ++i) {
    const double a = sensor.theta + beam_width * (static_cast<double>(i) / kSteps - 0.5);
    if (!view.covers(sensor.position() + range * geom::unitVector(a))) return false;
  }
  return true;
}

std::optional<double> crosstalkRange(const RmCorner& c, const geom::Vec2& e, const geom::Vec2& axis_e,
                                     const geom::Vec2& p, const geom::Vec2& axis_p, double cos_lobe) {
  if (!c.inside(e) || !c.inside(p)) return std::nullopt;
  // Sent towards the listener's image 2v - p, heard from the emitter's image 2v - e: one direction.
  const geom::Vec2 path = 2.0 * c.vertex - e - p;
  const double in_lobe = cos_lobe * path.norm();
  if (path.dot(axis_e) <= in_lobe || path.dot(axis_p) <= in_lobe) return std::nullopt;
  return 0.5 * path.norm();
}

std::optional<double> mirrorHalfPath(const geom::Segment& s, const geom::Vec2& e, const geom::Vec2& axis_e,
                                     const geom::Vec2& p, const geom::Vec2& axis_p, double cos_lobe) {
  const geom::Vec2 d = s.b - s.a;
  const double len = d.norm();
  if (!(len > 1e-9)) return std::nullopt;
  const geom::Vec2 n(-d.y() / len, d.x() / len);
  const double he = n.dot(e - s.a), hp = n.dot(p - s.a);
  if (he * hp <= 0) return std::nullopt;  // not both in front of the same face
  const geom::Vec2 mirrored = e - 2.0 * he * n;
  // The mirror point: where the straight line from p to e's image meets the line.
  const geom::Vec2 q = p + (hp / (hp + he)) * (mirrored - p);
  const double u = (q - s.a).dot(d) / (len * len);
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const geom::Vec2 out = q - e, in = q - p;
  if (out.dot(axis_e) < cos_lobe * out.norm() || in.dot(axis_p) < cos_lobe * in.norm()) return std::nullopt;
  return 0.5 * (mirrored - p).norm();
}

std::optional<double> firstLateEcho(const geom::Pose2& listener, double listener_beam, int64_t utime,
                                    const std::vector<Ping>& earlier, const RadarMap& rm, int64_t window_us) {
  const geom::Vec2 p = listener.position(), axis_p = geom::unitVector(listener.theta);
  std::optional<double> first;
  for (const Ping& ping : earlier) {
    const int64_t dt_us = utime - ping.utime;
    if (dt_us <= 0 || dt_us > window_us) continue;
    const double gone = 0.5 * kSpeedOfSound * static_cast<double>(dt_us) * 1e-6;
    const geom::Vec2 e = ping.sensor.position(), axis_e = geom::unitVector(ping.sensor.theta);
    // Far walls answer strongly only near both axes; one full opening admits the side lobes.
    const double lobe = std::max(listener_beam, ping.beam_width);
    const double cos_lobe = std::cos(std::min(lobe, 0.5 * geom::kPi));
    auto arrival = [&](std::optional<double> half_path) {
      if (!half_path || *half_path - gone <= 0) return;
      if (!first || *half_path - gone < *first) first = *half_path - gone;
    };
    for (const RmSegment& s : rm.segments) arrival(mirrorHalfPath(s.seg, e, axis_e, p, axis_p, cos_lobe));
    for (const RmCorner& c : rm.corners) arrival(crosstalkRange(c, e, axis_e, p, axis_p, cos_lobe));
  }
  return first;
}

const std::vector<Ping>& PingHistory::before(int64_t utime, int64_t window_us) {
  while (!pings_.empty() && utime - pings_.front().utime > window_us) pings_.pop_front();
  out_.assign(pings_.begin(), pings_.end());
  return out_;
}

void PingHistory::add(const GroupComplement& g) {
  for (const ClassifiedReading& r : g.readings)
    if (r.sensor_pose && std::isfinite(r.sensor_pose->x) && std::isfinite(r.sensor_pose->y) &&
        std::isfinite(r.sensor_pose->theta) && std::isfinite(r.beam_width))
      pings_.push_back({g.utime, *r.sensor_pose, r.beam_width});
}

std::vector<BeamOverlap> overlappingBeams(const SonarGroup& g, double default_beam_width) {
  std::vector<BeamOverlap> out;
  const auto width = [&](const SonarReading& r) { return r.beam_width > 0 ? r.beam_width : default_beam_width; };
  for (size_t i = 0; i < g.readings.size(); ++i) {
    const SonarReading& a = g.readings[i];
    if (!a.valid) continue;
    for (size_t j = i + 1; j < g.readings.size(); ++j) {
      const SonarReading& b = g.readings[j];
      if (!b.valid || a.sensor_id == b.sensor_id) continue;
      const double apart = std::abs(geom::normalizeAngle(a.mount.theta - b.mount.theta));
      if (apart > width(a) + width(b) + 1e-9) continue;
      const bool a_first = a.sensor_id < b.sensor_id;
      const SonarReading& lo = a_first ? a : b;
      const SonarReading& hi = a_first ? b : a;
      out.push_back({lo.sensor_id, hi.sensor_id, apart, width(lo), width(hi)});
    }
  }
  return out;
}

bool radarMapStale(const RadarMap* rm, int64_t utime, int64_t max_rm_age_us) {
  // Either direction: a map built long before or after the firing shows another scene.
  return rm == nullptr || std::llabs(utime - rm->utime) > max_rm_age_us;
}

GroupComplement extractComplement(const SonarGroup& g, const std::optional<geom::Pose2>& robot_pose,
                                  const RadarMap* rm, const ComplementParams& p, const std::vector<Ping>& earlier,
                                  const RadarMapMemory* memory) {
  GroupComplement out;
  out.utime = g.utime;
  out.group = g.group;
  out.radar_map_utime = rm ? rm->utime : 0;
  out.radar_map_stale = radarMapStale(rm, g.utime, p.max_rm_age_us);
  static const std::vector<RmSegment> kEmpty;
  static const std::vector<geom::Vec2> kNoPoles;
  const std::vector<RmSegment>& segments = rm ? rm->segments : kEmpty;
  const std::vector<geom::Vec2>& poles = rm ? rm->poles : kNoPoles;
  // sin and cos of the robot's heading once for the group's sensors (Pose2::compose's values).
  const double rc = robot_pose ? std::cos(robot_pose->theta) : 1.0, rs = robot_pose ? std::sin(robot_pose->theta) : 0.0;
  out.readings.reserve(g.readings.size());
  static const std::vector<RmCorner> kNoCorners;
  const std::vector<RmCorner>& corners = p.crosstalk_corners && rm ? rm->corners : kNoCorners;
  for (const SonarReading& r : g.readings) {
    ClassifiedReading c;
    c.sensor_id = r.sensor_id;
    c.range = r.range;
    c.hypothetical_range = std::numeric_limits<double>::quiet_NaN();
    // The ideal sonar has the real transducer's beam (the message says which; a Pioneer ring's
    // 25 deg, MOBOT-IV's 30 deg), so the hypothesis is what this sensor would hear.
    IdealSonarModel model = p.model;
    if (r.beam_width > 0 && r.beam_width < geom::kPi) model.beam_width = r.beam_width;
    c.beam_width = model.beam_width;
    if (robot_pose) {
      // robot_pose->compose(r.mount), and segmentMapPoint(sensor, r.range) = sensor.transform({range,
      // 0}) with the axis direction the beam's edges hold: the same operations on the same values,
      // without two of the five sin/cos pairs per reading.
      const geom::Pose2& rp = *robot_pose;
      const geom::Pose2 sensor{rp.x + rc * r.mount.x - rs * r.mount.y, rp.y + rs * r.mount.x + rc * r.mount.y,
                               geom::normalizeAngle(rp.theta + r.mount.theta)};
      c.sensor_pose = sensor;
      const geom::SectorEdges edges(geom::Sector{sensor.position(), sensor.theta, model.beam_width, model.range_limit});
      c.hypothetical_range = hypotheticalRange(sensor, edges, segments, model);
      if (r.valid && !r.no_echo) {
        const double ca = edges.axis.x(), sa = edges.axis.y();  // cos, sin of sensor.theta
        const geom::Vec2 l(r.range, 0.0);
        c.end = geom::Vec2(sensor.x + ca * l.x() - sa * l.y(), sensor.y + sa * l.x() + ca * l.y());
        if (rm) c.arc_seen = arcSeen(sensor, r.range, model.beam_width, rm->view);
        // An echo arc the newest scan did not see but an earlier one did: the hypothesis also
        // on that scan's lines there (RadarMapMemory).
        if (memory && rm && !out.radar_map_stale && r.range <= model.range_limit && !c.arc_seen)
          if (const std::vector<RmSegment>* before = memory->seenBefore(sensor, r.range, model.beam_width)) {
            c.seen_before = true;
            c.seen_before_range = c.hypothetical_range;
            if (!before->empty())
              c.seen_before_range = std::min(c.seen_before_range, hypotheticalRange(sensor, edges, *before, model));
          }
      }
    }
    if (!r.valid || !robot_pose)
      c.cls = SonarClass::Invalid;
    else if (out.radar_map_stale)
      c.cls = SonarClass::Unverifiable;
    else
      c.cls = classify(r.range, r.no_echo, c.hypothetical_range, p.tolerance, p.model.range_limit);
    // Nearer than the lines predict, but at a pole's distance: the laser sees what answered.
    if (c.cls == SonarClass::Complementary && c.sensor_pose)
      if (const auto d = poleEcho(*c.sensor_pose, poles, r.range, p.tolerance, model)) {
        c.cls = SonarClass::Redundant;
        c.hypothetical_range = *d;
        c.by_pole = true;
      }
    out.readings.push_back(c);
  }
  // Crosstalk by way of a corner: the group's sensors fired together, each heard by the others.
  for (ClassifiedReading& c : out.readings) {
    if (corners.empty() || c.cls != SonarClass::Complementary || !c.sensor_pose) continue;
    const geom::Vec2 pp = c.sensor_pose->position(), axis_p = geom::unitVector(c.sensor_pose->theta);
    for (const ClassifiedReading& emitter : out.readings) {
      if (&emitter == &c || !emitter.sensor_pose || c.by_crosstalk) continue;
      const geom::Vec2 e = emitter.sensor_pose->position(), axis_e = geom::unitVector(emitter.sensor_pose->theta);
      for (const RmCorner& corner : corners)
        if (const auto x = crosstalkRange(corner, e, axis_e, pp, axis_p); x && std::abs(c.range - *x) <= p.tolerance) {
          c.cls = SonarClass::Redundant;
          c.hypothetical_range = *x;
          c.by_crosstalk = true;
          break;
        }
    }
  }
  // Late echoes of earlier pings by way of a laser-seen wall or corner: the listener reads the
  // first one to arrive, so only the earliest predicted arrival explains a reading.
  if (p.late_echoes && rm && !earlier.empty())
    for (ClassifiedReading& c : out.readings) {
      if (c.cls != SonarClass::Complementary || !c.sensor_pose) continue;
      const auto first = firstLateEcho(*c.sensor_pose, c.beam_width, g.utime, earlier, *rm, p.late_echo_window_us);
      if (first && std::abs(c.range - *first) <= p.tolerance) {
        c.cls = SonarClass::Redundant;
        c.hypothetical_range = *first;
        c.by_late_echo = true;
      }
    }
  for (size_t i = 0; i < out.readings.size(); ++i) {
    ClassifiedReading& c = out.readings[i];
    const SonarReading& r = g.readings[i];
    // (Crosstalk and late echoes are explained whatever the listener's arc covers: they are no
    // echo from there.)
    // An outside-view echo the newest lines explain (redundant by them) keeps that hypothesis as
    // its hypothetical_range, so the pilot can tell it (|range - hypothetical_range| <= tolerance)
    // and the earlier lines are not asked: the newest scan saw what explains it.
    const bool explained = c.cls == SonarClass::Redundant;
    if (p.outside_view_complementary && rm && c.end && c.sensor_pose && !c.by_crosstalk && !c.by_late_echo &&
        (c.cls == SonarClass::Redundant || c.cls == SonarClass::False) &&
        !c.arc_seen)
      c.cls = SonarClass::OutsideView;
    // Where the newest scan does not look, the lines an earlier one saw there: an echo they
    // explain (or that passed them: false) is the laser's, seen before.
    if (c.seen_before && (c.cls == SonarClass::Complementary || (c.cls == SonarClass::OutsideView && !explained)) &&
        !c.by_pole) {
      const SonarClass before = classify(r.range, r.no_echo, c.seen_before_range, p.tolerance, p.model.range_limit);
      if (before == SonarClass::Redundant || before == SonarClass::False) {
        c.cls = SonarClass::SeenBefore;
        c.hypothetical_range = c.seen_before_range;
      }
    }
  }
  return out;
}

}  // namespace lasonic::complement
