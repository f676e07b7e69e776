#include "eval/metrics.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace lasonic::eval {

void Metrics::set(const std::string& key, Value v) {
  for (auto& e : entries_)
    if (e.first == key) {
      e.second = std::move(v);
      return;
    }
  entries_.emplace_back(key, std::move(v));
}

const Metrics::Value* Metrics::find(const std::string& key) const {
  for (const auto& e : entries_)
    if (e.first == key) return &e.second;
  return nullptr;
}

bool Metrics::has(const std::string& key) const { return find(key) != nullptr; }

double Metrics::number(const std::string& key) const {
  const Value* v = find(key);
  if (!v) throw std::out_of_range("no metric " + key);
  if (auto d = std::get_if<double>(v)) return *d;
  if (auto i = std::get_if<int64_t>(v)) return static_cast<double>(*i);
  throw std::invalid_argument("metric " + key + " is not a number");
}

namespace {
std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
      continue;
    }
    o += c;
  }
  return o + "\"";
}

std::string format(const Metrics::Value& v, bool json) {
  if (auto d = std::get_if<double>(&v)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", std::isfinite(*d) ? *d : 0.0);
    return buf;
  }
  if (auto i = std::get_if<int64_t>(&v)) return std::to_string(*i);
  const auto& s = std::get<std::string>(v);
  return json ? jsonString(s) : s;
}

// Ordered tree built from dotted keys.
struct Tree {
  std::vector<std::pair<std::string, std::unique_ptr<Tree>>> children;
  const Metrics::Value* value = nullptr;
  Tree& child(const std::string& name) {
    for (auto& c : children)
      if (c.first == name) return *c.second;
    children.emplace_back(name, std::make_unique<Tree>());
    return *children.back().second;
  }
};

void writeJson(const Tree& t, std::ostringstream& os, int indent) {
  if (t.value) {
    os << format(*t.value, true);
    return;
  }
  os << "{";
  bool first = true;
  for (const auto& [name, c] : t.children) {
    os << (first ? "\n" : ",\n") << std::string(static_cast<size_t>(indent + 2), ' ') << jsonString(name) << ": ";
    writeJson(*c, os, indent + 2);
    first = false;
  }
  os << "\n" << std::string(static_cast<size_t>(indent), ' ') << "}";
}
}  // namespace

std::string Metrics::toJson() const {
  Tree root;
  for (const auto& [key, v] : entries_) {
    Tree* t = &root;
    std::stringstream ks(key);
    std::string part;
    while (std::getline(ks, part, '.')) t = &t->child(part);
    t->value = &v;
  }
  std::ostringstream os;
  writeJson(root, os, 0);
  os << "\n";
  return os.str();
}

std::string Metrics::toTable() const {
  size_t w = 0;
  for (const auto& e : entries_) w = std::max(w, e.first.size());
  std::ostringstream os;
  std::string section;
  for (const auto& [key, v] : entries_) {
    const std::string sec = key.substr(0, key.find('.'));
    if (sec != section && !section.empty()) os << "\n";
    section = sec;
    os << "  " << key << std::string(w - key.size() + 2, ' ') << format(v, false) << "\n";
  }
  return os.str();
}

std::string Metrics::brief() const {
  std::ostringstream os;
  const auto num = [this](const char* key) -> const double* {
    const Value* v = find(key);
    return v ? std::get_if<double>(v) : nullptr;
  };
  const auto fmt = [](double d, int digits) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.*f", digits, d);
    return std::string(buf);
  };
  if (const double *om = num("sector_map.observable_missed_rate"), *fa = num("sector_map.false_alarm_rate"); om && fa) {
    os << "  sector map    observable missed " << fmt(*om, 4) << ", false alarms " << fmt(*fa, 4);
    if (const double* share = num("sector_map.false_alarm_share_of_reports")) os << " (" << fmt(*share, 3) << " of reports)";
    if (const double* lo = num("baselines.laser_only.sector_map.observable_missed_rate"))
      os << "; the laser alone misses " << fmt(*lo, 4);
    os << "\n";
  }
  if (const double* ir = num("complement.invisible_recall")) {
    os << "  complement    invisible recall " << fmt(*ir, 3);
    if (const double* sr = num("complement.specular_rejection")) os << ", specular rejection " << fmt(*sr, 3);
    os << "\n";
  }
  if (const double *tr = num("agm_tactical.invisible_recall"), *tp = num("agm_tactical.precision"); tr && tp) {
    os << "  tactical AGM  invisible recall " << fmt(*tr, 3) << " at precision " << fmt(*tp, 3);
    if (const double* ms = num("agm_tactical.mover_share")) os << ", mover share " << fmt(*ms, 3);
    os << "\n";
  }
  if (const double *lc = num("lines.invisible_coverage"), *lp = num("lines.precision"); lc && lp) {
    os << "  lines         invisible coverage " << fmt(*lc, 3) << " at precision " << fmt(*lp, 3);
    if (const double* n = num("lines.count")) os << " (" << fmt(*n, 1) << " lines per map)";
    os << "\n";
  }
  return os.str();
}

}  // namespace lasonic::eval
