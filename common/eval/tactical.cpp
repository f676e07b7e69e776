// Scoring the tactical level: the tactical AGM (AGM_TACTICAL) and the Current Sensor Map's
// sonar lines (CURRENT_SENSOR_MAP) against the simulator's truth. Definitions: README,
// section "Evaluation" ("Tactical AGM", "Lines"); keep both in step.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "core/pose_msg.hpp"
#include "eval/evaluate.hpp"
#include "eval/laser_seen.hpp"
#include "tactical/line_generation.hpp"

namespace lasonic::eval {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int64_t kNever = std::numeric_limits<int64_t>::max();

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
  explicit Window(const SparseGridMap& g, const geom::Pose2& true_from_odom)
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

// Occupied cells (Gp >= the map's threshold) at their centres, moved into the true frame, row by
// row (none for an incomplete map).
std::vector<geom::Vec2> occupiedCells(const SparseGridMap& g, const geom::Pose2& true_from_odom) {
  std::vector<geom::Vec2> out;
  for (const SparseGridMap::Cell& cell : g.cells()) {
    if (cell.gp <= 0 || cell.gp < g.gp_threshold) continue;
    out.push_back(true_from_odom.transform(g.cellCentre(cell.index)));
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
      for (int i = 0; i <= n; ++i) {
        const geom::Vec2 q = p.segment.a + (p.segment.b - p.segment.a) * (double(i) / n);
        // A stretch drawn on another obstacle's surface is that obstacle's (counted once, as
        // the one the laser sees best: a pane on a wall's line is wall).
        if (sc.canonicalObstacle(p.obstacle, q) != p.obstacle) continue;
        out.push_back({q, p.obstacle, surface});
      }
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

namespace {
// Every (point, echo) pair in which a DIRECT echo locates a boundary point (locatedTimes' rule),
// in firing order; skip(i, utime) lets the caller leave out points it is done with.
template <typename Skip, typename Visit>
void forEachLocating(const RunLog& log, const sim::Scenario& sc, const std::vector<BoundaryPoint>& pts, double radius,
                     const LaserSeen* seen, double seen_radius, double range_limit, Skip skip, Visit visit) {
  constexpr double kOnSurface = 0.01;  // [m]
  constexpr double kSightSlack = 0.03;  // [m] a ray that meets a surface this short of the point still reaches it
  const bool per_scan = seen && seen->available();
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
      if (per_scan && seen->saw(sc, scan, c.obstacle, hit, seen_radius)) continue;
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
          if (skip(i, t.utime) || (pts[i].p - hit).norm() > radius) continue;
          // Where the newest scan saw the point, the laser had it: not the sonar's alone.
          if (per_scan && seen->saw(sc, scan, pts[i].obstacle, pts[i].p, seen_radius)) continue;
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
          visit(i, t.utime, c.sensor_id);
        }
      }
    }
  }
}
}  // namespace

std::vector<int64_t> locatedTimes(const RunLog& log, const sim::Scenario& sc, const std::vector<BoundaryPoint>& pts,
                                  double radius, const LaserSeen* seen, double seen_radius, double range_limit) {
  std::vector<int64_t> first(pts.size(), kNever);
  forEachLocating(
      log, sc, pts, radius, seen, seen_radius, range_limit, [&](size_t i, int64_t utime) { return utime >= first[i]; },
      [&](size_t i, int64_t utime, int) { first[i] = utime; });
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
      if (seen.saw(sc, scan, boundary[i].obstacle, boundary[i].p, o.seen_radius)) continue;
      bool found = false;
      for (const auto& c : occupied)
        if ((c - boundary[i].p).norm() <= tol) {
          found = true;
          break;
        }
      recall.add(found);
    }
  }
  // How far the map's frame drifts: the robot's motion over the last 10 s in that frame against
  // the true motion (the odometry's error without scan matching, the matched pose's with it).
  double pos_err = 0, heading_err = 0;
  int64_t pairs = 0;
  size_t j = 0;
  for (const auto& g : log.agm_tactical) {
    while (j + 1 < log.agm_tactical.size() && log.agm_tactical[j + 1].utime <= g.utime - 10'000'000) ++j;
    const auto& before = log.agm_tactical[j];
    if (before.utime > g.utime - 10'000'000) continue;
    const geom::Pose2 map_move = toPose(before.robot_pose).inverse().compose(toPose(g.robot_pose));
    const geom::Pose2 true_move = truth.robotAt(before.utime).inverse().compose(truth.robotAt(g.utime));
    pos_err += (map_move.position() - true_move.position()).norm();
    heading_err += std::abs(geom::angleDiff(map_move.theta, true_move.theta));
    ++pairs;
  }
  if (pairs > 0) {
    m.set("agm_tactical.frame_error_10s_m", pos_err / static_cast<double>(pairs));
    m.set("agm_tactical.frame_error_10s_rad", heading_err / static_cast<double>(pairs));
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
    const SparseGridMap* g = sameTime(log.agm_tactical, csm.utime);
    if (!g) continue;
    const Window win(*g, true_from_odom);
    const int scan = seen.newestAt(csm.utime);
    for (size_t i = 0; i < boundary.size(); ++i) {
      if (located[i] >= csm.utime || !win.contains(boundary[i].p)) continue;
      if (seen.saw(sc, scan, boundary[i].obstacle, boundary[i].p, o.seen_radius)) continue;  // the laser's now
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


namespace {
// The cells of a grid message (odometry frame) whose centres lie within r of q: the largest G and Gp.
struct NearCells {
  int g = 0, gp = 0;
};
NearCells nearCells(const SparseGridMap& g, const geom::Vec2& q, double r) {
  NearCells out;
  if (!g.complete()) return out;
  const double cs = g.cell_size;
  const int x0 = std::max(0, static_cast<int>(std::floor((q.x() - r - g.origin_x) / cs)));
  const int x1 = std::min(g.width - 1, static_cast<int>(std::floor((q.x() + r - g.origin_x) / cs)));
  const int y0 = std::max(0, static_cast<int>(std::floor((q.y() - r - g.origin_y) / cs)));
  const int y1 = std::min(g.height - 1, static_cast<int>(std::floor((q.y() + r - g.origin_y) / cs)));
  for (int iy = y0; iy <= y1; ++iy)
    for (int ix = x0; ix <= x1; ++ix) {
      const geom::Vec2 c(g.origin_x + (ix + 0.5) * cs, g.origin_y + (iy + 0.5) * cs);
      if ((c - q).norm() > r) continue;
      const int64_t idx = int64_t{iy} * g.width + ix;
      out.g = std::max(out.g, g.g(idx));
      out.gp = std::max(out.gp, g.gp(idx));
    }
  return out;
}

// Shares of a set of samples by cause, as metrics under prefix.
struct Causes {
  std::map<std::string, int64_t> n;
  int64_t total = 0;
  void add(const std::string& cause) {
    ++n[cause];
    ++total;
  }
  void put(Metrics& m, const std::string& prefix) const {
    m.set(prefix + ".samples", total);
    for (const auto& [k, v] : n) m.set(prefix + "." + k, total > 0 ? double(v) / double(total) : 0.0);
  }
};
}  // namespace

void evalTacticalBreakdown(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o,
                           Metrics& m) {
  if (log.agm_tactical.empty() || log.sim_states.size() < 2) return;
  constexpr double kMisplaced = 0.30;  // [m] an occupied cell this near: the echoes went to a neighbouring cell
  constexpr int64_t kRecentUs = 1'000'000;  // located only within the last second
  const double forget_m = o.forget_after_m > 0 ? o.forget_after_m : kInf;  // navigator.agm.h_max_m
  TruthTrack truth(log.sim_states);
  const auto boundary = sonarOnlyCandidates(sc, seen);
  // Every locating echo of every point, and how the complement stage classified it.
  std::vector<std::vector<std::pair<int64_t, int>>> echoes(boundary.size());
  double prev_x = 0, prev_y = 0;
  forEachLocating(
      log, sc, boundary, o.located_radius, &seen, o.seen_radius, hypothesisRangeLimit(log, o),
      [](size_t, int64_t) { return false; },
      [&](size_t i, int64_t utime, int sensor) { echoes[i].emplace_back(utime, sensor); });
  std::map<std::pair<int64_t, int>, int> cls;
  for (const auto& c : log.complements)
    for (const auto& r : c.readings) cls[{c.utime, r.sensor_id}] = r.cls;
  auto complementaryBefore = [&](size_t i, int64_t utime, int64_t& last) {
    int n = 0;
    last = -1;
    for (const auto& [t, sensor] : echoes[i]) {
      if (t >= utime) break;
      const auto it = cls.find({t, sensor});
      if (it != cls.end() && (it->second == complement_reading_t::CLASS_COMPLEMENTARY ||
                              it->second == complement_reading_t::CLASS_OUTSIDE_VIEW ||
                              it->second == complement_reading_t::CLASS_SEEN_BEFORE)) {
        ++n;
        last = t;
      }
    }
    return n;
  };
  // The classes of the locating echoes before utime (the most common one names the cause).
  auto echoClass = [&](size_t i, int64_t utime) {
    std::map<int, int> n;
    for (const auto& [t, sensor] : echoes[i]) {
      if (t >= utime) break;
      const auto it = cls.find({t, sensor});
      ++n[it == cls.end() ? -1 : it->second];
    }
    int best = -1, most = -1;
    for (const auto& [c, k] : n)
      if (k > most) {
        most = k;
        best = c;
      }
    switch (best) {
      case complement_reading_t::CLASS_REDUNDANT: return std::string("redundant");
      case complement_reading_t::CLASS_FALSE: return std::string("false");
      case complement_reading_t::CLASS_UNVERIFIABLE: return std::string("unverifiable");
      default: return std::string("other");
    }
  };
  // Distance the robot drove (true path) up to each SIM_STATE, to tell forgetting by distance,
  // and the odometry error model's state there, to tell forgetting by odometry error.
  std::vector<std::pair<int64_t, double>> odo;
  std::vector<OdometryError::Mark> odo_error;
  OdometryError odometry_error(o.odometry);
  double prev_theta = 0;
  for (const auto& st : log.sim_states) {
    const double step = odo.empty() ? 0.0 : std::hypot(st.robot_pose.x - prev_x, st.robot_pose.y - prev_y);
    const double turn = odo.empty() ? 0.0 : geom::angleDiff(st.robot_pose.theta, prev_theta);
    const double d = odo.empty() ? 0.0 : odo.back().second + step;
    prev_x = st.robot_pose.x;
    prev_y = st.robot_pose.y;
    prev_theta = st.robot_pose.theta;
    odo.emplace_back(st.utime, d);
    odometry_error.advance(step, turn);
    odo_error.push_back(odometry_error.now());
  }
  auto stateIndex = [&](int64_t utime) {
    auto it = std::lower_bound(odo.begin(), odo.end(), utime,
                               [](const std::pair<int64_t, double>& a, int64_t t) { return a.first < t; });
    return it == odo.end() ? odo.size() - 1 : static_cast<size_t>(it - odo.begin());
  };
  auto drivenAt = [&](int64_t utime) { return odo[stateIndex(utime)].second; };
  // 1-sigma displacement between two times: the error model's variance between their marks.
  auto odometrySigma = [&](int64_t from, int64_t to) {
    return std::sqrt(odometry_error.varianceBetween(odo_error[stateIndex(from)], odo_error[stateIndex(to)]));
  };
  auto materialOf = [&](int obstacle) {
    return obstacle >= 0 && static_cast<size_t>(obstacle) < sc.obstacles.size()
               ? sc.obstacles[static_cast<size_t>(obstacle)].material
               : std::string("unknown");
  };
  std::map<std::string, Ratio> by_material;
  std::map<std::string, int64_t> samples_by_material;
  Causes agm_causes, line_causes, off_lines;
  std::vector<char> found_before(boundary.size(), 0), left_window(boundary.size(), 0);
  LineGenerationParams lp = o.lines;  // the run's line generation (evalOptions(config))
  const int64_t t0 = log.sim_states.empty() ? 0 : log.sim_states.front().utime;  // as the sector samples
  for (const auto& g : log.agm_tactical) {
    // (the threshold the navigator generated its lines at: G_T as its ring gave it)
    if (g.gp_threshold > 0) lp.gp_threshold = g.gp_threshold;
    const geom::Pose2 true_from_odom = truth.robotAt(g.utime).compose(toPose(g.robot_pose).inverse());
    const double tol = g.cell_size * (std::sqrt(0.5) + 1.0);
    const auto occupied = occupiedCells(g, true_from_odom);
    const Window win(g, true_from_odom);
    const int scan = seen.newestAt(g.utime);
    const geom::Pose2 odom_from_true = true_from_odom.inverse();
    // The line generation redone on this map's occupied cells (centres, odometry frame, with
    // their G, Gp and indices: the echo-weighted refit and the hidden cells' own support), to
    // tell where an uncovered point's cells were lost.
    std::vector<CandidateCell> cand;
    for (const SparseGridMap::Cell& cell : g.cells()) {
      if (cell.gp <= 0 || cell.gp < g.gp_threshold) continue;
      cand.push_back({g.cellCentre(cell.index), cell.gp, 0, cell.g, cell.index % g.width, cell.index / g.width});
    }
    const geom::Pose2 robot = toPose(g.robot_pose);
    std::vector<std::vector<PolarCell>> runs;
    std::vector<std::vector<AgmLine>> run_lines;
    auto addRuns = [&](const std::vector<CandidateCell>& group) {
      for (LineRun& r : lineRuns(group, robot, g.cell_size, lp)) {
        run_lines.push_back(std::move(r.lines));
        runs.push_back(std::move(r.cells));
      }
    };
    if (lp.occlusion == LineGenerationParams::Occlusion::Global) addRuns(cand);
    else
      for (const auto& cluster : clusterCells(cand, lp.max_gap)) addRuns(cluster);
    const line_map_t* csm = sameTime(log.current_sensor_maps, g.utime);
    std::vector<geom::Segment> sonar;
    if (csm)
      for (const auto& s : csm->segments)
        if (s.source == line_segment_t::SOURCE_SONAR) sonar.push_back({{s.x0, s.y0}, {s.x1, s.y1}});  // odometry frame
    // Where the sonar lines' length off every static surface lies: how far off, and the nearest
    // surface's material (a mover's trace counts as "none").
    for (const auto& seg : sonar) {
      const geom::Segment t{true_from_odom.transform(seg.a), true_from_odom.transform(seg.b)};
      const int n = std::max(1, static_cast<int>(std::ceil(t.length() / 0.01)));
      for (int k = 0; k < n; ++k) {
        const geom::Vec2 q = t.a + (t.b - t.a) * ((k + 0.5) / n);
        double best = kInf;
        int obstacle = -1;
        for (const auto& p : sc.statics)
          if (const double d = distanceTo(p, q); d < best) {
            best = d;
            obstacle = p.obstacle;
          }
        if (best <= o.line_tolerance) continue;
        off_lines.add(std::string(best <= 0.2 ? "within_20cm_of_" : best <= 0.4 ? "within_40cm_of_" : "farther_from_") +
                      materialOf(obstacle));
      }
    }
    for (size_t i = 0; i < boundary.size(); ++i) {
      if (echoes[i].empty() || echoes[i].front().first >= g.utime) continue;
      if (!win.contains(boundary[i].p)) {
        if (found_before[i]) left_window[i] = 1;  // out of the published window (and maybe the whole one)
        continue;
      }
      if (seen.saw(sc, scan, boundary[i].obstacle, boundary[i].p, o.seen_radius)) continue;
      const geom::Vec2 q = odom_from_true.transform(boundary[i].p);
      const NearCells near = nearCells(g, q, tol);
      const bool found = near.gp > 0 && near.gp >= g.gp_threshold;
      by_material[materialOf(boundary[i].obstacle)].add(found);
      ++samples_by_material[materialOf(boundary[i].obstacle)];
      // This sample's row of tactical_samples_csv: the AGM's cause and the lines' (empty: none).
      std::string agm_cause, line_cause;
      int line_covered = -1;  // -1: no CURRENT_SENSOR_MAP of this time
      auto emit = [&] {
        if (!o.tactical_samples_csv) return;
        *o.tactical_samples_csv << static_cast<double>(g.utime - t0) * 1e-6 << ',' << boundary[i].p.x() << ','
                                << boundary[i].p.y() << ',' << boundary[i].obstacle << ','
                                << materialOf(boundary[i].obstacle) << ',' << (found ? 1 : 0) << ',' << agm_cause
                                << ',';
        if (line_covered >= 0) *o.tactical_samples_csv << line_covered;
        *o.tactical_samples_csv << ',' << line_cause << '\n';
      };
      if (found) {
        found_before[i] = 1;
        left_window[i] = 0;
      } else {
        int64_t last = -1;
        const int ncomp = complementaryBefore(i, g.utime, last);
        if (found_before[i])
          agm_cause = last >= 0 && drivenAt(g.utime) - drivenAt(last) > forget_m ? "forgotten_after_15m"
                      : last >= 0 && o.forget_sigma_m > 0 && odometrySigma(last, g.utime) > o.forget_sigma_m
                          ? "forgotten_odometry_error"
                      : left_window[i] ? "forgotten_left_window"
                                       : "forgotten_other";
        else if (ncomp == 0) agm_cause = "no_complementary_echo_" + echoClass(i, g.utime);
        else if (near.g > 0 || near.gp > 0) agm_cause = "below_threshold";
        else if (nearCells(g, q, kMisplaced).gp >= g.gp_threshold) {
          // An occupied cell 0.17-0.3 m away: on the point's own surface (a gap between the cells
          // along it) or off it (the echoes were placed in front of or behind the surface).
          bool on_surface = false;
          for (const auto& c : occupied)
            if ((c - boundary[i].p).norm() <= kMisplaced &&
                distanceTo(sc.statics[static_cast<size_t>(boundary[i].surface)], c) <= tol)
              on_surface = true;
          agm_cause = on_surface ? "gap_along_surface" : "misplaced_off_surface";
        }
        else if (g.utime - echoes[i].front().first < kRecentUs) agm_cause = "located_within_1s";
        else if (ncomp == 1) agm_cause = "one_complementary_echo";
        else agm_cause = "not_placed";
        agm_causes.add(agm_cause);
      }
      if (!csm) {
        emit();
        continue;
      }
      bool covered = false;
      for (const auto& s : sonar)
        if (geom::distance(s, q) <= o.line_tolerance) covered = true;
      line_covered = covered ? 1 : 0;
      if (covered) {
        emit();
        continue;
      }
      if (!found) {
        line_cause = "no_cell";
        line_causes.add(line_cause);
        emit();
        continue;
      }
      // Where did the cells near q go?
      std::string cause = "hidden_by_nearer_cell";
      for (size_t r = 0; r < runs.size() && cause == "hidden_by_nearer_cell"; ++r) {
        bool in_run = false;
        for (const auto& pc : runs[r])
          if ((pc.cell.centre - q).norm() <= tol) in_run = true;
        if (!in_run) continue;
        if (runs[r].size() < static_cast<size_t>(lp.min_cells)) {
          cause = "short_run";
          break;
        }
        cause = "short_piece_or_off_line";
        for (const auto& l : run_lines[r])
          if (geom::distance(l.seg, q) <= o.line_tolerance) cause = "line_from_centroids_off";
      }
      line_cause = cause;
      line_causes.add(cause);
      emit();
    }
  }
  agm_causes.put(m, "agm_tactical.breakdown.missed");
  line_causes.put(m, "lines.breakdown.uncovered");
  off_lines.put(m, "lines.breakdown.off_surface");
  for (const auto& [mat, r] : by_material) setRatio(m, "agm_tactical.breakdown.recall_by_material." + mat, r);
  for (const auto& [mat, n] : samples_by_material) m.set("agm_tactical.breakdown.samples_by_material." + mat, n);
}

}  // namespace lasonic::eval
