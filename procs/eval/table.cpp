// lasonic-eval-table --keys K1,K2,... [--methods NAME=PREFIX,...] FILE.json...
//
// One table over many runs of lasonic-eval (`./run score --all`): the JSON files are grouped by
// scene, the file name being <scene>-s<seed>.json, and every key (a dotted path into the JSON,
// e.g. sector_map.missed_rate) is shown per scene as "mean (worst)" over the seeds, worst being
// the largest value for a rate (less is better) and the smallest for a key that names a recall,
// precision, coverage or rejection (more is better; its column says "worst: lowest"). Files of
// the same name in different folders are one run scored by different programs (`./run peer`:
// lasonic-eval and lasonic-mrpt-peer): a key is looked up in each. With --methods, each scene
// gets one row per method and a key K is read at PREFIX.K (lasonic=sector_map,
// MRPT=mrpt.sector_map, ...). A key missing from a run is left out of that mean and counted in
// the last column. --summary adds a last row over every run of every scene (the mean over runs,
// the worst run). --targets KEY<=X,KEY<KEY2,... prints instead how many runs, and how many
// scenes on every seed, meet each target and all of them (a run missing a key meets no target
// on it). --glance LABEL prints the set as one row of the README's *At a glance* (Results): the
// runs, the means over the runs that have each key of observable missed, false alarms, false
// alarms per report, the runs meeting every target (the default targets, or --targets) and the
// scenes meeting them on every seed, tactical recall / precision and line coverage / precision.
// Markdown, so the README can show the output as it is.
#include <CLI/CLI.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "core/cli.hpp"

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  size_t a = 0;
  while (a <= s.size()) {
    const size_t b = std::min(s.find(sep, a), s.size());
    if (b > a) out.push_back(s.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

std::optional<double> lookup(const YAML::Node& root, const std::string& key) {
  YAML::Node n = YAML::Clone(root);
  for (const std::string& part : split(key, '.')) {
    if (!n.IsMap() || !n[part]) return std::nullopt;
    n = n[part];
  }
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

// More is better for these keys (the last part of the path names the quantity).
bool higherIsBetter(const std::string& key) {
  const std::string last = key.substr(key.rfind('.') + 1);
  for (const char* word : {"recall", "precision", "coverage", "rejection"})
    if (last.find(word) != std::string::npos) return true;
  return false;
}

// One target: KEY OP VALUE, VALUE a number or another key of the same run.
struct Target {
  std::string key, op, rhs_key, text;
  double rhs = 0;
  bool met(const YAML::Node& root) const {
    const std::optional<double> a = lookup(root, key);
    const std::optional<double> b = rhs_key.empty() ? std::optional<double>(rhs) : lookup(root, rhs_key);
    if (!a || !b) return false;
    if (op == "<=") return *a <= *b;
    if (op == "<") return *a < *b;
    if (op == ">=") return *a >= *b;
    return *a > *b;
  }
};

std::optional<Target> parseTarget(const std::string& t) {
  for (const char* op : {"<=", ">=", "<", ">"}) {
    const size_t at = t.find(op);
    if (at == std::string::npos || at == 0) continue;
    Target target{t.substr(0, at), op, {}, t, 0};
    const std::string rhs = t.substr(at + std::string(op).size());
    if (rhs.empty()) return std::nullopt;
    try {
      size_t used = 0;
      target.rhs = std::stod(rhs, &used);
      if (used != rhs.size()) target.rhs_key = rhs;
    } catch (const std::exception&) {
      target.rhs_key = rhs;
    }
    return target;
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-eval-table: mean and worst of lasonic-eval's metrics per scene over seeds"};
  std::string keys_arg, methods_arg, targets_arg, glance;
  bool summary = false;
  std::vector<std::string> files;
  auto* keys_opt = app.add_option("--keys", keys_arg, "comma-separated metric keys (dotted paths)");
  auto* targets_opt = app.add_option("--targets", targets_arg,
                                     "comma-separated KEY<=X (or <, >=, >; X a number or another key): runs and "
                                     "scenes meeting each, instead of the table");
  keys_opt->excludes(targets_opt);
  app.add_flag("--summary", summary, "a last row over every run of every scene");
  auto* methods_opt =
      app.add_option("--methods", methods_arg,
                     "comma-separated NAME=PREFIX: one row per scene and method, the keys read at PREFIX.KEY");
  app.add_option("--glance", glance,
                 "the set as one row of README Results' 'At a glance' named LABEL (its targets: --targets, or the "
                 "sector map's: observable missed <= 0.03, false alarms <= 0.05, per report <= 0.15, fewer misses "
                 "than the laser alone)")
      ->excludes(keys_opt)
      ->excludes(methods_opt);
  app.add_option("files", files, "lasonic-eval JSON files named <scene>-s<seed>.json")->required();
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
  if (keys_arg.empty() && targets_arg.empty() && glance.empty()) {
    std::cerr << "lasonic-eval-table: --keys, --targets or --glance is required\n";
    return 2;
  }
  if (!glance.empty() && targets_arg.empty())
    targets_arg = "sector_map.observable_missed_rate<=0.03,sector_map.false_alarm_rate<=0.05,"
                  "sector_map.false_alarm_share_of_reports<=0.15,"
                  "sector_map.samples.missed<baselines.laser_only.sector_map.samples.missed";
  std::vector<Target> targets;
  for (const std::string& t : split(targets_arg, ',')) {
    const std::optional<Target> target = parseTarget(t);
    if (!target) {
      std::cerr << "lasonic-eval-table: --targets: '" << t << "' is not KEY<=VALUE (or <, >=, >)\n";
      return 2;
    }
    targets.push_back(*target);
  }
  const std::vector<std::string> keys = split(keys_arg, ',');
  struct Method {
    std::string name, prefix;  // prefix empty: the keys as given
  };
  std::vector<Method> methods;
  for (const std::string& m : split(methods_arg, ',')) {
    const size_t eq = m.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == m.size()) {
      std::cerr << "lasonic-eval-table: --methods: '" << m << "' is not NAME=PREFIX\n";
      return 2;
    }
    methods.push_back({m.substr(0, eq), m.substr(eq + 1)});
  }
  const bool by_method = !methods.empty();
  if (!by_method) methods.push_back({"", ""});
  const std::regex name_re(R"((.+)-s(\d+)\.json)");

  // Per scene, per seed: the JSON roots of that run (one per program that scored it).
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, std::vector<YAML::Node>>> runs;
  int status = 0;
  for (const std::string& f : files) {
    std::smatch m;
    const std::string base = std::filesystem::path(f).filename().string();
    if (!std::regex_match(base, m, name_re)) {
      std::cerr << "lasonic-eval-table: " << f << ": name is not <scene>-s<seed>.json\n";
      return 2;
    }
    YAML::Node root;
    try {
      root = YAML::LoadFile(f);  // JSON is YAML
    } catch (const YAML::Exception& e) {
      std::cerr << "lasonic-eval-table: " << f << ": " << e.what() << "\n";
      status = 1;
      continue;
    }
    const std::string scene = m[1];
    if (!runs.count(scene)) order.push_back(scene);
    runs[scene][m[2]].push_back(root);
  }
  size_t nruns = 0;
  for (const auto& [scene, seeds] : runs) nruns += seeds.size();
  // The runs whose JSON meets `met`, and the scenes where every seed's run does.
  auto meeting = [&](auto&& met) {
    size_t good_runs = 0, good_scenes = 0;
    for (const auto& [scene, seeds] : runs) {
      size_t good = 0;
      for (const auto& [seed, roots] : seeds)
        if (!roots.empty() && met(roots.front())) ++good;
      good_runs += good;
      if (good == seeds.size()) ++good_scenes;
    }
    return std::make_pair(good_runs, good_scenes);
  };
  auto meetingAll = [&]() {
    return meeting([&](const YAML::Node& r) {
      return std::all_of(targets.begin(), targets.end(), [&](const Target& t) { return t.met(r); });
    });
  };
  if (!glance.empty()) {
    // The mean over the runs that have the key (a run with no located laser-invisible surface has
    // no tactical recall); "-" when none has it.
    auto mean = [&](const std::string& key, int decimals) {
      double sum = 0;
      size_t n = 0;
      for (const auto& [scene, seeds] : runs)
        for (const auto& [seed, roots] : seeds)
          if (const std::optional<double> x = roots.empty() ? std::nullopt : lookup(roots.front(), key)) {
            sum += *x;
            ++n;
          }
      if (n == 0) return std::string("-");
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%.*f", decimals, sum / static_cast<double>(n));
      return std::string(buf);
    };
    const auto [good_runs, good_scenes] = meetingAll();
    std::cout << "| set | runs | observable missed | false alarms | false alarms per report | runs meeting every target "
                 "(scenes on every seed) | tactical recall / precision | line coverage / precision |\n"
                 "|---|---|---|---|---|---|---|---|\n";
    std::cout << "| " << glance << " | " << nruns << " | " << mean("sector_map.observable_missed_rate", 4) << " | "
              << mean("sector_map.false_alarm_rate", 4) << " | " << mean("sector_map.false_alarm_share_of_reports", 3)
              << " | " << good_runs << " (" << good_scenes << " of " << runs.size() << ") | "
              << mean("agm_tactical.invisible_recall", 3) << " / " << mean("agm_tactical.precision", 3) << " | "
              << mean("lines.invisible_coverage", 3) << " / " << mean("lines.precision", 3) << " |\n";
    return status;
  }
  if (!targets.empty()) {
    if (by_method) {
      std::cerr << "lasonic-eval-table: --targets reads the keys as given; --methods does not apply\n";
      return 2;
    }
    std::cout << "| target | runs meeting it | scenes meeting it on every seed |\n|---|---|---|\n";
    auto row = [&](const std::string& label, const std::pair<size_t, size_t>& good) {
      std::cout << "| " << label << " | " << good.first << " of " << nruns << " | " << good.second << " of "
                << runs.size() << " |\n";
    };
    for (const Target& t : targets) row(t.text, meeting([&](const YAML::Node& r) { return t.met(r); }));
    row("all of them", meetingAll());
    return status;
  }
  std::cout << "| scene |" << (by_method ? " method |" : "") << " seeds |";
  for (const auto& k : keys) std::cout << " " << k << (higherIsBetter(k) ? " (worst: lowest)" : "") << " |";
  std::cout << " missing |\n|---|" << (by_method ? "---|" : "") << "---|";
  for (size_t k = 0; k < keys.size(); ++k) std::cout << "---|";
  std::cout << "---|\n";
  // One row: per key the mean (worst) over the runs given (seed -> that run's JSON roots).
  using Runs = std::vector<const std::vector<YAML::Node>*>;
  auto printRow = [&](const std::string& label, const std::string& count, const Method& method, const Runs& rows) {
    std::cout << "| " << label << " |" << (by_method ? " " + method.name + " |" : "") << " " << count << " |";
    int missing = 0;
    for (const std::string& key : keys) {
      const std::string path = method.prefix.empty() ? key : method.prefix + "." + key;
      std::vector<double> v;
      for (const std::vector<YAML::Node>* roots : rows) {
        std::optional<double> x;
        for (size_t r = 0; r < roots->size() && !x; ++r) x = lookup((*roots)[r], path);
        if (x) v.push_back(*x);
        else ++missing;
      }
      if (v.empty()) {
        std::cout << " - |";
        continue;
      }
      double sum = 0;
      for (double x : v) sum += x;
      const double worst = higherIsBetter(key) ? *std::min_element(v.begin(), v.end())
                                               : *std::max_element(v.begin(), v.end());
      char buf[64];
      std::snprintf(buf, sizeof(buf), " %.3f (%.3f) |", sum / static_cast<double>(v.size()), worst);
      std::cout << buf;
    }
    std::cout << " " << missing << " |\n";
  };
  Runs all;
  for (const std::string& name : order) {
    Runs scene;
    for (const auto& [seed, roots] : runs[name]) scene.push_back(&roots);
    all.insert(all.end(), scene.begin(), scene.end());
    for (const Method& method : methods) printRow(name, std::to_string(scene.size()), method, scene);
  }
  if (summary)
    for (const Method& method : methods)
      printRow("**all " + std::to_string(order.size()) + " scenes**", std::to_string(all.size()) + " runs", method,
               all);
  return status;
}
