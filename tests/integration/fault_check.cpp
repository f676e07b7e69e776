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
//   maps LOG_A LOG_B CHANNEL [FROM_UTIME]
//                                    grid maps (AGM_TACTICAL, AGM_OPERATIONAL) of two logs, matched by
//                                    their utime (from FROM_UTIME on): maps_a, maps_b, matched,
//                                    identical (every byte), and over the matched maps the occupied
//                                    cells (Gp >= the map's gp_threshold, global cell coordinates):
//                                    union, differing (in one map only), differing_share (pooled),
//                                    worst_share (the worst map), b_in_a (of B's occupied cells, the
//                                    share A has: what a restarted process has rebuilt of its memory);
//                                    one "series UTIME occupied_a occupied_b common identical" line
//                                    per matched map
//   nearest LOG_A LOG_B CHANNEL [FROM_UTIME]
//                                    as maps, but each map of A is matched with B's latest one at or
//                                    before it (within 1 s): for maps published at another phase (a
//                                    restarted process against one that ran throughout; a live one
//                                    that got a message the log lacks)
//   same LOG_A LOG_B CHANNEL [FROM_UTIME]
//                                    any channel whose messages start with their utime: matched,
//                                    identical (bytes)
//   remembered LOG T_CUT T_RESTORE T_END
//                                    the pilot's remembered source (AGM_TACTICAL from another host)
//                                    across a link cut in [T_CUT, T_RESTORE): fresh_before (share of
//                                    SECTOR_MAP with it fresh in the 2 s before the cut),
//                                    sectors_remembered_before, stale_after_cut_s (log time to the
//                                    first map flagging it stale) and stale_age_s (its age then),
//                                    fresh_after_restore_s, and the violations (exit 1 if any):
//                                    used_while_stale (a sector sourced REMEMBERED, or a remembered
//                                    distance, in a map flagging it stale), fresh_during_cut (fresh
//                                    again before the restore, after it had gone stale)
//   laser-nearer LOG_A LOG_B T0 T1   SECTOR_MAP of two logs matched by utime, the maps of [T0, T1)
//                                    (utime) that flag the laser stale in both: matched, and of
//                                    their sectors' laser distances (none: infinitely far)
//                                    a_nearer and a_farther than B's; exit 1 if any is farther or
//                                    none nearer (A's stale laser values are B's plus more)
//   slice LOG OUT T0 [T1]            OUT = the events of LOG from log time T0 on (before T1)
//   starts LOG T0 T1                 the log times of LOG's events in [T0, T1), one per line
//   record URL OUT REGEX             records the channels matching REGEX to OUT (receive times,
//                                    as lcm-logger: evidently when LCM read the message, late by
//                                    however long the recorder was descheduled) until SIGINT/SIGTERM; says "... running" on
//                                    stderr once subscribed. Unlike lcm-logger (30 queued messages,
//                                    the rest of a burst dropped) it queues 100 000, so that a
//                                    recorder descheduled on a loaded machine loses nothing
// Exit status: 0 ok (or measured), 1 check failed, 2 usage or unreadable log.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <lasonic/grid_map_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "lcmio/signals.hpp"

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

// The utime a message starts with (grid_map_t, line_map_t, sector_map_t: the first field, after
// the 8-byte fingerprint, big-endian); nullopt if too short.
std::optional<int64_t> leadingUtime(const std::vector<uint8_t>& d) {
  if (d.size() < 16) return std::nullopt;
  uint64_t v = 0;
  for (size_t i = 8; i < 16; ++i) v = (v << 8) | d[i];
  return static_cast<int64_t>(v);
}

// CHANNEL's messages of a log by utime (the last one of a utime wins; none repeat in our logs).
std::map<int64_t, std::vector<uint8_t>> byUtime(const std::string& file, const std::string& channel, int64_t from) {
  std::map<int64_t, std::vector<uint8_t>> out;
  LogReader log(file);
  while (auto ev = log.next()) {
    if (ev->channel != channel) continue;
    const auto t = leadingUtime(ev->data);
    if (t && *t >= from) out[*t] = std::move(ev->data);
  }
  return out;
}

using Cells = std::set<std::pair<int64_t, int64_t>>;
Cells occupied(const grid_map_t& g) {
  Cells c;
  if (!(g.cell_size > 0)) return c;
  const int64_t ox = std::llround(g.origin_x / g.cell_size), oy = std::llround(g.origin_y / g.cell_size);
  const int thr = std::max(1, g.gp_threshold);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const size_t k = static_cast<size_t>(iy) * static_cast<size_t>(g.width) + static_cast<size_t>(ix);
      if (k < g.gp.size() && g.gp[k] >= thr) c.insert({ox + ix, oy + iy});
    }
  return c;
}

// nearest: match each map of A with B's latest at or before it (within 1 s) instead of B's of the
// same utime: two processes started at different times publish at different phases.
int compareMaps(const std::string& a_file, const std::string& b_file, const std::string& channel, int64_t from,
                bool grid, bool nearest = false) {
  const auto a = byUtime(a_file, channel, from), b = byUtime(b_file, channel, nearest ? 0 : from);
  int64_t matched = 0, identical = 0, uni = 0, differing = 0, b_total = 0, common_total = 0;
  double worst = 0;
  std::vector<std::string> series;
  for (const auto& [t, da] : a) {
    auto it = b.find(t);
    if (nearest) {
      it = b.upper_bound(t);
      if (it == b.begin()) continue;
      --it;
      if (t - it->first > 1'000'000) continue;
    }
    if (it == b.end()) continue;
    ++matched;
    if (da == it->second) ++identical;
    if (!grid) continue;
    const auto ga = decodeAs<grid_map_t>(da), gb = decodeAs<grid_map_t>(it->second);
    if (!ga || !gb) continue;
    const Cells ca = occupied(*ga), cb = occupied(*gb);
    int64_t common = 0;
    for (const auto& c : ca) common += cb.count(c);
    const int64_t u = static_cast<int64_t>(ca.size() + cb.size()) - common;
    const int64_t d = u - common;
    uni += u;
    differing += d;
    b_total += static_cast<int64_t>(cb.size());
    common_total += common;
    if (u > 0) worst = std::max(worst, static_cast<double>(d) / static_cast<double>(u));
    series.push_back("series " + std::to_string(t) + " " + std::to_string(ca.size()) + " " + std::to_string(cb.size()) +
                     " " + std::to_string(common) + " " + (da == it->second ? "1" : "0"));
  }
  std::printf("maps_a %zu\nmaps_b %zu\nmatched %lld\nidentical %lld\n", a.size(), b.size(),
              static_cast<long long>(matched), static_cast<long long>(identical));
  if (grid) {
    std::printf("union %lld\ndiffering %lld\ndiffering_share %.5f\nworst_share %.5f\nb_in_a %.5f\n",
                static_cast<long long>(uni), static_cast<long long>(differing),
                uni > 0 ? static_cast<double>(differing) / static_cast<double>(uni) : 0.0, worst,
                b_total > 0 ? static_cast<double>(common_total) / static_cast<double>(b_total) : 1.0);
    for (const auto& l : series) std::printf("%s\n", l.c_str());
  }
  return 0;
}

int laserNearer(const std::string& a_file, const std::string& b_file, int64_t t0, int64_t t1) {
  const auto a = byUtime(a_file, channels::SECTOR_MAP, t0), b = byUtime(b_file, channels::SECTOR_MAP, t0);
  int64_t matched = 0, nearer = 0, farther = 0;
  const auto far = [](float d) { return d < 0 ? std::numeric_limits<double>::infinity() : static_cast<double>(d); };
  for (const auto& [t, da] : a) {
    if (t >= t1) break;
    const auto it = b.find(t);
    if (it == b.end()) continue;
    const auto ma = decodeAs<sector_map_t>(da), mb = decodeAs<sector_map_t>(it->second);
    if (!ma || !mb || !ma->laser_stale || !mb->laser_stale || ma->laser_distance.size() != mb->laser_distance.size())
      continue;
    ++matched;
    for (size_t k = 0; k < ma->laser_distance.size(); ++k) {
      const double x = far(ma->laser_distance[k]), y = far(mb->laser_distance[k]);
      nearer += x < y;
      farther += x > y;
    }
  }
  std::printf("matched %lld\na_nearer %lld\na_farther %lld\n", static_cast<long long>(matched),
              static_cast<long long>(nearer), static_cast<long long>(farther));
  return matched > 0 && nearer > 0 && farther == 0 ? 0 : 1;
}

int remembered(const std::string& file, int64_t t_cut, int64_t t_restore, int64_t t_end) {
  LogReader log(file);
  int64_t before = 0, fresh_before = 0, sectors_before = 0, stale_at = -1, fresh_again = -1, used_stale = 0,
          fresh_during = 0;
  double stale_age = -1;
  while (auto ev = log.next()) {
    if (ev->channel != channels::SECTOR_MAP || ev->timestamp < t_cut - 2'000'000 || ev->timestamp >= t_end) continue;
    const auto m = decodeAs<sector_map_t>(ev->data);
    if (!m) continue;
    const bool stale = m->remembered_stale != 0;
    int64_t used = 0;
    for (size_t k = 0; k < m->source.size(); ++k)
      used += m->source[k] == sector_map_t::SOURCE_REMEMBERED ||
              (k < m->remembered_distance.size() && m->remembered_distance[k] != -1.0f);
    if (stale && used > 0) ++used_stale;
    if (ev->timestamp < t_cut) {
      ++before;
      if (!stale) ++fresh_before;
      for (const int8_t s : m->source) sectors_before += s == sector_map_t::SOURCE_REMEMBERED;
    } else if (ev->timestamp < t_restore) {
      if (stale && stale_at < 0) {
        stale_at = ev->timestamp;
        stale_age = m->remembered_age_s;
      }
      if (!stale && stale_at >= 0) ++fresh_during;
    } else if (!stale && fresh_again < 0) {
      fresh_again = ev->timestamp;
    }
  }
  const auto s = [](int64_t t, int64_t t0) { return t >= 0 ? static_cast<double>(t - t0) * 1e-6 : -1.0; };
  std::printf("maps_before %lld\nfresh_before %.3f\nsectors_remembered_before %lld\nstale_after_cut_s %.3f\n"
              "stale_age_s %.3f\nfresh_after_restore_s %.3f\nused_while_stale %lld\nfresh_during_cut %lld\n",
              static_cast<long long>(before), before > 0 ? static_cast<double>(fresh_before) / static_cast<double>(before) : 0.0,
              static_cast<long long>(sectors_before), s(stale_at, t_cut), stale_age, s(fresh_again, t_restore),
              static_cast<long long>(used_stale), static_cast<long long>(fresh_during));
  return used_stale == 0 && fresh_during == 0 ? 0 : 1;
}

int slice(const std::string& in, const std::string& out, int64_t t0, int64_t t1) {
  LogReader log(in);
  LogWriter w(out);
  while (auto ev = log.next())
    if (ev->timestamp >= t0 && ev->timestamp < t1) w.writeRaw(ev->channel, ev->timestamp, ev->data);
  std::printf("events %lld\n", static_cast<long long>(w.events()));
  return 0;
}

// The timestamps of the events in [t0, t1), one per line (the starts a slice can have there).
int starts(const std::string& in, int64_t t0, int64_t t1) {
  LogReader log(in);
  while (auto ev = log.next())
    if (ev->timestamp >= t0 && ev->timestamp < t1) std::printf("%lld\n", static_cast<long long>(ev->timestamp));
  return 0;
}

struct Recorder {
  LogWriter& out;
  void handle(const lcm::ReceiveBuffer* rb, const std::string& channel) {
    out.writeRaw(channel, rb->recv_utime, static_cast<const uint8_t*>(rb->data), rb->data_size);
  }
};

int record(const std::string& url, const std::string& path, const std::string& regex) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "lasonic-fault-check: cannot open LCM %s\n", url.c_str());
    return 2;
  }
  LogWriter out(path);
  Recorder rec{out};
  lcm::Subscription* sub = lcm.subscribe(regex, &Recorder::handle, &rec);
  sub->setQueueCapacity(100000);
  shutdown::installHandlers();
  // The line a test waits for, as a lasonic process's (tests/integration/lib.sh, wait_ready).
  std::fprintf(stderr, "lasonic-fault-check: recording %s to %s: running\n", regex.c_str(), path.c_str());
  while (!shutdown::requested()) lcm.handleTimeout(100);
  while (lcm.handleTimeout(0) > 0) {
  }  // what is queued already
  out.flush();
  std::printf("events %lld\n", static_cast<long long>(out.events()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  try {
    if (mode == "window" && argc == 6) return window(argv[2], argv[3], arg64(argv[4]), arg64(argv[5]));
    if (mode == "recovery" && argc == 6) return recovery(argv[2], arg64(argv[3]), arg64(argv[4]), argv[5]);
    if (mode == "stale" && argc == 6 && (std::string(argv[5]) == "laser" || std::string(argv[5]) == "sonar"))
      return stale(argv[2], arg64(argv[3]), arg64(argv[4]), std::string(argv[5]) == "laser");
    if ((mode == "maps" || mode == "same" || mode == "nearest") && (argc == 5 || argc == 6))
      return compareMaps(argv[2], argv[3], argv[4], argc == 6 ? arg64(argv[5]) : 0, mode != "same", mode == "nearest");
    if (mode == "laser-nearer" && argc == 6) return laserNearer(argv[2], argv[3], arg64(argv[4]), arg64(argv[5]));
    if (mode == "remembered" && argc == 6) return remembered(argv[2], arg64(argv[3]), arg64(argv[4]), arg64(argv[5]));
    if (mode == "record" && argc == 5) return record(argv[2], argv[3], argv[4]);
    if (mode == "starts" && argc == 5) return starts(argv[2], arg64(argv[3]), arg64(argv[4]));
    if (mode == "slice" && (argc == 5 || argc == 6))
      return slice(argv[2], argv[3], arg64(argv[4]), argc == 6 ? arg64(argv[5]) : std::numeric_limits<int64_t>::max());
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-fault-check: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr,
               "usage: lasonic-fault-check window LOG CHANNEL T0 T1 | recovery LOG T_KILL T_END CHANNEL |\n"
               "       stale LOG T_STOP T_RESUME laser|sonar | maps|nearest|same LOG_A LOG_B CHANNEL [FROM_UTIME] |\n"
               "       laser-nearer LOG_A LOG_B T0 T1 | remembered LOG T_CUT T_RESTORE T_END |\n"
               "       slice LOG OUT T0 [T1] | starts LOG T0 T1 |\n"
               "       record URL OUT REGEX\n"
               "       (times: log timestamps, us)\n");
  return 2;
}
