// lasonic-scenegen: random indoor scenes (README "Random scenes") for judging the method on
// scenes no one has tuned it on. Writes OUT/random_<index>.yaml for each index and OUT/scenes.list
// in the format of deploy/scenarios/suite.list (a Pioneer-type scene carries the pipeline's
// Pioneer overlay), which `./run score --random N` scores like the suite.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>

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
  app.add_option("--first", first, "index of the first scene (every draw derives from the index)");
  app.add_option("--count", count, "number of scenes")->check(CLI::Range(1, 10000));
  app.add_option("--out", out_dir, "directory to write the scenes and scenes.list into")->required();
  app.add_option("--pioneer-overlay", pioneer_overlay,
                 "config overlay listed in scenes.list for the Pioneer-type scenes");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;

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
  for (uint64_t index = first; index < first + static_cast<uint64_t>(count); ++index) {
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
