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
// the last column. Markdown, so the README can show the output as it is.
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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-eval-table: mean and worst of lasonic-eval's metrics per scene over seeds"};
  std::string keys_arg, methods_arg;
  std::vector<std::string> files;
  app.add_option("--keys", keys_arg, "comma-separated metric keys (dotted paths)")->required();
  app.add_option("--methods", methods_arg,
                 "comma-separated NAME=PREFIX: one row per scene and method, the keys read at PREFIX.KEY");
  app.add_option("files", files, "lasonic-eval JSON files named <scene>-s<seed>.json")->required();
  CLI11_PARSE(app, argc, argv);
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
  std::cout << "| scene |" << (by_method ? " method |" : "") << " seeds |";
  for (const auto& k : keys) std::cout << " " << k << (higherIsBetter(k) ? " (worst: lowest)" : "") << " |";
  std::cout << " missing |\n|---|" << (by_method ? "---|" : "") << "---|";
  for (size_t k = 0; k < keys.size(); ++k) std::cout << "---|";
  std::cout << "---|\n";
  for (const std::string& name : order) {
    const auto& seeds = runs[name];
    for (const Method& method : methods) {
      std::cout << "| " << name << " |" << (by_method ? " " + method.name + " |" : "") << " " << seeds.size() << " |";
      int missing = 0;
      for (const std::string& key : keys) {
        const std::string path = method.prefix.empty() ? key : method.prefix + "." + key;
        std::vector<double> v;
        for (const auto& [seed, roots] : seeds) {
          std::optional<double> x;
          for (size_t r = 0; r < roots.size() && !x; ++r) x = lookup(roots[r], path);
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
    }
  }
  return status;
}
