// lasonic-scenegen: random indoor scenes (README "Random scenes") for judging the method on
// scenes no one has tuned it on. Writes OUT/random_<index>.yaml for each index and OUT/scenes.list
// in the format of deploy/scenarios/suite.list (a Pioneer-type scene carries the pipeline's
// Pioneer overlay), which `./run score --random N` scores like the suite.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>

#include "core/cli.hpp"
#include "core/config.hpp"
#include "sim/scenario.hpp"
#include "sim/scene_generator.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  CLI::App app{"lasonic-scenegen: random indoor scenes with glass, mesh, black boxes, pipes and people"};
  uint64_t first = 1;
  int count = 10;
  std::string out_dir, pioneer_overlay = "deploy/config/pioneer.yaml";
  app.add_option("--first", first, "index of the first scene, an integer >= 0 (every draw derives from the index)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--count", count, "number of scenes")->check(CLI::Range(1, 10000));
  app.add_option("--out", out_dir, "directory to write the scenes and scenes.list into")->required();
  app.add_option("--pioneer-overlay", pioneer_overlay,
                 "config overlay listed in scenes.list for the Pioneer-type scenes");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
  // Indices are 64-bit: the last one must not wrap round to 0.
  if (first > std::numeric_limits<uint64_t>::max() - static_cast<uint64_t>(count - 1)) {
    std::cerr << "lasonic-scenegen: --first " << first << " --count " << count
              << ": the last index would pass 2^64 - 1\n";
    return 2;
  }
  // scenes.list names the overlay as given (from where ./run reads the list: the repository's
  // root); a name that is no file would fail every Pioneer-type scene's run later.
  if (!std::filesystem::is_regular_file(pioneer_overlay)) {
    std::cerr << "lasonic-scenegen: --pioneer-overlay " << pioneer_overlay
              << ": no such file (give its path from the repository's root, where scenes.list is read)\n";
    return 2;
  }

  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    std::cerr << "lasonic-scenegen: --out " << out_dir << ": " << ec.message() << "\n";
    return 2;
  }
  const std::filesystem::path dir(out_dir);
  std::ofstream list(dir / "scenes.list");
  if (!list) {
    std::cerr << "lasonic-scenegen: cannot write " << (dir / "scenes.list").string() << "\n";
    return 2;
  }
  list << "# lasonic-scenegen --first " << first << " --count " << count
       << ": SCENARIO [CONFIG-OVERLAY...] (README \"Random scenes\")\n";
  int written = 0, skipped = 0;
  for (uint64_t k = 0; k < static_cast<uint64_t>(count); ++k) {
    const uint64_t index = first + k;
    const std::optional<sim::GeneratedScene> scene = sim::generateScene(index);
    if (!scene) {
      std::cerr << "lasonic-scenegen: scene " << index << ": no robot path with clearance fits; skipped\n";
      ++skipped;
      continue;
    }
    // Every scene written must load as a scenario; a failure here is a generator bug.
    try {
      sim::parseScenario(Config::fromString(scene->yaml, scene->name));
    } catch (const ConfigError& e) {
      std::cerr << "lasonic-scenegen: scene " << index << " does not load: " << e.what() << "\n";
      return 1;
    }
    const std::filesystem::path file = dir / (scene->name + ".yaml");
    std::ofstream out(file);
    out << scene->yaml;
    if (!out) {
      std::cerr << "lasonic-scenegen: cannot write " << file.string() << "\n";
      return 2;
    }
    list << file.string() << (scene->pioneer ? " " + pioneer_overlay : "") << "\n";
    ++written;
  }
  std::cout << "lasonic-scenegen: " << written << " scenes in " << out_dir << " (" << skipped
            << " indices without a path skipped)\n";
  return written > 0 ? 0 : 1;
}
