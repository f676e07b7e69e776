#include "sim/scenario.hpp"

#include "sim/drivers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace lasonic::sim {

std::map<std::string, Material> builtinMaterials() {
  using geom::deg2rad;
  // Ideal profile: laser behaviour, largest sonar incidence that echoes, echo probability.
  auto m = [](const char* name, LaserBehaviour laser, double echo_deg, double prob) {
    Material mat{name, laser, deg2rad(echo_deg), prob};
    return mat;
  };
  // Physical profile (sources: README "Sensor models"). Sonar at 49.4 kHz (wavelength 6.9 mm):
  // reflection loss [dB], rms roughness [mm], lobe [deg], diffuse share, transmitted share;
  // laser: remission at the scanner's near-infrared wavelength, specular cone [deg].
  auto phys = [](Material mat, double reflect_db, double rough_mm, double lobe_deg, double diffuse,
                 double transmit, double remission, double specular_deg) {
    mat.sonar_reflect_db = reflect_db;
    mat.sonar_roughness = rough_mm * 1e-3;
    mat.sonar_lobe = deg2rad(lobe_deg);
    mat.sonar_diffuse = diffuse;
    mat.sonar_transmit = transmit;
    mat.laser_remission = remission;
    mat.laser_specular = deg2rad(specular_deg);
    return mat;
  };
  // Rigid surfaces (plaster, metal, glass, plastic) reflect all but ~0.1 % of the power: their
  // acoustic impedance is 10^4 times that of air. Painted plaster (rms ~0.2 mm) is smooth
  // against the wavelength: 88 % mirror; sheet metal, glass and PVC are mirrors. A wire mesh
  // covers ~15 % of its area with wires thinner than the wavelength: it scatters that part in
  // all directions (-8 dB) and lets 85 % through. Cardboard is a slightly porous mirror; clothing
  // absorbs about three quarters of the power (-6 dB) and folds make a person a rough,
  // fluctuating reflector.
  Material person = phys(m("person", LaserBehaviour::Reflect, 90, 0.8), -6.0, 5.0, 20, 0.5, 0, 0.30, 0);
  person.sonar_fluct_db = 4.0;   // posture and swinging arms: a few dB
  person.sonar_fluct_s = 0.5;    // about half a stride at walking pace
  person.sonar_aspect_db = 3.0;  // torso ~0.45 m wide front-on, ~0.25 m from the side
  std::map<std::string, Material> out;
  for (const Material& mat : {
           phys(m("wall", LaserBehaviour::Reflect, 60, 1.0), 0.0, 0.2, 5, 0.1, 0, 0.85, 0),
           phys(m("metal", LaserBehaviour::Reflect, 12, 1.0), 0.0, 0.01, 1, 0.0, 0, 0.40, 0),
           phys(m("glass", LaserBehaviour::Transparent, 10, 1.0), 0.0, 0.001, 0.5, 0.0, 0, 0.0, 2),
           phys(m("mesh", LaserBehaviour::Transparent, 90, 0.9), -8.0, 5.0, 30, 1.0, 0.85, 0.0, 0),
           phys(m("black_cardboard", LaserBehaviour::Absorb, 40, 1.0), -1.0, 0.1, 3, 0.1, 0, 0.03, 0),
           phys(m("plastic", LaserBehaviour::Reflect, 90, 1.0), 0.0, 0.01, 1, 0.0, 0, 0.50, 0),
           person,
       })
    out[mat.name] = mat;
  return out;
}

namespace {

// Re-points every primitive's material at the map that now owns the materials.
void relink(std::vector<Primitive>& prims, const std::map<std::string, Material>& materials) {
  for (Primitive& p : prims)
    if (p.material) p.material = &materials.at(p.material->name);
}

std::string knownNames(const std::map<std::string, Material>& materials) {
  std::string s;
  for (const auto& kv : materials) s += (s.empty() ? "" : ", ") + kv.first;
  return s;
}

LaserBehaviour parseLaserBehaviour(const Config& c, const std::string& key) {
  const std::string v = c.require<std::string>(key);
  if (v == "reflect") return LaserBehaviour::Reflect;
  if (v == "transparent") return LaserBehaviour::Transparent;
  if (v == "absorb") return LaserBehaviour::Absorb;
  c.fail(key, "must be reflect, transparent or absorb (got \"" + v + "\")");
}

PathMode parseMode(const Config& c, PathMode def) {
  const auto v = c.getOptionalString("mode");
  if (!v) return def;
  if (*v == "once") return PathMode::Once;
  if (*v == "loop") return PathMode::Loop;
  if (*v == "pingpong") return PathMode::PingPong;
  c.fail("mode", "must be once, loop or pingpong (got \"" + *v + "\")");
}

// A material name that must exist in the (built-in + scenario) materials.
std::string requireMaterial(const Config& c, const std::string& key,
                            const std::map<std::string, Material>& materials,
                            const std::optional<std::string>& def = std::nullopt) {
  const auto name = def ? std::optional<std::string>(c.get<std::string>(key, *def))
                        : std::optional<std::string>(c.require<std::string>(key));
  if (!materials.count(*name))
    c.fail(key, "unknown material \"" + *name + "\" (known: " + knownNames(materials) + ")");
  return *name;
}

// A place in the world: within bounds::kMaxCoordinate of the origin.
void checkPoint(const Config& c, const std::string& key, const geom::Vec2& p) {
  if (!(std::abs(p.x()) <= bounds::kMaxCoordinate && std::abs(p.y()) <= bounds::kMaxCoordinate))
    c.fail(key, "must lie within 1000 km of the origin (|x|, |y| <= 1e6 m)");
}
void checkPoints(const Config& c, const std::string& key, const std::vector<geom::Vec2>& pts) {
  for (size_t i = 0; i < pts.size(); ++i) checkPoint(c, key + "[" + std::to_string(i) + "]", pts[i]);
}
geom::Vec2 requirePlace(const Config& c, const std::string& key) {
  const geom::Vec2 p = c.requireVec2(key);
  checkPoint(c, key, p);
  return p;
}

// Whether all points lie on one line (within 1e-9 m): a closed polyline through them encloses
// nothing. (Not a zero signed area: a figure of eight that crosses itself has one too.)
bool collinear(const std::vector<geom::Vec2>& pts) {
  size_t far = 0;
  for (size_t i = 1; i < pts.size(); ++i)
    if ((pts[i] - pts[0]).norm() > (pts[far] - pts[0]).norm()) far = i;
  const geom::Vec2 u = pts[far] - pts[0];
  const double len = u.norm();
  if (len < 1e-9) return true;
  for (const geom::Vec2& p : pts) {
    const geom::Vec2 v = p - pts[0];
    if (std::abs(u.x() * v.y() - u.y() * v.x()) / len > 1e-9) return false;
  }
  return true;
}

// Waypoints of a path (robot or mover): at least two, no two consecutive ones equal, since a
// zero-length leg has no direction of travel.
std::vector<geom::Vec2> requirePath(const Config& c, const std::string& key) {
  std::vector<geom::Vec2> pts = c.requirePoints(key, 2);
  checkPoints(c, key, pts);
  for (size_t i = 1; i < pts.size(); ++i)
    if ((pts[i] - pts[i - 1]).norm() < 1e-9)
      c.fail(key + "[" + std::to_string(i) + "]", "repeats the previous point (zero-length leg)");
  return pts;
}

// Physical parameters of a material that gives only the ideal keys: an echo angle up to 30°
// means a smooth surface whose lobe reaches about that far; a larger one a rough surface, the
// more diffuse the wider. Its echo probability carries over (README "Scenario format").
void physicalFromIdeal(Material& mat) {
  const double deg = geom::rad2deg(mat.sonar_echo_angle);
  const bool smooth = deg <= 30;
  mat.sonar_roughness = smooth ? 0.1e-3 : 3e-3;
  mat.sonar_lobe = std::max(geom::deg2rad(0.5), mat.sonar_echo_angle / (smooth ? 3.0 : 2.0));
  mat.sonar_diffuse = smooth ? 0.0 : std::min(1.0, deg / 90.0);
  mat.sonar_hear_prob = mat.sonar_echo_prob;
}

// Ideal parameters of a material that gives only physical keys: mostly diffuse -> echoes from
// every angle, else up to twice its lobe width.
void idealFromPhysical(Material& mat) {
  const double deg = geom::rad2deg(mat.sonar_lobe);
  mat.sonar_echo_angle = geom::deg2rad(mat.sonar_diffuse >= 0.5 ? 90.0 : std::clamp(2 * deg, 5.0, 90.0));
  mat.sonar_echo_prob = 1;
}

double defaultRemission(LaserBehaviour b) {
  switch (b) {
    case LaserBehaviour::Reflect: return 0.5;       // a mid-grey surface
    case LaserBehaviour::Absorb: return 0.03;       // matte black
    case LaserBehaviour::Transparent: return 0.0;
  }
  return 0.5;
}

void parseMaterials(const Config& root, std::map<std::string, Material>& materials) {
  const Config mats = root.section("materials");
  static const std::vector<std::string> kPhysicalSonar = {"sonar_reflect_db", "sonar_roughness_mm", "sonar_lobe_deg",
                                                          "sonar_diffuse", "sonar_transmit", "sonar_fluct_db",
                                                          "sonar_fluct_s", "sonar_aspect_db"};
  for (const std::string& name : mats.keys()) {
    const Config m = mats.section(name);
    m.allowOnly({"laser", "sonar_echo_angle_deg", "sonar_echo_prob", "sonar_reflect_db", "sonar_roughness_mm",
                 "sonar_lobe_deg", "sonar_diffuse", "sonar_transmit", "sonar_fluct_db", "sonar_fluct_s",
                 "sonar_aspect_db", "laser_remission", "laser_specular_deg"});
    const bool is_new = !materials.count(name);
    Material mat = is_new ? Material{name} : materials.at(name);
    bool physical = false;
    for (const std::string& k : kPhysicalSonar) physical = physical || m.has(k);
    // A new material must say how both sensors see it: `laser`, and the sonar by either the ideal
    // echo angle or the physical roughness (the other profile's parameters are derived).
    const LaserBehaviour laser_before = mat.laser;
    if (is_new || m.has("laser")) mat.laser = parseLaserBehaviour(m, "laser");
    if (is_new && !m.has("sonar_echo_angle_deg") && !m.has("sonar_roughness_mm"))
      m.fail("sonar_echo_angle_deg", "is required (or give the physical sonar_roughness_mm)");
    if (m.has("sonar_echo_angle_deg"))
      mat.sonar_echo_angle = geom::deg2rad(m.requireNum("sonar_echo_angle_deg", Range::between(0, 90)));
    mat.sonar_echo_prob = m.get("sonar_echo_prob", mat.sonar_echo_prob, Range::probability());
    // The physical profile (the default) follows ideal keys given without physical ones, for a
    // built-in material too: `wall: {sonar_echo_prob: 0}` must silence the wall in either profile.
    if (!physical && (is_new || m.has("sonar_echo_angle_deg"))) physicalFromIdeal(mat);
    else if (!physical && m.has("sonar_echo_prob")) mat.sonar_hear_prob = mat.sonar_echo_prob;
    if (m.has("sonar_roughness_mm"))
      mat.sonar_roughness = 1e-3 * m.requireNum("sonar_roughness_mm", Range::between(0, 1000));
    mat.sonar_reflect_db = m.get("sonar_reflect_db", mat.sonar_reflect_db, Range::between(-100, 0));
    mat.sonar_lobe = geom::deg2rad(m.get("sonar_lobe_deg", geom::rad2deg(mat.sonar_lobe), Range::between(0, 89)));
    mat.sonar_diffuse = m.get("sonar_diffuse", mat.sonar_diffuse, Range::probability());
    mat.sonar_transmit = m.get("sonar_transmit", mat.sonar_transmit, Range{0, 1, false});
    if (mat.sonar_transmit >= 1.0) m.fail("sonar_transmit", "must be < 1 (1 would be no surface at all)");
    mat.sonar_fluct_db = m.get("sonar_fluct_db", mat.sonar_fluct_db, Range::between(0, 40));
    mat.sonar_fluct_s = m.get("sonar_fluct_s", mat.sonar_fluct_s, Range::positive());
    mat.sonar_aspect_db = m.get("sonar_aspect_db", mat.sonar_aspect_db, Range::between(0, 40));
    if (is_new && physical && !m.has("sonar_echo_angle_deg")) idealFromPhysical(mat);
    // Likewise the remission follows a changed `laser` (glass made `reflect` must return the beam).
    if (!m.has("laser_remission") && (is_new || mat.laser != laser_before))
      mat.laser_remission = defaultRemission(mat.laser);
    mat.laser_remission = m.get("laser_remission", mat.laser_remission, Range::probability());
    mat.laser_specular =
        geom::deg2rad(m.get("laser_specular_deg", geom::rad2deg(mat.laser_specular), Range::between(0, 90)));
    materials[name] = mat;
  }
}

// frame: {material, width, depth}: a jamb at each end of a segment or open polyline, e.g. a
// glass door in a wooden frame. The obstacle's ends are moved inwards by the width.
void parseFrame(const Config& o, ObstacleSpec& spec, const std::map<std::string, Material>& materials) {
  const Config f = o.section("frame");
  f.allowOnly({"material", "width", "depth"});
  if (spec.closed) o.fail("frame", "only segments and open polylines can have a frame");
  spec.frame_material = requireMaterial(f, "material", materials);
  spec.frame_width = f.requireNum("width", Range::positive());
  spec.frame_depth = f.get("depth", spec.frame_width, Range::positive());
  if (spec.frame_depth > bounds::kMaxCoordinate) f.fail("depth", "must be <= 1e6 m (1000 km)");
  auto& p = spec.points;
  const double first = (p[1] - p[0]).norm(), last = (p[p.size() - 1] - p[p.size() - 2]).norm();
  const double need = p.size() == 2 ? 2 * spec.frame_width : spec.frame_width;
  if (first <= need || last <= need)
    f.fail("width", "leaves nothing of the " + std::string(p.size() == 2 ? "segment" : "end segments") +
                        " it frames (" + std::to_string(std::min(first, last)) + " m)");
  const geom::Vec2 in_front = (p[1] - p[0]) / first, in_back = (p[p.size() - 2] - p.back()) / last;
  p.front() += spec.frame_width * in_front;
  p.back() += spec.frame_width * in_back;
}

// The two jambs of a framed obstacle, as boxes: `width` along its end segment (ending where the
// obstacle ended), `depth` across it.
std::vector<ObstacleSpec> frameJambs(const ObstacleSpec& spec, int index) {
  std::vector<ObstacleSpec> out;
  const auto& p = spec.points;
  for (const auto& [end, next] : {std::pair{p.front(), p[1]}, std::pair{p.back(), p[p.size() - 2]}}) {
    const geom::Vec2 u = (next - end).normalized();  // inwards
    const geom::Vec2 c = end - 0.5 * spec.frame_width * u;
    const geom::Pose2 frame{c.x(), c.y(), std::atan2(u.y(), u.x())};
    const double hx = 0.5 * spec.frame_width, hy = 0.5 * spec.frame_depth;
    ObstacleSpec j;
    j.shape = "box";
    j.material = spec.frame_material;
    j.points = {frame.transform({-hx, -hy}), frame.transform({hx, -hy}), frame.transform({hx, hy}),
                frame.transform({-hx, hy})};
    j.closed = true;
    j.frame_of = index;
    out.push_back(j);
  }
  return out;
}

EmitterSpec parseEmitter(const Config& e) {
  e.allowOnly({"position", "period_s", "phase_s", "level_db", "heading_deg"});
  EmitterSpec spec;
  spec.position = requirePlace(e, "position");
  spec.period_s = e.requireNum("period_s", Range{bounds::kMinEmitterPeriodS, std::numeric_limits<double>::infinity(), false});
  spec.phase_s = e.get("phase_s", spec.phase_s, Range::nonNegative());
  if (e.has("level_db")) spec.level_db = e.requireNum("level_db", Range::between(-100, 200));
  if (e.has("heading_deg")) spec.heading = geom::deg2rad(e.requireNum("heading_deg", Range::any()));
  return spec;
}

ObstacleSpec parseObstacle(const Config& o, const std::map<std::string, Material>& materials) {
  ObstacleSpec spec;
  spec.shape = o.require<std::string>("shape");
  if (spec.shape == "segment") {
    o.allowOnly({"shape", "material", "from", "to", "frame"});
    spec.points = {requirePlace(o, "from"), requirePlace(o, "to")};
    if ((spec.points[1] - spec.points[0]).norm() < 1e-9) o.fail("to", "equals from (zero-length segment)");
  } else if (spec.shape == "polyline") {
    o.allowOnly({"shape", "material", "points", "closed", "frame"});
    spec.points = o.requirePoints("points", 2);
    checkPoints(o, "points", spec.points);
    spec.closed = o.get<bool>("closed", false);
    for (size_t i = 1; i < spec.points.size(); ++i)
      if ((spec.points[i] - spec.points[i - 1]).norm() < 1e-9)
        o.fail("points[" + std::to_string(i) + "]", "repeats the previous point (zero-length segment)");
    if (spec.closed && spec.points.size() < 3) o.fail("points", "a closed polyline needs at least 3 points");
    if (spec.closed && (spec.points.back() - spec.points.front()).norm() < 1e-9)
      o.fail("closed", "the last point already equals the first (leave out closed: true or the last point)");
    if (spec.closed && collinear(spec.points))
      o.fail("points", "a closed polyline must enclose an area (its points are collinear)");
  } else if (spec.shape == "circle") {
    o.allowOnly({"shape", "material", "center", "radius"});
    spec.circle.center = requirePlace(o, "center");
    spec.circle.radius = o.requireNum("radius", Range::positive());
    if (spec.circle.radius > bounds::kMaxCoordinate) o.fail("radius", "must be <= 1e6 m (1000 km)");
  } else if (spec.shape == "box") {
    o.allowOnly({"shape", "material", "center", "size", "yaw_deg"});
    const geom::Vec2 c = requirePlace(o, "center");
    const geom::Vec2 size = o.requireVec2("size");
    if (size.x() <= 0 || size.y() <= 0) o.fail("size", "both sides must be > 0");
    if (size.x() > bounds::kMaxCoordinate || size.y() > bounds::kMaxCoordinate)
      o.fail("size", "both sides must be <= 1e6 m (1000 km)");
    const geom::Pose2 frame{c.x(), c.y(), geom::deg2rad(o.get("yaw_deg", 0.0, Range::any()))};
    const double hx = 0.5 * size.x(), hy = 0.5 * size.y();
    spec.points = {frame.transform({-hx, -hy}), frame.transform({hx, -hy}), frame.transform({hx, hy}),
                   frame.transform({-hx, hy})};
    spec.closed = true;
  } else {
    o.fail("shape", "must be segment, polyline, circle or box (got \"" + spec.shape + "\")");
  }
  spec.material = requireMaterial(o, "material", materials);
  if (o.has("frame")) parseFrame(o, spec, materials);
  return spec;
}

// Expands one obstacle into primitives: polylines and boxes become their edge segments.
void expand(const ObstacleSpec& spec, int index, const std::map<std::string, Material>& materials,
            std::vector<Primitive>& out) {
  const Material* mat = &materials.at(spec.material);
  if (spec.shape == "circle") {
    Primitive p;
    p.kind = Primitive::Kind::Circle;
    p.circle = spec.circle;
    p.obstacle = index;
    p.material = mat;
    out.push_back(p);
    return;
  }
  const size_t n = spec.points.size();
  const size_t edges = spec.closed ? n : n - 1;
  for (size_t i = 0; i < edges; ++i) {
    Primitive p;
    p.kind = Primitive::Kind::Segment;
    p.segment = {spec.points[i], spec.points[(i + 1) % n]};
    p.obstacle = index;
    p.material = mat;
    out.push_back(p);
  }
}

MoverSpec parseMover(const Config& m, int id, const std::map<std::string, Material>& materials) {
  // The shape first: a box's keys (size) are unknown to a mover because it must be a circle.
  const std::string shape = m.get<std::string>("shape", "circle");
  if (shape != "circle") m.fail("shape", "movers must be circles (got \"" + shape + "\")");
  m.allowOnly({"shape", "radius", "material", "speed", "path", "mode", "start_delay_s", "avoid_robot", "keep_clear_m"});
  MoverSpec spec;
  spec.id = id;
  spec.radius = m.get("radius", spec.radius, Range{0, bounds::kMaxBodyRadius, true});
  spec.material = requireMaterial(m, "material", materials, spec.material);
  spec.speed = m.get("speed", spec.speed, Range{0, bounds::kMaxMoverSpeed, true});
  spec.path = requirePath(m, "path");
  spec.mode = parseMode(m, spec.mode);
  spec.start_delay_s = m.get("start_delay_s", spec.start_delay_s, Range::nonNegative());
  spec.avoid_robot = m.get<bool>("avoid_robot", spec.avoid_robot);
  spec.keep_clear_m = m.get("keep_clear_m", spec.keep_clear_m, Range::between(0, 5));
  return spec;
}

RobotSpec parseRobot(const Config& r) {
  r.allowOnly({"radius", "path", "speed", "mode", "turn_rate"});
  RobotSpec spec;
  spec.radius = r.get("radius", spec.radius, Range{0, bounds::kMaxBodyRadius, true});
  spec.path = requirePath(r, "path");
  spec.speed = r.get("speed", spec.speed, Range{0, bounds::kMaxRobotSpeed, true});
  spec.mode = parseMode(r, spec.mode);
  spec.turn_rate = r.get("turn_rate", spec.turn_rate, Range::positive());
  return spec;
}

}  // namespace

Scenario::Scenario(const Scenario& other)
    : name(other.name), file(other.file), duration_s(other.duration_s), seed(other.seed),
      materials(other.materials), obstacles(other.obstacles), statics(other.statics),
      movers(other.movers), emitters(other.emitters), robot(other.robot), laser(other.laser), sonar(other.sonar),
      odometry(other.odometry) {
  relink(statics, materials);
}

Scenario& Scenario::operator=(const Scenario& other) {
  if (this != &other) {
    Scenario copy(other);
    *this = std::move(copy);
  }
  return *this;
}

const Material& Scenario::material(const std::string& n) const {
  const auto it = materials.find(n);
  if (it == materials.end()) throw std::out_of_range("unknown material \"" + n + "\"");
  return it->second;
}

bool Scenario::laserVisible(int obstacle) const {
  if (obstacle >= 0 && obstacle < static_cast<int>(obstacles.size()))
    return material(obstacles[obstacle].material).laser == LaserBehaviour::Reflect;
  const int mover = -obstacle - 2;
  if (mover >= 0 && mover < static_cast<int>(movers.size()))
    return material(movers[mover].material).laser == LaserBehaviour::Reflect;
  return false;
}

Scenario parseScenario(const Config& root) {
  root.allowOnly({"name", "duration_s", "seed", "materials", "obstacles", "movers", "emitters", "robot",
                  "laser", "sonar", "odometry"});
  Scenario s;
  s.name = root.require<std::string>("name");
  // The name names a run's logs and files: neither empty nor a path.
  if (s.name.empty()) root.fail("name", "must not be empty (it names the run's files)");
  if (s.name.find('/') != std::string::npos) root.fail("name", "must not contain '/' (it names the run's files)");
  s.duration_s = root.get("duration_s", s.duration_s, Range{0, bounds::kMaxDurationS, true});
  // A seed is an int64 >= 0 (as --seed): one message for a number beyond it, a negative or a
  // fractional one, which says what is allowed.
  if (root.has("seed") && root.node()["seed"].IsScalar()) {
    int64_t v = 0;
    if (!YAML::convert<int64_t>::decode(root.node()["seed"], v) || v < 0)
      root.fail("seed", "must be an integer in [0, 9223372036854775807] (got " + root.node()["seed"].Scalar() + ")");
  }
  s.seed = static_cast<uint64_t>(root.get<int64_t>("seed", static_cast<int64_t>(s.seed)));

  s.materials = builtinMaterials();
  parseMaterials(root, s.materials);

  const std::vector<Config> obstacles = root.list("obstacles");
  for (size_t i = 0; i < obstacles.size(); ++i) s.obstacles.push_back(parseObstacle(obstacles[i], s.materials));
  // Frames after the scenario's own obstacles, so that those keep their indices.
  for (size_t i = 0; i < obstacles.size(); ++i)
    if (!s.obstacles[i].frame_material.empty())
      for (ObstacleSpec& j : frameJambs(s.obstacles[i], static_cast<int>(i))) s.obstacles.push_back(j);
  for (size_t i = 0; i < s.obstacles.size(); ++i) expand(s.obstacles[i], static_cast<int>(i), s.materials, s.statics);
  for (const Config& e : root.list("emitters")) s.emitters.push_back(parseEmitter(e));
  const std::vector<Config> movers = root.list("movers");
  for (size_t i = 0; i < movers.size(); ++i)
    s.movers.push_back(parseMover(movers[i], static_cast<int>(i), s.materials));
  s.robot = parseRobot(root.requireSection("robot"));

  // Sensor overrides keep their paths ("laser.noise_std"), so the drivers' config readers name
  // the scenario key when they reject one. Each key is checked here, by the simulator's own
  // readers, so that every tool refuses a scenario the simulator would refuse; what depends on
  // the configuration they are layered over (range_min < range_max, ...) is checked with it.
  s.laser = root.section("laser");
  s.sonar = root.section("sonar");
  s.odometry = root.section("odometry");
  checkLaserKeys(s.laser);
  checkSonarKeys(s.sonar);
  checkOdometryKeys(s.odometry);
  cutPanesIntoWalls(s);
  findCoincidentObstacles(s);
  return s;
}

namespace {
// The laser's view of a material, best first: what the evaluation counts a shared surface as.
int laserRank(const Material& m) {
  switch (m.laser) {
    case LaserBehaviour::Reflect: return 2;
    case LaserBehaviour::Absorb: return 1;
    case LaserBehaviour::Transparent: return 0;
  }
  return 0;
}

// The stretch [t0, t1] along `a` (from a.a, clamped to a) that `b` lies on, when both of b's
// ends are within tol of a's line; else nothing.
std::optional<std::pair<double, double>> collinearSpan(const geom::Segment& a, const geom::Segment& b, double tol) {
  const double len = a.length();
  if (len < 1e-9 || b.length() < 1e-9) return std::nullopt;
  const geom::Vec2 u = (a.b - a.a) / len;
  const auto off = [&](const geom::Vec2& p) { return std::abs(u.x() * (p.y() - a.a.y()) - u.y() * (p.x() - a.a.x())); };
  if (off(b.a) > tol || off(b.b) > tol) return std::nullopt;
  const double t0 = u.dot(b.a - a.a), t1 = u.dot(b.b - a.a);
  return std::make_pair(std::clamp(std::min(t0, t1), 0.0, len), std::clamp(std::max(t0, t1), 0.0, len));
}

// Length along `a` that `b` lies on.
double collinearOverlap(const geom::Segment& a, const geom::Segment& b, double tol) {
  const auto span = collinearSpan(a, b, tol);
  return span ? span->second - span->first : 0.0;
}
}  // namespace

void cutPanesIntoWalls(Scenario& s) {
  constexpr double kMinOverlapM = 0.05;
  std::vector<Primitive> out;
  out.reserve(s.statics.size());
  for (const Primitive& w : s.statics) {
    if (w.kind != Primitive::Kind::Segment || w.obstacle < 0 || w.material->laser == LaserBehaviour::Transparent) {
      out.push_back(w);
      continue;
    }
    // The stretches of w that transparent obstacles are drawn on, as [t0, t1] along it.
    const double len = w.segment.length();
    std::vector<std::pair<double, double>> cuts;
    for (const Primitive& t : s.statics) {
      if (t.kind != Primitive::Kind::Segment || t.obstacle == w.obstacle ||
          t.material->laser != LaserBehaviour::Transparent)
        continue;
      const auto span = collinearSpan(w.segment, t.segment, Scenario::kCoincidentM);
      if (span && span->second - span->first >= kMinOverlapM) cuts.push_back(*span);
    }
    if (cuts.empty()) {
      out.push_back(w);
      continue;
    }
    std::sort(cuts.begin(), cuts.end());
    double from = 0;
    const auto piece = [&](double t0, double t1) {
      if (t1 - t0 < 1e-6) return;
      Primitive p = w;
      const geom::Vec2 d = w.segment.b - w.segment.a;
      p.segment = geom::Segment{w.segment.a + d * (t0 / len), w.segment.a + d * (t1 / len)};
      out.push_back(p);
    };
    for (const auto& [t0, t1] : cuts) {
      piece(from, t0);
      from = std::max(from, t1);
    }
    piece(from, len);
  }
  s.statics = std::move(out);
}

void findCoincidentObstacles(Scenario& s) {
  constexpr double kMinOverlapM = 0.05;  // a touching end or corner is no shared surface
  s.coincident.assign(s.obstacles.size(), {});
  for (size_t i = 0; i < s.statics.size(); ++i)
    for (size_t j = i + 1; j < s.statics.size(); ++j) {
      const Primitive &a = s.statics[i], &b = s.statics[j];
      if (a.obstacle == b.obstacle || a.obstacle < 0 || b.obstacle < 0 || a.kind != Primitive::Kind::Segment ||
          b.kind != Primitive::Kind::Segment)
        continue;
      if (collinearOverlap(a.segment, b.segment, Scenario::kCoincidentM) < kMinOverlapM) continue;
      auto& pa = s.coincident[static_cast<size_t>(a.obstacle)];
      auto& pb = s.coincident[static_cast<size_t>(b.obstacle)];
      if (std::find(pa.begin(), pa.end(), b.obstacle) == pa.end()) pa.push_back(b.obstacle);
      if (std::find(pb.begin(), pb.end(), a.obstacle) == pb.end()) pb.push_back(a.obstacle);
    }
}

std::vector<int> Scenario::partnersAt(int obstacle, const geom::Vec2& p) const {
  std::vector<int> out;
  if (obstacle < 0 || static_cast<size_t>(obstacle) >= coincident.size() || coincident[obstacle].empty())
    return out;
  const auto& partners = coincident[static_cast<size_t>(obstacle)];
  for (const Primitive& q : statics) {
    if (q.obstacle == obstacle || q.kind != Primitive::Kind::Segment) continue;
    if (std::find(partners.begin(), partners.end(), q.obstacle) == partners.end()) continue;
    if (std::find(out.begin(), out.end(), q.obstacle) == out.end() && geom::distance(q.segment, p) <= kCoincidentM)
      out.push_back(q.obstacle);
  }
  return out;
}

int Scenario::canonicalObstacle(int obstacle, const geom::Vec2& p) const {
  const auto rank = [this](int o) { return std::make_pair(laserRank(material(obstacles[o].material)), -o); };
  int best = obstacle;
  for (const int o : partnersAt(obstacle, p))
    if (rank(o) > rank(best)) best = o;
  return best;
}

std::string simStateMoversMismatch(const Scenario& scenario, const std::vector<int>& mover_ids) {
  const size_t n = scenario.movers.size();
  if (mover_ids.size() != n)
    return "its SIM_STATE has " + std::to_string(mover_ids.size()) + " movers, the scenario " + std::to_string(n);
  for (const int id : mover_ids)
    if (id < 0 || static_cast<size_t>(id) >= n)
      return "its SIM_STATE names mover " + std::to_string(id) + ", the scenario has " + std::to_string(n);
  return {};
}

double distanceToRobotPath(const Scenario& scenario, const geom::Vec2& p) {
  const auto& path = scenario.robot.path;
  double best = std::numeric_limits<double>::infinity();
  if (path.size() == 1) return (path.front() - p).norm();
  for (size_t i = 0; i + 1 < path.size(); ++i)
    best = std::min(best, geom::distance(geom::Segment{path[i], path[i + 1]}, p));
  if (scenario.robot.mode == PathMode::Loop && path.size() > 2)
    best = std::min(best, geom::distance(geom::Segment{path.back(), path.front()}, p));
  return best;
}

Scenario loadScenario(const std::string& file) {
  Scenario s = parseScenario(Config::loadFile(file));
  s.file = file;
  return s;
}

}  // namespace lasonic::sim
