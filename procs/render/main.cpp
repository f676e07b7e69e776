// lasonic-render --log LOG --out PNG [--time S [--every S] | --most-sonar] [--scenario FILE]
//
// Draws the paper's Fig. 8 (section 4) for one moment of a log, or a frame sequence: the Radar
// Map, the hypothetical and the real sonar scan, the complementary readings, the operational and
// the tactical Accumulative Grid Map, the Current Sensor Map and the Sector Map, with the true
// obstacles beneath when the log has SIM_STATE and --scenario is given. --most-sonar picks the
// moment whose Sector Map holds the most sectors from the sonar (own, copied or remembered).
// Time is message time, in seconds from the earliest message on a drawn channel. The log is read
// twice (its span, then the pictures) and only a short history is kept, so any length of log works.
//
// Exit status: 0 ok; 1 a picture could not be drawn or written; 2 bad arguments, an unreadable
// log or scenario, or a time outside the log.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "core/cli.hpp"
#include "core/config.hpp"
#include "lcmio/eventlog.hpp"
#include "render/fig8.hpp"
#include "render/snapshot.hpp"
#include "core/same_file.hpp"
#include "sim/scenario.hpp"
#include "core/utime.hpp"

namespace {

using namespace lasonic;
using namespace lasonic::render;

constexpr const char* kName = "lasonic-render";
constexpr int64_t kMaxFrames = 100000;
// A frame is drawn once the log has moved this far past it (message time), so messages that a
// live log records a little out of order are still in it.
constexpr int64_t kLookaheadUs = 1'000'000;

std::string basename(const std::string& p) {
  const auto i = p.find_last_of('/');
  return i == std::string::npos ? p : p.substr(i + 1);
}

// OUT with a frame number before its ".png": frames.png -> frames-00012.png.
std::string framePath(const std::string& out, int64_t k) {
  char num[32];
  std::snprintf(num, sizeof num, "-%05lld", static_cast<long long>(k));
  const auto dot = out.rfind('.');
  const auto slash = out.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return out + num + ".png";
  return out.substr(0, dot) + num + out.substr(dot);
}

int fail(int code, const std::string& msg) {
  std::cerr << kName << ": " << msg << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // On every way out, after all drawing: Cairo's and fontconfig's caches freed.
  struct ReleaseAtExit {
    ~ReleaseAtExit() { releaseStaticData(); }
  } release_at_exit;
  CLI::App app{"lasonic-render: the paper's Fig. 8 panels (Radar Map, hypothetical and real sonar scan, "
               "complementary readings, operational and tactical AGM, Current Sensor Map, Sector Map) "
               "for one moment of an LCM log, as a PNG"};
  std::string log_path, out_path, scenario_path;
  std::optional<double> time_s, every_s;
  bool most_sonar = false;
  RenderOptions ro;
  app.add_option("--log", log_path, "LCM log (lasonic-replay output, or recorded live with lcm-logger)")->required();
  app.add_option("--out", out_path, "PNG to write; with --every, frames go to OUT with -00000, -00001, ... before its .png")->required();
  app.add_option("--time", time_s,
                 "moment to draw [s of message time from the log's start]; default: the end (with --every: the start)");
  app.add_option("--every", every_s, "write a frame every S seconds of message time, from --time to the end");
  app.add_flag("--most-sonar", most_sonar,
               "draw the moment whose SECTOR_MAP holds the most sectors from the sonar (its own value, a copy or "
               "the navigator's memory): where the laser alone shows least (instead of --time; the end if the "
               "log has no SECTOR_MAP)")
      ->excludes("--time")
      ->excludes("--every");
  app.add_option("--scenario", scenario_path, "scenario YAML the log was simulated from: true obstacles drawn faintly");
  app.add_option("--view", ro.view_m, "ground shown across each panel [m] (default 7)");
  app.add_option("--panel", ro.panel_px, "panel size [px] (default 400; the image is 4 x 2 panels)");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;

  try {
    checkOptions(ro);
  } catch (const RenderError& e) {
    return fail(2, e.what());
  }
  if (time_s && (!std::isfinite(*time_s) || *time_s < 0)) return fail(2, "--time: must be a number >= 0");
  if (every_s && (!std::isfinite(*every_s) || *every_s <= 0)) return fail(2, "--every: must be a number > 0");
  // A picture written over the log or the scenario would destroy what it was drawn from.
  auto overwritesInput = [&](const std::string& out) -> std::optional<std::string> {
    if (lasonic::sameExistingFile(out, log_path)) return "--out " + out + " is the --log file " + log_path + ": not overwritten";
    if (!scenario_path.empty() && lasonic::sameExistingFile(out, scenario_path))
      return "--out " + out + " is the --scenario file " + scenario_path + ": not overwritten";
    return std::nullopt;
  };
  if (!every_s)
    if (const auto why = overwritesInput(out_path)) return fail(2, *why);

  std::optional<sim::Scenario> scenario;
  if (!scenario_path.empty()) {
    try {
      scenario = sim::loadScenario(scenario_path);
    } catch (const ConfigError& e) {
      return fail(2, std::string("bad scenario: ") + e.what());
    }
  }

  // ---- pass 1: the log's span and channels
  LogInfo info;
  try {
    info = scanLog(log_path);
  } catch (const LogError& e) {
    return fail(2, e.what());
  }
  if (info.empty()) {
    std::string list;
    for (const auto& c : drawnChannels()) list += (list.empty() ? "" : ", ") + c;
    return fail(2, log_path + ": no lasonic message on any drawn channel (" + list + ") in " +
                       std::to_string(info.events) + " events: not an LCM log of lasonic, or empty");
  }
  if (info.undecodableTotal() > 0) {
    std::string per;
    for (const auto& [ch, n] : info.undecodable) per += " " + ch + " " + std::to_string(n);
    std::cerr << kName << ": warning: " << info.undecodableTotal()
              << " events did not decode (or had no message time) and are skipped:" << per << "\n";
  }
  const double duration = info.durationS();

  // ---- the moments to draw
  std::vector<double> frames;
  if (every_s) {
    // (Message times are microseconds, a display's frames tens of milliseconds apart.)
    if (!(*every_s >= 1e-3 && *every_s <= 1e6))
      return fail(2, "--every " + std::to_string(*every_s) + ": must be a step of 0.001 to 1e6 s");
    const double start = time_s.value_or(0.0);
    if (start > duration + 1e-6)
      return fail(2, "--time " + std::to_string(start) + " is after the log's end (" + std::to_string(duration) + " s)");
    const double n = std::floor((duration - start) / *every_s + 1e-9) + 1;
    if (n > kMaxFrames)
      return fail(2, "--every " + std::to_string(*every_s) + " would write " + std::to_string(static_cast<long long>(n)) +
                         " frames (at most " + std::to_string(kMaxFrames) + "): choose a larger step");
    for (int64_t k = 0; k < static_cast<int64_t>(n); ++k) frames.push_back(start + static_cast<double>(k) * *every_s);
    for (size_t k = 0; k < frames.size(); ++k)
      if (const auto why = overwritesInput(framePath(out_path, static_cast<int64_t>(k)))) return fail(2, *why);
  } else {
    if (most_sonar) {
      if (info.most_sonar_sectors < 0)
        std::cerr << kName << ": --most-sonar: the log has no SECTOR_MAP; drawing its end\n";
      else
        time_s = static_cast<double>(info.most_sonar_utime - info.start_utime) * 1e-6;
    }
    const double t = time_s.value_or(duration);
    if (t > duration + 1e-6) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "--time %.3f is outside the log: it spans 0 .. %.3f s of message time", t, duration);
      return fail(2, buf);
    }
    frames.push_back(t);
  }
  auto frameUtime = [&](double t) {
    return std::min(info.end_utime, info.start_utime + secondsToUs(t));
  };

  // ---- pass 2: the pictures
  const std::string log_name = basename(log_path);
  SnapshotCollector collector;
  bool scenario_mismatch = false;
  size_t next = 0;
  int64_t written = 0;
  auto emit = [&](size_t k) {
    const int64_t utime = frameUtime(frames[k]);
    Snapshot s = collector.at(utime);
    s.t_s = static_cast<double>(utime - info.start_utime) * 1e-6;
    s.duration_s = duration;
    s.log_name = log_name;
    for (const auto& [ch, n] : info.messages) s.in_log.insert(ch);
    const std::string path = every_s ? framePath(out_path, static_cast<int64_t>(k)) : out_path;
    // A scenario the log was not simulated from would draw a wrong truth under right maps: its
    // movers must be the log's (SIM_STATE names them by their index in the scenario), and its
    // robot on the scenario's path (the simulator drives the path's legs exactly; 1 m off it, as
    // lasonic-eval decides, is another scene).
    if (scenario && s.true_robot && !scenario_mismatch) {
      std::vector<int> ids;
      for (const auto& m : s.movers) ids.push_back(m.id);
      std::string why = sim::simStateMoversMismatch(*scenario, ids);
      if (const double d = sim::distanceToRobotPath(*scenario, s.true_robot->position());
          why.empty() && !(d <= sim::kRobotOffPathM)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "its robot's true pose (%g, %g) is %g m from the scenario's robot.path",
                      s.true_robot->x, s.true_robot->y, d);
        why = buf;
      }
      if (!why.empty()) {
        scenario_mismatch = true;
        std::fprintf(stderr, "%s: warning: %s was not simulated from %s (%s): no truth drawn\n", kName,
                     log_path.c_str(), scenario_path.c_str(), why.c_str());
      }
    }
    const auto status = writeFig8Png(path, s, scenario && !scenario_mismatch ? &*scenario : nullptr, ro);
    ++written;
    const auto size = fig8Size(ro);
    std::printf("%s: wrote %s (%d x %d px, t = %.2f s)\n", kName, path.c_str(), size.width, size.height, s.t_s);
    if (most_sonar && info.most_sonar_sectors >= 0)
      std::printf("  the moment of the most sectors from the sonar: %d of the Sector Map's\n", info.most_sonar_sectors);
    if (!every_s || k == 0)
      for (const auto& p : status)
        if (!p.drawn) std::printf("  panel %s %s: %s\n", p.letter.c_str(), p.title.c_str(), p.note.c_str());
    collector.forget(utime);
  };
  try {
    LogReader reader(log_path);
    while (auto r = reader.next()) {
      const auto t = collector.add(*r);
      if (!t) continue;
      while (next < frames.size() && *t > frameUtime(frames[next]) + kLookaheadUs) emit(next++);
      if (next == frames.size()) break;
    }
    while (next < frames.size()) emit(next++);
  } catch (const LogError& e) {
    return fail(2, e.what());
  } catch (const RenderError& e) {
    return fail(1, e.what());
  } catch (const std::exception& e) {
    return fail(1, std::string("failed: ") + e.what());
  }
  if (every_s) std::printf("%s: %lld frames\n", kName, static_cast<long long>(written));
  return 0;
}
