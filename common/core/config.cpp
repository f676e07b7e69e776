#include "core/config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/version.hpp"

namespace lasonic {

Config::Config(YAML::Node node, std::string path, std::string file)
    : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)) {}

namespace {
// " (line L, column C)" where yaml-cpp knows the place, else "".
std::string where(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  if (m.is_null()) return "";
  return " (line " + std::to_string(m.line + 1) + ", column " + std::to_string(m.column + 1) + ")";
}

std::string childPath(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

// A map's key as the string every reader looks it up by; a key that is a list, a map or empty
// (`[a, b]: 1`, `? [x]`) cannot be named in the configuration, so it is an error.
std::string keyName(const YAML::Node& key, const std::string& file, const std::string& map_path) {
  if (!key.IsScalar())
    throw ConfigError((file.empty() ? "" : file + ": ") + (map_path.empty() ? std::string("<root>") : map_path) +
                      ": " + (key.IsNull() ? "an empty key" : "a key that is not a string") + where(key));
  return key.Scalar();
}

// Every map of a file, at any depth: its keys are strings, each given once. yaml-cpp keeps both
// pairs of a repeated key, and one reader takes the first while a layered merge takes the last,
// so a repeated key is an error rather than a guess. `ancestors` stops an alias that refers to a
// node containing it (`a: &x {b: *x}`), which every walk of the tree would follow for ever.
void checkTree(const YAML::Node& n, const std::string& path, const std::string& file,
               std::vector<YAML::Node>& ancestors) {
  if (!n.IsMap() && !n.IsSequence()) return;
  const auto prefix = file.empty() ? std::string() : file + ": ";
  for (const YAML::Node& a : ancestors)
    if (a.is(n))
      throw ConfigError(prefix + (path.empty() ? std::string("<root>") : path) +
                        ": refers to itself (an alias of a node that contains it)");
  ancestors.push_back(n);
  if (n.IsMap()) {
    std::map<std::string, YAML::Node> seen;
    for (const auto& kv : n) {
      const std::string k = keyName(kv.first, file, path);
      const auto [it, fresh] = seen.emplace(k, kv.first);
      if (!fresh) {
        const YAML::Mark a = it->second.Mark(), b = kv.first.Mark();
        throw ConfigError(prefix + childPath(path, k) + ": given twice in one map" +
                          (a.is_null() || b.is_null() ? std::string()
                                                      : " (lines " + std::to_string(a.line + 1) + " and " +
                                                            std::to_string(b.line + 1) + ")") +
                          "; give each key once");
      }
      checkTree(kv.second, childPath(path, k), file, ancestors);
    }
  } else {
    for (size_t i = 0; i < n.size(); ++i) checkTree(n[i], path + "[" + std::to_string(i) + "]", file, ancestors);
  }
  ancestors.pop_back();
}
}  // namespace

Config Config::loadFile(const std::string& filename) {
  // std::ifstream opens a directory and reads nothing from it: an empty configuration, silently.
  // (A pipe, as /dev/fd/N from `--config <(...)`, is read as a file.)
  if (std::error_code ec; std::filesystem::is_directory(filename, ec))
    throw ConfigError(filename + ": is a directory, not a YAML file");
  std::ifstream in(filename);
  if (!in) throw ConfigError(filename + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return fromString(ss.str(), filename);
}

Config Config::fromString(const std::string& yaml, const std::string& name) {
  YAML::Node n;
  try {
    // (Every document: a second one after "---" would be ignored without a word by Load.)
    std::vector<YAML::Node> docs = YAML::LoadAll(yaml);
    if (docs.size() > 1)
      throw ConfigError(name + ": " + std::to_string(docs.size()) +
                        " YAML documents (separated by ---): give one; the later ones would be ignored");
    if (!docs.empty()) n = docs.front();
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                      ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (!n || n.IsNull()) n = YAML::Node(YAML::NodeType::Map);
  if (!n.IsMap()) throw ConfigError(name + ": the top level must be a map of keys");
  std::vector<YAML::Node> ancestors;
  checkTree(n, "", name, ancestors);
  return Config(n, "", name);
}

bool Config::has(const std::string& key) const {
  if (!node_ || !node_.IsMap()) return false;
  return static_cast<bool>(node_[key]);
}

bool Config::hasNull(const std::string& key) const { return has(key) && node_[key].IsNull(); }

YAML::Node Config::value(const std::string& key) const {
  const YAML::Node n = node_[key];
  if (n.IsNull()) fail(key, "has no value");
  return n;
}

std::string Config::keyPath(const std::string& key) const {
  if (key.empty()) return path_.empty() ? std::string("<root>") : path_;
  if (path_.empty()) return key;
  if (!key.empty() && key[0] == '[') return path_ + key;
  return path_ + "." + key;
}

void Config::fail(const std::string& key, const std::string& message) const {
  std::string prefix = file_.empty() ? std::string() : file_ + ": ";
  throw ConfigError(prefix + keyPath(key) + ": " + message);
}

void Config::failHere(const std::string& message) const { fail("", message); }

Config Config::section(const std::string& key) const {
  // A section whose keys are all commented out (`pilot:` alone) says nothing: an empty map.
  if (!has(key) || hasNull(key)) return Config(YAML::Node(YAML::NodeType::Map), keyPath(key), file_);
  const YAML::Node n = node_[key];
  if (!n.IsMap()) fail(key, "must be a map of keys");
  return Config(n, keyPath(key), file_);
}

Config Config::requireSection(const std::string& key) const {
  if (!has(key)) fail(key, "is required");
  if (hasNull(key)) fail(key, "has no value (a map of keys is required)");
  return section(key);
}

std::vector<Config> Config::list(const std::string& key) const {
  std::vector<Config> out;
  if (!has(key) || hasNull(key)) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) fail(key, "must be a list");
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string p = keyPath(key) + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap()) throw ConfigError((file_.empty() ? "" : file_ + ": ") + p + ": must be a map of keys");
    out.emplace_back(n[i], p, file_);
  }
  return out;
}

std::vector<std::string> Config::keys() const {
  std::vector<std::string> out;
  if (!node_ || !node_.IsMap()) return out;
  for (const auto& kv : node_) out.push_back(keyName(kv.first, file_, path_));
  return out;
}

std::string showNumber(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

static std::string describe(const Range& r) {
  std::ostringstream os;
  const bool has_lo = std::isfinite(r.lo), has_hi = std::isfinite(r.hi);
  if (has_lo && has_hi) os << "must be in " << (r.lo_open ? "(" : "[") << r.lo << ", " << r.hi << "]";
  else if (has_lo) os << "must be " << (r.lo_open ? "> " : ">= ") << r.lo;
  else if (has_hi) os << "must be <= " << r.hi;
  else os << "must be a finite number";
  return os.str();
}

double Config::get(const std::string& key, double def, const Range& r) const {
  if (!has(key)) {
    if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(def), false);
    return def;
  }
  const double v = convert<double>(value(key), key);
  if (!std::isfinite(v) || v < r.lo || v > r.hi || (r.lo_open && v == r.lo)) fail(key, describe(r));
  if (DefaultsAudit::active()) DefaultsAudit::check(keyPath(key), auditText(def), auditText(v), auditEqual(def, v));
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(v), true, file_);
  return v;
}

int Config::get(const std::string& key, int def, const Range& r) const {
  if (!has(key)) {
    if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(def), false);
    return def;
  }
  const int v = convert<int>(value(key), key);
  if (v < r.lo || v > r.hi || (r.lo_open && v == r.lo)) fail(key, describe(r));
  if (DefaultsAudit::active()) DefaultsAudit::check(keyPath(key), auditText(def), auditText(v), def == v);
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(v), true, file_);
  return v;
}

double Config::requireNum(const std::string& key, const Range& r) const {
  if (!has(key)) fail(key, "is required");
  return get(key, 0.0, r);
}

std::optional<std::string> Config::getOptionalString(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  std::string v = convert<std::string>(value(key), key);
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), v, true, file_);
  return v;
}

static geom::Vec2 toVec2(const Config& c, const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 2) c.fail(key, "must be a pair [x, y]");
  try {
    const geom::Vec2 v(n[0].as<double>(), n[1].as<double>());
    if (!std::isfinite(v.x()) || !std::isfinite(v.y())) c.fail(key, "must be finite numbers");
    return v;
  } catch (const YAML::Exception&) {
    c.fail(key, "must be a pair of numbers [x, y]");
  }
}

namespace {
std::string vec2Text(const geom::Vec2& v) { return "[" + showNumber(v.x()) + ", " + showNumber(v.y()) + "]"; }
std::string doublesText(const std::vector<double>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + showNumber(v[i]);
  return s + "]";
}
}  // namespace

geom::Vec2 Config::requireVec2(const std::string& key) const {
  if (!has(key)) fail(key, "is required");
  const geom::Vec2 v = toVec2(*this, value(key), key);
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), vec2Text(v), true, file_);
  return v;
}

geom::Vec2 Config::getVec2(const std::string& key, const geom::Vec2& def) const {
  if (!has(key)) {
    if (ConfigReport::active()) ConfigReport::note(keyPath(key), vec2Text(def), false);
    return def;
  }
  const geom::Vec2 v = toVec2(*this, value(key), key);
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), vec2Text(v), true, file_);
  if (DefaultsAudit::active())
    DefaultsAudit::check(keyPath(key), auditText(def.x()) + "," + auditText(def.y()),
                         auditText(v.x()) + "," + auditText(v.y()), auditEqual(def.x(), v.x()) && auditEqual(def.y(), v.y()));
  return v;
}

std::vector<geom::Vec2> Config::requirePoints(const std::string& key, size_t min_points) const {
  if (!has(key)) fail(key, "is required");
  const YAML::Node n = value(key);
  if (!n.IsSequence()) fail(key, "must be a list of [x, y] points");
  std::vector<geom::Vec2> pts;
  for (size_t i = 0; i < n.size(); ++i)
    pts.push_back(toVec2(*this, n[i], key + "[" + std::to_string(i) + "]"));
  if (pts.size() < min_points) fail(key, "needs at least " + std::to_string(min_points) + " points");
  return pts;
}

std::vector<double> Config::getDoubles(const std::string& key, const std::vector<double>& def) const {
  if (!has(key)) {
    if (ConfigReport::active()) ConfigReport::note(keyPath(key), doublesText(def), false);
    return def;
  }
  const YAML::Node n = value(key);
  if (!n.IsSequence()) fail(key, "must be a list of numbers");
  std::vector<double> out;
  for (size_t i = 0; i < n.size(); ++i) {
    try {
      out.push_back(n[i].as<double>());
    } catch (const YAML::Exception&) {
      fail(key + "[" + std::to_string(i) + "]", "must be a number");
    }
  }
  if (DefaultsAudit::active()) {
    bool eq = out.size() == def.size();
    std::string a, b;
    for (size_t i = 0; i < out.size(); ++i) b += (i ? "," : "") + auditText(out[i]);
    for (size_t i = 0; i < def.size(); ++i) {
      a += (i ? "," : "") + auditText(def[i]);
      if (eq) eq = auditEqual(def[i], out[i]);
    }
    DefaultsAudit::check(keyPath(key), a, b, eq);
  }
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), doublesText(out), true, file_);
  return out;
}

void Config::allowOnly(const std::vector<std::string>& allowed) const {
  for (const auto& k : keys()) {
    bool ok = false;
    for (const auto& a : allowed) ok = ok || (a == k);
    if (!ok) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(k, "unknown key (allowed: " + list + ")");
    }
  }
}

namespace {
thread_local DefaultsAudit* g_audit = nullptr;
}  // namespace
DefaultsAudit::DefaultsAudit() : previous_(g_audit) { g_audit = this; }
DefaultsAudit::~DefaultsAudit() { g_audit = previous_; }
bool DefaultsAudit::active() { return g_audit != nullptr; }
void DefaultsAudit::check(const std::string& key, const std::string& code_default, const std::string& value, bool equal) {
  if (g_audit && !equal) g_audit->mismatches_.push_back({key, code_default, value});
}

namespace {
thread_local ConfigReport* g_report = nullptr;

// The node at `key` ("a.b[2].c") in `root`, or an undefined node.
YAML::Node nodeAtPath(YAML::Node root, const std::string& key) {
  YAML::Node n = root;
  size_t i = 0;
  while (i < key.size()) {
    if (key[i] == '.') {
      ++i;
      continue;
    }
    if (key[i] == '[') {
      const size_t close = key.find(']', i);
      if (close == std::string::npos || !n.IsSequence()) return YAML::Node(YAML::NodeType::Undefined);
      size_t idx = 0;
      try {
        idx = std::stoul(key.substr(i + 1, close - i - 1));
      } catch (const std::exception&) {
        return YAML::Node(YAML::NodeType::Undefined);
      }
      if (idx >= n.size()) return YAML::Node(YAML::NodeType::Undefined);
      n.reset(static_cast<const YAML::Node&>(n)[idx]);
      i = close + 1;
      continue;
    }
    size_t end = key.find_first_of(".[", i);
    if (end == std::string::npos) end = key.size();
    const std::string k = key.substr(i, end - i);
    if (!n.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node child = static_cast<const YAML::Node&>(n)[k];
    if (!child) return YAML::Node(YAML::NodeType::Undefined);
    n.reset(child);
    i = end;
  }
  return n;
}
}  // namespace

ConfigReport::ConfigReport() : previous_(g_report) { g_report = this; }
ConfigReport::~ConfigReport() { g_report = previous_; }
bool ConfigReport::active() { return g_report != nullptr; }
void ConfigReport::note(const std::string& key, const std::string& value, bool from_file, const std::string& origin) {
  if (!g_report) return;
  std::vector<std::string>& seen = g_report->seen_;
  const auto it = std::lower_bound(seen.begin(), seen.end(), key);
  if (it != seen.end() && *it == key) return;
  seen.insert(it, key);
  g_report->entries_.push_back({key, value, from_file, origin});
}

namespace {
// Each file's own YAML (an undefined node for one that cannot be read again).
std::vector<YAML::Node> loadEach(const std::vector<std::string>& files) {
  std::vector<YAML::Node> roots;
  for (const std::string& f : files) {
    try {
      roots.push_back(YAML::LoadFile(f));
    } catch (const std::exception&) {
      roots.emplace_back(YAML::NodeType::Undefined);  // (loadFiles has read it already)
    }
  }
  return roots;
}
std::string sourceOf(const std::vector<std::string>& files, const std::vector<YAML::Node>& roots, const std::string& key) {
  for (size_t i = files.size(); i-- > 0;) {
    if (!roots[i].IsDefined()) continue;
    const YAML::Node n = nodeAtPath(roots[i], key);
    if (n.IsDefined() && !n.IsNull()) return files[i];
  }
  return {};
}
}  // namespace

std::string configSourceFile(const std::vector<std::string>& files, const std::string& key) {
  return sourceOf(files, loadEach(files), key);
}

std::string formatConfigReport(const std::vector<ConfigEntry>& entries, const std::vector<std::string>& files) {
  const std::vector<YAML::Node> roots = loadEach(files);
  std::map<std::string, std::vector<YAML::Node>> origin_roots;  // (another file's YAML, loaded once)
  std::string out;
  for (const ConfigEntry& e : entries) {
    std::string source;
    if (!e.from_file) {
      source = "default";
    } else {
      // A reading map of one file that is no --config file (a scenario) is the last layer.
      const bool other = !e.origin.empty() && e.origin.find(" + ") == std::string::npos &&
                         std::find(files.begin(), files.end(), e.origin) == files.end();
      if (other) {
        auto it = origin_roots.find(e.origin);
        if (it == origin_roots.end()) it = origin_roots.emplace(e.origin, loadEach({e.origin})).first;
        source = sourceOf({e.origin}, it->second, e.key);
      }
      if (source.empty()) source = sourceOf(files, roots, e.key);
      if (source.empty()) source = other ? e.origin : "configuration";
    }
    out += e.key + ": " + e.value + "  # " + source + "\n";
  }
  return out;
}

std::string configReportForProgram(const std::string& program, const std::vector<ConfigEntry>& entries,
                                   const std::vector<std::string>& files) {
  std::string names;
  for (const std::string& f : files) names += " " + f;
  // YAML comments and `key.path: value  # source` lines: readable, and greppable by key.
  return "# " + program + ": the configuration in effect (" + versionString() + "); --config" +
         (names.empty() ? " (the built-in defaults)" : names) + "\n" + formatConfigReport(entries, files);
}

namespace {
// `file` and `path` name the later layer's map, for an error.
YAML::Node deepMerge(const YAML::Node& base, const YAML::Node& over, const std::string& file, const std::string& path) {
  if (!base || !base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string k = keyName(kv.first, file, path);
    const YAML::Node old = out[k];
    // A section whose keys are all commented out in the later file (`pilot:` alone, a null)
    // says nothing: the earlier file's map stays. A null over anything else stays a null, which
    // a reader reports as a key with no value.
    if (old && old.IsMap() && kv.second.IsNull()) continue;
    out[k] = old && old.IsMap() && kv.second.IsMap() ? deepMerge(old, kv.second, file, childPath(path, k))
                                                    : YAML::Clone(kv.second);
  }
  return out;
}
}  // namespace

namespace {
// The files layered in order; with `top_level`, each file's top-level keys checked on its own,
// so that a message names the file that holds the key.
Config layerFiles(const std::vector<std::string>& filenames, const std::vector<std::string>* top_level) {
  if (filenames.empty()) return Config{};
  YAML::Node merged(YAML::NodeType::Map);
  std::string names;
  for (const std::string& f : filenames) {
    const Config c = Config::loadFile(f);
    if (top_level) c.allowOnly(*top_level);
    if (filenames.size() == 1) return c;
    try {
      merged = deepMerge(merged, c.node(), f, "");
    } catch (const YAML::Exception& e) {
      throw ConfigError(f + ": cannot merge it with the files before it: " + e.what());
    }
    names += (names.empty() ? "" : " + ") + f;
  }
  return Config(merged, "", names);
}
}  // namespace

Config Config::loadFiles(const std::vector<std::string>& filenames) { return layerFiles(filenames, nullptr); }

Config Config::loadConfiguration(const std::vector<std::string>& filenames) {
  return layerFiles(filenames, &kConfigSections);
}

Config Config::mergedWith(const Config& over) const {
  YAML::Node merged(YAML::NodeType::Map);
  if (node_.IsMap())
    for (const auto& kv : node_) merged[keyName(kv.first, file_, path_)] = kv.second;
  if (over.node_.IsMap())
    for (const auto& kv : over.node_) {
      const std::string k = keyName(kv.first, over.file_, over.path_);
      // As layered files: a map whose keys are all commented out in the override says nothing.
      if (const YAML::Node& m = merged; kv.second.IsNull() && m[k] && m[k].IsMap()) continue;
      merged[k] = kv.second;
    }
  // Errors in the merged map name the override's path when it has one (that is where users edit).
  return Config(merged, over.path_.empty() ? path_ : over.path_, over.file_.empty() ? file_ : over.file_);
}

}  // namespace lasonic
