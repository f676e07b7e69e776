#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

#include "core/cli.hpp"
#include "core/config.hpp"
#include "core/logging.hpp"
#include "scratch_dir.hpp"

using lasonic::Config;
using lasonic::ConfigError;
using lasonic::Range;

static std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ReadsValuesAndDefaults) {
  const Config c = Config::fromString("a: 1.5\nb: {c: 3}\nname: x\n");
  EXPECT_DOUBLE_EQ(c.get("a", 0.0, Range::positive()), 1.5);
  EXPECT_DOUBLE_EQ(c.get("missing", 7.0, Range::positive()), 7.0);
  EXPECT_EQ(c.section("b").get("c", 0, Range::any()), 3);
  EXPECT_EQ(c.require<std::string>("name"), "x");
}

TEST(Config, ErrorsNameTheKeyPath) {
  const Config c = Config::fromString(
      "obstacles:\n  - {radius: 1}\n  - {radius: -2}\nsonar: {rate: abc}\n", "s.yaml");
  const auto obs = c.list("obstacles");
  ASSERT_EQ(obs.size(), 2u);
  EXPECT_EQ(errorOf([&] { obs[1].get("radius", 1.0, Range::positive()); }),
            "s.yaml: obstacles[1].radius: must be > 0");
  EXPECT_EQ(errorOf([&] { c.section("sonar").get("rate", 1.0, Range::any()); }),
            "s.yaml: sonar.rate: must be a number");
  EXPECT_EQ(errorOf([&] { c.require<int>("nope"); }), "s.yaml: nope: is required");
  // An interval open at its lower end says so.
  EXPECT_EQ(errorOf([&] { obs[1].get("radius", 1.0, Range{-2, 5, true}); }),
            "s.yaml: obstacles[1].radius: must be in (-2, 5]");
  EXPECT_EQ(errorOf([&] { obs[1].get("radius", 1.0, Range::between(0, 5)); }),
            "s.yaml: obstacles[1].radius: must be in [0, 5]");
  EXPECT_NE(errorOf([&] { c.section("sonar").allowOnly({"x"}); }).find("sonar.rate: unknown key"),
            std::string::npos);
}

TEST(Config, ChoiceNamesItsOptions) {
  const Config c = Config::fromString("pilot: {rule: paper, mode: sideways}\n", "c.yaml");
  const Config p = c.section("pilot");
  EXPECT_EQ(p.getChoice("rule", 0, {{"paper", 1}, {"ours", 2}}), 1);
  EXPECT_EQ(p.getChoice("absent", 7, {{"paper", 1}}), 7);
  EXPECT_EQ(errorOf([&] { p.getChoice("mode", 0, {{"up", 1}, {"down", 2}}); }),
            "c.yaml: pilot.mode: must be one of up, down (got \"sideways\")");
}

TEST(Config, SyntaxAndFileErrors) {
  EXPECT_NE(errorOf([] { Config::fromString("a: [1, 2\n", "bad.yaml"); }).find("bad.yaml: YAML syntax error"),
            std::string::npos);
  EXPECT_NE(errorOf([] { Config::loadFile("/nonexistent/file.yaml"); }).find("cannot open"),
            std::string::npos);
  EXPECT_NE(errorOf([] { Config::fromString("- 1\n- 2\n", "l.yaml"); }).find("top level must be a map"),
            std::string::npos);
  // Two documents: the second was ignored.
  EXPECT_NE(errorOf([] { Config::fromString("a: 1\n---\nb: 2\n", "two.yaml"); }).find("two.yaml: 2 YAML documents"),
            std::string::npos);
  EXPECT_EQ(Config::fromString("---\na: 1\n", "one.yaml").get("a", 0), 1);  // one, marked as such
  EXPECT_FALSE(Config::fromString("", "empty.yaml").has("a"));
}

TEST(Config, PointsAndMerge) {
  const Config c = Config::fromString("p: [[0, 0], [1, 2]]\nq: [1]\nbase: {a: 1, b: 2}\nover: {b: 3}\n");
  const auto pts = c.requirePoints("p", 2);
  EXPECT_DOUBLE_EQ(pts[1].y(), 2.0);
  EXPECT_NE(errorOf([&] { c.requirePoints("q", 2); }).find("q[0]: must be a pair"), std::string::npos);
  const Config m = c.section("base").mergedWith(c.section("over"));
  EXPECT_EQ(m.get("a", 0, Range::any()), 1);
  EXPECT_EQ(m.get("b", 0, Range::any()), 3);
}

TEST(Config, RejectsNonFinite) {
  const Config c = Config::fromString("a: .nan\nb: .inf\n");
  EXPECT_NE(errorOf([&] { c.get("a", 0.0, Range::any()); }), "");
  EXPECT_NE(errorOf([&] { c.get("b", 0.0, Range::any()); }), "");
}

TEST(Config, LayeredFilesMergeKeyByKey) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string& dir = scratch.path();
  const std::string a = dir + "/layer_a.yaml", b = dir + "/layer_b.yaml";
  {
    std::ofstream(a) << "pilot: {robot_radius: 0.25, agm: {g_t: 5, h_max: 12}}\nsonar: {beam: 30}\nlist: [1, 2]\n";
    std::ofstream(b) << "pilot: {robot_radius: 0.27, agm: {h_max: 15}}\nlist: [3]\n";
  }
  const Config c = Config::loadFiles({a, b});
  EXPECT_DOUBLE_EQ(c.section("pilot").get("robot_radius", 0.0, Range::any()), 0.27);
  EXPECT_EQ(c.section("pilot").section("agm").get("g_t", 0, Range::any()), 5);   // kept from a
  EXPECT_EQ(c.section("pilot").section("agm").get("h_max", 0, Range::any()), 15);  // replaced by b
  EXPECT_EQ(c.section("sonar").get("beam", 0, Range::any()), 30);
  EXPECT_EQ(c.node()["list"].size(), 1u);  // lists are replaced, not appended
  EXPECT_TRUE(Config::loadFiles({}).node().IsMap());
  EXPECT_NE(errorOf([&] { Config::loadFiles({a, "/nonexistent/over.yaml"}); }).find("cannot open"),
            std::string::npos);
}

// A misspelt section in a --config file is an error naming the file and the key: each process
// reads only its own sections, so it would otherwise change nothing anywhere.
TEST(Config, ConfigurationFilesAllowOnlyTheKnownSections) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string& dir = scratch.path();
  const std::string good = dir + "/sections_good.yaml", typo = dir + "/sections_typo.yaml";
  {
    std::ofstream(good) << "pilot: {robot_radius: 0.27}\nnavigator: {}\n";
    std::ofstream(typo) << "pilto: {robot_radius: 0.27}\n";
  }
  const Config c = Config::loadConfiguration({good});
  EXPECT_DOUBLE_EQ(c.section("pilot").get("robot_radius", 0.0, Range::positive()), 0.27);
  const std::string e = errorOf([&] { Config::loadConfiguration({good, typo}); });
  EXPECT_EQ(e.rfind(typo + ": pilto: unknown key (allowed: sim_world, odometry", 0), 0u) << e;
  // Layered files are merged as loadFiles merges them.
  EXPECT_EQ(errorOf([&] { Config::loadConfiguration({good, good}); }), "");
  // Every section of the shipped file is known.
  const std::string shipped = std::string(LASONIC_SOURCE_DIR) + "/deploy/config/lasonic.yaml";
  EXPECT_EQ(errorOf([&] { Config::loadConfiguration({shipped}); }), "");
  EXPECT_EQ(Config::loadConfiguration({shipped}).keys().size(), lasonic::kConfigSections.size());
}

TEST(CommandLine, HelpIsZeroAnyOtherErrorTwo) {
  const auto parse = [](std::vector<const char*> args) {
    CLI::App app{"test"};
    std::string in;
    int n = 0;
    app.add_option("--in", in, "input")->required();
    app.add_option("--n", n, "a count")->check(CLI::Range(0, 9));
    args.insert(args.begin(), "tool");
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const auto rc = lasonic::parseCommandLine(app, static_cast<int>(args.size()), args.data());
    testing::internal::GetCapturedStdout();
    testing::internal::GetCapturedStderr();
    return rc;
  };
  EXPECT_EQ(parse({"--in", "x"}), std::nullopt);
  EXPECT_EQ(parse({"--help"}), std::optional<int>(0));
  EXPECT_EQ(parse({}), std::optional<int>(2));                        // a required option missing
  EXPECT_EQ(parse({"--in", "x", "--bogus"}), std::optional<int>(2));  // an unknown option
  EXPECT_EQ(parse({"--in", "x", "--n", "99"}), std::optional<int>(2));  // out of range
}

// --version prints the build and exits 0 before any requirement is checked (a tool with a
// required input answers it too), and names the project's version.
TEST(CommandLine, VersionIsZeroAndNamesTheBuild) {
  CLI::App app{"test"};
  std::string in;
  app.add_option("--in", in, "input")->required();
  std::vector<const char*> args = {"tool", "--version"};
  testing::internal::CaptureStdout();
  const auto rc = lasonic::parseCommandLine(app, static_cast<int>(args.size()), args.data());
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_EQ(rc, std::optional<int>(0));
  EXPECT_EQ(out, std::string(lasonic::versionString()) + "\n");
  EXPECT_EQ(out.rfind("lasonic " LASONIC_VERSION " (", 0), 0u) << out;
}

// CLI::Range and CLI::NonNegativeNumber let "nan" through; lasonic::FiniteNumberIn does not.
TEST(CommandLine, FiniteNumberInRejectsNanInfAndOutOfRange) {
  const auto parse = [](const char* value) {
    CLI::App app{"test"};
    double s = 0;
    app.add_option("--s", s, "seconds")->check(lasonic::FiniteNumberIn(0, 1e6));
    std::vector<const char*> args = {"tool", "--s", value};
    testing::internal::CaptureStderr();
    const auto rc = lasonic::parseCommandLine(app, static_cast<int>(args.size()), args.data());
    const std::string err = testing::internal::GetCapturedStderr();
    return std::make_pair(rc, err);
  };
  EXPECT_EQ(parse("2.5").first, std::nullopt);
  EXPECT_EQ(parse("0").first, std::nullopt);
  EXPECT_EQ(parse("1e6").first, std::nullopt);
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "1e300", "-1", "abc"}) {
    const auto [rc, err] = parse(bad);
    EXPECT_EQ(rc, std::optional<int>(2)) << bad;
    EXPECT_NE(err.find("--s"), std::string::npos) << err;
  }
}

TEST(Logging, LevelNamesAndUnknownOnes) {
  EXPECT_EQ(lasonic::parseLogLevel("debug"), spdlog::level::debug);
  EXPECT_EQ(lasonic::parseLogLevel("Info"), spdlog::level::info);
  EXPECT_EQ(lasonic::parseLogLevel("WARNING"), spdlog::level::warn);
  EXPECT_EQ(lasonic::parseLogLevel("error"), spdlog::level::err);
  EXPECT_EQ(lasonic::parseLogLevel("off"), spdlog::level::off);
  // spdlog itself would read these as "off" and hide every warning.
  EXPECT_EQ(lasonic::parseLogLevel("bogus"), std::nullopt);
  EXPECT_EQ(lasonic::parseLogLevel(""), std::nullopt);
}

// A key that is a list or a map (or empty) cannot be named in the configuration: an error naming
// the file, the map's key path and the line, not a yaml-cpp exception (which ended the processes
// with exit 1, or an abort).
TEST(Config, AKeyThatIsNotAStringIsAnError) {
  EXPECT_EQ(errorOf([] { Config::fromString("[a, b]: 1\n", "my.yaml"); }),
            "my.yaml: <root>: a key that is not a string (line 1, column 1)");
  EXPECT_EQ(errorOf([] { Config::fromString("pilot:\n  [a, b]: 1\n", "my.yaml"); }),
            "my.yaml: pilot: a key that is not a string (line 2, column 3)");
  EXPECT_EQ(errorOf([] { Config::fromString("pilot:\n  ? [x]\n", "my.yaml"); }),
            "my.yaml: pilot: a key that is not a string (line 2, column 5)");
  EXPECT_EQ(errorOf([] { Config::fromString("pilot: {agm: {? {x: 1} : 3}}\n", "my.yaml"); }).rfind(
                "my.yaml: pilot.agm: a key that is not a string", 0),
            0u);
  EXPECT_EQ(errorOf([] { Config::fromString("obstacles:\n  - {[a]: 1}\n", "my.yaml"); }).rfind(
                "my.yaml: obstacles[0]: a key that is not a string", 0),
            0u);
  EXPECT_EQ(errorOf([] { Config::fromString("pilot: {: 1}\n", "my.yaml"); }).rfind("my.yaml: pilot: an empty key", 0),
            0u);
  // Through the --config loader, and for a map that did not come from a file.
  const lasonic::fixture::ScratchDir scratch;
  const std::string f = scratch.file("list_key.yaml");
  std::ofstream(f) << "pilot:\n  robot_radius: 0.3\n  [a, b]: 1\n";
  EXPECT_EQ(errorOf([&] { Config::loadConfiguration({f}); }).rfind(f + ": pilot: a key that is not a string", 0), 0u);
  const Config raw(YAML::Load("{[a]: 1}"), "sec", "raw.yaml");
  EXPECT_EQ(errorOf([&] { raw.keys(); }).rfind("raw.yaml: sec: a key that is not a string", 0), 0u);
  EXPECT_EQ(errorOf([&] { raw.allowOnly({"x"}); }).rfind("raw.yaml: sec: a key that is not a string", 0), 0u);
  EXPECT_EQ(errorOf([&] { Config{}.mergedWith(raw); }).rfind("raw.yaml: sec: a key that is not a string", 0), 0u);
  EXPECT_EQ(errorOf([&] { raw.mergedWith(Config{}); }).rfind("raw.yaml: sec: a key that is not a string", 0), 0u);
}

// yaml-cpp keeps both pairs of a repeated key: one reader took the first, a layered merge the
// last. A key given twice in one map is an error naming the file, the key path and both lines.
TEST(Config, AKeyGivenTwiceInOneMapIsAnError) {
  EXPECT_EQ(errorOf([] { Config::fromString("pilot:\n  robot_radius: 0.27\n  robot_radius: 5\n", "my.yaml"); }),
            "my.yaml: pilot.robot_radius: given twice in one map (lines 2 and 3); give each key once");
  EXPECT_EQ(errorOf([] { Config::fromString("pilot: {}\npilot: {}\n", "my.yaml"); }).rfind("my.yaml: pilot: given twice", 0),
            0u);
  EXPECT_EQ(errorOf([] { Config::fromString("obstacles: [{r: 1, 'r': 2}]\n", "my.yaml"); })
                .rfind("my.yaml: obstacles[0].r: given twice", 0),
            0u);
  // The same key in different maps, or in different files, is fine.
  EXPECT_EQ(errorOf([] { Config::fromString("a: {r: 1}\nb: {r: 2}\n"); }), "");
  const lasonic::fixture::ScratchDir scratch;
  const std::string& dir = scratch.path();
  const std::string base = dir + "/dup_base.yaml", twice = dir + "/dup_twice.yaml";
  {
    std::ofstream(base) << "pilot: {robot_radius: 0.3}\n";
    std::ofstream(twice) << "pilot:\n  robot_radius: 0.27\n  robot_radius: 5\n";
  }
  EXPECT_EQ(errorOf([&] { Config::loadConfiguration({base, base}); }), "");
  EXPECT_EQ(errorOf([&] { Config::loadConfiguration({base, twice}); }).rfind(twice + ": pilot.robot_radius: given twice", 0),
            0u);
  // An alias of a map that contains it would be followed for ever by a layered merge.
  EXPECT_EQ(errorOf([] { Config::fromString("a: &x {b: *x}\n", "my.yaml"); }).rfind("my.yaml: a.b: refers to itself", 0),
            0u);
  EXPECT_EQ(errorOf([] { Config::fromString("a: &x {p: 1}\nb: *x\n"); }), "");  // a plain alias is fine
}

// A section whose keys are all commented out (`pilot:` alone: a null) in a later --config layer
// says nothing: the earlier layer's section stays. A key with no value is an error, not the default.
TEST(Config, ANullSectionKeepsTheEarlierLayerAndANullKeyIsAnError) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string& dir = scratch.path();
  const std::string base = dir + "/null_base.yaml", commented = dir + "/null_commented.yaml",
                    novalue = dir + "/null_novalue.yaml";
  {
    std::ofstream(base) << "pilot:\n  robot_radius: 0.3\n  agm: {g_t: 5}\nnavigator: {cell_size: 0.1}\n";
    std::ofstream(commented) << "pilot:\n  # robot_radius: 0.27\n  agm:\n    # g_t: 6\nnavigator:\n";
    std::ofstream(novalue) << "navigator:\n  cell_size:\n";
  }
  const Config c = Config::loadConfiguration({base, commented});
  EXPECT_DOUBLE_EQ(c.section("pilot").get("robot_radius", 0.0, Range::positive()), 0.3);
  EXPECT_EQ(c.section("pilot").section("agm").get("g_t", 0, Range::any()), 5);
  EXPECT_DOUBLE_EQ(c.section("navigator").get("cell_size", 0.0, Range::positive()), 0.1);
  // Alone, a commented-out section is an empty one.
  const Config alone = Config::loadConfiguration({commented});
  EXPECT_TRUE(alone.section("pilot").section("agm").empty());
  EXPECT_DOUBLE_EQ(alone.section("pilot").get("robot_radius", 0.25, Range::positive()), 0.25);
  EXPECT_TRUE(alone.list("navigator").empty());
  // `cell_size:` alone, over a value or not.
  for (const auto& files : {std::vector<std::string>{novalue}, std::vector<std::string>{base, novalue}}) {
    const Config nav = Config::loadConfiguration(files).section("navigator");
    const std::string e = errorOf([&] { nav.get("cell_size", 0.1, Range::positive()); });
    EXPECT_NE(e.find("navigator.cell_size: has no value"), std::string::npos) << e;
    EXPECT_NE(e.find(novalue), std::string::npos) << e;
  }
  const Config n = Config::fromString("s: {a: , b: ~, c: null}\n", "n.yaml").section("s");
  EXPECT_EQ(errorOf([&] { n.get("a", 1.0, Range::any()); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.get("b", 1, Range::any()); }), "n.yaml: s.b: has no value");
  EXPECT_EQ(errorOf([&] { n.get<bool>("c", true); }), "n.yaml: s.c: has no value");
  EXPECT_EQ(errorOf([&] { n.get<std::string>("a", "x"); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.require<double>("a"); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.requireNum("a", Range::any()); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.getChoice("a", 0, {{"x", 1}}); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.getVec2("a", {0, 0}); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.getDoubles("a", {}); }), "n.yaml: s.a: has no value");
  EXPECT_EQ(errorOf([&] { n.requirePoints("a", 1); }), "n.yaml: s.a: has no value");
  EXPECT_NE(errorOf([&] { n.requireSection("a"); }).find("s.a: has no value"), std::string::npos);
  EXPECT_TRUE(n.has("a"));  // present, without a value
  // The scenario's one-level override (mergedWith): a commented-out map keeps the base's.
  const Config m = Config::fromString("base: {mount: {x: 1}, r: 2}\nover: {mount: , r: 3}\n");
  const Config merged = m.section("base").mergedWith(m.section("over"));
  EXPECT_DOUBLE_EQ(merged.section("mount").get("x", 0.0, Range::any()), 1.0);
  EXPECT_EQ(merged.get("r", 0, Range::any()), 3);
}

// A directory given as a configuration file is an error (std::ifstream reads it as an empty
// file); a pipe (`--config <(...)`, /dev/fd/N) is read.
TEST(Config, ADirectoryIsNotAFileAPipeIs) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string& dir = scratch.path();
  EXPECT_NE(errorOf([&] { Config::loadFile(dir); }).find(": is a directory, not a YAML file"), std::string::npos);
  EXPECT_NE(errorOf([&] { Config::loadConfiguration({dir}); }).find("is a directory"), std::string::npos);
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const std::string text = "pilot: {robot_radius: 0.31}\n";
  ASSERT_EQ(::write(fds[1], text.data(), text.size()), static_cast<ssize_t>(text.size()));
  ::close(fds[1]);
  const Config c = Config::loadConfiguration({"/dev/fd/" + std::to_string(fds[0])});
  ::close(fds[0]);
  EXPECT_DOUBLE_EQ(c.section("pilot").get("robot_radius", 0.0, Range::positive()), 0.31);
}

// --print-config's record: every key read, with the value in effect and whether a file set it
// (else the code's default), in the order first read, each once; nothing while no report is alive.
TEST(ConfigReport, RecordsEveryReadWithItsValueAndWhetherAFileSetIt) {
  const Config c = Config::fromString(
      "pilot:\n  sectors: 36\n  mode: fast\n  offset: [0.5, -1]\n  weights: [1, 2.5]\n  flag: true\n");
  const Config p = c.section("pilot");
  enum class Mode { Slow, Fast };
  {
    lasonic::ConfigReport report;
    EXPECT_EQ(p.get("sectors", 48, Range::between(3, 3600)), 36);
    EXPECT_DOUBLE_EQ(p.get("max_range", 3.0, Range::positive()), 3.0);  // no file sets it
    EXPECT_EQ(p.getChoice("mode", Mode::Slow, {{"slow", Mode::Slow}, {"fast", Mode::Fast}}), Mode::Fast);
    EXPECT_EQ(p.getChoice("other", Mode::Slow, {{"slow", Mode::Slow}, {"fast", Mode::Fast}}), Mode::Slow);
    EXPECT_EQ(p.getVec2("offset", {0, 0}), lasonic::geom::Vec2(0.5, -1));
    EXPECT_EQ(p.getDoubles("weights", {}), std::vector<double>({1, 2.5}));
    EXPECT_TRUE(p.get<bool>("flag", false));
    EXPECT_EQ(p.get("sectors", 48, Range::between(3, 3600)), 36);  // read again: kept once
    const std::vector<lasonic::ConfigEntry>& e = report.entries();
    ASSERT_EQ(e.size(), 7u);
    const auto expect = [&](size_t i, const char* key, const char* value, bool from_file) {
      EXPECT_EQ(e[i].key, key);
      EXPECT_EQ(e[i].value, value) << key;
      EXPECT_EQ(e[i].from_file, from_file) << key;
    };
    expect(0, "pilot.sectors", "36", true);
    expect(1, "pilot.max_range", "3", false);
    expect(2, "pilot.mode", "fast", true);
    expect(3, "pilot.other", "slow", false);
    expect(4, "pilot.offset", "[0.5, -1]", true);
    expect(5, "pilot.weights", "[1, 2.5]", true);
    expect(6, "pilot.flag", "true", true);
    {
      lasonic::ConfigReport inner;  // a nested report takes the reads while it lives
      p.get("sectors", 48, Range::between(3, 3600));
      EXPECT_EQ(inner.entries().size(), 1u);
    }
    p.get("gp_threshold", 2, Range::between(1, 100));
    EXPECT_EQ(report.entries().size(), 8u);
  }
  EXPECT_FALSE(lasonic::ConfigReport::active());
}

// Each key's source is the last layered file that sets it; a key no file sets is the default.
TEST(ConfigReport, NamesTheLastFileThatSetsEachKey) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string base = scratch.file("base.yaml"), robot = scratch.file("robot.yaml");
  std::ofstream(base) << "pilot:\n  sectors: 48\n  robot_radius: 0.35\n  list: [{a: 1}, {a: 2}]\n";
  std::ofstream(robot) << "pilot:\n  robot_radius: 0.27\n";
  EXPECT_EQ(lasonic::configSourceFile({base, robot}, "pilot.robot_radius"), robot);
  EXPECT_EQ(lasonic::configSourceFile({base, robot}, "pilot.sectors"), base);
  EXPECT_EQ(lasonic::configSourceFile({base, robot}, "pilot.list[1].a"), base);
  EXPECT_EQ(lasonic::configSourceFile({base, robot}, "pilot.list[2].a"), "");
  EXPECT_EQ(lasonic::configSourceFile({base, robot}, "pilot.max_range"), "");
  EXPECT_EQ(lasonic::configSourceFile({base, "/nonexistent.yaml"}, "pilot.sectors"), base);
  const Config c = Config::loadFiles({base, robot});
  std::string text;
  {
    lasonic::ConfigReport report;
    const Config p = c.section("pilot");
    p.get("robot_radius", 0.3, Range::positive());
    p.get("sectors", 24, Range::between(3, 3600));
    p.get("max_range", 3.0, Range::positive());
    text = lasonic::formatConfigReport(report.entries(), {base, robot});
  }
  EXPECT_EQ(text, "pilot.robot_radius: 0.27  # " + robot + "\npilot.sectors: 48  # " + base +
                      "\npilot.max_range: 3  # default\n");
  // A scenario's section over the configuration's (mergedWith): its keys name the scenario, the
  // others the configuration file; the scenario's own keys name it too.
  const std::string scenario = scratch.file("scene.yaml");
  std::ofstream(scenario) << "name: scene\nlaser: {fov_deg: 270}\n";
  std::ofstream(scratch.file("sensors.yaml")) << "laser:\n  fov_deg: 360\n  readings: 720\n";
  const std::vector<std::string> cfg_files = {scratch.file("sensors.yaml")};
  const Config sensors = Config::loadFiles(cfg_files), scene = Config::loadFile(scenario);
  {
    lasonic::ConfigReport report;
    scene.get<std::string>("name", "");
    const Config laser = sensors.section("laser").mergedWith(scene.section("laser"));
    laser.get("fov_deg", 360.0, Range::positive());
    laser.get("readings", 720, Range::positive());
    text = lasonic::formatConfigReport(report.entries(), cfg_files);
  }
  EXPECT_EQ(text, "name: scene  # " + scenario + "\nlaser.fov_deg: 270  # " + scenario +
                      "\nlaser.readings: 720  # " + cfg_files[0] + "\n");
}
