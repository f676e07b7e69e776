#include "render/snapshot.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "core/pose_msg.hpp"
#include "core/utime.hpp"
#include "lcmio/node.hpp"

namespace lasonic::render {

namespace {


// decodeAs, but a message whose array counts are absurd (an allocation that fails) is
// undecodable too, not a crash.
template <typename T>
std::optional<T> safeDecode(const std::vector<uint8_t>& data) {
  try {
    return decodeAs<T>(data);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

enum class Kind {
  Odometry, SimState, RadarMap, AgmLines, Csm, AgmOp, AgmTac, SectorMap, Sonar, Hypothesis,
  Complement, Other
};

Kind kindOf(const std::string& ch) {
  static const std::map<std::string, Kind> kinds = {
      {channels::ODOMETRY, Kind::Odometry},
      {channels::SIM_STATE, Kind::SimState},
      {channels::RADAR_MAP, Kind::RadarMap},
      {channels::AGM_LINES, Kind::AgmLines},
      {channels::CURRENT_SENSOR_MAP, Kind::Csm},
      {channels::AGM_OPERATIONAL, Kind::AgmOp},
      {channels::AGM_TACTICAL, Kind::AgmTac},
      {channels::SECTOR_MAP, Kind::SectorMap},
      {channels::SONAR_RING, Kind::Sonar},
      {channels::SONAR_HYPOTHESIS, Kind::Hypothesis},
      {channels::SONAR_COMPLEMENT, Kind::Complement},
  };
  auto it = kinds.find(ch);
  return it == kinds.end() ? Kind::Other : it->second;
}

// The message time of an event on a drawn channel, or nullopt if it does not decode.
std::optional<int64_t> messageTime(Kind k, const std::vector<uint8_t>& d) {
  auto t = [](const auto& m) -> std::optional<int64_t> {
    if (!m) return std::nullopt;
    return m->utime;
  };
  switch (k) {
    case Kind::Odometry: return t(safeDecode<odometry_t>(d));
    case Kind::SimState: return t(safeDecode<sim_state_t>(d));
    case Kind::RadarMap:
    case Kind::AgmLines:
    case Kind::Csm: return t(safeDecode<line_map_t>(d));
    case Kind::AgmOp:
    case Kind::AgmTac: return t(safeDecode<grid_map_t>(d));
    case Kind::SectorMap: return t(safeDecode<sector_map_t>(d));
    case Kind::Sonar: return t(safeDecode<sonar_ring_t>(d));
    case Kind::Hypothesis: return t(safeDecode<hypothetical_scan_t>(d));
    case Kind::Complement: return t(safeDecode<complement_t>(d));
    case Kind::Other: break;
  }
  return std::nullopt;
}

// The sectors of a SECTOR_MAP whose source is the sonar (own, copied) or the memory.
int sonarSectors(const sector_map_t& m) {
  int n = 0;
  for (const int8_t src : m.source)
    n += src == sector_map_t::SOURCE_SONAR || src == sector_map_t::SOURCE_SONAR_COPIED ||
         src == sector_map_t::SOURCE_REMEMBERED;
  return n;
}

}  // namespace

const std::vector<std::string>& drawnChannels() {
  static const std::vector<std::string> v = {
      channels::RADAR_MAP,       channels::SONAR_HYPOTHESIS, channels::SONAR_RING,
      channels::SONAR_COMPLEMENT, channels::AGM_OPERATIONAL, channels::AGM_TACTICAL,
      channels::AGM_LINES,       channels::CURRENT_SENSOR_MAP, channels::SECTOR_MAP,
      channels::ODOMETRY,        channels::SIM_STATE};
  return v;
}

int64_t LogInfo::undecodableTotal() const {
  int64_t n = 0;
  for (const auto& [ch, c] : undecodable) n += c;
  return n;
}

LogInfo scanLog(const std::string& path) {
  LogInfo info;
  info.path = path;
  LogReader reader(path);
  bool first = true;
  while (auto r = reader.next()) {
    ++info.events;
    const Kind k = kindOf(r->channel);
    if (k == Kind::Other) continue;
    // (A SECTOR_MAP is decoded once: its time and its sonar sectors.)
    const auto sector_map = k == Kind::SectorMap ? safeDecode<sector_map_t>(r->data) : std::nullopt;
    const auto t = k == Kind::SectorMap ? (sector_map ? std::optional<int64_t>(sector_map->utime) : std::nullopt)
                                        : messageTime(k, r->data);
    if (!t || *t <= 0) {
      ++info.undecodable[r->channel];
      continue;
    }
    ++info.messages[r->channel];
    if (sector_map) {
      const int n = sonarSectors(*sector_map);
      if (n > info.most_sonar_sectors || (n == info.most_sonar_sectors && *t < info.most_sonar_utime)) {
        info.most_sonar_sectors = n;
        info.most_sonar_utime = *t;
      }
    }
    if (first || *t < info.start_utime) info.start_utime = *t;
    if (first || *t > info.end_utime) info.end_utime = *t;
    first = false;
  }
  return info;
}

std::optional<geom::Pose2> Snapshot::odomFromTrue() const {
  if (!robot || !true_robot) return std::nullopt;
  return robot->compose(true_robot->inverse());
}

// ------------------------------------------------------------------------------ tracks

template <typename T>
void SnapshotCollector::Track<T>::insert(T m) {
  if (items.empty() || items.back().utime <= m.utime) {
    items.push_back(std::move(m));
    return;
  }
  // Out of order (a live log interleaves processes): keep the track sorted.
  auto it = std::upper_bound(items.begin(), items.end(), m.utime,
                             [](int64_t t, const T& x) { return t < x.utime; });
  items.insert(it, std::move(m));
}

template <typename T>
const T* SnapshotCollector::Track<T>::newestAtOrBefore(int64_t utime) const {
  auto it = std::upper_bound(items.begin(), items.end(), utime,
                             [](int64_t t, const T& x) { return t < x.utime; });
  if (it == items.begin()) return nullptr;
  return &*std::prev(it);
}

template <typename T>
void SnapshotCollector::Track<T>::forget(int64_t before) {
  auto it = std::lower_bound(items.begin(), items.end(), before,
                             [](const T& x, int64_t t) { return x.utime < t; });
  // Keep the newest message before `before`: a channel that fell silent still shows its last.
  if (it == items.begin()) return;
  items.erase(items.begin(), std::prev(it));
}

SnapshotCollector::SnapshotCollector() : SnapshotCollector(Options{}) {}
SnapshotCollector::SnapshotCollector(Options opts) : opts_(opts) {}

std::optional<int64_t> SnapshotCollector::add(const LogRecord& r) {
  const Kind k = kindOf(r.channel);
  if (k == Kind::Other) return std::nullopt;
  auto put = [&](auto msg, auto& track) -> std::optional<int64_t> {
    if (!msg || msg->utime <= 0) {
      ++rejected_;
      return std::nullopt;
    }
    const int64_t t = msg->utime;
    track.insert(std::move(*msg));
    return t;
  };
  switch (k) {
    case Kind::Odometry: return put(safeDecode<odometry_t>(r.data), odometry_);
    case Kind::SimState: return put(safeDecode<sim_state_t>(r.data), sim_state_);
    case Kind::RadarMap: return put(safeDecode<line_map_t>(r.data), radar_map_);
    case Kind::AgmLines: return put(safeDecode<line_map_t>(r.data), agm_lines_);
    case Kind::Csm: return put(safeDecode<line_map_t>(r.data), csm_);
    case Kind::AgmOp: return put(safeDecode<grid_map_t>(r.data), agm_op_);
    case Kind::AgmTac: return put(safeDecode<grid_map_t>(r.data), agm_tac_);
    case Kind::SectorMap: return put(safeDecode<sector_map_t>(r.data), sector_map_);
    case Kind::Sonar: return put(safeDecode<sonar_ring_t>(r.data), sonar_);
    case Kind::Hypothesis: return put(safeDecode<hypothetical_scan_t>(r.data), hypothesis_);
    case Kind::Complement: return put(safeDecode<complement_t>(r.data), complement_);
    case Kind::Other: break;
  }
  return std::nullopt;
}

void SnapshotCollector::forget(int64_t before) {
  const auto sonar_before = before - secondsToUs(opts_.sonar_window_s);
  odometry_.forget(sonar_before);  // sonar firings in the window are placed with it
  sim_state_.forget(before);
  radar_map_.forget(before);
  agm_lines_.forget(before);
  csm_.forget(before);
  agm_op_.forget(before);
  agm_tac_.forget(before);
  sector_map_.forget(before);
  sonar_.forget(sonar_before);
  hypothesis_.forget(sonar_before);
  complement_.forget(sonar_before);
}

std::optional<geom::Pose2> SnapshotCollector::odometryAt(int64_t utime) const {
  const auto& v = odometry_.items;
  if (v.empty()) return std::nullopt;
  auto it = std::lower_bound(v.begin(), v.end(), utime,
                             [](const odometry_t& o, int64_t t) { return o.utime < t; });
  if (it == v.begin()) return toPose(v.front().pose);  // before the first: held
  if (it == v.end()) return toPose(v.back().pose);     // after the last: held
  const odometry_t& b = *it;
  const odometry_t& a = *std::prev(it);
  const double s = b.utime > a.utime ? static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime) : 1.0;
  return geom::interpolate(toPose(a.pose), toPose(b.pose), s);
}

// ------------------------------------------------------------------------------ the moment

Snapshot SnapshotCollector::at(int64_t utime) const {
  Snapshot s;
  s.utime = utime;

  auto copy = [utime](const auto& track, auto& out) {
    if (const auto* m = track.newestAtOrBefore(utime)) out = *m;
  };
  copy(radar_map_, s.radar_map);
  copy(agm_lines_, s.agm_lines);
  copy(csm_, s.current_sensor_map);
  copy(agm_op_, s.agm_operational);
  copy(agm_tac_, s.agm_tactical);
  copy(sector_map_, s.sector_map);

  // The navigator's frame into the odometry's (scan matching; nothing to do without it).
  auto odomFromNavigator = [this](const auto& m) -> std::optional<geom::Pose2> {
    const auto o = odometryAt(m.utime);
    const geom::Pose2 r = toPose(m.robot_pose);
    if (!o || !std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.theta)) return std::nullopt;
    if (o->x == r.x && o->y == r.y && o->theta == r.theta) return std::nullopt;
    return o->compose(r.inverse());
  };
  auto intoOdometry = [&](std::optional<line_map_t>& m) {
    if (!m) return;
    const auto t = odomFromNavigator(*m);
    if (!t) return;
    for (line_segment_t& sg : m->segments) {
      const geom::Vec2 a = t->transform({sg.x0, sg.y0}), b = t->transform({sg.x1, sg.y1});
      sg.x0 = a.x(), sg.y0 = a.y(), sg.x1 = b.x(), sg.y1 = b.y();
    }
    const geom::Pose2 r = t->compose(toPose(m->robot_pose));
    m->robot_pose = {r.x, r.y, r.theta};
  };
  intoOdometry(s.agm_lines);
  intoOdometry(s.current_sensor_map);
  if (s.agm_tactical) s.agm_tactical_frame = odomFromNavigator(*s.agm_tactical);

  // Where the robot is (odometry frame): ODOMETRY, else the newest map that carries its pose.
  s.robot = odometryAt(utime);
  if (!s.robot) {
    int64_t best = std::numeric_limits<int64_t>::min();
    auto consider = [&](const auto& m) {
      if (m && m->utime > best) {
        best = m->utime;
        s.robot = toPose(m->robot_pose);
      }
    };
    consider(s.sector_map);
    consider(s.agm_operational);
    consider(s.agm_tactical);
    consider(s.radar_map);
    consider(s.current_sensor_map);
  }
  if (s.sector_map && std::isfinite(s.sector_map->robot_radius) && s.sector_map->robot_radius > 0 &&
      s.sector_map->robot_radius < 10)
    s.robot_radius = s.sector_map->robot_radius;

  const int64_t window_start = utime - secondsToUs(opts_.sonar_window_s);
  // Newest reading per sensor among the messages in (window_start, utime], newest first.
  auto perSensor = [&](const auto& track, auto&& visit) {
    std::set<int> seen;
    for (auto it = track.items.rbegin(); it != track.items.rend(); ++it) {
      if (it->utime > utime) continue;
      if (it->utime <= window_start) break;
      visit(*it, seen);
    }
  };

  perSensor(hypothesis_, [&](const hypothetical_scan_t& h, std::set<int>& seen) {
    if (s.hypothesis.empty()) s.hypothesis_limit = h.range_limit;
    for (size_t i = 0; i < h.range.size(); ++i) {
      if (!seen.insert(h.sensor_id[i]).second) continue;
      SonarBeam b;
      b.sensor_id = h.sensor_id[i];
      b.utime = h.utime;
      b.pose = toPose(h.sensor_pose[i]);
      b.beam_width = h.beam_width;
      b.range = h.range[i];
      s.hypothesis.push_back(b);
    }
  });

  // Beam width of a reading fired at `t` by `sensor`: from SONAR_RING (it carries it), else
  // from the hypothesis of that firing, else the paper's 30 degrees.
  auto beamOf = [&](int64_t t, int sensor) {
    if (const auto* r = sonar_.newestAtOrBefore(t); r && r->utime == t)
      for (size_t i = 0; i < r->sensor_id.size(); ++i)
        if (r->sensor_id[i] == sensor) return static_cast<double>(r->beam_width[i]);
    if (const auto* h = hypothesis_.newestAtOrBefore(t); h && h->utime == t) return static_cast<double>(h->beam_width);
    return geom::deg2rad(30.0);
  };
  // The sensor's global pose at firing time: ODOMETRY ∘ mount, else the pose the complement
  // stage computed for that firing (SONAR_HYPOTHESIS carries it).
  auto sensorPose = [&](int64_t t, int sensor, const pose2d_t& mount) -> std::optional<geom::Pose2> {
    if (auto odo = odometryAt(t)) return odo->compose(toPose(mount));
    if (const auto* h = hypothesis_.newestAtOrBefore(t); h && h->utime == t)
      for (size_t i = 0; i < h->sensor_id.size(); ++i)
        if (h->sensor_id[i] == sensor) return toPose(h->sensor_pose[i]);
    return std::nullopt;
  };

  perSensor(sonar_, [&](const sonar_ring_t& r, std::set<int>& seen) {
    for (size_t i = 0; i < r.range.size(); ++i) {
      if (!seen.insert(r.sensor_id[i]).second) continue;
      const auto pose = sensorPose(r.utime, r.sensor_id[i], r.mount[i]);
      if (!pose) {
        ++s.sonar_unplaced;
        continue;
      }
      SonarBeam b;
      b.sensor_id = r.sensor_id[i];
      b.utime = r.utime;
      b.pose = *pose;
      b.beam_width = r.beam_width[i];
      b.echo = r.no_echo[i] == 0;
      b.range = b.echo ? r.range[i] : r.range_max;
      s.sonar.push_back(b);
    }
  });

  perSensor(complement_, [&](const complement_t& c, std::set<int>& seen) {
    if (s.complement.empty()) s.complement_tolerance = c.tolerance;
    for (const auto& rd : c.readings) {
      if (!seen.insert(rd.sensor_id).second) continue;
      SonarBeam b;
      b.sensor_id = rd.sensor_id;
      b.utime = c.utime;
      b.pose = toPose(rd.sensor_pose);
      b.beam_width = beamOf(c.utime, rd.sensor_id);
      b.range = rd.range;
      b.cls = rd.cls;
      b.hypothetical = rd.hypothetical_range;
      s.complement.push_back(b);
    }
  });

  // Truth at utime, interpolated between SIM_STATE messages.
  const auto& st = sim_state_.items;
  if (!st.empty()) {
    auto it = std::lower_bound(st.begin(), st.end(), utime,
                               [](const sim_state_t& x, int64_t t) { return x.utime < t; });
    const sim_state_t* a = nullptr;
    const sim_state_t* b = nullptr;
    double f = 0;
    if (it == st.end()) a = b = &st.back();
    else if (it == st.begin()) a = b = &st.front();
    else {
      a = &*std::prev(it);
      b = &*it;
      f = b->utime > a->utime ? static_cast<double>(utime - a->utime) / static_cast<double>(b->utime - a->utime) : 1.0;
    }
    s.true_robot = geom::interpolate(toPose(a->robot_pose), toPose(b->robot_pose), f);
    for (size_t k = 0; k < a->movers.size(); ++k) {
      const mover_state_t& ma = a->movers[k];
      const mover_state_t& mb = k < b->movers.size() ? b->movers[k] : ma;
      s.movers.push_back({ma.id, {ma.x + f * (mb.x - ma.x), ma.y + f * (mb.y - ma.y)}, ma.radius});
    }
  }
  return s;
}

}  // namespace lasonic::render
