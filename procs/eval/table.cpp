// lasonic-eval-table --keys K1,K2,... FILE.json...
//
// One table over many runs of lasonic-eval (`./run score --all`): the JSON files are grouped by
// scene, the file name being <scene>-s<seed>.json, and every key (a dotted path into the JSON,
// e.g. sector_map.missed_rate) is shown per scene as "mean (worst)" over the seeds, worst being
// the largest value for a rate (less is better) and the smallest for a key that names a recall,
// precision, coverage or rejection (more is better; its column says "worst: lowest"). A key
// missing from a file is left out of that scene's mean and counted in the last column. Markdown,
// so the README can show the output as it is.
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
  std::string keys_arg;
  std::vector<std::string> files;
  app.add_option("--keys", keys_arg, "comma-separated metric keys (dotted paths)")->required();
  app.add_option("files", files, "lasonic-eval JSON files named <scene>-s<seed>.json")->required();
  CLI11_PARSE(app, argc, argv);
  const std::vector<std::string> keys = split(keys_arg, ',');
  const std::regex name_re(R"((.+)-s(\d+)\.json)");

  struct Scene {
    std::vector<std::vector<double>> values;  // per key
    std::vector<std::string> seeds;
    int missing = 0;
  };
  std::vector<std::string> order;
  std::map<std::string, Scene> scenes;
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
    if (!scenes.count(scene)) order.push_back(scene);
    Scene& s = scenes[scene];
    s.values.resize(keys.size());
    s.seeds.push_back(m[2]);
    for (size_t k = 0; k < keys.size(); ++k) {
      if (const auto v = lookup(root, keys[k])) s.values[k].push_back(*v);
      else ++s.missing;
    }
  }
  std::cout << "| scene | seeds |";
  for (const auto& k : keys) std::cout << " " << k << (higherIsBetter(k) ? " (worst: lowest)" : "") << " |";
  std::cout << " missing |\n|---|---|";
  for (size_t k = 0; k < keys.size(); ++k) std::cout << "---|";
  std::cout << "---|\n";
  for (const std::string& name : order) {
    const Scene& s = scenes[name];
    std::cout << "| " << name << " | " << s.seeds.size() << " |";
    for (size_t k = 0; k < keys.size(); ++k) {
      const std::vector<double>& v = s.values[k];
      if (v.empty()) {
        std::cout << " - |";
        continue;
      }
      double sum = 0;
      for (double x : v) sum += x;
      char buf[64];
      const double worst = higherIsBetter(keys[k]) ? *std::min_element(v.begin(), v.end())
                                                   : *std::max_element(v.begin(), v.end());
      std::snprintf(buf, sizeof(buf), " %.3f (%.3f) |", sum / static_cast<double>(v.size()), worst);
      std::cout << buf;
    }
    std::cout << " " << s.missing << " |\n";
  }
  return status;
}
