#include "complement/radar_map_memory.hpp"

#include <cmath>
#include <utility>

#include "complement/complement.hpp"

namespace lasonic::complement {

namespace {
double cross(const geom::Vec2& a, const geom::Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
}  // namespace

void clipOutsideView(const RmSegment& s, const LaserView& view, std::vector<RmSegment>& out) {
  if (view.full_circle) return;
  const geom::Vec2 a = s.seg.a, d = s.seg.b - s.seg.a, o = view.sensor.position();
  // Where the segment crosses the view's two edge rays (from the sensor at the first and the last
  // reading's angle): there it goes from seen to unseen.
  double cuts[4] = {0.0, 1.0, 1.0, 1.0};
  int n = 1;
  for (const double edge : {view.angle_min, view.angle_max}) {
    const geom::Vec2 u = geom::unitVector(view.sensor.theta + edge);
    const double den = cross(d, u);
    if (std::abs(den) < 1e-12) continue;  // parallel to the ray
    const double t = cross(o - a, u) / den, along = cross(o - a, d) / den;
    if (t > 0 && t < 1 && along > 0) cuts[n++] = t;
  }
  cuts[n++] = 1.0;
  for (int i = 1; i < n; ++i)  // (in order: at most four)
    for (int j = i; j > 0 && cuts[j - 1] > cuts[j]; --j) std::swap(cuts[j - 1], cuts[j]);
  for (int i = 0; i + 1 < n; ++i) {
    const double t0 = cuts[i], t1 = cuts[i + 1];
    if (!(t1 - t0 > 1e-9)) continue;
    const geom::Vec2 p0 = a + t0 * d, p1 = a + t1 * d;
    if (view.covers(0.5 * (p0 + p1))) continue;
    out.push_back({{p0, p1}, s.npoints, s.rms});
  }
}

bool seenOnlyNearNormal(const geom::Segment& s, const geom::Vec2& from, double max_incidence) {
  const geom::Vec2 d = s.b - s.a;
  const double len = d.norm();
  if (!(len > 0)) return true;
  const geom::Vec2 n(-d.y() / len, d.x() / len);
  const double c = std::cos(max_incidence);
  for (const geom::Vec2& e : {s.a, s.b}) {
    const geom::Vec2 v = from - e;
    const double r = v.norm();
    if (!(r > 0) || std::abs(v.dot(n)) < c * r) return false;  // this end seen more obliquely
  }
  return true;
}

void RadarMapMemory::update(const RadarMap& rm) {
  if (!enabled()) return;
  if (have_newest_ && rm.utime < newest_.utime) return;
  if (have_newest_) earlier_.push_back(std::move(newest_));
  newest_ = Earlier{rm.utime, rm.view, {}, {}};
  for (const RmSegment& s : rm.segments)
    if (s.seg.length() >= min_length_ &&
        (!(max_incidence_ > 0) || !seenOnlyNearNormal(s.seg, rm.view.sensor.position(), max_incidence_)))
      newest_.segments.push_back(s);
  have_newest_ = true;
  while (!earlier_.empty() && rm.utime - earlier_.front().utime > memory_us_) earlier_.pop_front();
  if (rm.view.full_circle) {  // the newest scan sees everywhere: nothing earlier is needed
    earlier_.clear();
    return;
  }
  for (Earlier& e : earlier_) e.clipped = false;  // (clipped when asked: most never are)
}

const std::vector<RmSegment>& RadarMapMemory::Earlier::outsideOf(const LaserView& newest) const {
  if (!clipped) {
    outside.clear();
    for (const RmSegment& s : segments) clipOutsideView(s, newest, outside);
    clipped = true;
  }
  return outside;
}

const std::vector<RmSegment>* RadarMapMemory::seenBefore(const geom::Pose2& sensor, double range,
                                                         double beam_width) const {
  for (auto it = earlier_.rbegin(); it != earlier_.rend(); ++it)
    if (arcSeen(sensor, range, beam_width, it->view)) return &it->outsideOf(newest_.view);
  return nullptr;
}

size_t RadarMapMemory::lines() const {
  size_t n = 0;
  for (const Earlier& e : earlier_) n += e.outsideOf(newest_.view).size();
  return n;
}

}  // namespace lasonic::complement
