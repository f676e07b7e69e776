#pragma once
// An ordered set of named results with dotted keys ("sector_map.missed_rate"), printed as a
// readable table or as nested JSON.
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace lasonic::eval {

class Metrics {
 public:
  using Value = std::variant<double, int64_t, std::string>;
  void set(const std::string& key, Value v);
  bool has(const std::string& key) const;
  const Value* find(const std::string& key) const;
  double number(const std::string& key) const;  // throws if absent or not numeric
  const std::vector<std::pair<std::string, Value>>& entries() const { return entries_; }

  std::string toJson() const;
  std::string toTable() const;
  // The headline of a run in a few lines, after the long table (README "Evaluation" defines the
  // keys): the sector map's observable misses and false alarms against the laser alone, the
  // complement's recall and rejection, the tactical memory's and its lines' recall at their
  // precision. A part whose keys the run lacks is left out; nothing at all: "".
  std::string brief() const;

 private:
  std::vector<std::pair<std::string, Value>> entries_;
};

// A rate with its denominator: NaN-free JSON needs "no samples" to be visible, so rates with an
// empty denominator are omitted and the count is reported next to them.
struct Ratio {
  int64_t num = 0, den = 0;
  void add(bool hit) {
    ++den;
    if (hit) ++num;
  }
  bool valid() const { return den > 0; }
  double value() const { return den > 0 ? static_cast<double>(num) / static_cast<double>(den) : 0.0; }
};

}  // namespace lasonic::eval
