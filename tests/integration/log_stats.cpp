// lasonic-log-stats LOG: what an LCM log holds, as "key value" lines for scripts (awk '$1 == k').
//   first_us                       the first event's timestamp [us]
//   span_s                         first to last event timestamp [s]
//   <CHANNEL> <count>              events per channel
//   <CHANNEL>.rate_hz <rate>       (count - 1) / (first to last event of the channel)
//   <CHANNEL>.max_gap_s <gap>      the longest time between two of the channel's events [s]
//   LASER_SCAN.readings <n>        readings per scan (of the last scan)
//   LASER_SCAN.ok_fraction <f>     fraction of all readings with FLAG_OK
//   <process>.<counter> <value>    from each process's last PROCESS_STATUS: errors, and counters
// Exit status: 0, or 2 when the log cannot be read or holds no event (a recording that failed).
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>

#include <lasonic/laser_scan_t.hpp>
#include <lasonic/process_status_t.hpp>

#include "lcmio/eventlog.hpp"

using namespace lasonic;

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]) == "--help") {
    std::fprintf(stderr, "usage: lasonic-log-stats LOG   (prints 'key value' lines)\n");
    return argc == 2 ? 0 : 2;
  }
  struct Channel {
    int64_t count = 0, first = 0, last = 0, max_gap = 0;
  };
  std::map<std::string, Channel> channels;
  std::map<std::string, process_status_t> status;
  int64_t first = 0, last = 0, events = 0, readings = 0, ok = 0, scan_size = 0;
  try {
    LogReader log(argv[1]);
    while (auto e = log.next()) {
      if (events++ == 0) first = e->timestamp;
      last = e->timestamp;
      Channel& c = channels[e->channel];
      if (c.count++ == 0) c.first = e->timestamp;
      else c.max_gap = std::max(c.max_gap, e->timestamp - c.last);
      c.last = e->timestamp;
      if (e->channel == "LASER_SCAN") {
        if (auto s = decodeAs<laser_scan_t>(e->data)) {
          scan_size = s->nranges;
          for (int8_t f : s->flags) ok += f == laser_scan_t::FLAG_OK ? 1 : 0;
          readings += s->nranges;
        }
      } else if (e->channel == "PROCESS_STATUS") {
        if (auto s = decodeAs<process_status_t>(e->data)) status[s->process] = *s;
      }
    }
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-log-stats: %s\n", e.what());
    return 2;
  }
  if (events == 0) {
    std::fprintf(stderr, "lasonic-log-stats: %s: no event in the log\n", argv[1]);
    return 2;
  }
  std::printf("events %lld\nfirst_us %lld\nspan_s %.3f\n", static_cast<long long>(events),
              static_cast<long long>(first), static_cast<double>(last - first) * 1e-6);
  for (const auto& [name, c] : channels) {
    const double span = static_cast<double>(c.last - c.first) * 1e-6;
    std::printf("%s %lld\n%s.rate_hz %.2f\n%s.max_gap_s %.3f\n", name.c_str(), static_cast<long long>(c.count),
                name.c_str(), span > 0 ? static_cast<double>(c.count - 1) / span : 0.0, name.c_str(),
                static_cast<double>(c.max_gap) * 1e-6);
  }
  if (readings > 0)
    std::printf("LASER_SCAN.readings %lld\nLASER_SCAN.ok_fraction %.4f\n", static_cast<long long>(scan_size),
                static_cast<double>(ok) / static_cast<double>(readings));
  for (const auto& [process, s] : status) {
    std::printf("%s.errors %lld\n", process.c_str(), static_cast<long long>(s.errors));
    for (size_t i = 0; i < s.counter_names.size() && i < s.counter_values.size(); ++i)
      std::printf("%s.%s %lld\n", process.c_str(), s.counter_names[i].c_str(),
                  static_cast<long long>(s.counter_values[i]));
  }
  return 0;
}
