#include "sim/scenario.hpp"

#include <cmath>

namespace lasonic::sim {

std::map<std::string, Material> builtinMaterials() {
  using geom::deg2rad;
  auto m = [](const char* name, LaserBehaviour laser, double echo_deg, double prob) {
    return Material{name, laser, deg2rad(echo_deg), prob};
  };
  std::map<std::string, Material> out;
  for (const Material& mat : {
           m("wall", LaserBehaviour::Reflect, 60, 1.0),
           m("metal", LaserBehaviour::Reflect, 12, 1.0),
           m("glass", LaserBehaviour::Transparent, 10, 1.0),
           m("mesh", LaserBehaviour::Transparent, 90, 0.9),
           m("black_cardboard", LaserBehaviour::Absorb, 40, 1.0),
           m("plastic", LaserBehaviour::Reflect, 90, 1.0),
           m("person", LaserBehaviour::Reflect, 90, 0.8),
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

// Waypoints of a path (robot or mover): at least two, no two consecutive ones equal, since a
// zero-length leg has no direction of travel.
std::vector<geom::Vec2> requirePath(const Config& c, const std::string& key) {
  std::vector<geom::Vec2> pts = c.requirePoints(key, 2);
  for (size_t i = 1; i < pts.size(); ++i)
    if ((pts[i] - pts[i - 1]).norm() < 1e-9)
      c.fail(key + "[" + std::to_string(i) + "]", "repeats the previous point (zero-length leg)");
  return pts;
}

void parseMaterials(const Config& root, std::map<std::string, Material>& materials) {
  const Config mats = root.section("materials");
  for (const std::string& name : mats.keys()) {
    const Config m = mats.section(name);
    m.allowOnly({"laser", "sonar_echo_angle_deg", "sonar_echo_prob"});
    const bool is_new = !materials.count(name);
    Material mat = is_new ? Material{name} : materials.at(name);
    // A new material must say how both sensors see it; an override may change any subset.
    if (is_new || m.has("laser")) mat.laser = parseLaserBehaviour(m, "laser");
    if (is_new || m.has("sonar_echo_angle_deg"))
      mat.sonar_echo_angle = geom::deg2rad(m.requireNum("sonar_echo_angle_deg", Range::between(0, 90)));
    mat.sonar_echo_prob = m.get("sonar_echo_prob", mat.sonar_echo_prob, Range::probability());
    materials[name] = mat;
  }
}

ObstacleSpec parseObstacle(const Config& o, const std::map<std::string, Material>& materials) {
  ObstacleSpec spec;
  spec.shape = o.require<std::string>("shape");
  if (spec.shape == "segment") {
    o.allowOnly({"shape", "material", "from", "to"});
    spec.points = {o.requireVec2("from"), o.requireVec2("to")};
    if ((spec.points[1] - spec.points[0]).norm() < 1e-9) o.fail("to", "equals from (zero-length segment)");
  } else if (spec.shape == "polyline") {
    o.allowOnly({"shape", "material", "points", "closed"});
    spec.points = o.requirePoints("points", 2);
    spec.closed = o.get<bool>("closed", false);
    for (size_t i = 1; i < spec.points.size(); ++i)
      if ((spec.points[i] - spec.points[i - 1]).norm() < 1e-9)
        o.fail("points[" + std::to_string(i) + "]", "repeats the previous point (zero-length segment)");
    if (spec.closed && spec.points.size() < 3) o.fail("points", "a closed polyline needs at least 3 points");
    if (spec.closed && (spec.points.back() - spec.points.front()).norm() < 1e-9)
      o.fail("closed", "the last point already equals the first (leave out closed: true or the last point)");
  } else if (spec.shape == "circle") {
    o.allowOnly({"shape", "material", "center", "radius"});
    spec.circle.center = o.requireVec2("center");
    spec.circle.radius = o.requireNum("radius", Range::positive());
  } else if (spec.shape == "box") {
    o.allowOnly({"shape", "material", "center", "size", "yaw_deg"});
    const geom::Vec2 c = o.requireVec2("center");
    const geom::Vec2 size = o.requireVec2("size");
    if (size.x() <= 0 || size.y() <= 0) o.fail("size", "both sides must be > 0");
    const geom::Pose2 frame{c.x(), c.y(), geom::deg2rad(o.get("yaw_deg", 0.0, Range::any()))};
    const double hx = 0.5 * size.x(), hy = 0.5 * size.y();
    spec.points = {frame.transform({-hx, -hy}), frame.transform({hx, -hy}), frame.transform({hx, hy}),
                   frame.transform({-hx, hy})};
    spec.closed = true;
  } else {
    o.fail("shape", "must be segment, polyline, circle or box (got \"" + spec.shape + "\")");
  }
  spec.material = requireMaterial(o, "material", materials);
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
  m.allowOnly({"shape", "radius", "material", "speed", "path", "mode", "start_delay_s"});
  MoverSpec spec;
  spec.id = id;
  const std::string shape = m.get<std::string>("shape", "circle");
  if (shape != "circle") m.fail("shape", "movers must be circles (got \"" + shape + "\")");
  spec.radius = m.get("radius", spec.radius, Range::positive());
  spec.material = requireMaterial(m, "material", materials, spec.material);
  spec.speed = m.get("speed", spec.speed, Range::positive());
  spec.path = requirePath(m, "path");
  spec.mode = parseMode(m, spec.mode);
  spec.start_delay_s = m.get("start_delay_s", spec.start_delay_s, Range::nonNegative());
  return spec;
}

RobotSpec parseRobot(const Config& r) {
  r.allowOnly({"radius", "path", "speed", "mode", "turn_rate"});
  RobotSpec spec;
  spec.radius = r.get("radius", spec.radius, Range::positive());
  spec.path = requirePath(r, "path");
  spec.speed = r.get("speed", spec.speed, Range::positive());
  spec.mode = parseMode(r, spec.mode);
  spec.turn_rate = r.get("turn_rate", spec.turn_rate, Range::positive());
  return spec;
}

}  // namespace

Scenario::Scenario(const Scenario& other)
    : name(other.name), file(other.file), duration_s(other.duration_s), seed(other.seed),
      materials(other.materials), obstacles(other.obstacles), statics(other.statics),
      movers(other.movers), robot(other.robot), laser(other.laser), sonar(other.sonar),
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
  root.allowOnly({"name", "duration_s", "seed", "materials", "obstacles", "movers", "robot", "laser",
                  "sonar", "odometry"});
  Scenario s;
  s.name = root.require<std::string>("name");
  s.duration_s = root.get("duration_s", s.duration_s, Range::positive());
  const int64_t seed = root.get<int64_t>("seed", static_cast<int64_t>(s.seed));
  if (seed < 0) root.fail("seed", "must be >= 0");
  s.seed = static_cast<uint64_t>(seed);

  s.materials = builtinMaterials();
  parseMaterials(root, s.materials);

  const std::vector<Config> obstacles = root.list("obstacles");
  for (size_t i = 0; i < obstacles.size(); ++i) {
    s.obstacles.push_back(parseObstacle(obstacles[i], s.materials));
    expand(s.obstacles.back(), static_cast<int>(i), s.materials, s.statics);
  }
  const std::vector<Config> movers = root.list("movers");
  for (size_t i = 0; i < movers.size(); ++i)
    s.movers.push_back(parseMover(movers[i], static_cast<int>(i), s.materials));
  s.robot = parseRobot(root.requireSection("robot"));

  // Sensor overrides keep their paths ("laser.noise_std"), so the drivers' config readers name
  // the scenario key when they reject one.
  s.laser = root.section("laser");
  s.sonar = root.section("sonar");
  s.odometry = root.section("odometry");
  return s;
}

Scenario loadScenario(const std::string& file) {
  Scenario s = parseScenario(Config::loadFile(file));
  s.file = file;
  return s;
}

}  // namespace lasonic::sim
