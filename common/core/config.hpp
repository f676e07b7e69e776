#pragma once
// YAML configuration with errors that name the key path (e.g. "obstacles[3].radius: must be > 0").
//
// A Config is a view on one YAML map plus its path from the file's root. Typical use:
//   Config c = Config::loadFile(path);            // throws ConfigError
//   Config laser = c.section("laser");            // missing section -> empty map
//   cfg.rate_hz = laser.get("rate_hz", cfg.rate_hz, Range::positive());
//   laser.allowOnly({"rate_hz", ...});            // unknown keys are errors
// Processes catch ConfigError at start-up, log it and exit with code 2.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <type_traits>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry.hpp"

namespace lasonic {

// The top-level sections of lasonic's configuration (deploy/config/lasonic.yaml), read by some
// process or tool each.
inline const std::vector<std::string> kConfigSections = {"sim_world", "odometry", "laser",    "sonar",
                                                         "complement", "pilot",  "navigator", "baselines"};

class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(const std::string& what) : std::runtime_error(what) {}
};

// Inclusive numeric bounds with a readable description for the error message.
// A number as a configuration message shows it: shortest form, 6 significant digits (8, 0.35, 1e+300).
std::string showNumber(double v);

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true}; }
  static Range nonNegative() { return {0.0, std::numeric_limits<double>::infinity(), false}; }
  static Range between(double lo, double hi) { return {lo, hi, false}; }
  static Range probability() { return {0.0, 1.0, false}; }
  // A time span [s] that is turned into int64 microseconds or added to message times: beyond
  // 10^6 s (11.6 days) no span means anything to a robot's world model, and µs stay far from
  // overflowing.
  static Range duration() { return {0.0, 1e6, false}; }
  static Range positiveDuration() { return {0.0, 1e6, true}; }
};

// DefaultsAudit: while one is alive (on this thread), every Config::get* of a key that is present
// compares the value with the default the code passed and records a mismatch. With the shipped
// configuration this shows every key whose code default differs from it (tests/unit/test_config:
// the code's defaults are the shipped configuration, so a process run without --config behaves as
// shipped).
struct DefaultMismatch {
  std::string key, code_default, value;
};
class DefaultsAudit {
 public:
  DefaultsAudit();
  ~DefaultsAudit();
  DefaultsAudit(const DefaultsAudit&) = delete;
  DefaultsAudit& operator=(const DefaultsAudit&) = delete;
  const std::vector<DefaultMismatch>& mismatches() const { return mismatches_; }
  // Called by Config when the audit is active.
  static void check(const std::string& key, const std::string& code_default, const std::string& value, bool equal);
  static bool active();

 private:
  std::vector<DefaultMismatch> mismatches_;
  DefaultsAudit* previous_ = nullptr;
};

// ConfigReport: while one is alive (on this thread), every Config::get* and require* records
// the key path it read and the value in effect: the files' (after layering) or, where no file
// sets the key, the code's default. It is what `--print-config` prints: every parameter a
// process runs with, and where each came from, without reading the code.
struct ConfigEntry {
  std::string key;    // "pilot.agm.size", "obstacles[2].radius"
  std::string value;  // as YAML would write it: 0.35, true, arc_votes, [0.1, 0.2]
  bool from_file = false;
  std::string origin;  // the file the reading map came from where it is one (a scenario), else ""
};
class ConfigReport {
 public:
  ConfigReport();
  ~ConfigReport();
  ConfigReport(const ConfigReport&) = delete;
  ConfigReport& operator=(const ConfigReport&) = delete;
  // In the order first read; a key read again (by two readers of one section) is kept once.
  const std::vector<ConfigEntry>& entries() const { return entries_; }
  // Called by Config when a report is active.
  static void note(const std::string& key, const std::string& value, bool from_file, const std::string& origin = {});
  static bool active();

 private:
  std::vector<ConfigEntry> entries_;
  std::vector<std::string> seen_;  // (sorted keys of entries_)
  ConfigReport* previous_ = nullptr;
};
// The last of `files` (in layering order) whose own YAML holds `key` (a path as Config::keyPath
// gives it); empty when none does or a file cannot be read.
std::string configSourceFile(const std::vector<std::string>& files, const std::string& key);
// The report as lines of `key: value  # file`, `# default` where no file sets it. A key read from
// a map of another file (a scenario, whose sensor sections go over the configuration's) is looked
// up there too, as the last layer.
std::string formatConfigReport(const std::vector<ConfigEntry>& entries, const std::vector<std::string>& files);
// The same under a comment line naming the program, the build and the files: what
// `--print-config` prints.
std::string configReportForProgram(const std::string& program, const std::vector<ConfigEntry>& entries,
                                   const std::vector<std::string>& files);

template <typename T> std::string reportText(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_same_v<T, std::string>) return v;
  else if constexpr (std::is_floating_point_v<T>) return showNumber(static_cast<double>(v));
  else if constexpr (std::is_integral_v<T>) return std::to_string(v);
  else return "?";
}

template <typename T> std::string auditText(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_same_v<T, std::string>) return v;
  else if constexpr (std::is_arithmetic_v<T>) return std::to_string(v);
  else return "?";
}
template <typename T> bool auditEqual(const T& a, const T& b) {
  if constexpr (std::is_floating_point_v<T>) return std::abs(a - b) <= 1e-9 * std::max({1.0, std::abs(a), std::abs(b)});
  else return a == b;
}

class Config {
 public:
  Config() : node_(YAML::NodeType::Map) {}
  Config(YAML::Node node, std::string path, std::string file = {});

  // Reads and parses a YAML file whose root must be a map (not a directory; a pipe is fine).
  static Config loadFile(const std::string& filename);
  // Several files layered in order: maps are merged key by key at every depth, a later file's
  // value (scalar or list) replaces an earlier one's; a section whose keys are all commented out
  // in a later file (`pilot:` alone) keeps the earlier one's. No files: an empty map. So a robot's file
  // can override a few keys of the shipped configuration:
  //   --config deploy/config/lasonic.yaml --config deploy/config/pioneer.yaml
  static Config loadFiles(const std::vector<std::string>& filenames);
  // lasonic's configuration from the --config files: loadFiles, and then a top-level key that is
  // none of kConfigSections is an error. Each process reads only its own sections, so a misspelt
  // one (`pilto:`) would otherwise change nothing, silently, in every process.
  static Config loadConfiguration(const std::vector<std::string>& filenames);
  static Config fromString(const std::string& yaml, const std::string& name = "<string>");

  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }
  // The key is in this map, with a value or without one (`cell_size:` alone, a null): reading a
  // key without a value is an error ("has no value"), except as a section or a list, which it
  // leaves empty (a section whose keys are all commented out).
  bool has(const std::string& key) const;
  bool empty() const { return !node_ || node_.IsNull() || node_.size() == 0; }

  // "path.key" (or "key" at the root), for messages.
  std::string keyPath(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  [[noreturn]] void failHere(const std::string& message) const;

  // A sub-map; a missing or null key gives an empty map. A non-map value is an error.
  Config section(const std::string& key) const;
  // A required sub-map.
  Config requireSection(const std::string& key) const;
  // Elements of a sequence (missing or null -> empty). Each element gets the path "key[i]".
  std::vector<Config> list(const std::string& key) const;
  // Keys of this map, in file order. (A file's keys are checked when it is read: each a string,
  // none repeated in one map; a message names the file and the key path.)
  std::vector<std::string> keys() const;

  template <typename T> T get(const std::string& key, const T& def) const;
  template <typename T> T require(const std::string& key) const;
  double get(const std::string& key, double def, const Range& r) const;
  int get(const std::string& key, int def, const Range& r) const;
  double requireNum(const std::string& key, const Range& r) const;
  std::optional<std::string> getOptionalString(const std::string& key) const;
  // A string that names one of `choices` (name, value); missing -> def; any other string is an
  // error listing the names.
  template <typename T>
  T getChoice(const std::string& key, T def, std::initializer_list<std::pair<const char*, T>> choices) const;

  // [x, y]
  geom::Vec2 requireVec2(const std::string& key) const;
  geom::Vec2 getVec2(const std::string& key, const geom::Vec2& def) const;
  // [[x, y], ...]
  std::vector<geom::Vec2> requirePoints(const std::string& key, size_t min_points) const;
  std::vector<double> getDoubles(const std::string& key, const std::vector<double>& def) const;

  // Unknown keys are errors that list the allowed keys.
  void allowOnly(const std::vector<std::string>& allowed) const;

  // This map with every key of `over` replacing ours (one level deep, like the scenario's
  // `laser: {...}` overriding the driver config). Paths of overridden keys point to `over`.
  Config mergedWith(const Config& over) const;

 private:
  template <typename T> T convert(const YAML::Node& n, const std::string& key) const;
  bool hasNull(const std::string& key) const;
  // node_[key], which must not be a null ("has no value").
  YAML::Node value(const std::string& key) const;
  YAML::Node node_;
  std::string path_;
  std::string file_;
};

template <typename T>
T Config::convert(const YAML::Node& n, const std::string& key) const {
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    if constexpr (std::is_same_v<T, bool>) fail(key, "must be true or false");
    else if constexpr (std::is_integral_v<T>) fail(key, "must be an integer");
    else if constexpr (std::is_floating_point_v<T>) fail(key, "must be a number");
    else fail(key, "has the wrong type");
  }
}

template <typename T>
T Config::get(const std::string& key, const T& def) const {
  if (!has(key)) {
    if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(def), false);
    return def;
  }
  T v = convert<T>(value(key), key);
  if (DefaultsAudit::active()) DefaultsAudit::check(keyPath(key), auditText(def), auditText(v), auditEqual(def, v));
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(v), true, file_);
  return v;
}

template <typename T>
T Config::require(const std::string& key) const {
  if (!has(key)) fail(key, "is required");
  T v = convert<T>(value(key), key);
  if (ConfigReport::active()) ConfigReport::note(keyPath(key), reportText(v), true, file_);
  return v;
}

template <typename T>
T Config::getChoice(const std::string& key, T def, std::initializer_list<std::pair<const char*, T>> choices) const {
  const auto v = getOptionalString(key);
  if (!v) {
    if (ConfigReport::active())
      for (const auto& [name, value] : choices)
        if (value == def) {
          ConfigReport::note(keyPath(key), name, false);
          break;
        }
    return def;
  }
  std::string names;
  if (DefaultsAudit::active())
    for (const auto& [name, value] : choices)
      if (value == def) DefaultsAudit::check(keyPath(key), name, *v, *v == name);
  for (const auto& [name, value] : choices) {
    if (*v == name) return value;
    names += (names.empty() ? "" : ", ") + std::string(name);
  }
  fail(key, "must be one of " + names + " (got \"" + *v + "\")");
}

}  // namespace lasonic
