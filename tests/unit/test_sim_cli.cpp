// The simulator's executables at start-up (README "Processes: start-up, exit codes, status"): a
// bad command line or scenario exits 2 with one line naming the option or the file and key --
// never an abort, never exit 0 with nothing done -- and no tool writes its output over an input.
// Every case here fails before any LCM traffic (no network needed).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "scratch_dir.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kBin = LASONIC_BIN_DIR;
const std::string kSource = LASONIC_SOURCE_DIR;

struct ToolRun {
  int status = -1;  // exit status, or 128 + signal
  std::string output;
};

// One scratch directory for the test program, removed when it exits.
fs::path tmpDir() {
  static const lasonic::fixture::ScratchDir d{"lasonic-test-sim-cli"};
  return d.path();
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// TOOL ARGS, from `cwd` (default: here), stdout and stderr together.
ToolRun run(const std::string& tool, const std::string& args, const std::string& cwd = "") {
  const fs::path out = tmpDir() / "run.txt";
  const std::string cmd = (cwd.empty() ? "" : "cd '" + cwd + "' && ") + "timeout 60 " + kBin + "/" + tool + " " + args +
                          " > " + out.string() + " 2>&1";
  const int raw = std::system(cmd.c_str());
  ToolRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.output = slurp(out);
  return r;
}

void expectBad(const std::string& tool, const std::string& args, const std::string& want) {
  const ToolRun r = run(tool, args);
  EXPECT_EQ(r.status, 2) << tool << " " << args << ":\n" << r.output;
  EXPECT_NE(r.output.find(want), std::string::npos) << tool << " " << args << ": wanted '" << want << "' in:\n" << r.output;
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = tmpDir() / name;
  std::ofstream(p) << text;
  return p.string();
}

const std::string kRoom = kSource + "/deploy/scenarios/fig4_room.yaml";

// A small room, with `extra` top-level keys.
std::string roomWith(const std::string& name, const std::string& extra) {
  return write(name, "name: t\n"
                     "obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[-3,-3],[3,-3],[3,3],[-3,3]]}\n"
                     "robot: {path: [[0,0],[1,0]]}\n" + extra);
}

}  // namespace

TEST(SimCli, DurationsAndRatesMustBeFiniteAndBounded) {
  const std::string out = "--out " + (tmpDir() / "x.lcmlog").string();
  for (const char* d : {"nan", "inf", "1e300", "0", "-1", "86401"})
    expectBad("lasonic-sim", "--scenario " + kRoom + " " + out + " --duration " + d, "--duration must be in (0, 86400]");
  for (const char* d : {"nan", "1e300"})
    expectBad("lasonic-sim-world", "--scenario " + kRoom + " --duration " + d, "--duration must be in (0, 86400]");
  for (const char* r : {"nan", "inf", "1e-300", "0", "1000"})
    expectBad("lasonic-sim-world", "--scenario " + kRoom + " --rate " + r, "--rate must be in [0.01, 100]");
  // A much slower robot over the same path would take more than a day.
  expectBad("lasonic-sim", "--scenario " + kRoom + " " + out + " --robot-speed 1e-9 --same-path", "more than a day");
  expectBad("lasonic-sim", "--scenario " + roomWith("long.yaml", "duration_s: 1e300\n") + " " + out,
            "long.yaml: duration_s: must be in (0, 86400]");
}

TEST(SimCli, SeedsAgreeWithTheScenario) {
  const std::string out = "--out " + (tmpDir() / "x.lcmlog").string();
  expectBad("lasonic-sim", "--scenario " + kRoom + " " + out + " --seed -1", "--seed");
  expectBad("lasonic-sim", "--scenario " + kRoom + " " + out + " --seed 18446744073709551615", "--seed");
  expectBad("lasonic-sim-world", "--scenario " + kRoom + " --seed -1", "--seed");
  expectBad("lasonic-sim-world", "--scenario " + kRoom + " --seed 9223372036854775808", "--seed must be an integer in [0, 2^63 - 1]");
  expectBad("lasonic-sonar-driver", "--scenario " + kRoom + " --seed 9223372036854775808", "--seed must be");
  expectBad("lasonic-laser-driver", "--scenario " + kRoom + " --seed -1", "--seed");
  expectBad("lasonic-sonar-driver", "--scenario " + kRoom + " --seed -1", "--seed");
}

// A path through an obstacle is driven through, with a warning that names the obstacle and
// where the robot's disc first overlaps it (README "Scenario format"); the log is written.
TEST(SimCli, ARobotPathThroughAnObstacleIsAWarning) {
  const std::string log = (tmpDir() / "through.lcmlog").string();
  const std::string scene = write("through.yaml",
                                  "name: t\nduration_s: 2\n"
                                  "obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[-3,-3],[3,-3],[3,3],[-3,3]]}\n"
                                  "  - {shape: box, material: metal, center: [1.5,0], size: [0.5,0.5]}\n"
                                  "robot: {path: [[0,0],[2,0]], speed: 1}\n");
  const ToolRun r = run("lasonic-sim", "--scenario " + scene + " --out " + log);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("lasonic-sim: warning: " + scene +
                          ": robot.path: the robot (radius 0.35) overlaps obstacles[1] at (0.9"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(log));
  // A mover's path through an obstacle too.
  const std::string walker = write("walker.yaml",
                                   "name: t\nduration_s: 2\n"
                                   "obstacles:\n  - {shape: polyline, material: wall, closed: true, points: [[-3,-3],[3,-3],[3,3],[-3,3]]}\n"
                                   "  - {shape: segment, material: glass, from: [-1,2], to: [1,2]}\n"
                                   "movers:\n  - {radius: 0.25, speed: 1, path: [[0,1],[0,2.5]]}\n"
                                   "robot: {path: [[0,-2],[1,-2]], speed: 1}\n");
  const ToolRun w = run("lasonic-sim", "--scenario " + walker + " --out " + log);
  EXPECT_EQ(w.status, 0) << w.output;
  EXPECT_NE(w.output.find("lasonic-sim: warning: " + walker +
                          ": movers[0].path: the mover (radius 0.25) overlaps obstacles[1] at (0.00, 1.7"),
            std::string::npos)
      << w.output;
  EXPECT_EQ(w.output.find("robot.path"), std::string::npos) << w.output;
  // Past where it stops (--duration), nothing is said.
  const ToolRun short_run = run("lasonic-sim", "--scenario " + scene + " --out " + log + " --duration 0.5");
  EXPECT_EQ(short_run.status, 0) << short_run.output;
  EXPECT_EQ(short_run.output.find("warning"), std::string::npos) << short_run.output;
}

// A mover or robot of radius 1e300 made SIM_STATE non-finite and lasonic-sim abort (SIGABRT).
TEST(SimCli, HugeBodiesAreRefusedNotAborted) {
  const std::string out = "--out " + (tmpDir() / "x.lcmlog").string();
  const std::string mover = roomWith("mover.yaml", "movers:\n  - {radius: 1e300, path: [[1, 1], [2, 1]]}\n");
  expectBad("lasonic-sim", "--scenario " + mover + " " + out, "mover.yaml: movers[0].radius: must be in (0, 5]");
  for (const char* tool : {"lasonic-sim-world", "lasonic-laser-driver", "lasonic-sonar-driver"})
    expectBad(tool, "--scenario " + mover, "mover.yaml: movers[0].radius: must be in (0, 5]");
}

// Every tool refuses a scenario whose override section lasonic-sim refuses -- also the one that
// does not read that section.
TEST(SimCli, OverrideSectionsAreCheckedByEveryTool) {
  const std::string laser = roomWith("laser.yaml", "laser: {readings: 0}\n");
  const std::string sonar = roomWith("sonar.yaml", "sonar: {zzz_typo: 1}\n");
  const std::string odo = roomWith("odo.yaml", "odometry: {trans_noise: 1e300}\n");
  for (const char* tool : {"lasonic-sim-world", "lasonic-laser-driver", "lasonic-sonar-driver"}) {
    expectBad(tool, "--scenario " + laser, "laser.yaml: laser.readings: must be in [2, 100000]");
    expectBad(tool, "--scenario " + sonar, "sonar.yaml: sonar.zzz_typo: unknown key");
    expectBad(tool, "--scenario " + odo, "odo.yaml: odometry.trans_noise: must be in [0, 1]");
  }
  // A section valid on its own but not over the configuration (6 m needs more than the default
  // 0.03 s between groups): lasonic-sim-world refuses it as the sonar driver does, instead of
  // running on alone.
  const std::string far = roomWith("far.yaml", "sonar: {range_max: 6}\n");
  expectBad("lasonic-sim-world", "--scenario " + far, "far.yaml: sonar.range_max: group_period_s (0.03) must be >=");
  expectBad("lasonic-sonar-driver", "--scenario " + far, "far.yaml: sonar.range_max: group_period_s (0.03) must be >=");
}

TEST(SimCli, OutputNeverOverwritesAnInput) {
  const std::string scenario = write("copy.yaml", slurp(kRoom));
  const std::string cfg = write("c.yaml", "odometry: {rate_hz: 50}\n");
  expectBad("lasonic-sim", "--scenario " + scenario + " --out " + scenario, "is the --scenario file");
  EXPECT_EQ(slurp(scenario), slurp(kRoom));
  // However spelt.
  expectBad("lasonic-sim", "--scenario " + scenario + " --out " + (tmpDir() / "." / "copy.yaml").string(),
            "is the --scenario file");
  expectBad("lasonic-sim", "--scenario " + scenario + " --config " + cfg + " --out " + cfg, "is the --config file");
  EXPECT_EQ(slurp(cfg), "odometry: {rate_hz: 50}\n");
#ifdef LASONIC_RENDER_BIN
  const std::string log = (tmpDir() / "room.lcmlog").string();
  const ToolRun sim = run("lasonic-sim", "--scenario " + kRoom + " --out " + log + " --duration 1");
  ASSERT_EQ(sim.status, 0) << sim.output;
  const std::string before = slurp(log);
  expectBad("lasonic-render", "--log " + log + " --out " + log, "is the --log file");
  expectBad("lasonic-render", "--log " + log + " --scenario " + scenario + " --out " + scenario, "is the --scenario file");
  EXPECT_EQ(slurp(log), before);
  EXPECT_EQ(slurp(scenario), slurp(kRoom));
  // A frame of --every named like the log.
  const std::string frame0 = (tmpDir() / "f-00000.lcmlog").string();
  fs::copy_file(log, frame0, fs::copy_options::overwrite_existing);
  expectBad("lasonic-render", "--log " + frame0 + " --every 0.5 --out " + (tmpDir() / "f.lcmlog").string(),
            "is the --log file");
  EXPECT_EQ(slurp(frame0), before);
#endif
}

TEST(SimCli, ScenegenIndicesAndOverlay) {
  const std::string out = "--out " + (tmpDir() / "scenes").string();
  expectBad("lasonic-scenegen", "--first 18446744073709551615 --count 2 " + out, "would pass 2^64 - 1");
  expectBad("lasonic-scenegen", "--first -1 " + out, "--first");
  expectBad("lasonic-scenegen", "--pioneer-overlay " + (tmpDir() / "none.yaml").string() + " " + out,
            "none.yaml: no such file");
  // The last index there is still generated.
  const ToolRun last = run("lasonic-scenegen", "--first 18446744073709551615 --count 1 " + out, kSource);
  EXPECT_NE(last.status, 2) << last.output;
}
