// The physical sonar model: echo strengths, reflectors, late echoes (sim/sonar_physical.hpp).
#include "sim/sonar_physical.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>

#include "sim/sonar_model.hpp"

namespace lasonic::sim {

namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();
constexpr double kJunctionEps = 1e-4;  // [m] segment ends this close meet
constexpr int kMaxSurfacesPerRay = 8;  // transmissions + reflections followed along one ray

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double cross(const geom::Vec2& a, const geom::Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double heading(const geom::Vec2& v) { return std::atan2(v.y(), v.x()); }

// Counter-clockwise angle from `from` to `to`, in [0, 2 pi).
double ccw(double from, double to) {
  double d = std::fmod(to - from, 2 * geom::kPi);
  if (d < 0) d += 2 * geom::kPi;
  return d;
}

struct LocalHit {
  double t = 0;
  const Primitive* prim = nullptr;
  geom::Vec2 point, normal;  // normal faces the ray's origin
};

// Nearest hit among `prims` within max_range, ignoring up to three primitives. from_transducer:
// the ray starts at a transducer, which a surface it is flush with meets at 0 (rangeAlong); a ray
// from a point where it was reflected is not stopped by another surface drawn through that point
// (a wall drawn twice).
std::optional<LocalHit> cast(const std::vector<const Primitive*>& prims, const geom::Ray& ray, double max_range,
                             const Primitive* x1 = nullptr, const Primitive* x2 = nullptr,
                             const Primitive* x3 = nullptr, bool from_transducer = false) {
  const Primitive* best = nullptr;
  double best_t = max_range;
  for (const Primitive* p : prims) {
    if (p == x1 || p == x2 || p == x3) continue;
    const std::optional<double> t = from_transducer                        ? rangeAlong(ray, *p)
                                    : p->kind == Primitive::Kind::Segment ? geom::intersect(ray, p->segment)
                                                                          : geom::intersect(ray, p->circle);
    if (t && *t <= best_t) {
      best_t = *t;
      best = p;
    }
  }
  if (!best) return std::nullopt;
  LocalHit h;
  h.t = best_t;
  h.prim = best;
  h.point = ray.origin + best_t * ray.dir;
  if (best->kind == Primitive::Kind::Segment) {
    h.normal = geom::normal(best->segment);
  } else {
    const geom::Vec2 radial = h.point - best->circle.center;
    h.normal = radial.norm() > 1e-12 ? geom::Vec2(radial.normalized()) : geom::Vec2(-ray.dir);
  }
  if (h.normal.dot(ray.dir) > 0) h.normal = -h.normal;
  return h;
}

int8_t reflectorOf(const Primitive& p) {
  return p.kind == Primitive::Kind::Circle ? sonar_cause_t::REFLECTOR_CYLINDER : sonar_cause_t::REFLECTOR_PLANE;
}

}  // namespace

// ------------------------------------------------------------------ reflectors

bool insideWedge(double start, double opening, const geom::Vec2& apex, const geom::Vec2& p) {
  const geom::Vec2 d = p - apex;
  if (d.norm() < 1e-9) return false;
  return ccw(start, heading(d)) < opening;
}

Reflectors findReflectors(const std::vector<Primitive>& statics, double corner_tolerance) {
  // Junction points: every segment end, merged when closer than kJunctionEps.
  std::vector<geom::Vec2> points;
  for (const Primitive& p : statics) {
    if (p.kind != Primitive::Kind::Segment) continue;
    for (const geom::Vec2& e : {p.segment.a, p.segment.b}) {
      bool known = false;
      for (const geom::Vec2& q : points) known = known || (q - e).norm() < kJunctionEps;
      if (!known) points.push_back(e);
    }
  }
  Reflectors out;
  struct Arm {
    double dir;
    const Primitive* prim;
  };
  for (const geom::Vec2& v : points) {
    std::vector<Arm> arms;
    for (const Primitive& p : statics) {
      if (p.kind != Primitive::Kind::Segment) continue;
      const geom::Segment& s = p.segment;
      if ((s.a - v).norm() < kJunctionEps) arms.push_back({heading(s.b - s.a), &p});
      else if ((s.b - v).norm() < kJunctionEps) arms.push_back({heading(s.a - s.b), &p});
      else if (geom::distance(s, v) < kJunctionEps) {  // a T: the segment runs through the point
        arms.push_back({heading(s.b - s.a), &p});
        arms.push_back({heading(s.a - s.b), &p});
      }
    }
    if (arms.empty()) continue;
    std::sort(arms.begin(), arms.end(), [](const Arm& x, const Arm& y) { return x.dir < y.dir; });
    for (size_t i = 0; i < arms.size(); ++i) {
      const Arm& a = arms[i];
      const Arm& b = arms[(i + 1) % arms.size()];
      const double opening = arms.size() == 1 ? 2 * geom::kPi : ccw(a.dir, b.dir);
      if (opening < 1e-9) continue;
      if (std::abs(opening - geom::kPi / 2) <= corner_tolerance) {
        out.corners.push_back({v, a.dir, opening, a.prim, b.prim});
      } else if (opening > geom::kPi + 1e-6) {
        const bool single = arms.size() == 1;
        const Primitive* strong = a.prim;
        if (!single && b.prim->material->sonar_reflect_db > a.prim->material->sonar_reflect_db) strong = b.prim;
        out.edges.push_back({v, a.dir, opening, strong, single ? nullptr : (strong == a.prim ? b.prim : a.prim)});
      }
    }
  }
  return out;
}

// ------------------------------------------------------------------ PhysicalSonar

namespace {
double absorptionOf(const SonarConfig& c) {
  return c.air_absorption >= 0 ? c.air_absorption : acoustics::airAbsorptionDbPerM(c.frequency_hz);
}
}  // namespace

PhysicalSonar::PhysicalSonar(const Scenario& s, const SonarConfig& c, uint64_t seed)
    : scenario_(&s),
      cfg_(c),
      tx_(c.frequency_hz, c.transducer_radius, c.pulse_cycles, c.side_lobes, c.beam_scale),
      budget_(c.plane_range, absorptionOf(c), c.tvg_range),
      refl_(findReflectors(s.statics, geom::deg2rad(5.0))) {
  // The strongest a ray's echo can be: a rough patch met head-on (its specular lobe over the
  // beam's footprint can exceed a mirror's level), or a mirror at the end of a multipath (0 dB),
  // plus a fluctuating material at three standard deviations. The ray fan reaches as far as
  // that can be heard, and a ray stops where nothing farther along can be.
  max_incoherent_ = -300;
  double fluct = 0;
  std::vector<const Material*> used;
  for (const ObstacleSpec& o : s.obstacles) used.push_back(&s.material(o.material));
  for (const MoverSpec& m : s.movers) used.push_back(&s.material(m.material));
  for (const Material* mp : used) {
    const Material& m = *mp;
    const double share = 1.0 - acoustics::coherentShare(tx_.wavenumber(), m.sonar_roughness);
    const double s0 = m.sonar_diffuse * 4.0 +
                      (m.sonar_diffuse < 1 && m.sonar_lobe > 0 ? (1 - m.sonar_diffuse) / (2 * std::pow(std::tan(m.sonar_lobe), 2)) : 0.0);
    const double w = tx_.effectiveWidth();
    if (share > 1e-12 && s0 > 0)
      max_incoherent_ = std::max(max_incoherent_, m.sonar_reflect_db + 10 * std::log10(share * s0 * w * w / geom::kPi));
    fluct = std::max(fluct, 3 * m.sonar_fluct_db);
  }
  ray_bound_ = std::max(max_incoherent_, 0.0) + fluct;
  fan_ = tx_.reach(budget_.planeMargin(std::max(c.range_min, 1e-3)) + ray_bound_);
  const int n = static_cast<int>(std::floor(fan_ / c.ray_step));
  for (int i = -n; i <= n; ++i) {
    ray_cos_.push_back(std::cos(i * c.ray_step));
    ray_sin_.push_back(std::sin(i * c.ray_step));
  }
  mover_velocity_.assign(s.movers.size(), geom::Vec2::Zero());
  // Fluctuating echo levels: one slowly varying state per (obstacle, sensor), each with its own
  // random stream, so that they do not depend on which echoes a firing happened to compute.
  std::vector<int> fluct_obstacles;
  for (size_t i = 0; i < s.obstacles.size(); ++i)
    if (s.material(s.obstacles[i].material).sonar_fluct_db > 0) fluct_obstacles.push_back(static_cast<int>(i));
  for (size_t i = 0; i < s.movers.size(); ++i)
    if (s.material(s.movers[i].material).sonar_fluct_db > 0) fluct_obstacles.push_back(-static_cast<int>(i) - 2);
  for (int o : fluct_obstacles)
    for (size_t k = 0; k < c.sensors.size(); ++k) {
      const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(o)) << 20) ^ static_cast<uint64_t>(k);
      fluct_[{o, static_cast<int>(k)}].rng.seed(deriveSeed(seed ^ key, "sonar fluctuation"));
    }
}

double PhysicalSonar::fluctuation(int obstacle, int sensor) const {
  const auto it = fluct_.find({obstacle, sensor});
  return it == fluct_.end() ? 0.0 : it->second.level;
}

void PhysicalSonar::advanceFluctuation(int sensor, int64_t utime) {
  for (auto& [key, f] : fluct_) {
    if (key.second != sensor) continue;
    const int o = key.first;
    const Material& m = o >= 0 ? scenario_->material(scenario_->obstacles[static_cast<size_t>(o)].material)
                               : scenario_->material(scenario_->movers[static_cast<size_t>(-o - 2)].material);
    const double n = std::normal_distribution<double>()(f.rng);
    if (f.utime < 0) {
      f.level = m.sonar_fluct_db * n;
    } else {
      // Ornstein-Uhlenbeck: correlation exp(-dt / tau), stationary std-dev sonar_fluct_db.
      const double rho = std::exp(-static_cast<double>(utime - f.utime) * 1e-6 / m.sonar_fluct_s);
      f.level = rho * f.level + std::sqrt(std::max(0.0, 1 - rho * rho)) * m.sonar_fluct_db * n;
    }
    f.utime = utime;
  }
}

double PhysicalSonar::aspectDb(const Primitive& p, const geom::Vec2& from) const {
  const Material& m = *p.material;
  if (p.obstacle > -2 || m.sonar_aspect_db <= 0 || p.kind != Primitive::Kind::Circle) return 0.0;
  const size_t id = static_cast<size_t>(-p.obstacle - 2);
  if (id >= mover_velocity_.size()) return 0.0;
  const geom::Vec2 v = mover_velocity_[id];
  const geom::Vec2 los = p.circle.center - from;
  if (v.norm() < 0.05 || los.norm() < 1e-9) return 0.0;  // standing: assume facing
  return -m.sonar_aspect_db * std::abs(cross(v.normalized(), los.normalized()));
}

const Primitive* PhysicalSonar::inWorld(const WorldGeometry& world, const Primitive* stat) const {
  if (!stat) return nullptr;  // (an edge's free end)
  // WorldGeometry copies the scenario's statics first, in order (world_geometry.cpp).
  const auto i = static_cast<size_t>(stat - scenario_->statics.data());
  assert(i < scenario_->statics.size() && i < world.primitives().size());
  return &world.primitives()[i];
}

std::vector<const Primitive*> PhysicalSonar::near(const WorldGeometry& world, const geom::Vec2& p, double reach) const {
  std::vector<const Primitive*> out;
  for (const Primitive& prim : world.primitives()) {
    const double d = prim.kind == Primitive::Kind::Segment ? geom::distance(prim.segment, p)
                                                           : (prim.circle.center - p).norm() - prim.circle.radius;
    if (d <= reach) out.push_back(&prim);
  }
  return out;
}

double PhysicalSonar::transmission(const std::vector<const Primitive*>& prims, const geom::Vec2& a,
                                   const geom::Vec2& b, const Primitive* skip_a, const Primitive* skip_b,
                                   bool from_transducer) const {
  const double dist = (b - a).norm();
  if (dist < 1e-9) return 0.0;
  const geom::Vec2 dir = (b - a) / dist;
  geom::Vec2 origin = a;
  double travelled = 0, loss = 0;
  const Primitive* last = nullptr;
  for (int k = 0; k < kMaxSurfacesPerRay; ++k) {
    const auto h =
        cast(prims, {origin, dir}, dist - travelled - kJunctionEps, skip_a, skip_b, last, k == 0 && from_transducer);
    if (!h) return loss;
    const double t = h->prim->material->sonar_transmit;
    if (t <= 0) return kNegInf;
    loss += 10.0 * std::log10(t);
    travelled += h->t;
    origin = h->point;
    last = h->prim;
  }
  return kNegInf;
}

double PhysicalSonar::coherentDb(const Material& m) const {
  return 10.0 * std::log10(std::max(1e-30, acoustics::coherentShare(tx_.wavenumber(), m.sonar_roughness)));
}

double PhysicalSonar::incoherentDb(const Material& m, double beta, double range) const {
  const double share = 1.0 - acoustics::coherentShare(tx_.wavenumber(), m.sonar_roughness);
  if (share < 1e-12) return kNegInf;
  const double sigma0 = acoustics::incoherentBackscatter(beta, m.sonar_lobe, m.sonar_diffuse);
  return m.sonar_reflect_db + 10.0 * std::log10(share) +
         acoustics::patchDb(sigma0, range, beta, tx_.effectiveWidth(), tx_.pulseCell());
}

void PhysicalSonar::rayEchoes(const std::vector<const Primitive*>& prims, const geom::Pose2& sensor, int sensor_id,
                              std::vector<Echo>& out) const {
  const double step = cfg_.ray_step;
  const int n = static_cast<int>(std::floor(fan_ / step));
  const double best = budget_.planeMargin(std::max(cfg_.range_min, 1e-3)) + ray_bound_;
  const double ct = std::cos(sensor.theta), st = std::sin(sensor.theta);
  for (int i = -n; i <= n; ++i) {
    const double alpha = i * step;
    const double d = tx_.oneWayDb(alpha);
    if (best + 2 * d < 0) continue;
    geom::Vec2 origin = sensor.position();
    const double ca = ray_cos_[static_cast<size_t>(i + n)], sa = ray_sin_[static_cast<size_t>(i + n)];
    geom::Vec2 dir(ct * ca - st * sa, st * ca + ct * sa);
    double path = 0, trans = 0, mirrors = 0;  // one-way: distance, transmission and mirror losses [dB]
    int bounces = 0;
    const Primitive* first_mirror = nullptr;
    const Primitive* last = nullptr;
    for (int k = 0; k < kMaxSurfacesPerRay; ++k) {
      const auto h = cast(prims, {origin, dir}, cfg_.range_max - path, last, nullptr, nullptr, k == 0);
      if (!h) break;
      const double range = path + h->t;
      const double reach = budget_.planeMargin(range) + 2 * d + 2 * trans + 2 * mirrors;
      if (reach + ray_bound_ < 0) break;  // nothing here or farther along can be heard
      const Material& m = *h->prim->material;
      const double beta = geom::incidenceAngle(dir, h->normal);
      const double base = reach + fluctuation(h->prim->obstacle, sensor_id) + aspectDb(*h->prim, origin);
      // This patch's incoherent backscatter, back along the ray.
      const double inc = base + max_incoherent_ >= 0 ? base + incoherentDb(m, beta, range) : -1.0;
      const bool direct = bounces == 0;
      if (inc >= 0)
        out.push_back({range, inc, direct ? sonar_cause_t::CAUSE_DIRECT : sonar_cause_t::CAUSE_SPECULAR_LONG,
                       reflectorOf(*h->prim), direct ? h->prim : first_mirror, h->point});
      // After a mirror, a surface met head-on (within the ray's tube) returns its coherent share.
      // (Met first, that is the analytic plane / cylinder echo of ownEchoes.)
      if (!direct && beta <= 0.5 * step) {
        const double spec = base + m.sonar_reflect_db + coherentDb(m);
        if (spec >= 0)
          out.push_back({range, spec, sonar_cause_t::CAUSE_SPECULAR_LONG, reflectorOf(*h->prim), first_mirror, h->point});
      }
      if (m.sonar_transmit > 0) {  // the rest goes on through (a mesh)
        trans += 10.0 * std::log10(m.sonar_transmit);
      } else {
        // The coherent share mirrors on; nothing further along can be louder than a mirror there.
        const double coh = m.sonar_reflect_db + coherentDb(m);
        if (bounces >= cfg_.multipath_bounces || coh < -20.0) break;
        mirrors += coh;
        if (budget_.planeMargin(range) + 2 * d + 2 * trans + 2 * mirrors + ray_bound_ < 0) break;
        if (!first_mirror) first_mirror = h->prim;
        dir = mirror(dir, h->normal);
        ++bounces;
      }
      origin = h->point;
      path = range;
      last = h->prim;
    }
  }
}

std::vector<Echo> PhysicalSonar::ownEchoes(const WorldGeometry& world, const geom::Pose2& sensor, int sensor_id) const {
  std::vector<Echo> out;
  const geom::Vec2 s = sensor.position();
  const std::vector<const Primitive*> prims = near(world, s, cfg_.range_max);
  auto offAxis = [&](const geom::Vec2& p) { return geom::angleDiff(heading(p - s), sensor.theta); };

  for (const Primitive* p : prims) {
    const Material& m = *p->material;
    const double extra = fluctuation(p->obstacle, sensor_id) + aspectDb(*p, s) + m.sonar_reflect_db + coherentDb(m);
    geom::Vec2 foot;
    double range, term = 0;
    if (p->kind == Primitive::Kind::Segment) {
      // The mirror's echo comes from the foot of the perpendicular, if it lies on the segment.
      const geom::Vec2 e = p->segment.b - p->segment.a;
      const double u = (s - p->segment.a).dot(e) / e.squaredNorm();
      if (u <= 1e-9 || u >= 1 - 1e-9) continue;
      foot = p->segment.a + u * e;
      range = (foot - s).norm();
    } else {
      const geom::Vec2 to_c = p->circle.center - s;
      const double dc = to_c.norm();
      if (dc <= p->circle.radius) continue;
      range = dc - p->circle.radius;
      foot = s + range * to_c / dc;
      term = acoustics::cylinderDb(p->circle.radius, range);
    }
    if (range < 1e-6 || range > cfg_.range_max) continue;
    double margin = budget_.planeMargin(range) + 2 * tx_.oneWayDb(offAxis(foot)) + term + extra;
    if (margin < 0) continue;
    margin += 2 * transmission(prims, s, foot, p, nullptr, true);
    if (margin >= 0) out.push_back({range, margin, sonar_cause_t::CAUSE_DIRECT, reflectorOf(*p), p, foot});
  }

  for (const CornerReflector& c : refl_.corners) {
    const double range = (c.vertex - s).norm();
    if (range > cfg_.range_max || !insideWedge(c.start, c.opening, c.vertex, s)) continue;
    const Material& ma = *c.a->material;
    const Material& mb = *c.b->material;
    double margin = budget_.planeMargin(range) + 2 * tx_.oneWayDb(offAxis(c.vertex)) + ma.sonar_reflect_db +
                    mb.sonar_reflect_db + coherentDb(ma) + coherentDb(mb);
    if (margin < 0) continue;
    margin += 2 * transmission(prims, s, c.vertex, inWorld(world, c.a), inWorld(world, c.b), true);
    if (margin >= 0) out.push_back({range, margin, sonar_cause_t::CAUSE_DIRECT, sonar_cause_t::REFLECTOR_CORNER, c.a, c.vertex});
  }

  for (const EdgeReflector& e : refl_.edges) {
    const double range = (e.point - s).norm();
    if (range > cfg_.range_max || !insideWedge(e.start, e.opening, e.point, s)) continue;
    double margin = budget_.planeMargin(range) + 2 * tx_.oneWayDb(offAxis(e.point)) +
                    acoustics::edgeDb(tx_.wavelength(), range) + e.a->material->sonar_reflect_db;
    if (margin < 0) continue;
    margin += 2 * transmission(prims, s, e.point, inWorld(world, e.a), inWorld(world, e.b), true);
    if (margin >= 0) out.push_back({range, margin, sonar_cause_t::CAUSE_DIRECT, sonar_cause_t::REFLECTOR_EDGE, e.a, e.point});
  }

  rayEchoes(prims, sensor, sensor_id, out);
  return out;
}

std::vector<Echo> PhysicalSonar::arrivals(const WorldGeometry& world, const Ping& ping, const geom::Pose2& listener,
                                          int64_t utime, int listener_id) const {
  std::vector<Echo> out;
  const geom::Vec2 e = ping.pose.position(), p = listener.position();
  // The listening window, as one-way path lengths of the ping's sound.
  const double elapsed = acoustics::kSpeedOfSound * static_cast<double>(utime - ping.utime) * 1e-6;
  const double lo = elapsed + 2 * cfg_.range_min, hi = elapsed + 2 * cfg_.range_max;
  if (2 * budget_.hearingRange() < lo) return out;
  const int8_t cause = ping.utime == utime ? sonar_cause_t::CAUSE_CROSSTALK : sonar_cause_t::CAUSE_LATE_ECHO;
  const std::vector<const Primitive*> prims = near(world, p, 0.5 * hi + 0.5 * (e - p).norm());
  auto dirDb = [&](const geom::Pose2& at, const geom::Vec2& towards) {
    return tx_.oneWayDb(geom::angleDiff(heading(towards - at.position()), at.theta));
  };
  // margin of an arrival over a path of length L that reads at range (L - elapsed) / 2
  auto budget = [&](double L) { return budget_.snr() + budget_.pathDb(L) + budget_.tvgDb(0.5 * (L - elapsed)); };
  auto keep = [&](double L, double margin, const Primitive* prim, int8_t refl, const geom::Vec2& hit) {
    out.push_back({0.5 * (L - elapsed), margin, cause, refl, prim, hit});
  };

  for (const Primitive* q : prims) {
    const Material& m = *q->material;
    if (q->kind == Primitive::Kind::Segment) {
      // Mirror path: the image of the emitter behind the surface's line.
      const geom::Vec2 n = geom::normal(q->segment);
      const double de = (e - q->segment.a).dot(n), dp = (p - q->segment.a).dot(n);
      if (de * dp <= 0) continue;  // not both in front of the same face
      const geom::Vec2 image = e - 2 * de * n;
      const double L = (image - p).norm();
      if (L < lo || L > hi) continue;
      const geom::Vec2 hit = p + (image - p) * (std::abs(dp) / (std::abs(dp) + std::abs(de)));
      const geom::Vec2 ab = q->segment.b - q->segment.a;
      const double u = (hit - q->segment.a).dot(ab) / ab.squaredNorm();
      if (u <= 0 || u >= 1) continue;
      double margin = budget(L) + dirDb(ping.pose, hit) + dirDb(listener, hit) + m.sonar_reflect_db + coherentDb(m) +
                      fluctuation(q->obstacle, listener_id);
      if (margin < 0) continue;
      margin += transmission(prims, e, hit, q, nullptr, true) + transmission(prims, p, hit, q, nullptr, true);
      if (margin >= 0) keep(L, margin, q, sonar_cause_t::REFLECTOR_PLANE, hit);
    } else {
      const geom::Vec2 c = q->circle.center;
      const double a = q->circle.radius;
      if ((e - c).norm() <= a || (p - c).norm() <= a) continue;
      const geom::Vec2 bis = (e - c).normalized() + (p - c).normalized();
      if (bis.norm() < 1e-9) continue;
      const geom::Vec2 hit = c + a * bis.normalized();
      const double L = (hit - e).norm() + (p - hit).norm();
      if (L < lo || L > hi) continue;
      double margin = budget(L) + dirDb(ping.pose, hit) + dirDb(listener, hit) + acoustics::cylinderDb(a, 0.5 * L) +
                      m.sonar_reflect_db + coherentDb(m) + fluctuation(q->obstacle, listener_id) + aspectDb(*q, p);
      if (margin < 0) continue;
      margin += transmission(prims, e, hit, q, nullptr, true) + transmission(prims, p, hit, q, nullptr, true);
      if (margin >= 0) keep(L, margin, q, sonar_cause_t::REFLECTOR_CYLINDER, hit);
    }
  }
  for (const CornerReflector& cr : refl_.corners) {
    if (!insideWedge(cr.start, cr.opening, cr.vertex, e) || !insideWedge(cr.start, cr.opening, cr.vertex, p)) continue;
    const geom::Vec2 image = 2 * cr.vertex - e;  // twice mirrored: the point image through the vertex
    const double L = (image - p).norm();
    if (L < lo || L > hi) continue;
    const Material& ma = *cr.a->material;
    const Material& mb = *cr.b->material;
    // Twice reflected, the sound comes back parallel to how it left: the emitter sends it towards
    // the listener's image (2v - p), the listener hears it from the emitter's (2v - e).
    double margin = budget(L) + dirDb(ping.pose, 2 * cr.vertex - p) + dirDb(listener, image) + ma.sonar_reflect_db +
                    mb.sonar_reflect_db + coherentDb(ma) + coherentDb(mb);
    if (margin < 0) continue;
    const Primitive *wa = inWorld(world, cr.a), *wb = inWorld(world, cr.b);
    margin += transmission(prims, e, cr.vertex, wa, wb, true) + transmission(prims, p, cr.vertex, wa, wb, true);
    if (margin >= 0) keep(L, margin, cr.a, sonar_cause_t::REFLECTOR_CORNER, cr.vertex);
  }
  return out;
}

std::vector<Echo> PhysicalSonar::emitterArrivals(const WorldGeometry& world, const geom::Pose2& listener,
                                                 int64_t utime) const {
  std::vector<Echo> out;
  if (scenario_->emitters.empty()) return out;
  const geom::Vec2 p = listener.position();
  const double t = static_cast<double>(utime - WorldCore::kStartUtime) * 1e-6;  // sim time of this firing
  const double c = acoustics::kSpeedOfSound;
  for (size_t i = 0; i < scenario_->emitters.size(); ++i) {
    const EmitterSpec& em = scenario_->emitters[i];
    const double d = (p - em.position).norm();
    // Pings sent at phase + n period whose sound arrives inside the listening window.
    const double first = t + 2 * cfg_.range_min / c - d / c, last = t + 2 * cfg_.range_max / c - d / c;
    const double n0 = std::max(0.0, std::ceil((first - em.phase_s) / em.period_s));
    for (double n = n0; em.phase_s + n * em.period_s <= last; n += 1) {
      const double sent = em.phase_s + n * em.period_s;
      const double range = 0.5 * c * (sent + d / c - t);
      // Our own transducer's direct sound at 1 m is 6 dB above its flat-mirror echo at 1 m (half the path).
      const double level = em.level_db.value_or(budget_.snr() + 20.0 * std::log10(2.0));
      double margin = level - 20.0 * std::log10(std::max(d, 1e-3)) - budget_.absorption() * (d - 1.0) +
                      budget_.tvgDb(range) + tx_.oneWayDb(geom::angleDiff(heading(em.position - p), listener.theta));
      if (em.heading) margin += tx_.oneWayDb(geom::angleDiff(heading(p - em.position), *em.heading));
      if (margin < 0) continue;
      margin += transmission(near(world, p, d), p, em.position, nullptr, nullptr, true);
      if (margin >= 0) out.push_back({range, margin, sonar_cause_t::CAUSE_FOREIGN, sonar_cause_t::REFLECTOR_NONE, nullptr, em.position});
    }
  }
  return out;
}

std::vector<SonarReading> PhysicalSonar::fireGroup(const WorldGeometry& world, int64_t utime,
                                                   const std::vector<int>& ids, const std::vector<geom::Pose2>& poses,
                                                   const std::vector<geom::Vec2>& mover_velocity,
                                                   std::mt19937_64& rng) {
  for (size_t i = 0; i < mover_velocity.size() && i < mover_velocity_.size(); ++i) mover_velocity_[i] = mover_velocity[i];
  // Pings older than the longest audible path plus a listening window cannot arrive any more.
  const double max_age_s = 2.0 * (budget_.hearingRange() + cfg_.range_max) / acoustics::kSpeedOfSound;
  while (!history_.empty() && static_cast<double>(utime - history_.front().utime) * 1e-6 > max_age_s)
    history_.pop_front();

  std::vector<SonarReading> out;
  for (size_t k = 0; k < ids.size(); ++k) {
    const int id = ids[k];
    advanceFluctuation(id, utime);
    std::vector<Echo> own = ownEchoes(world, poses[k], id);
    std::vector<Echo> other;
    if (cfg_.crosstalk == CrosstalkModel::Geometric) {
      for (const Ping& ping : history_) {
        auto a = arrivals(world, ping, poses[k], utime, id);
        other.insert(other.end(), a.begin(), a.end());
      }
      for (size_t j = 0; j < ids.size(); ++j) {
        if (j == k) continue;
        auto a = arrivals(world, Ping{utime, ids[j], poses[j]}, poses[k], utime, id);
        other.insert(other.end(), a.begin(), a.end());
      }
    }
    auto fe = emitterArrivals(world, poses[k], utime);
    other.insert(other.end(), fe.begin(), fe.end());

    // Materials described only by the ideal keys keep their echo probability: one draw per
    // reading and obstacle, in the order the echoes arrive.
    std::map<int, bool> heard;
    auto audible = [&](const Echo& e) {
      if (e.margin < 0 || e.range < cfg_.range_min || e.range > cfg_.range_max) return false;  // blanked, or too late
      if (!e.prim || e.prim->material->sonar_hear_prob >= 1.0) return true;
      auto [it, fresh] = heard.try_emplace(e.prim->obstacle, false);
      if (fresh) it->second = uniform01(rng) < e.prim->material->sonar_hear_prob;
      return it->second;
    };
    auto byRange = [](const Echo& a, const Echo& b) { return a.range < b.range; };
    std::stable_sort(own.begin(), own.end(), byRange);
    std::stable_sort(other.begin(), other.end(), byRange);
    const Echo* first_own = nullptr;
    for (const Echo& e : own)
      if (audible(e)) {
        first_own = &e;
        break;
      }
    const Echo* first_other = nullptr;
    for (const Echo& e : other)
      if (audible(e)) {
        first_other = &e;
        break;
      }
    const Echo* read = first_own;
    if (first_other && (!read || first_other->range < read->range)) read = first_other;

    SonarReading r;
    r.truth.obstacle = -1;
    r.truth.true_range = -1;
    r.truth.cause = sonar_cause_t::CAUSE_NO_ECHO;
    r.truth.reflector = sonar_cause_t::REFLECTOR_NONE;
    if (first_own) {  // what this sensor's own ping gave (replaced, if something else came first)
      r.truth.obstacle = first_own->prim->obstacle;
      r.truth.laser_visible = first_own->prim->material->laser == LaserBehaviour::Reflect;
      if (first_own->cause == sonar_cause_t::CAUSE_DIRECT) {
        r.truth.true_range = static_cast<float>(first_own->range);
        r.truth.hit_x = first_own->hit.x();
        r.truth.hit_y = first_own->hit.y();
        r.truth.reflector = first_own->reflector;
      }
    }
    if (read) {
      r.truth.cause = read->cause;
      // A weak echo crosses the threshold late: its envelope rises over half the pulse cell.
      const double rise = 0.5 * tx_.pulseCell() * std::pow(10.0, -read->margin / 20.0);
      const double noise = (cfg_.noise_std + cfg_.noise_rel * read->range) * std::normal_distribution<double>()(rng);
      r.range = static_cast<float>(std::clamp(read->range + rise + noise, cfg_.range_min, cfg_.range_max));
      r.no_echo = false;
    } else {
      r.range = static_cast<float>(cfg_.range_max);
    }
    // The random models: an unmodelled foreign source, and random crosstalk if chosen.
    const double xt = cfg_.crosstalk == CrosstalkModel::Random ? cfg_.crosstalk_prob : 0.0;
    const double u = uniform01(rng);
    if (u < xt + cfg_.foreign_prob) {
      const double upper = r.no_echo ? cfg_.range_max : r.range;
      r.range = static_cast<float>(cfg_.range_min + uniform01(rng) * std::max(0.0, upper - cfg_.range_min));
      r.no_echo = false;
      r.truth.cause = u < xt ? sonar_cause_t::CAUSE_CROSSTALK : sonar_cause_t::CAUSE_FOREIGN;
    }
    const geom::Sector ideal{poses[k].position(), poses[k].theta, cfg_.ideal_beam_width, cfg_.ideal_range};
    r.truth.nearest_laser_visible = static_cast<float>(nearestLaserVisible(world.primitives(), ideal));
    out.push_back(r);
  }
  for (size_t k = 0; k < ids.size(); ++k) history_.push_back({utime, ids[k], poses[k]});
  return out;
}

}  // namespace lasonic::sim
