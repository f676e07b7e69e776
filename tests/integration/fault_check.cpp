// lasonic-fault-check: reads an lcm-logger log of a live run (event timestamps: the logger's wall
// clock, microseconds) and measures what the fault tests need; prints "key value" lines.
//   window LOG CHANNEL T0 T1         messages of CHANNEL received in [T0, T1): count, rate_hz,
//                                    max_gap_s, first_s (T0 to the first one; -1: none)
//   recovery LOG T_KILL T_END CHANNEL
//                                    after a kill at T_KILL: output_s (to the first CHANNEL message),
//                                    and fresh_s: to the first SECTOR_MAP with both sensors fresh
//                                    after the last one that was not (or after the kill); -1: never
//                                    before T_END
//   stale LOG T_STOP T_RESUME laser|sonar
//                                    a sensor driver frozen from T_STOP to T_RESUME: the SECTOR_MAP
//                                    must flag it stale and never report more free space than its last
//                                    fresh map did. Prints last_data_age... see below; exit 1 if a
//                                    sector got freer or the flag never came.
// Exit status: 0 ok (or measured), 1 check failed, 2 usage or unreadable log.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include <lasonic/sector_map_t.hpp>

#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"

using namespace lasonic;

namespace {

int64_t arg64(const char* s) { return std::strtoll(s, nullptr, 10); }
bool fresh(const sector_map_t& m) {
  return !m.laser_stale && !m.sonar_stale && m.laser_age_s >= 0 && m.sonar_age_s >= 0;
}

int window(const std::string& file, const std::string& channel, int64_t t0, int64_t t1) {
  int64_t n = 0, prev = t0, max_gap = 0, first = -1;
  LogReader log(file);
  while (auto ev = log.next()) {
    if (ev->channel != channel || ev->timestamp < t0 || ev->timestamp >= t1) continue;
    if (first < 0) first = ev->timestamp - t0;
    max_gap = std::max(max_gap, ev->timestamp - prev);
    prev = ev->timestamp;
    ++n;
  }
  max_gap = std::max(max_gap, t1 - prev);
  std::printf("count %lld\nrate_hz %.2f\nmax_gap_s %.3f\nfirst_s %.3f\n", static_cast<long long>(n),
              static_cast<double>(n) / (static_cast<double>(t1 - t0) * 1e-6), static_cast<double>(max_gap) * 1e-6,
              first < 0 ? -1.0 : static_cast<double>(first) * 1e-6);
  return 0;
}

int recovery(const std::string& file, int64_t t_kill, int64_t t_end, const std::string& channel) {
  int64_t output = -1, fresh_at = -1;  // log times; -1: not yet
  LogReader log(file);
  while (auto ev = log.next()) {
    if (ev->timestamp <= t_kill || ev->timestamp >= t_end) continue;
    if (output < 0 && ev->channel == channel) output = ev->timestamp;
    if (ev->channel != channels::SECTOR_MAP) continue;
    const auto m = decodeAs<sector_map_t>(ev->data);
    if (!m) continue;
    if (!fresh(*m)) fresh_at = -1;  // not yet recovered
    else if (fresh_at < 0) fresh_at = ev->timestamp;
  }
  // Recovered: the process's own output is back and the maps are fresh from then on.
  const auto s = [&](int64_t t) { return t >= 0 ? static_cast<double>(t - t_kill) * 1e-6 : -1.0; };
  std::printf("output_s %.3f\nfresh_s %.3f\n", s(output), s(fresh_at));
  if (output >= 0 && fresh_at >= 0) std::printf("recovered_s %.3f\n", std::max(s(output), s(fresh_at)));
  return output >= 0 && fresh_at >= 0 ? 0 : 1;
}

int stale(const std::string& file, int64_t t_stop, int64_t t_resume, bool laser) {
  LogReader log(file);
  std::optional<sector_map_t> last_fresh, first_stale;
  int64_t first_stale_ts = 0, maps_stale = 0, freer = 0, unflagged_after = 0;
  std::string freer_example;
  while (auto ev = log.next()) {
    if (ev->channel != channels::SECTOR_MAP || ev->timestamp >= t_resume) continue;
    const auto m = decodeAs<sector_map_t>(ev->data);
    if (!m) continue;
    const bool is_stale = laser ? m->laser_stale : m->sonar_stale;
    if (ev->timestamp < t_stop || !is_stale) {
      if (ev->timestamp >= t_stop && first_stale) ++unflagged_after;  // flag dropped while still stopped
      if (!is_stale) last_fresh = *m;
      continue;
    }
    if (!first_stale) {
      first_stale = *m;
      first_stale_ts = ev->timestamp;
    }
    ++maps_stale;
    if (!last_fresh) continue;
    const auto& was = laser ? last_fresh->laser_distance : last_fresh->sonar_distance;
    const auto& now = laser ? m->laser_distance : m->sonar_distance;
    for (size_t k = 0; k < now.size() && k < was.size(); ++k) {
      // -1: nothing seen (free); a held value may only get nearer.
      const bool freer_here = was[k] >= 0 && (now[k] < 0 || now[k] > was[k] + 1e-4f);
      const bool total_freer = was[k] >= 0 && (m->distance[k] < 0 || m->distance[k] > was[k] + 1e-4f);
      if (freer_here || total_freer) {
        if (freer == 0)
          freer_example = "sector " + std::to_string(k) + ": last fresh " + std::to_string(was[k]) + " m, stale " +
                          std::to_string(now[k]) + " m, distance " + std::to_string(m->distance[k]) + " m";
        ++freer;
      }
    }
  }
  if (!first_stale || !last_fresh) {
    std::printf("stale_flagged 0\n");
    std::fprintf(stderr, "lasonic-fault-check: no SECTOR_MAP flagged the %s stale\n", laser ? "laser" : "sonar");
    return 1;
  }
  const double age = laser ? first_stale->laser_age_s : first_stale->sonar_age_s;
  std::printf("stale_flagged 1\nstale_age_s %.3f\nstale_after_last_fresh_map_s %.3f\nstale_after_stop_s %.3f\n"
              "maps_stale %lld\nmaps_freer %lld\nflag_dropped %lld\n",
              age, static_cast<double>(first_stale->utime - last_fresh->utime) * 1e-6,
              static_cast<double>(first_stale_ts - t_stop) * 1e-6, static_cast<long long>(maps_stale),
              static_cast<long long>(freer), static_cast<long long>(unflagged_after));
  if (freer > 0) std::fprintf(stderr, "lasonic-fault-check: a stale map is freer than the last fresh one: %s\n",
                              freer_example.c_str());
  return freer == 0 && unflagged_after == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  try {
    if (mode == "window" && argc == 6) return window(argv[2], argv[3], arg64(argv[4]), arg64(argv[5]));
    if (mode == "recovery" && argc == 6) return recovery(argv[2], arg64(argv[3]), arg64(argv[4]), argv[5]);
    if (mode == "stale" && argc == 6 && (std::string(argv[5]) == "laser" || std::string(argv[5]) == "sonar"))
      return stale(argv[2], arg64(argv[3]), arg64(argv[4]), std::string(argv[5]) == "laser");
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-fault-check: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr,
               "usage: lasonic-fault-check window LOG CHANNEL T0 T1 | recovery LOG T_KILL T_END CHANNEL |\n"
               "       stale LOG T_STOP T_RESUME laser|sonar   (times: log timestamps, us)\n");
  return 2;
}
