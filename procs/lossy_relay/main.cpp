// lasonic-lossy-relay: message loss on purpose, for testing (this project's kernels have no
// netem). Live: subscribes every channel on --from URL and republishes each message on --to URL,
// dropping a share --loss of the messages of the lossy channels. Offline (--in-log/--out-log):
// the same on a log file. Which messages are dropped is a pure function of (--seed, channel,
// index of the message on its channel): the same stream and seed drop the same messages, live or
// offline, whatever the timing.
//
//   lasonic-lossy-relay --from URL1 --to URL2 --loss 0.2 --seed 1
//   lasonic-lossy-relay --in-log raw.lcmlog --out-log lossy.lcmlog --loss 0.2 --seed 1
//
// By default the robot's own channels lose messages and the simulator's truth (SIM_STATE,
// SONAR_TRUTH, LASER_TRUTH: evaluation only, not part of a robot's network) passes untouched;
// --lossy REGEX chooses otherwise.
//
// --outage START:END (seconds, repeatable) drops every message of the lossy channels from START
// to END seconds after the first message (offline: by the log's timestamps; live: by this host's
// clock since the first message received): a driver that dies and comes back, e.g. a laser on a
// flaky USB link.
//
//   lasonic-lossy-relay --in-log raw.lcmlog --out-log outage.lcmlog --lossy LASER_SCAN --outage 15:25
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "core/cli.hpp"
#include "core/same_file.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/signals.hpp"

namespace {

// splitmix64: a good 64-bit mix, so neighbouring indices give independent draws.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
uint64_t hashString(const std::string& s) {
  uint64_t h = 1469598103934665603ULL;  // FNV-1a
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

struct Outage {
  int64_t start_us = 0, end_us = 0;  // after the first message, [start, end)
};

// "START:END" in seconds, 0 <= START < END.
std::optional<Outage> parseOutage(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) return std::nullopt;
  try {
    size_t used_a = 0, used_b = 0;
    const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
    const double s = std::stod(a, &used_a), e = std::stod(b, &used_b);
    if (used_a != a.size() || used_b != b.size() || !(s >= 0) || !(e > s) || !(e < 1e9)) return std::nullopt;
    return Outage{static_cast<int64_t>(std::llround(s * 1e6)), static_cast<int64_t>(std::llround(e * 1e6))};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

struct Dropper {
  double loss = 0;
  uint64_t seed = 1;
  std::regex lossy;
  std::vector<Outage> outages;
  std::optional<int64_t> first_us;
  std::map<std::string, int64_t> index, passed, dropped;
  // True: drop this message, which arrived (or was logged) at time_us.
  bool drop(const std::string& channel, int64_t time_us) {
    const int64_t i = index[channel]++;
    if (!first_us) first_us = time_us;
    bool d = false;
    if (std::regex_match(channel, lossy)) {
      for (const Outage& o : outages)
        if (time_us - *first_us >= o.start_us && time_us - *first_us < o.end_us) d = true;
      if (!d && loss > 0) {
        const uint64_t r = mix(mix(seed ^ hashString(channel)) + static_cast<uint64_t>(i));
        d = static_cast<double>(r >> 11) * 0x1.0p-53 < loss;
      }
    }
    ++(d ? dropped : passed)[channel];
    return d;
  }
  void report() const {
    for (const auto& [ch, n] : index) {
      const auto get = [&](const std::map<std::string, int64_t>& m) {
        const auto it = m.find(ch);
        return it == m.end() ? int64_t{0} : it->second;
      };
      std::printf("%s %lld passed %lld dropped\n", ch.c_str(), static_cast<long long>(get(passed)),
                  static_cast<long long>(get(dropped)));
    }
  }
};

struct Relay {
  lcm::LCM* to = nullptr;
  Dropper* dropper = nullptr;
  void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    if (channel == "LCM_SELF_TEST") return;
    const auto now = std::chrono::steady_clock::now().time_since_epoch();
    if (dropper->drop(channel, std::chrono::duration_cast<std::chrono::microseconds>(now).count())) return;
    to->publish(channel, rbuf->data, rbuf->data_size);
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-lossy-relay: relay LCM messages (live or log to log), dropping a seeded share of them or an outage"};
  std::string from, to, in_log, out_log, lossy = "^(?!SIM_STATE$|SONAR_TRUTH$|LASER_TRUTH$).*";
  Dropper d;
  app.add_option("--from", from, "LCM URL to listen on (live)");
  app.add_option("--to", to, "LCM URL to publish on (live); must differ from --from");
  app.add_option("--in-log", in_log, "input log (offline)");
  app.add_option("--out-log", out_log, "output log (offline)");
  app.add_option("--loss", d.loss, "share of the lossy channels' messages to drop")->check(lasonic::FiniteNumberIn(0.0, 1.0));
  app.add_option("--seed", d.seed, "seed of the drops")->capture_default_str();
  std::vector<std::string> outage_text;
  app.add_option("--outage", outage_text,
                 "START:END in seconds after the first message: drop every message of the lossy channels then "
                 "(repeatable)")
      ->allow_extra_args(false);
  app.add_option("--lossy", lossy, "regex of the channels that lose messages (default: all but the truth)")
      ->capture_default_str();
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
  try {
    d.lossy = std::regex(lossy, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    std::fprintf(stderr, "lasonic-lossy-relay: --lossy %s: %s\n", lossy.c_str(), e.what());
    return 2;
  }
  for (const auto& t : outage_text) {
    const auto o = parseOutage(t);
    if (!o) {
      std::fprintf(stderr, "lasonic-lossy-relay: --outage %s: expected START:END in seconds, 0 <= START < END\n",
                   t.c_str());
      return 2;
    }
    d.outages.push_back(*o);
  }
  const bool live = !from.empty() || !to.empty();
  const bool offline = !in_log.empty() || !out_log.empty();
  if (live == offline || (live && (from.empty() || to.empty() || from == to)) ||
      (offline && (in_log.empty() || out_log.empty()))) {
    std::fprintf(stderr, "lasonic-lossy-relay: give either --from URL1 --to URL2 (different) or --in-log and --out-log\n");
    return 2;
  }
  // The output is opened (truncated) before the input is read: the same file would be lost.
  if (offline && lasonic::sameExistingFile(out_log, in_log)) {
    std::fprintf(stderr, "lasonic-lossy-relay: --out-log %s is the --in-log file %s: not overwritten\n",
                 out_log.c_str(), in_log.c_str());
    return 2;
  }
  if (offline) {
    try {
      lasonic::LogReader in(in_log);
      lasonic::LogWriter out(out_log);
      while (auto ev = in.next())
        if (!d.drop(ev->channel, ev->timestamp)) out.writeRaw(ev->channel, ev->timestamp, ev->data);
    } catch (const lasonic::LogError& e) {
      std::fprintf(stderr, "lasonic-lossy-relay: %s\n", e.what());
      return 1;
    }
    d.report();
    return 0;
  }
  lcm::LCM src(from), dst(to);
  if (!src.good() || !dst.good()) {
    std::fprintf(stderr, "lasonic-lossy-relay: cannot open LCM (%s)\n", !src.good() ? from.c_str() : to.c_str());
    return 1;
  }
  Relay relay{&dst, &d};
  src.subscribe(".*", &Relay::onMessage, &relay);
  lasonic::shutdown::installHandlers();
  while (!lasonic::shutdown::requested()) src.handleTimeout(100);
  d.report();
  return 0;
}
