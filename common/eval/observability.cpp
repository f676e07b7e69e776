#include "eval/observability.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <lasonic/sector_map_t.hpp>

#include "eval/laser_seen.hpp"
#include "core/utime.hpp"

namespace lasonic::eval {

std::vector<SectorTruth> trueSectorHits(const sim::WorldGeometry& world, const geom::Pose2& robot,
                                        double robot_radius, int nsectors, double max_range) {
  std::vector<SectorTruth> out(static_cast<size_t>(std::max(nsectors, 0)));
  const double width = 2.0 * geom::kPi / nsectors;
  for (int k = 0; k < nsectors; ++k) {
    const geom::Sector sec{robot.position(), robot.theta - geom::kPi + (k + 0.5) * width, width,
                           robot_radius + max_range};
    SectorTruth& best = out[static_cast<size_t>(k)];
    double best_r = std::numeric_limits<double>::infinity();
    for (const auto& p : world.primitives()) {
      const auto q = p.kind == sim::Primitive::Kind::Segment ? geom::nearestPointInSector(sec, p.segment)
                                                             : geom::nearestPointInSector(sec, p.circle);
      if (!q) continue;
      const double r = (*q - sec.apex).norm();
      if (r < best_r) {
        best_r = r;
        best.point = *q;
        best.primitive = &p;
      }
    }
    if (best.primitive) best.distance = std::max(0.0, best_r - robot_radius);
  }
  return out;
}

// ------------------------------------------------------------------------------ located points

LocatedPoints::LocatedPoints(double radius) : radius_(radius > 0 ? radius : 0.30) {}

size_t LocatedPoints::KeyHash::operator()(const Key& k) const {
  const uint64_t h = static_cast<uint64_t>(k.cx) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(k.cy) * 0xC2B2AE3D27D4EB4Full ^
                     static_cast<uint64_t>(static_cast<int64_t>(k.obstacle)) * 0x165667B19E3779F9ull;
  return static_cast<size_t>(h ^ (h >> 29));
}

int64_t LocatedPoints::cell(double v) const {
  return static_cast<int64_t>(std::clamp(std::floor(v / radius_), -1e15, 1e15));
}

void LocatedPoints::add(int obstacle, int64_t utime, const geom::Vec2& p) {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return;
  auto& v = buckets_[Key{obstacle, cell(p.x()), cell(p.y())}];
  v.push_back({utime, p});
  // Keep time order (SONAR_TRUTH comes in time order, so this rarely moves anything).
  for (size_t i = v.size() - 1; i > 0 && v[i - 1].utime > v[i].utime; --i) std::swap(v[i - 1], v[i]);
  ++n_;
}

void LocatedPoints::addDirectEchoes(const std::vector<sonar_truth_t>& truths) {
  addDirectEchoes(truths, {}, std::numeric_limits<double>::infinity());
}

void LocatedPoints::addDirectEchoes(const std::vector<sonar_truth_t>& truths, const std::vector<sonar_ring_t>& rings,
                                    double max_range, const sim::Scenario* scenario) {
  std::map<std::pair<int64_t, int>, float> read;
  for (const auto& r : rings)
    for (size_t i = 0; i < r.sensor_id.size() && i < r.range.size(); ++i) read[{r.utime, r.sensor_id[i]}] = r.range[i];
  for (const auto& t : truths)
    for (const auto& c : t.causes) {
      if (c.cause != sonar_cause_t::CAUSE_DIRECT || c.true_range < 0 || c.obstacle == -1) continue;
      const auto it = read.find({t.utime, c.sensor_id});
      const double range = it != read.end() ? double(it->second) : double(c.true_range);
      if (!(range <= max_range)) continue;
      const geom::Vec2 hit(c.hit_x, c.hit_y);
      add(scenario ? scenario->canonicalObstacle(c.obstacle, hit) : c.obstacle, t.utime, hit);
    }
}

bool LocatedPoints::located(int obstacle, const geom::Vec2& p, int64_t utime) const {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return false;
  const int64_t cx = cell(p.x()), cy = cell(p.y());
  const double r2 = radius_ * radius_;
  for (int64_t y = cy - 1; y <= cy + 1; ++y)
    for (int64_t x = cx - 1; x <= cx + 1; ++x) {
      const auto it = buckets_.find(Key{obstacle, x, y});
      if (it == buckets_.end()) continue;
      for (const Entry& e : it->second) {
        if (e.utime > utime) break;
        if ((e.p - p).squaredNorm() <= r2) return true;
      }
    }
  return false;
}

std::optional<int64_t> LocatedPoints::lastLocated(int obstacle, const geom::Vec2& p, int64_t utime) const {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return std::nullopt;
  const int64_t cx = cell(p.x()), cy = cell(p.y());
  const double r2 = radius_ * radius_;
  std::optional<int64_t> last;
  for (int64_t y = cy - 1; y <= cy + 1; ++y)
    for (int64_t x = cx - 1; x <= cx + 1; ++x) {
      const auto it = buckets_.find(Key{obstacle, x, y});
      if (it == buckets_.end()) continue;
      const std::vector<Entry>& v = it->second;
      // Newest first from the last entry at or before utime: the first one within the radius is
      // this bucket's answer.
      auto end = std::upper_bound(v.begin(), v.end(), utime, [](int64_t t, const Entry& e) { return t < e.utime; });
      for (auto e = end; e != v.begin();) {
        --e;
        if (last && e->utime <= *last) break;
        if ((e->p - p).squaredNorm() <= r2) {
          last = e->utime;
          break;
        }
      }
    }
  return last;
}

int LocatedPoints::countLocated(int obstacle, const geom::Vec2& p, int64_t from, int64_t to) const {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || from > to) return 0;
  const int64_t cx = cell(p.x()), cy = cell(p.y());
  const double r2 = radius_ * radius_;
  int n = 0;
  for (int64_t y = cy - 1; y <= cy + 1; ++y)
    for (int64_t x = cx - 1; x <= cx + 1; ++x) {
      const auto it = buckets_.find(Key{obstacle, x, y});
      if (it == buckets_.end()) continue;
      const std::vector<Entry>& v = it->second;
      auto e = std::lower_bound(v.begin(), v.end(), from, [](const Entry& a, int64_t t) { return a.utime < t; });
      for (; e != v.end() && e->utime <= to; ++e) n += (e->p - p).squaredNorm() <= r2;
    }
  return n;
}

// ------------------------------------------------------------------------------ truth table

SectorTruthTable sectorTruthTable(const RunLog& log, const sim::Scenario& sc, const EvalOptions& o) {
  return sectorTruthTable(log, sc, LaserSeen(log, o.seen_radius), o);
}

SectorTruthTable sectorTruthTable(const RunLog& log, const sim::Scenario& sc, const LaserSeen& seen,
                                  const EvalOptions& o) {
  SectorTruthTable table;
  table.offset.push_back(0);
  if (log.sector_maps.empty() || log.sim_states.size() < 2) return table;
  TruthTrack truth(log.sim_states);
  sim::WorldGeometry world(sc);
  LocatedPoints located(o.observe_radius), within_limit(o.observe_radius);
  located.addDirectEchoes(log.sonar_truths, {}, std::numeric_limits<double>::infinity(), &sc);
  within_limit.addDirectEchoes(log.sonar_truths, log.sonar_rings, hypothesisRangeLimit(log, o), &sc);
  std::map<std::string, int16_t> material_index;
  table.echo_memory_s = operationalMemory(log, o);
  // Rounded, not truncated: 4 cycles of 0.1 s are 400,000 us, not 399,999.
  const auto memory = secondsToUs(table.echo_memory_s);
  for (size_t i = 0; i < log.sector_maps.size(); ++i) {
    const sector_map_t& sm = log.sector_maps[i];
    // A map that says it has never heard from one of its sensors (age -1: the pilot's start-up,
    // before the first scan or firing group) declares itself blind there: counted, not scored.
    if (sm.laser_age_s < 0 || sm.sonar_age_s < 0) {
      ++table.warmup;
      continue;
    }
    if (sm.nsectors < 3 || sm.nsectors > 3600 || sm.distance.size() != static_cast<size_t>(sm.nsectors) ||
        sm.laser_distance.size() != sm.distance.size() || sm.source.size() != sm.distance.size())
      continue;  // malformed: nothing to score
    world.setMovers(truth.moversAt(sm.utime));
    const auto hits = trueSectorHits(world, truth.robotAt(sm.utime), sm.robot_radius, sm.nsectors,
                                     o.sector_range + 1.0);
    table.maps.push_back(i);
    const int scan = seen.newestAt(sm.utime);
    for (const SectorTruth& h : hits) {
      SectorSample s;
      s.truth = static_cast<float>(h.distance);
      if (h.primitive) {
        // A surface drawn on another's (a pane on a wall's line) counts as the one the laser
        // sees best, whichever of the two the nearest-point search met first.
        const int obstacle = sc.canonicalObstacle(h.primitive->obstacle, h.point);
        const sim::Material& mat = obstacle == h.primitive->obstacle
                                       ? *h.primitive->material
                                       : sc.material(sc.obstacles[static_cast<size_t>(obstacle)].material);
        auto [it, fresh] = material_index.emplace(mat.name, static_cast<int16_t>(table.materials.size()));
        if (fresh) table.materials.push_back(mat.name);
        s.material = it->second;
        s.x = static_cast<float>(h.point.x());
        s.y = static_cast<float>(h.point.y());
        if (obstacle >= 0 && static_cast<size_t>(obstacle) < sc.obstacles.size())
          s.obstacle = static_cast<int16_t>(obstacle);
        // The laser saw the point (the newest scan returned from its obstacle near it; without
        // LASER_TRUTH: its material reflects the laser), or an echo located it.
        const bool laser = seen.available()
                               ? seen.saw(sc, scan, h.primitive->obstacle, h.point, o.seen_radius, sm.utime)
                               : mat.laser == sim::LaserBehaviour::Reflect;
        if (h.distance <= o.sector_range) {
          if (laser) {
            s.cue = Cue::Laser;
          } else if (const auto t = within_limit.lastLocated(obstacle, h.point, sm.utime)) {
            if (sm.utime - *t > memory) s.cue = Cue::EchoOld;
            else s.cue = within_limit.countLocated(obstacle, h.point, sm.utime - memory, sm.utime) >= 2 ? Cue::EchoRepeated : Cue::EchoOnce;
          } else if (located.located(obstacle, h.point, sm.utime)) {
            s.cue = Cue::EchoFar;  // observable, but only by readings the hypothesis cannot classify
          }
          s.observable = s.cue != Cue::None;
        }
      }
      table.samples.push_back(s);
    }
    table.offset.push_back(table.samples.size());
  }
  return table;
}

// ------------------------------------------------------------------------------ scores

namespace {
void setRatio(Metrics& m, const std::string& key, const Ratio& r) {
  if (r.valid()) m.set(key, r.value());
}
}  // namespace

bool sectorMissed(double reported, const SectorSample& s, const EvalOptions& o) {
  return s.truth <= o.sector_range && (reported < 0 || reported > s.truth + o.sector_tolerance);
}

bool sectorFalseAlarm(double reported, const SectorSample& s, const EvalOptions& o) {
  return reported >= 0 && reported <= o.sector_range && reported < s.truth - o.sector_tolerance;
}

const char* cueName(Cue c) {
  static const char* kNames[kCues] = {"none", "laser", "echo_once", "echo_repeated", "echo_old", "echo_far"};
  const int i = static_cast<int>(c);
  return i >= 0 && i < kCues ? kNames[i] : "none";
}

const char* sectorSourceName(int source) {
  static const char* kNames[5] = {"none", "laser", "sonar", "sonar_copied", "remembered"};
  return source >= 0 && source < 5 ? kNames[source] : "none";
}

void SectorScore::add(double reported, const SectorSample& s, const EvalOptions& o, int source) {
  const bool has = reported >= 0;
  const double truth = s.truth;
  if (truth <= o.sector_range) {
    const bool miss = sectorMissed(reported, s, o);
    missed_.add(miss);
    unobservable_.add(!s.observable);
    if (s.observable) {
      observable_missed_.add(miss);
      if (miss) ++observable_missed_by_cue_[static_cast<int>(s.cue)];
    }
    if (s.material >= 0) {
      if (missed_by_material_.size() <= static_cast<size_t>(s.material))
        missed_by_material_.resize(static_cast<size_t>(s.material) + 1);
      missed_by_material_[static_cast<size_t>(s.material)].add(miss);
    }
    if (has) {
      abs_err_ += std::abs(reported - truth);
      ++err_n_;
    }
  }
  // Every sector of every map is an opportunity for a false alarm (like missed_rate's
  // denominator is every sector that holds a true obstacle); the share among the sectors
  // that report something within range is kept too, as the stricter view.
  const bool fa = sectorFalseAlarm(reported, s, o);
  false_alarm_.add(fa);
  if (has && reported <= o.sector_range) false_of_reports_.add(fa);
  if (fa && source >= 0 && source < 5) ++false_by_source_[source];
}

void SectorScore::write(Metrics& m, const std::string& prefix, bool details,
                        const std::vector<std::string>& materials) const {
  setRatio(m, prefix + ".missed_rate", missed_);
  // The counts behind missed_rate, for every source: the rates are printed to four decimals, and
  // where the laser sees nearly everything lasonic and a baseline both miss 0.0003 of some 50,000
  // samples, which of them missed fewer is a matter of a few samples (the baselines are read out
  // on the same samples: the counts compare).
  m.set(prefix + ".samples.within_range", missed_.den);
  m.set(prefix + ".samples.missed", missed_.num);
  setRatio(m, prefix + ".observable_missed_rate", observable_missed_);
  if (details) setRatio(m, prefix + ".unobservable_share", unobservable_);
  setRatio(m, prefix + ".false_alarm_rate", false_alarm_);
  setRatio(m, prefix + ".false_alarm_share_of_reports", false_of_reports_);
  if (err_n_ > 0) m.set(prefix + ".mae_m", abs_err_ / static_cast<double>(err_n_));
  for (size_t i = 0; i < missed_by_material_.size() && i < materials.size(); ++i)
    setRatio(m, prefix + ".missed_by_material." + materials[i], missed_by_material_[i]);
  if (!details) return;
  if (observable_missed_.num > 0) {
    for (int c = 1; c < kCues; ++c)
      m.set(prefix + ".observable_missed_by_cue." + cueName(static_cast<Cue>(c)),
            static_cast<double>(observable_missed_by_cue_[c]) / static_cast<double>(observable_missed_.num));
  }
  if (false_alarm_.num > 0) {
    for (int s = 1; s < 5; ++s)
      m.set(prefix + ".false_alarms_by_source." + sectorSourceName(s),
            static_cast<double>(false_by_source_[s]) / static_cast<double>(false_alarm_.num));
  }
  m.set(prefix + ".samples.observable", observable_missed_.den);
  for (size_t i = 0; i < missed_by_material_.size() && i < materials.size(); ++i)
    if (missed_by_material_[i].den > 0)
      m.set(prefix + ".samples.by_material." + materials[i], missed_by_material_[i].den);
}

}  // namespace lasonic::eval
