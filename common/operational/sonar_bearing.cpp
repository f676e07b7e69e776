#include "operational/sonar_bearing.hpp"

#include <algorithm>
#include <cmath>
#include "core/utime.hpp"

namespace lasonic {

namespace {
// What one side of the axis says: Shorter wins over Similar (the surface comes nearer there).
struct Side {
  bool shorter = false;
  bool similar = false;
  double similar_offset = 0;  // angleDiff(psi_j, psi_i) of the similar neighbour nearest the axis
};
}  // namespace

BearingEstimate echoBearingEstimate(const SonarEcho& self, const std::vector<SonarEcho>& others,
                                    const SonarBearingParams& p) {
  const double psi = self.sensor.theta;
  // Each echo's own beam (a ring may mix transducers); two beams overlap when their axes are
  // closer than the mean of their openings.
  const auto beamOf = [&p](const SonarEcho& e) { return e.beam_width > 0 ? e.beam_width : p.beam_width; };
  const double b = beamOf(self);
  const auto max_age_us = secondsToUs(p.max_age_s);
  Side side[2];  // 0: right (clockwise), 1: left
  for (const SonarEcho& o : others) {
    const int64_t age = self.utime - o.utime;
    if (age < 0 || (max_age_us > 0 && age > max_age_us)) continue;
    const double off = geom::angleDiff(o.sensor.theta, psi);
    if (std::abs(off) >= 0.5 * (b + beamOf(o)) || off == 0.0) continue;
    Side& s = side[off > 0 ? 1 : 0];
    if (o.range < self.range - p.similar) {
      s.shorter = true;
    } else if (o.range <= self.range + p.similar) {
      if (!s.similar || std::abs(off) < std::abs(s.similar_offset)) s.similar_offset = off;
      s.similar = true;
    }
  }
  const auto some = [](const Side& s) { return s.shorter || s.similar; };
  for (int k = 0; k < 2; ++k) {
    const Side& s = side[k];
    const Side& other = side[1 - k];
    if (!some(s) || some(other)) continue;
    if (s.shorter) return {geom::normalizeAngle(psi + (k == 1 ? 0.5 : -0.5) * b), 0.0};
    return {geom::normalizeAngle(psi + 0.5 * s.similar_offset), std::max(0.0, 0.5 * (b - std::abs(s.similar_offset)))};
  }
  return {psi, 0.5 * b};
}

double echoBearing(const SonarEcho& self, const std::vector<SonarEcho>& others, const SonarBearingParams& p) {
  return echoBearingEstimate(self, others, p).bearing;
}

geom::Vec2 echoPoint(const SonarEcho& self, const std::vector<SonarEcho>& others, const SonarBearingParams& p) {
  return self.sensor.position() + self.range * geom::unitVector(echoBearing(self, others, p));
}

BearingEstimate SonarBearingTracker::estimate(int id, const SonarEcho& e) const {
  // This ring cycle: since the sensor's previous firing, or, after a gap, within kIrregularCycle
  // times its cycle before (nothing known yet: every latest reading).
  int64_t since = std::numeric_limits<int64_t>::min();
  if (p_.max_age_s <= 0) {
    const auto f = fired_.find(id);
    if (f != fired_.end() && f->second.last < e.utime) {
      const SensorFiring& own = f->second;
      since = own.regular(e.utime)
                  ? own.last
                  : e.utime - static_cast<int64_t>(SensorFiring::kIrregularCycle * static_cast<double>(own.cycle));
    }
  }
  scratch_.clear();
  for (const auto& [other, echo] : latest_)
    if (other != id && echo && echo->utime >= since) scratch_.push_back(*echo);
  return echoBearingEstimate(e, scratch_, p_);
}

double SonarBearingTracker::bearing(int id, const SonarEcho& e) const { return estimate(id, e).bearing; }

geom::Vec2 SonarBearingTracker::place(int id, const SonarEcho& e) const {
  return e.sensor.position() + e.range * geom::unitVector(bearing(id, e));
}

void SonarBearingTracker::record(int id, int64_t utime, const std::optional<SonarEcho>& e) {
  // No ring has this many transducers: a stream of ever new ids (malformed messages) must not
  // grow the table without bound.
  if (latest_.size() >= kMaxSensors && latest_.find(id) == latest_.end()) {
    latest_.clear();
    fired_.clear();
  }
  latest_[id] = e;
  fired_[id].fire(utime);
}

void RingGroups::fired(int group) {
  const int64_t index = messages_++;
  if (group < 0 || group >= kMaxGroups) return;
  const auto g = static_cast<size_t>(group);
  if (last_.size() <= g) last_.resize(g + 1, -1);
  if (last_[g] >= 0) {
    if (counts_.size() == kWindow) counts_.erase(counts_.begin());
    counts_.push_back(static_cast<int>(std::min<int64_t>(index - last_[g], kMaxGroups)));
    // The most frequent count; a tie goes to the larger (the ring's own count, not a short one).
    int best = 0, best_n = 0;
    for (const int c : counts_) {
      const auto n = static_cast<int>(std::count(counts_.begin(), counts_.end(), c));
      if (n > best_n || (n == best_n && c > best)) best = c, best_n = n;
    }
    per_cycle_ = best;
  }
  last_[g] = index;
}

void RingGroups::fired(int group, int64_t utime) {
  fired(group);
  intervals_.stamp(utime);
}

double RingGroups::shortestCycleS() const {
  if (per_cycle_ <= 0 || intervals_.size() < kMinIntervals) return 0;
  const int64_t median = intervals_.median();
  const int64_t floor = median / 2;
  int64_t shortest = median;
  for (const int64_t d : intervals_.intervals())
    if (d >= floor) shortest = std::min(shortest, d);
  return static_cast<double>(per_cycle_) * static_cast<double>(shortest) * 1e-6;
}

int maxBeamOverlap(const std::vector<BeamAxis>& beams, double margin) {
  struct Arc {
    double axis, half;
  };
  std::vector<Arc> arcs;
  arcs.reserve(beams.size());
  const double m = std::isfinite(margin) && margin > 0 ? margin : 0.0;
  for (const BeamAxis& b : beams)
    if (std::isfinite(b.axis) && std::isfinite(b.beam) && b.beam > 0 && b.beam < 2 * geom::kPi)
      arcs.push_back({geom::normalizeAngle(b.axis), 0.5 * b.beam - std::min(m, 0.25 * b.beam)});
  // The count is highest just inside some beam's (narrowed) edge: try each.
  int best = 0;
  for (const Arc& a : arcs) {
    const double at = geom::normalizeAngle(a.axis - a.half + 1e-9);
    int n = 0;
    for (const Arc& o : arcs)
      if (std::abs(geom::normalizeAngle(at - o.axis)) < o.half) ++n;
    best = std::max(best, n);
  }
  return best;
}

}  // namespace lasonic
