// Scoring the tactical level: the tactical AGM (AGM_TACTICAL) and the Current Sensor Map's
// sonar lines (CURRENT_SENSOR_MAP) against the simulator's truth. Definitions: README,
// section "Evaluation" ("Tactical AGM", "Lines"); keep both in step.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "eval/evaluate.hpp"
#include "eval/laser_seen.hpp"

namespace lasonic::eval {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int64_t kNever = std::numeric_limits<int64_t>::max();

geom::Pose2 toPose(const pose2d_t& p) { return {p.x, p.y, p.theta}; }
void setRatio(Metrics& m, const std::string& key, const Ratio& r) {
  if (r.valid()) m.set(key, r.value());
}

double distanceTo(const sim::Primitive& p, const geom::Vec2& c) {
  return p.kind == sim::Primitive::Kind::Segment ? geom::distance(p.segment, c)
                                                 : std::abs((c - p.circle.center).norm() - p.circle.radius);
}

// Distance from c to the nearest static surface of the scenario.
double staticDistance(const sim::Scenario& sc, const geom::Vec2& c) {
  double best = kInf;
  for (const auto& p : sc.statics) best = std::min(best, distanceTo(p, c));
  return best;
}

// The window of a grid message, for points in the true frame.
struct Window {
  geom::Pose2 odom_from_true;
  double x0, y0, x1, y1;
  explicit Window(const grid_map_t& g, const geom::Pose2& true_from_odom)
      : odom_from_true(true_from_odom.inverse()),
        x0(g.origin_x),
        y0(g.origin_y),
        x1(g.origin_x + g.width * double(g.cell_size)),
        y1(g.origin_y + g.height * double(g.cell_size)) {}
  bool contains(const geom::Vec2& true_point) const {
    const geom::Vec2 q = odom_from_true.transform(true_point);
    return q.x() >= x0 && q.x() < x1 && q.y() >= y0 && q.y() < y1;
  }
};

// Occupied cells (Gp >= the map's threshold) at their centres, moved into the true frame.
std::vector<geom::Vec2> occupiedCells(const grid_map_t& g, const geom::Pose2& true_from_odom) {
  std::vector<geom::Vec2> out;
  if (g.width <= 0 || g.height <= 0 || static_cast<int64_t>(g.gp.size()) < int64_t{g.width} * g.height) return out;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const size_t idx = static_cast<size_t>(iy) * static_cast<size_t>(g.width) + static_cast<size_t>(ix);
      if (g.gp[idx] <= 0 || g.gp[idx] < g.gp_threshold) continue;
      const geom::Vec2 c(g.origin_x + (ix + 0.5) * g.cell_size, g.origin_y + (iy + 0.5) * g.cell_size);
      out.push_back(true_from_odom.transform(c));
    }
  return out;
}

// The movers' tracks up to a time: per mover its positions (true frame) in time order.
struct MoverTracks {
  struct Sample {
    int64_t utime;
    geom::Vec2 p;
  };
  std::map<int, std::vector<Sample>> tracks;
  std::map<int, double> radius;
  explicit MoverTracks(const std::vector<sim_state_t>& states) {
    for (const auto& st : states)
      for (const auto& mv : st.movers) {
        auto& tr = tracks[mv.id];
        const geom::Vec2 p(mv.x, mv.y);
        radius[mv.id] = mv.radius;
        // Samples 2 cm apart are plenty for a one-cell tolerance.
        if (tr.empty() || (tr.back().p - p).norm() >= 0.02) tr.push_back({st.utime, p});
      }
  }
  // True if c lies within a mover's radius + tol of where that mover has been up to utime.
  bool onTrack(const geom::Vec2& c, int64_t utime, double tol) const {
    for (const auto& [id, tr] : tracks) {
      const double r = radius.at(id) + tol;
      for (size_t i = 0; i < tr.size() && tr[i].utime <= utime; ++i) {
        const geom::Vec2 a = tr[i].p;
        const geom::Vec2 b = (i + 1 < tr.size() && tr[i + 1].utime <= utime) ? tr[i + 1].p : a;
        if (geom::distance(geom::Segment{a, b}, c) <= r) return true;
      }
    }
    return false;
  }
};

template <typename Grid>
const Grid* sameTime(const std::vector<Grid>& v, int64_t utime) {
  auto it = std::lower_bound(v.begin(), v.end(), utime, [](const Grid& g, int64_t t) { return g.utime < t; });
  return it != v.end() && it->utime == utime ? &*it : nullptr;
}
}  // namespace

namespace {
std::vector<BoundaryPoint> boundary(const sim::Scenario& sc, double spacing, bool laser_invisible_only) {
  std::vector<BoundaryPoint> out;
  spacing = spacing > 0 ? spacing : 0.05;
  for (size_t k = 0; k < sc.statics.size(); ++k) {
    const sim::Primitive& p = sc.statics[k];
    if (laser_invisible_only && sc.laserVisible(p.obstacle)) continue;
    const int surface = static_cast<int>(k);
    if (p.kind == sim::Primitive::Kind::Segment) {
      const int n = std::max(1, static_cast<int>(std::ceil(p.segment.length() / spacing)));
      for (int i = 0; i <= n; ++i)
        out.push_back({p.segment.a + (p.segment.b - p.segment.a) * (double(i) / n), p.obstacle, surface});
    } else {
      const int n = std::max(8, static_cast<int>(std::ceil(2 * geom::kPi * p.circle.radius / spacing)));
      for (int i = 0; i < n; ++i)
        out.push_back({p.circle.center + p.circle.radius * geom::unitVector(2 * geom::kPi * i / n), p.obstacle, surface});
    }
  }
  return out;
}
}  // namespace

std::vector<BoundaryPoint> staticBoundary(const sim::Scenario& sc, double spacing) {
  return boundary(sc, spacing, false);
}

std::vector<BoundaryPoint> laserInvisibleBoundary(const sim::Scenario& sc, double spacing) {
  return boundary(sc, spacing, true);
}

std::vector<BoundaryPoint> sonarOnlyCandidates(const sim::Scenario& sc, const LaserSeen& seen, double spacing) {
  return boundary(sc, spacing, !seen.available());
}

std::vector<int64_t> locatedTimes(const RunLog& log, const sim::Scenario& sc, const std::vector<BoundaryPoint>& pts,
                                  double radius, const LaserSeen* seen, double seen_radius, double range_limit) {
  constexpr double kOnSurface = 0.01;  // [m]
  constexpr double kSightSlack = 0.03;  // [m] a ray that meets a surface this short of the point still reaches it
  const bool per_scan = seen && seen->available();
  std::vector<int64_t> first(pts.size(), kNever);
  // Points per surface, and the surfaces of each obstacle, so each echo is compared only with
  // the boundary of the surfaces it hit.
  std::map<int, std::vector<size_t>> by_surface;
  std::map<int, std::vector<int>> surfaces;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (by_surface[pts[i].surface].empty()) surfaces[pts[i].obstacle].push_back(pts[i].surface);
    by_surface[pts[i].surface].push_back(i);
  }
  // Each reading's measured range and where its transducer was (true frame: its mount, SONAR_RING,
  // on the true robot pose).
  struct Reading {
    float range;
    pose2d_t mount;
  };
  std::map<std::pair<int64_t, int>, Reading> readings;
  for (const auto& r : log.sonar_rings)
    for (size_t i = 0; i < r.sensor_id.size() && i < r.mount.size() && i < r.range.size(); ++i)
      readings[{r.utime, r.sensor_id[i]}] = {r.range[i], r.mount[i]};
  const TruthTrack truth(log.sim_states);
  const sim::WorldGeometry world(sc);  // static only: what hides a surface point from a transducer
  for (const auto& t : log.sonar_truths) {
    const int scan = per_scan ? seen->newestAt(t.utime) : -1;
    // Before the first scan nothing says what the laser would have seen (and the complement has
    // no Radar Map to classify against): such echoes locate nothing.
    if (per_scan && scan < 0) continue;
    for (const auto& c : t.causes) {
      if (c.cause != sonar_cause_t::CAUSE_DIRECT || c.true_range < 0) continue;
      auto it = surfaces.find(c.obstacle);
      if (it == surfaces.end()) continue;
      const geom::Vec2 hit(c.hit_x, c.hit_y);
      // An echo from a surface the laser saw (its hit point) is redundant: the Radar Map has that
      // surface, and the echo is no evidence of anything only the sonar knows.
      if (per_scan && seen->saw(scan, c.obstacle, hit, seen_radius)) continue;
      const auto reading = readings.find({t.utime, c.sensor_id});
      // Only what the complement can keep reaches a grid: echoes within the hypothetical scan's limit.
      const double range = reading != readings.end() ? double(reading->second.range) : double(c.true_range);
      if (!(range <= range_limit)) continue;
      std::optional<geom::Vec2> sensor;
      if (reading != readings.end() && !truth.empty())
        sensor = truth.robotAt(t.utime).compose(toPose(reading->second.mount)).position();
      for (int k : it->second) {
        if (distanceTo(sc.statics[static_cast<size_t>(k)], hit) > kOnSurface) continue;
        for (size_t i : by_surface[k]) {
          if (t.utime >= first[i] || (pts[i].p - hit).norm() > radius) continue;
          // Where the newest scan saw the point, the laser had it: not the sonar's alone.
          if (per_scan && seen->saw(scan, pts[i].obstacle, pts[i].p, seen_radius)) continue;
          // A point hidden from the transducer (the back of a bin, the far side of a box's
          // corner, a wall behind a box) was not located by this echo.
          if (sensor) {
            const geom::Vec2 d = pts[i].p - *sensor;
            const double dist = d.norm();
            if (dist > 1e-6) {
              const auto h = world.castRay(geom::Ray{*sensor, d / dist}, dist + kSightSlack);
              if (h && h->range < dist - kSightSlack) continue;
            }
          }
          first[i] = t.utime;
        }
      }
    }
  }
  return first;
}

void evalAgmTactical(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m) {
  evalAgmTactical(log, sc, LaserSeen(log, o.seen_radius), o, m);
}

void evalAgmTactical(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o,
                     Metrics& m) {
  if (log.agm_tactical.empty() || log.sim_states.size() < 2) return;
  TruthTrack truth(log.sim_states);
  const MoverTracks movers(log.sim_states);
  const auto boundary = sonarOnlyCandidates(sc, seen);
  const auto located =
      locatedTimes(log, sc, boundary, o.located_radius, &seen, o.seen_radius, hypothesisRangeLimit(log, o));
  Ratio precision, recall, mover_share;
  for (const auto& g : log.agm_tactical) {
    const geom::Pose2 true_from_odom = truth.robotAt(g.utime).compose(toPose(g.robot_pose).inverse());
    const double tol = g.cell_size * (std::sqrt(0.5) + 1.0);  // one-cell tolerance
    const auto occupied = occupiedCells(g, true_from_odom);
    for (const auto& c : occupied) {
      const bool on_static = staticDistance(sc, c) <= tol;
      precision.add(on_static);
      mover_share.add(!on_static && movers.onTrack(c, g.utime, tol));
    }
    const Window win(g, true_from_odom);
    const int scan = seen.newestAt(g.utime);
    for (size_t i = 0; i < boundary.size(); ++i) {
      if (located[i] >= g.utime || !win.contains(boundary[i].p)) continue;
      // What the newest scan sees now is the Radar Map's, not the tactical level's memory.
      if (seen.saw(scan, boundary[i].obstacle, boundary[i].p, o.seen_radius)) continue;
      bool found = false;
      for (const auto& c : occupied)
        if ((c - boundary[i].p).norm() <= tol) {
          found = true;
          break;
        }
      recall.add(found);
    }
  }
  m.set("agm_tactical.maps", static_cast<int64_t>(log.agm_tactical.size()));
  setRatio(m, "agm_tactical.precision", precision);
  setRatio(m, "agm_tactical.invisible_recall", recall);
  setRatio(m, "agm_tactical.mover_share", mover_share);
  m.set("agm_tactical.samples.occupied", precision.den);
  m.set("agm_tactical.samples.located_boundary", recall.den);
}

void evalLines(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m) {
  evalLines(log, sc, LaserSeen(log, o.seen_radius), o, m);
}

void evalLines(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o, Metrics& m) {
  if (log.current_sensor_maps.empty() || log.sim_states.size() < 2) return;
  TruthTrack truth(log.sim_states);
  sim::WorldGeometry world(sc);
  const auto boundary = sonarOnlyCandidates(sc, seen);
  const auto located =
      locatedTimes(log, sc, boundary, o.located_radius, &seen, o.seen_radius, hypothesisRangeLimit(log, o));
  constexpr double kStep = 0.01;  // [m] line samples for the precision
  int64_t maps = 0, lines = 0;
  Ratio coverage, precision;
  for (const auto& csm : log.current_sensor_maps) {
    ++maps;
    const geom::Pose2 true_from_odom = truth.robotAt(csm.utime).compose(toPose(csm.robot_pose).inverse());
    world.setMovers(truth.moversAt(csm.utime));
    std::vector<geom::Segment> sonar;
    for (const auto& s : csm.segments) {
      if (s.source != line_segment_t::SOURCE_SONAR) continue;
      const geom::Segment seg{true_from_odom.transform({s.x0, s.y0}), true_from_odom.transform({s.x1, s.y1})};
      if (!std::isfinite(seg.length())) continue;
      sonar.push_back(seg);
      // Precision: the share of the line's length near any true surface (static or a mover now).
      const int n = std::max(1, static_cast<int>(std::ceil(seg.length() / kStep)));
      for (int i = 0; i < n; ++i) {
        const geom::Vec2 q = seg.a + (seg.b - seg.a) * ((i + 0.5) / n);
        double best = kInf;
        for (const auto& p : world.primitives()) best = std::min(best, distanceTo(p, q));
        precision.add(best <= o.line_tolerance);
      }
    }
    lines += static_cast<int64_t>(sonar.size());
    // Coverage: located laser-invisible boundary inside the tactical AGM's window at this time.
    const grid_map_t* g = sameTime(log.agm_tactical, csm.utime);
    if (!g) continue;
    const Window win(*g, true_from_odom);
    const int scan = seen.newestAt(csm.utime);
    for (size_t i = 0; i < boundary.size(); ++i) {
      if (located[i] >= csm.utime || !win.contains(boundary[i].p)) continue;
      if (seen.saw(scan, boundary[i].obstacle, boundary[i].p, o.seen_radius)) continue;  // the laser's now
      bool covered = false;
      for (const auto& s : sonar)
        if (geom::distance(s, boundary[i].p) <= o.line_tolerance) {
          covered = true;
          break;
        }
      coverage.add(covered);
    }
  }
  m.set("lines.maps", maps);
  m.set("lines.count", maps > 0 ? static_cast<double>(lines) / static_cast<double>(maps) : 0.0);
  setRatio(m, "lines.invisible_coverage", coverage);
  setRatio(m, "lines.precision", precision);
}

}  // namespace lasonic::eval
