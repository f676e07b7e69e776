#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <string>

#include "launch/profile.hpp"
#include "launch/supervisor.hpp"
#include "scratch_dir.hpp"

using namespace lasonic;
using namespace lasonic::launch;

namespace {
HostProfile load(const std::string& yaml, std::map<std::string, std::string> set = {}) {
  return loadProfile(Config::fromString(yaml, "host.yaml"), set, {{"bin", "/opt/bin"}});
}
std::string errorOf(const std::string& yaml) {
  try {
    load(yaml);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(HostProfile, ParsesAndExpandsVariables) {
  const auto p = load(R"(
host: pilot
lcm_url: "udpm://239.255.76.67:7667?ttl=1"
vars: {config: c.yaml}
processes:
  - name: a
    command: ["${bin}/a", --config, "${config}", --lcm-url, "${lcm_url}", "$$HOME"]
    restart: on-failure
    start_delay_s: 1.5
  - name: b
    command: [b, "${scenario}"]
    optional: true
    finish: true
)",
                      {{"scenario", "s.yaml"}});
  EXPECT_EQ(p.host, "pilot");
  ASSERT_EQ(p.processes.size(), 2u);
  EXPECT_EQ(p.processes[0].command,
            (std::vector<std::string>{"/opt/bin/a", "--config", "c.yaml", "--lcm-url", "udpm://239.255.76.67:7667?ttl=1",
                                      "$HOME"}));
  EXPECT_EQ(p.processes[0].restart, RestartPolicy::OnFailure);
  EXPECT_DOUBLE_EQ(p.processes[0].start_delay_s, 1.5);
  EXPECT_EQ(p.processes[1].command[1], "s.yaml");
  EXPECT_TRUE(p.processes[1].optional);
  EXPECT_TRUE(p.processes[1].finish);
  EXPECT_EQ(p.processes[1].restart, RestartPolicy::Always);
}

TEST(HostProfile, SetOverridesVarsAndTheUrl) {
  const auto p = load("lcm_url: u1\nvars: {x: 1}\nprocesses: [{name: a, command: [a, '${x}', '${lcm_url}']}]\n",
                      {{"x", "2"}, {"lcm_url", "u2"}});
  EXPECT_EQ(p.processes[0].command[1], "2");
  EXPECT_EQ(p.processes[0].command[2], "u2");
  EXPECT_EQ(p.lcm_url, "u2");
}

TEST(HostProfile, SetOfAVariableTheProfileDoesNotUseIsAnError) {
  const std::string yaml = "lcm_url: u\nvars: {config: c.yaml}\nprocesses: [{name: a, command: [a, '${config}']}]\n";
  EXPECT_EQ(load(yaml, {{"config", "d.yaml"}}).processes[0].command[1], "d.yaml");
  try {
    load(yaml, {{"robot", "pioneer.yaml"}});
    ADD_FAILURE() << "a --set of an unused variable was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--set robot: the profile uses no variable ${robot} (it uses: config"),
              std::string::npos)
        << e.what();
  }
}

TEST(HostProfile, EnvironmentFillsUnknownVariables) {
  ::setenv("LASONIC_TEST_LAUNCH_VAR", "from-env", 1);
  const auto p = load("lcm_url: u\nprocesses: [{name: a, command: [a, '${LASONIC_TEST_LAUNCH_VAR}']}]\n");
  EXPECT_EQ(p.processes[0].command[1], "from-env");
}

TEST(HostProfile, EnabledTakesAVariable) {
  const std::string yaml = "lcm_url: u\nprocesses: [{name: a, command: [a], enabled: '${spy}'}]\n";
  EXPECT_FALSE(load(yaml, {{"spy", "0"}}).processes[0].enabled);
  EXPECT_TRUE(load(yaml, {{"spy", "1"}}).processes[0].enabled);
}

// "$${name}" is a literal "${name}" in a command: a --set of that name changes nothing in the
// profile and is refused as a variable the profile does not use, at the start of an argument too.
TEST(HostProfile, AnEscapedVariableIsNotAUsedOne) {
  const std::string yaml = "lcm_url: u\nprocesses: [{name: a, command: [a, '$${x}']}]\n";
  EXPECT_EQ(load(yaml).processes[0].command[1], "${x}");
  EXPECT_THROW(load(yaml, {{"x", "1"}}), ConfigError);
}

// "enabled" taking a variable that expands to nothing turns the process off (as 0, false, no):
// a profile's optional process is left out by leaving its variable empty.
TEST(HostProfile, AnEnabledVariableThatIsEmptyDisablesTheProcess) {
  const std::string yaml = "lcm_url: u\nprocesses: [{name: a, command: [a], enabled: '${spy}'}]\n";
  EXPECT_FALSE(load(yaml, {{"spy", ""}}).processes[0].enabled);
  EXPECT_TRUE(load(yaml, {{"spy", "yes"}}).processes[0].enabled);
}

// --lcm-url (--set lcm_url) is the launcher's own option: it overrides the profile's URL even where
// no command names ${lcm_url}, and is no "unused variable".
TEST(HostProfile, SetOfTheLcmUrlIsAcceptedWhereNoCommandUsesIt) {
  const auto p = load("lcm_url: u1\nprocesses: [{name: a, command: [a]}]\n", {{"lcm_url", "u2"}});
  EXPECT_EQ(p.lcm_url, "u2");
}

TEST(HostProfile, ErrorsNameTheKey) {
  EXPECT_NE(errorOf("processes: [{name: a, command: [a]}]").find("lcm_url: is required"), std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: [{name: a, command: [a, '${nope_not_set}']}]")
                .find("processes[0].command[1]: unknown variable ${nope_not_set}"),
            std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: [{name: a, command: []}]").find("processes[0].command"), std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: [{name: a, command: [a]}, {name: a, command: [b]}]")
                .find("processes[1].name: \"a\" is used twice"),
            std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: [{name: a, command: [a], restart: sometimes}]")
                .find("processes[0].restart: must be one of always, on-failure, never"),
            std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: [{name: a, command: [a], colour: red}]").find("colour"), std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: [{name: ../x, command: [a]}]").find("plain file name"), std::string::npos);
  EXPECT_NE(errorOf("lcm_url: u\nprocesses: []").find("at least one process"), std::string::npos);
}

// A profile is read as any configuration file: a key given twice in one map, or a key that is a
// list, is an error naming the key path (which copy counted depended on the reader).
TEST(HostProfile, AKeyGivenTwiceOrNotAStringIsAnError) {
  try {
    load("lcm_url: u\nprocesses:\n  - name: a\n    command: [a]\n    restart: never\n    restart: always\n");
    ADD_FAILURE() << "a key given twice was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "host.yaml: processes[0].restart: given twice in one map (lines 5 and 6); give each key once");
  }
  try {
    load("lcm_url: u\nprocesses: [{name: a, command: [a], [x]: 1}]\n");
    ADD_FAILURE() << "a key that is a list was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("host.yaml: processes[0]: a key that is not a string", 0), 0u) << e.what();
  }
}

// A time of 1e300 s overflowed the supervisor's clock arithmetic and acted at once (while its
// message said 1e300 s): every time is finite and at most kMaxSeconds.
TEST(HostProfile, TimesAreBounded) {
  const std::string procs = "processes: [{name: a, command: [a]}]\n";
  EXPECT_EQ(errorOf("lcm_url: u\nprocesses: [{name: a, command: [a], start_delay_s: 1e300}]\n"),
            "host.yaml: processes[0].start_delay_s: must be in [0, 1e+06]");
  EXPECT_EQ(errorOf("lcm_url: u\nrestart: {initial_delay_s: 1e300, max_delay_s: 1e300}\n" + procs),
            "host.yaml: restart.initial_delay_s: must be in (0, 1e+06]");
  EXPECT_EQ(errorOf("lcm_url: u\nrestart: {max_delay_s: 1e7}\n" + procs), "host.yaml: restart.max_delay_s: must be in (0, 1e+06]");
  EXPECT_EQ(errorOf("lcm_url: u\nrestart: {reset_after_s: .inf}\n" + procs),
            "host.yaml: restart.reset_after_s: must be in [0, 1e+06]");
  EXPECT_EQ(errorOf("lcm_url: u\nstop_timeout_s: 1e300\n" + procs), "host.yaml: stop_timeout_s: must be in (0, 1e+06]");
  EXPECT_EQ(errorOf("lcm_url: u\nfinish_grace_s: .nan\n" + procs), "host.yaml: finish_grace_s: must be in [0, 1e+06]");
  EXPECT_DOUBLE_EQ(load("lcm_url: u\nprocesses: [{name: a, command: [a], start_delay_s: 1e6}]\n").processes[0].start_delay_s,
                   kMaxSeconds);
}

// Every process would be started with an empty --lcm-url.
TEST(HostProfile, AnEmptyLcmUrlIsAnError) {
  const std::string procs = "processes: [{name: a, command: [a]}]\n";
  EXPECT_EQ(errorOf("lcm_url: \"\"\n" + procs).rfind("host.yaml: lcm_url: must not be empty", 0), 0u);
  EXPECT_EQ(errorOf("lcm_url: ${url}\nvars: {url: ''}\n" + procs).rfind("host.yaml: lcm_url: must not be empty", 0), 0u);
  try {
    load("lcm_url: u\n" + procs, {{"lcm_url", ""}});
    ADD_FAILURE() << "an empty --lcm-url was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "--lcm-url (or --set lcm_url): must not be empty");
  }
}

// The files lasonic-launch --check looks for: both forms of the options.
TEST(HostProfile, FilesNamedInBothOptionForms) {
  ProcessSpec s;
  s.command = {"lasonic-pilot", "--config", "a.yaml", "--config=b.yaml", "--scenario=c.yaml", "--scenario", "d.yaml",
               "--lcm-url", "u", "--config"};
  const std::vector<std::pair<std::string, std::string>> want = {
      {"--config", "a.yaml"}, {"--config", "b.yaml"}, {"--scenario", "c.yaml"}, {"--scenario", "d.yaml"}};
  EXPECT_EQ(filesNamed(s), want);
}

TEST(Backoff, DoublesUpToTheCap) {
  const BackoffParams p{0.5, 10, 30};
  EXPECT_DOUBLE_EQ(restartDelay(p, 1), 0.5);
  EXPECT_DOUBLE_EQ(restartDelay(p, 2), 1.0);
  EXPECT_DOUBLE_EQ(restartDelay(p, 3), 2.0);
  EXPECT_DOUBLE_EQ(restartDelay(p, 6), 10.0);
  EXPECT_DOUBLE_EQ(restartDelay(p, 1000), 10.0);
}

// A restart count below 1 (none yet) waits as the first restart does: never less than
// initial_delay_s.
TEST(Backoff, ACountBelowOneWaitsTheInitialDelay) {
  const BackoffParams p{0.5, 10, 30};
  EXPECT_DOUBLE_EQ(restartDelay(p, 0), 0.5);
  EXPECT_DOUBLE_EQ(restartDelay(p, -3), 0.5);
}

TEST(ResolveExecutable, SearchesDirsThenPath) {
  EXPECT_FALSE(resolveExecutable("sh", {"/nonexistent"}).empty());  // from $PATH
  EXPECT_EQ(resolveExecutable("/bin/sh", {}), "/bin/sh");
  EXPECT_EQ(resolveExecutable("no-such-program-lasonic", {"/usr/bin"}), "");
  EXPECT_EQ(resolveExecutable("/etc/passwd", {}), "");  // not executable
}

// runToEnd (lasonic-launch --check runs each process's --check-config through it): the exit
// status, a signal, and stdout and stderr together.
TEST(RunToEnd, ExitStatusSignalAndOutput) {
  std::string out;
  EXPECT_EQ(launch::runToEnd("/bin/sh", {"-c", "echo to-out; echo to-err >&2; exit 3"}, out), 3);
  EXPECT_NE(out.find("to-out"), std::string::npos);
  EXPECT_NE(out.find("to-err"), std::string::npos);
  EXPECT_EQ(launch::runToEnd("/bin/sh", {"-c", "kill -TERM $$"}, out), 128 + SIGTERM);
  EXPECT_EQ(launch::runToEnd("/bin/sh", {"-c", "read x; echo \"got:$x\""}, out), 0);
  EXPECT_EQ(out, "got:\n");  // stdin is /dev/null: nothing waits for input
  EXPECT_EQ(launch::runToEnd("/no/such/program", {}, out), 127);
}

namespace {
// How many times the supervisor started `name`: its log has a launcher line before each start.
int startsIn(const std::string& dir, const std::string& name) {
  std::ifstream log(dir + "/" + name + ".txt");
  int starts = 0;
  for (std::string line; std::getline(log, line);) starts += line.find("] start ") != std::string::npos ? 1 : 0;
  return starts;
}
}  // namespace

// Exit status 2 is a bad command line or configuration: starting the process again cannot help,
// so it is not restarted (whatever its policy) and the launcher exits 2 once nothing runs.
TEST(Supervisor, AProcessThatExitsTwoIsNotRestartedAndTheLauncherExitsTwo) {
  const lasonic::fixture::ScratchDir log_dir{"lasonic-launch"};  // the supervisor's logs
  const std::string& dir = log_dir.path();
  const HostProfile profile = load("lcm_url: u\nprocesses: [{name: bad, command: [/bin/sh, -c, 'exit 2'], restart: always}]\n");
  Supervisor supervisor(profile, dir, {});
  ASSERT_TRUE(supervisor.prepare());
  EXPECT_EQ(supervisor.run(3.0), 2);
  EXPECT_EQ(startsIn(dir, "bad"), 1);
}

// A process that ran for reset_after_s before it failed was healthy: its restart waits the
// initial delay again, not the doubled one of a process that keeps dying.
TEST(Supervisor, AfterAHealthyRunTheRestartDelayStartsAfresh) {
  const lasonic::fixture::ScratchDir log_dir{"lasonic-launch"};  // the supervisor's logs
  const std::string& dir = log_dir.path();
  const HostProfile profile = load(
      "lcm_url: u\nrestart: {initial_delay_s: 0.05, max_delay_s: 10, reset_after_s: 0.1}\n"
      "processes: [{name: flaky, command: [/bin/sh, -c, 'sleep 0.15; exit 1'], restart: always}]\n");
  Supervisor supervisor(profile, dir, {});
  ASSERT_TRUE(supervisor.prepare());
  EXPECT_EQ(supervisor.run(3.0), 124);
  // Every 0.2 s or so (about 15 starts; 10 if a loaded machine takes 0.1 s to start the shell);
  // with the delay doubling (0.05, 0.1, 0.2, 0.4, 0.8, 1.6 s) it would be 6 starts at most.
  EXPECT_GE(startsIn(dir, "flaky"), 9);
}
