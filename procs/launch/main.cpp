// lasonic-launch PROFILE: starts the processes of one host from a host profile
// (deploy/hosts/*.yaml), restarts any that dies (with back-off), writes each one's output to
// <log dir>/<name>.txt, and stops them all on SIGINT / SIGTERM. The launcher for development,
// demos, tests and machines without systemd; on a robot, deploy/systemd/ holds the units.
// See common/launch/ and the README, "Deploying on two computers".
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

#include "core/cli.hpp"
#include "core/config.hpp"
#include "launch/profile.hpp"
#include "launch/supervisor.hpp"

using namespace lasonic;

namespace {
std::string selfDir() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : p.parent_path().string();
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-launch: run the processes of one host from a host profile (deploy/hosts/*.yaml)"};
  std::string profile_file, log_dir = "logs", lcm_url;
  std::vector<std::string> sets;
  std::string bin = selfDir();
  bool check = false, print_config = false;
  double max_time = 0;
  app.add_option("profile", profile_file, "host profile (YAML)")->required();
  app.add_option("--set", sets, "VAR=VALUE: define ${VAR} for the profile (repeatable)");
  app.add_option("--log-dir", log_dir, "directory for each process's output (<name>.txt)")->capture_default_str();
  app.add_option("--lcm-url", lcm_url, "override the profile's lcm_url");
  app.add_option("--bin", bin, "where executables named without a path are looked for first (then $PATH)")
      ->capture_default_str();
  app.add_option("--max-time", max_time, "stop everything after S seconds and exit 124 (demos, tests); 0: no limit")
      ->check(lasonic::FiniteNumberIn(0, launch::kMaxSeconds));
  app.add_flag("--check", check, "check the profile, the executables and each process's configuration; print the commands, start nothing");
  app.add_flag("--print-config", print_config,
               "as --check, then print each process's configuration in effect (its --print-config: every "
               "parameter, its value and the file it came from); start nothing");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;

  std::map<std::string, std::string> overrides;
  for (const std::string& s : sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) {
      std::cerr << "lasonic-launch: --set " << s << ": expected VAR=VALUE\n";
      return 2;
    }
    overrides[s.substr(0, eq)] = s.substr(eq + 1);
  }
  if (app.count("--lcm-url")) overrides["lcm_url"] = lcm_url;
  const std::map<std::string, std::string> builtins = {{"bin", bin}, {"log_dir", log_dir}};

  launch::HostProfile profile;
  try {
    profile = launch::loadProfile(Config::loadFile(profile_file), overrides, builtins);
  } catch (const ConfigError& e) {
    std::cerr << "lasonic-launch: " << e.what() << "\n";
    return 2;
  }
  launch::Supervisor sup(profile, log_dir, {bin});
  if (print_config) check = true;
  const bool ready = sup.prepare(!check);
  if (check) {
    std::cout << "host " << profile.host << ", LCM " << profile.lcm_url << "\n";
    bool files_ok = true;
    for (const auto& p : profile.processes) {
      std::cout << (p.enabled ? "  " : "  (disabled) ") << p.name << ":";
      for (const auto& a : p.command) std::cout << " " << a;
      std::cout << "\n";
      // The files every lasonic process reads at start-up: a profile names them relative to
      // where it is started (the repository, or PREFIX/share/lasonic), so say so before a run
      // would end in exit 2.
      if (!p.enabled) continue;
      bool files_there = true;
      for (const auto& [option, file] : launch::filesNamed(p)) {
        std::error_code ec;
        const auto st = std::filesystem::status(file, ec);
        if (std::filesystem::exists(st) && !std::filesystem::is_directory(st)) continue;
        std::error_code cwd_ec;
        std::cerr << "lasonic-launch: " << p.name << ": " << option << " " << file << ": "
                  << (std::filesystem::is_directory(st) ? "a directory, not a file" : "no such file") << " (from "
                  << std::filesystem::current_path(cwd_ec).string() << ")\n";
        files_ok = false;
        files_there = false;
      }
      // And what is in them: a process that offers --check-config (every lasonic process,
      // lcmio/process.hpp) loads its configuration and scenario as it would at start-up and
      // exits, so a bad key is found now, not as an exit 2 on the robot.
      const std::string exe = launch::resolveExecutable(p.command[0], {bin});
      std::string help, out;
      if (!files_there || exe.empty() || launch::runToEnd(exe, {"--help"}, help) != 0 ||
          help.find("--check-config") == std::string::npos)
        continue;
      std::vector<std::string> args(p.command.begin() + 1, p.command.end());
      // --print-config checks as --check-config does, and says what it found.
      const bool print = print_config && help.find("--print-config") != std::string::npos;
      args.push_back(print ? "--print-config" : "--check-config");
      const int rc = launch::runToEnd(exe, args, out);
      if (rc == 0) {
        if (print) std::cout << "\n" << out;
        continue;
      }
      while (!out.empty() && out.back() == '\n') out.pop_back();
      std::cerr << "lasonic-launch: " << p.name << ": configuration not usable (--check-config: exit " << rc
                << "):\n  " << out << "\n";
      files_ok = false;
    }
    return ready && files_ok ? 0 : 2;
  }
  if (!ready) return 2;
  return sup.run(max_time);
}
