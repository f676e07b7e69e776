#include "eval/evaluate.hpp"

#include <sstream>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <ostream>

#include "complement/complement.hpp"
#include "core/geometry.hpp"
#include "core/pose_msg.hpp"
#include "eval/baselines.hpp"
#include "eval/laser_seen.hpp"
#include "eval/observability.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "operational/sonar_bearing.hpp"
#include "stages/navigator_stage.hpp"
#include "stages/pilot_stage.hpp"

namespace lasonic::eval {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename T>
void decodeInto(const LogRecord& r, std::vector<T>& out, int64_t& bad) {
  if (auto m = decodeAs<T>(r.data)) out.push_back(std::move(*m));
  else ++bad;
}

// A grid is kept without its zero cells as soon as it is decoded (eval/sparse_grid_map.hpp).
void decodeGrid(const LogRecord& r, std::vector<SparseGridMap>& out, int64_t& bad) {
  if (auto m = decodeAs<grid_map_t>(r.data)) out.emplace_back(*m);
  else ++bad;
}


void setRatio(Metrics& m, const std::string& key, const Ratio& r) {
  if (r.valid()) m.set(key, r.value());
}
}  // namespace

RunLog loadRunLog(const std::string& path) {
  RunLog log;
  LogReader reader(path);
  while (auto r = reader.next()) {
    const std::string& ch = r->channel;
    if (ch == channels::SIM_STATE) {
      const size_t before = log.sim_states.size();
      decodeInto(*r, log.sim_states, log.undecodable);
      if (log.sim_states.size() > before) log.sim_time.add(log.sim_states.back().utime);
    }
    else if (ch == channels::ODOMETRY) decodeInto(*r, log.odometry, log.undecodable);
    else if (ch == channels::LASER_SCAN) decodeInto(*r, log.laser_scans, log.undecodable);
    else if (ch == channels::LASER_TRUTH) decodeInto(*r, log.laser_truths, log.undecodable);
    else if (ch == channels::SONAR_RING) decodeInto(*r, log.sonar_rings, log.undecodable);
    else if (ch == channels::SONAR_TRUTH) decodeInto(*r, log.sonar_truths, log.undecodable);
    else if (ch == channels::SONAR_HYPOTHESIS) decodeInto(*r, log.hypotheses, log.undecodable);
    else if (ch == channels::SONAR_COMPLEMENT) decodeInto(*r, log.complements, log.undecodable);
    else if (ch == channels::SECTOR_MAP) decodeInto(*r, log.sector_maps, log.undecodable);
    else if (ch == channels::AGM_OPERATIONAL) decodeGrid(*r, log.agm_operational, log.undecodable);
    else if (ch == channels::AGM_TACTICAL) decodeGrid(*r, log.agm_tactical, log.undecodable);
    else if (ch == channels::CURRENT_SENSOR_MAP) decodeInto(*r, log.current_sensor_maps, log.undecodable);
  }
  // Live logs interleave processes: order by message time (stable for equal times).
  std::stable_sort(log.sim_states.begin(), log.sim_states.end(),
                   [](const auto& a, const auto& b) { return a.utime < b.utime; });
  return log;
}

ScenarioMatch checkLogMatchesScenario(const RunLog& log, const sim::Scenario& scenario) {
  ScenarioMatch m;
  if (log.sim_states.empty()) return m;
  const size_t n = scenario.movers.size();
  std::vector<int> ids;
  for (const sim_state_t& st : log.sim_states) {
    ids.clear();
    for (const mover_state_t& mv : st.movers) ids.push_back(mv.id);
    if (m.error = sim::simStateMoversMismatch(scenario, ids); !m.error.empty()) return m;
  }
  // The truth channels name obstacles by their index in the scenario (movers -(id)-2).
  const auto known = [&](int64_t o) {
    return o == -1 || (o >= 0 && static_cast<size_t>(o) < scenario.obstacles.size()) ||
           (o <= -2 && static_cast<size_t>(-o - 2) < n);
  };
  for (const laser_truth_t& t : log.laser_truths)
    for (const int32_t o : t.obstacle)
      if (!known(o)) {
        m.error = "its LASER_TRUTH names obstacle " + std::to_string(o) + ", the scenario has " +
                  std::to_string(scenario.obstacles.size()) + " obstacles and " + std::to_string(n) + " movers";
        return m;
      }
  for (const sonar_truth_t& t : log.sonar_truths)
    for (const sonar_cause_t& c : t.causes)
      if (!known(c.obstacle)) {
        m.error = "its SONAR_TRUTH names obstacle " + std::to_string(c.obstacle) + ", the scenario has " +
                  std::to_string(scenario.obstacles.size()) + " obstacles and " + std::to_string(n) + " movers";
        return m;
      }
  if (scenario.robot.path.empty()) return m;
  // The simulated robot drives the path's legs exactly, so its farthest true pose from them says
  // whether this is its scenario: metres off, it is another scene (or this one moved); a few
  // centimetres off, a waypoint was edited after the run.
  double worst = 0;
  const sim_state_t* worst_state = nullptr;
  for (const sim_state_t& st : log.sim_states) {
    const double d = sim::distanceToRobotPath(scenario, {st.robot_pose.x, st.robot_pose.y});
    if (!(d <= worst)) {  // NaN poses count as off the path
      worst = d;
      worst_state = &st;
    }
  }
  if (worst_state) {
    std::ostringstream os;
    os << "at t = " << static_cast<double>(worst_state->utime - log.sim_states.front().utime) * 1e-6
       << " s its robot's true pose (" << worst_state->robot_pose.x << ", " << worst_state->robot_pose.y << ") is "
       << worst << " m from the scenario's robot.path";
    if (!(worst <= kOffPathErrorM)) {
      m.error = os.str();
      return m;
    }
    if (worst > kOffPathWarningM) m.warning = os.str() + " (edited after the run?)";
  }
  const geom::Pose2 p0{log.sim_states.front().robot_pose.x, log.sim_states.front().robot_pose.y,
                       log.sim_states.front().robot_pose.theta};
  const geom::Vec2 start = scenario.robot.path.front();
  const double d = std::hypot(p0.x - start.x(), p0.y - start.y());
  if (d > 0.5 && m.warning.empty())
    m.warning = "the robot's first true pose (" + std::to_string(p0.x) + ", " + std::to_string(p0.y) +
                ") is " + std::to_string(d) + " m from the scenario's first waypoint";
  return m;
}

std::string robotRadiusWarning(const RunLog& log, const sim::Scenario& scenario) {
  for (const sector_map_t& sm : log.sector_maps) {
    if (!std::isfinite(sm.robot_radius) || std::abs(sm.robot_radius - scenario.robot.radius) <= 0.01) continue;
    std::ostringstream os;
    os << "SECTOR_MAP's robot_radius " << sm.robot_radius << " m (the pilot's pilot.robot_radius) is not the "
       << "scenario's robot.radius " << scenario.robot.radius << " m: the sector map is measured and scored from the "
       << "pilot's boundary (was the robot's configuration overlay layered?)";
    return os.str();
  }
  return {};
}

// ------------------------------------------------------------------------------ truth

TruthTrack::TruthTrack(const std::vector<sim_state_t>& states) : states_(&states) {}

size_t TruthTrack::bracket(int64_t utime, double& s) const {
  const auto& v = *states_;
  auto it = std::lower_bound(v.begin(), v.end(), utime,
                             [](const sim_state_t& st, int64_t t) { return st.utime < t; });
  if (it == v.begin()) {
    s = 0;
    return 0;
  }
  if (it == v.end()) {
    s = 1;
    return v.size() - 2 < v.size() ? v.size() - 2 : 0;
  }
  const size_t i = static_cast<size_t>(it - v.begin()) - 1;
  s = static_cast<double>(utime - v[i].utime) / static_cast<double>(v[i + 1].utime - v[i].utime);
  return i;
}

geom::Pose2 TruthTrack::robotAt(int64_t utime) const {
  const auto& v = *states_;
  if (v.size() == 1) return toPose(v[0].robot_pose);
  double s = 0;
  const size_t i = bracket(utime, s);
  return geom::interpolate(toPose(v[i].robot_pose), toPose(v[i + 1].robot_pose), s);
}

std::vector<sim::MoverPose> TruthTrack::moversAt(int64_t utime) const {
  const auto& v = *states_;
  std::vector<sim::MoverPose> out;
  if (v.empty()) return out;
  double s = 0;
  const size_t i = v.size() == 1 ? 0 : bracket(utime, s);
  const sim_state_t& a = v[i];
  const sim_state_t& b = v.size() == 1 ? v[0] : v[i + 1];
  for (size_t k = 0; k < a.movers.size(); ++k) {
    const mover_state_t& ma = a.movers[k];
    const mover_state_t& mb = k < b.movers.size() ? b.movers[k] : ma;
    out.push_back({ma.id, {ma.x + s * (mb.x - ma.x), ma.y + s * (mb.y - ma.y)}, ma.radius});
  }
  return out;
}

// ------------------------------------------------------------------------------ sensors

namespace {
constexpr int kNumCauses = 6;  // sonar_cause_t::CAUSE_*
const char* causeName(int cause) {
  static const char* kCauses[kNumCauses] = {"direct", "specular_long", "no_echo", "crosstalk", "foreign", "late_echo"};
  return cause >= 0 && cause < kNumCauses ? kCauses[cause] : "unknown";
}

// The material of a SONAR_TRUTH obstacle index (a mover: -(id)-2; none: -1); empty without the
// scenario or for none.
std::string obstacleMaterial(const sim::Scenario* sc, int obstacle) {
  if (!sc) return {};
  if (obstacle >= 0 && static_cast<size_t>(obstacle) < sc->obstacles.size())
    return sc->obstacles[static_cast<size_t>(obstacle)].material;
  if (obstacle <= -2 && static_cast<size_t>(-obstacle - 2) < sc->movers.size())
    return sc->movers[static_cast<size_t>(-obstacle - 2)].material;
  return {};
}
}  // namespace

void evalSensors(const RunLog& log, const sim::Scenario& sc, Metrics& m) {
  m.set("sensors.laser_scans", static_cast<int64_t>(log.laser_scans.size()));
  int64_t readings = 0;
  for (const auto& r : log.sonar_rings) readings += static_cast<int64_t>(r.range.size());
  m.set("sensors.sonar_readings", readings);
  if (!log.sonar_truths.empty()) {
    static const char* kReflectors[] = {"none", "plane", "corner", "edge", "cylinder"};
    constexpr int kNumReflectors = 5;
    int64_t counts[kNumCauses] = {}, reflectors[kNumReflectors] = {}, total = 0, direct = 0;
    for (const auto& t : log.sonar_truths)
      for (const auto& c : t.causes) {
        if (c.cause >= 0 && c.cause < kNumCauses) ++counts[c.cause];
        if (c.cause == sonar_cause_t::CAUSE_DIRECT) {
          ++direct;
          if (c.reflector >= 0 && c.reflector < kNumReflectors) ++reflectors[c.reflector];
        }
        ++total;
      }
    for (int i = 0; i < kNumCauses; ++i)
      m.set(std::string("sensors.sonar_causes.") + causeName(i),
            total > 0 ? static_cast<double>(counts[i]) / static_cast<double>(total) : 0.0);
    // Which geometry answered the direct echoes (shares of the direct readings).
    if (direct > 0)
      for (int i = 1; i < kNumReflectors; ++i)
        m.set(std::string("sensors.sonar_reflectors.") + kReflectors[i],
              static_cast<double>(reflectors[i]) / static_cast<double>(direct));
  }
  if (!log.laser_truths.empty()) {
    // Shares of all laser readings: returned by a surface of each material, a mixed pixel (a
    // return between two surfaces), or nothing.
    std::map<std::string, int64_t> by_material;
    for (const auto& kv : sc.materials) by_material[kv.first] = 0;
    int64_t total = 0, mixed = 0, none = 0;
    std::map<std::pair<int64_t, int32_t>, const laser_scan_t*> scans;
    for (const auto& s : log.laser_scans) scans[{s.utime, s.seq}] = &s;
    for (const auto& t : log.laser_truths) {
      const auto it = scans.find({t.utime, t.seq});
      const laser_scan_t* scan = it == scans.end() ? nullptr : it->second;
      for (size_t i = 0; i < t.obstacle.size(); ++i) {
        ++total;
        const bool returned = scan && i < scan->flags.size() && scan->flags[i] == laser_scan_t::FLAG_OK;
        const int o = t.obstacle[i];
        if (!returned) ++none;
        else if (o >= 0 && o < static_cast<int>(sc.obstacles.size())) ++by_material[sc.obstacles[static_cast<size_t>(o)].material];
        else if (o <= -2 && -o - 2 < static_cast<int>(sc.movers.size())) ++by_material[sc.movers[static_cast<size_t>(-o - 2)].material];
        else ++mixed;
      }
    }
    if (total > 0) {
      for (const auto& [mat, n] : by_material)
        m.set("sensors.laser_returns_by_material." + mat, static_cast<double>(n) / static_cast<double>(total));
      m.set("sensors.laser_mixed_pixels", static_cast<double>(mixed) / static_cast<double>(total));
      m.set("sensors.laser_no_return", static_cast<double>(none) / static_cast<double>(total));
    }
  }
}

// ------------------------------------------------------------------------------ complement

double hypothesisRangeLimit(const RunLog& log, const EvalOptions& o) {
  if (!log.hypotheses.empty() && std::isfinite(log.hypotheses.front().range_limit) &&
      log.hypotheses.front().range_limit > 0)
    return log.hypotheses.front().range_limit;
  return o.range_limit;
}

double operationalMemory(const RunLog& log, const EvalOptions& o) {
  if (o.operational_h_max <= 0) return o.recent_echo_s;
  std::vector<int64_t> gaps;
  for (size_t i = 1; i < log.sonar_rings.size(); ++i)
    if (const int64_t d = log.sonar_rings[i].utime - log.sonar_rings[i - 1].utime; d > 0) gaps.push_back(d);
  if (gaps.empty()) return o.recent_echo_s;
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  RingGroups ring;
  for (const sonar_ring_t& r : log.sonar_rings) ring.fired(r.group);
  const int h_max = ring.hMax(o.operational_h_max_ring_cycles, o.operational_h_max);
  return static_cast<double>(h_max) * static_cast<double>(gaps[gaps.size() / 2]) * 1e-6;
}

void writeComplementSampleHeader(std::ostream& out) {
  out << "t_s,sensor_id,range_m,cause,true_range_m,obstacle,material,hit_x,hit_y,laser_saw,laser_nearest_m,"
         "hypothetical_m,class,invisible,informative,specular_long,redundant,complementary\n";
}

void evalLaserTruth(const LaserSeen& seen, Metrics& m) {
  m.set("sensors.laser_truth", int64_t{seen.available() ? 1 : 0});
  if (seen.available()) m.set("sensors.laser_scans_without_truth", seen.scansWithoutTruth());
}

void evalComplement(const RunLog& log, const EvalOptions& o, Metrics& m) {
  evalComplement(log, LaserSeen(log, o.seen_radius), o, m);
}

void evalComplement(const RunLog& log, const LaserSeen& seen, const EvalOptions& o, Metrics& m,
                    const sim::Scenario* sc) {
  if (log.complements.empty() || log.sonar_truths.empty()) return;
  using Key = std::pair<int64_t, int>;
  std::map<Key, const sonar_cause_t*> truth;
  for (const auto& t : log.sonar_truths)
    for (const auto& c : t.causes) truth[{t.utime, c.sensor_id}] = &c;
  struct Real {
    float range;
    bool no_echo;
    pose2d_t mount;
  };
  std::map<Key, Real> real;
  for (const auto& r : log.sonar_rings)
    for (size_t i = 0; i < r.range.size() && i < r.sensor_id.size() && i < r.no_echo.size(); ++i)
      real[{r.utime, r.sensor_id[i]}] = {r.range[i], r.no_echo[i] != 0, i < r.mount.size() ? r.mount[i] : pose2d_t{}};
  const double limit = hypothesisRangeLimit(log, o);
  const bool per_scan = seen.available();
  const TruthTrack track(log.sim_states);

  Ratio invisible, informative, specular, redundant, precision;
  // What the complement called the invisible echoes, per class (CLASS_*): where recall is lost.
  constexpr int kClasses = 7;
  std::array<double, kClasses> invisible_by_class{}, informative_by_class{};
  for (const auto& cm : log.complements) {
    // The scan the complement compared this firing with: the one its Radar Map came from, else
    // the newest completed at or before the firing.
    int scan = per_scan ? seen.completedAt(cm.radar_map_utime) : -1;
    if (per_scan && scan < 0) scan = seen.newestAt(cm.utime);
    // Before the first scan there is nothing the laser saw to compare with: such firings are
    // left out of the laser-based splits (specular_rejection and precision keep them).
    const bool no_scan = per_scan && scan < 0;
    const double group_beam = geom::plausibleBeamWidth(cm.beam_width)
                            ? double(cm.beam_width)
                            : geom::deg2rad(30.0);
    for (const auto& rd : cm.readings) {
      // The beam this reading's hypothesis used (logs before readings carried it: the group's).
      const double beam = geom::plausibleBeamWidth(rd.beam_width)
                              ? double(rd.beam_width)
                              : group_beam;
      const Key k{cm.utime, rd.sensor_id};
      auto t = truth.find(k);
      auto r = real.find(k);
      if (t == truth.end() || r == real.end()) continue;
      const sonar_cause_t& c = *t->second;
      const double range = r->second.range;
      const bool echo = !r->second.no_echo && std::isfinite(range);
      const bool comp = rd.cls == complement_reading_t::CLASS_COMPLEMENTARY;
      const bool direct = c.cause == sonar_cause_t::CAUSE_DIRECT && echo;
      // Laser-visible: the compared scan returned from the echoing obstacle within seen_radius
      // of the echo's hit point (fallback: the material reflects the laser).
      bool laser_saw = c.laser_visible != 0;
      // The nearest surface the laser saw inside the ideal beam (fallback: the nearest
      // laser-reflecting one, SONAR_TRUTH); none: the limit.
      double visible = c.nearest_laser_visible < 0 ? limit : c.nearest_laser_visible;
      if (per_scan && direct && !no_scan) {
        const geom::Vec2 hit{c.hit_x, c.hit_y};
        laser_saw = sc ? seen.saw(*sc, scan, c.obstacle, hit, o.seen_radius, cm.utime)
                       : seen.saw(scan, c.obstacle, hit, o.seen_radius, cm.utime);
        const geom::Pose2 sensor = track.robotAt(cm.utime).compose(toPose(r->second.mount));
        visible = seen.nearestInSector(scan, geom::Sector{sensor.position(), sensor.theta, beam, limit}).value_or(limit);
      }
      const bool informative_echo = direct && !no_scan && range <= limit && range < visible - cm.tolerance;
      if (direct && !no_scan && !laser_saw && range <= limit) {
        invisible.add(comp);
        if (rd.cls >= 0 && rd.cls < kClasses) invisible_by_class[static_cast<size_t>(rd.cls)] += 1;
      }
      if (informative_echo) {
        informative.add(comp);
        if (rd.cls >= 0 && rd.cls < kClasses) informative_by_class[static_cast<size_t>(rd.cls)] += 1;
      }
      if (c.cause == sonar_cause_t::CAUSE_SPECULAR_LONG) specular.add(!comp);
      // "The RM holds it": the Radar Map has a surface inside the ideal beam no farther than the
      // echoing one (+ tolerance). A laser-reflecting pipe too thin to give an RM segment is
      // thus not held, and its complementary echo counts as correct, not as a failed drop.
      const bool rm_holds = std::isfinite(rd.hypothetical_range) && c.true_range >= 0 &&
                            rd.hypothetical_range <= c.true_range + cm.tolerance;
      const bool counts_redundant = direct && !no_scan && laser_saw && rm_holds;
      if (counts_redundant) redundant.add(!comp);
      if (comp) precision.add(direct && c.true_range >= 0 && !rm_holds);
      if (o.complement_samples_csv) {
        std::ostream& out = *o.complement_samples_csv;
        const int64_t t0 = log.sim_states.empty() ? log.complements.front().utime : log.sim_states.front().utime;
        out << static_cast<double>(cm.utime - t0) * 1e-6 << ',' << rd.sensor_id << ',';
        if (echo) out << range;
        out << ',' << causeName(c.cause) << ',';
        if (c.true_range >= 0) out << c.true_range;
        out << ',' << c.obstacle << ',' << obstacleMaterial(sc, c.obstacle) << ',';
        if (c.true_range >= 0) out << c.hit_x << ',' << c.hit_y;
        else out << ',';
        out << ',';
        if (!no_scan) out << (laser_saw ? 1 : 0);
        out << ',' << visible << ',';
        if (std::isfinite(rd.hypothetical_range)) out << rd.hypothetical_range;
        out << ','
            << (rd.cls >= 0 && rd.cls < kClasses ? complement::className(static_cast<complement::SonarClass>(rd.cls))
                                                 : "unknown");
        // Per rate: empty when the reading does not count in it, else 1 where it counted as right.
        const auto field = [&out](bool counts, bool right) {
          out << ',';
          if (counts) out << (right ? 1 : 0);
        };
        field(direct && !no_scan && !laser_saw && range <= limit, comp);
        field(informative_echo, comp);
        field(c.cause == sonar_cause_t::CAUSE_SPECULAR_LONG, !comp);
        field(counts_redundant, !comp);
        field(comp, direct && c.true_range >= 0 && !rm_holds);
        out << '\n';
      }
    }
  }
  setRatio(m, "complement.invisible_recall", invisible);
  setRatio(m, "complement.informative_recall", informative);
  setRatio(m, "complement.specular_rejection", specular);
  setRatio(m, "complement.redundant_drop", redundant);
  setRatio(m, "complement.precision", precision);
  for (int k = 0; k < kClasses; ++k) {
    const std::string cls = complement::className(static_cast<complement::SonarClass>(k));
    if (invisible.den > 0)
      m.set("complement.invisible_by_class." + cls,
            invisible_by_class[static_cast<size_t>(k)] / static_cast<double>(invisible.den));
    if (informative.den > 0)
      m.set("complement.informative_by_class." + cls,
            informative_by_class[static_cast<size_t>(k)] / static_cast<double>(informative.den));
  }
  m.set("complement.samples.invisible", invisible.den);
  m.set("complement.samples.informative", informative.den);
  m.set("complement.samples.specular_long", specular.den);
  m.set("complement.samples.redundant", redundant.den);
  m.set("complement.samples.complementary", precision.den);
}

// ------------------------------------------------------------------------------ sector map

std::vector<double> trueSectorDistances(const sim::WorldGeometry& world, const geom::Pose2& robot,
                                        double robot_radius, int nsectors, double max_range) {
  std::vector<double> out;
  for (const SectorTruth& t : trueSectorHits(world, robot, robot_radius, nsectors, max_range))
    out.push_back(t.distance);
  return out;
}

void evalSectorMap(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m) {
  if (log.sector_maps.empty() || log.sim_states.size() < 2) return;
  evalSectorMap(log, sectorTruthTable(log, sc, o), o, m);
}

namespace {
// One value of a sector map as a CSV field: empty when unknown (< 0).
void csvDistance(std::ostream& out, double d) {
  if (d >= 0) out << d;
}

void writeSectorSample(std::ostream& out, const RunLog& log, const sector_map_t& sm, size_t k, const SectorSample& s,
                       const std::vector<std::string>& materials, const EvalOptions& o) {
  const int64_t t0 = log.sim_states.front().utime;
  const double reported = sm.distance[k];
  const bool in_range = s.truth <= o.sector_range;
  // The sector's centre bearing in the robot frame (sector 0 starts at -180 deg, behind).
  const double bearing = -180.0 + 360.0 * (static_cast<double>(k) + 0.5) / static_cast<double>(sm.nsectors);
  out << static_cast<double>(sm.utime - t0) * 1e-6 << ',' << k << ',' << bearing << ',';
  if (std::isfinite(s.truth)) out << s.truth;
  out << ',';
  csvDistance(out, reported);
  out << ',' << sectorSourceName(sm.source[k]) << ',';
  csvDistance(out, sm.laser_distance[k]);
  out << ',';
  csvDistance(out, sm.sonar_distance[k]);
  out << ',';
  if (k < sm.remembered_distance.size()) csvDistance(out, sm.remembered_distance[k]);
  out << ',' << (s.material >= 0 && static_cast<size_t>(s.material) < materials.size() ? materials[static_cast<size_t>(s.material)] : "")
      << ',' << (in_range && s.observable ? cueName(s.cue) : in_range ? "unobservable" : "")
      << ',' << (sectorMissed(reported, s, o) ? 1 : 0) << ',' << (sectorFalseAlarm(reported, s, o) ? 1 : 0) << ',';
  if (std::isfinite(s.x) && std::isfinite(s.y)) out << s.x << ',' << s.y;
  else out << ',';
  out << ',';
  if (s.obstacle >= 0) out << s.obstacle;
  out << '\n';
}
}  // namespace

void writeSectorSampleHeader(std::ostream& out) {
  out << "t_s,sector,bearing_deg,truth_m,reported_m,source,laser_m,sonar_m,remembered_m,material,cue,missed,"
         "false_alarm,truth_x,truth_y,obstacle\n";
}

void writeTacticalSampleHeader(std::ostream& out) {
  out << "t_s,x,y,obstacle,material,in_map,agm_cause,line_covered,line_cause\n";
}

void evalSectorMap(const RunLog& log, const SectorTruthTable& truth, const EvalOptions& o, Metrics& m) {
  if (log.sector_maps.empty() || log.sim_states.size() < 2) return;
  SectorScore fused;
  for (size_t i = 0; i < truth.maps.size(); ++i) {
    const sector_map_t& sm = log.sector_maps[truth.maps[i]];
    const SectorSample* s = truth.mapSamples(i);
    for (size_t k = 0; k < static_cast<size_t>(truth.sectors(i)); ++k) {
      fused.add(sm.distance[k], s[k], o, sm.source[k]);
      if (o.samples_csv) writeSectorSample(*o.samples_csv, log, sm, k, s[k], truth.materials, o);
    }
  }
  m.set("sector_map.maps", static_cast<int64_t>(truth.maps.size()));
  m.set("sector_map.maps_before_first_data", truth.warmup);
  m.set("sector_map.echo_memory_s", truth.echo_memory_s);
  fused.write(m, "sector_map", true, truth.materials);
}

// ------------------------------------------------------------------------------ AGM

void evalAgmOperational(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, Metrics& m) {
  evalAgmOperational(log, sc, LaserSeen(log, o.seen_radius), o, m);
}

void evalAgmOperational(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen, const EvalOptions& o,
                        Metrics& m) {
  if (log.agm_operational.empty() || log.sim_states.size() < 2) return;
  TruthTrack truth(log.sim_states);
  sim::WorldGeometry world(sc);
  // Boundary samples the sonar alone can provide: what the complement exists to find (those the
  // newest scan saw are skipped below).
  const std::vector<BoundaryPoint> candidates = sonarOnlyCandidates(sc, seen);
  Ratio precision, recall;
  for (const auto& g : log.agm_operational) {
    world.setMovers(truth.moversAt(g.utime));
    const geom::Pose2 true_robot = truth.robotAt(g.utime);
    // Odometry (global) frame -> true frame at the map's time.
    const geom::Pose2 true_from_odom = true_robot.compose(toPose(g.robot_pose).inverse());
    const double tol = g.cell_size * (std::sqrt(0.5) + 1.0);
    std::vector<geom::Vec2> occupied;
    for (const SparseGridMap::Cell& cell : g.cells()) {  // row by row, as the message's arrays
      if (cell.gp <= 0 || cell.gp < g.gp_threshold) continue;
      const geom::Vec2 c = g.cellCentre(cell.index);
      occupied.push_back(true_from_odom.transform(c));
    }
    for (const auto& c : occupied) {
      double best = kInf;
      for (const auto& p : world.primitives()) {
        const double d = p.kind == sim::Primitive::Kind::Segment
                             ? geom::distance(p.segment, c)
                             : std::abs((c - p.circle.center).norm() - p.circle.radius);
        best = std::min(best, d);
      }
      precision.add(best <= tol);
    }
    const double reach = sc.robot.radius + o.range_limit;
    const int scan = seen.newestAt(g.utime);
    if (seen.available() && scan < 0) continue;  // before the first scan: nothing to compare with
    for (const BoundaryPoint& b : candidates) {
      const geom::Vec2 d = b.p - true_robot.position();
      const double dist = d.norm();
      if (dist > reach || dist < 1e-6) continue;
      // What the newest scan saw is the Radar Map's, not the AGM's.
      if (seen.saw(sc, scan, b.obstacle, b.p, o.seen_radius)) continue;
      // Only boundary the sonar can see: nothing else in the line of sight.
      const auto hit = world.castRay(geom::Ray{true_robot.position(), d / dist}, dist + 0.05);
      if (hit && hit->range < dist - 0.03) continue;
      bool found = false;
      for (const auto& c : occupied) found = found || (c - b.p).norm() <= tol;
      recall.add(found);
    }
  }
  m.set("agm_operational.maps", static_cast<int64_t>(log.agm_operational.size()));
  setRatio(m, "agm_operational.precision", precision);
  setRatio(m, "agm_operational.recall", recall);
  m.set("agm_operational.samples.boundary", recall.den);
  m.set("agm_operational.samples.occupied", precision.den);
}

EvalOptions evalOptions(const Config& config) {
  EvalOptions o;
  const NavigatorConfig nav = navigatorConfig(config.section("navigator"));
  o.lines = nav.lines;
  const AgmParams agm = nav.effectiveAgm();  // with scan matching: the matched pose's error model
  o.forget_after_m = agm.h_max_m;
  o.forget_sigma_m = agm.forget_sigma_m;
  o.odometry = {agm.odometry_trans_noise, agm.odometry_rot_noise, agm.odometry_drift_noise};
  const PilotConfig pilot = pilotConfig(config.section("pilot"));
  o.operational_h_max = pilot.agm.h_max;
  o.operational_h_max_ring_cycles = pilot.h_max_ring_cycles;
  return o;
}

Metrics evaluate(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o, const BaselinesConfig* baselines) {
  Metrics m;
  m.set("scenario", sc.name);
  m.set("duration_s", log.sim_time.seconds());
  evalSensors(log, sc, m);
  const LaserSeen seen(log, o.seen_radius);
  evalLaserTruth(seen, m);
  evalComplement(log, seen, o, m, &sc);
  if (!log.sector_maps.empty() && log.sim_states.size() >= 2) {
    const SectorTruthTable truth = sectorTruthTable(log, sc, seen, o);
    evalSectorMap(log, truth, o, m);
    evalBaselines(log, truth, baselines ? *baselines : baselinesConfig(Config{}), o, m);
  }
  evalAgmOperational(log, sc, seen, o, m);
  evalAgmTactical(log, sc, seen, o, m);
  evalLines(log, sc, seen, o, m);
  if (o.breakdown) evalTacticalBreakdown(log, sc, seen, o, m);
  return m;
}

}  // namespace lasonic::eval
