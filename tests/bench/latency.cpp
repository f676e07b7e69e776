// lasonic-latency --in LOG [--lcm-url URL] [--speed S] [--min-groups N]
//
// End-to-end latency of the live pipeline: plays a log's sensor channels (ODOMETRY, LASER_SCAN,
// SONAR_GEOMETRY, SONAR_RING) into LCM at S times real time, paced by the log's timestamps, and
// listens for SECTOR_MAP. A firing group's latency is the wall time from just before its
// SONAR_RING is published to the arrival of the first SECTOR_MAP whose sonar data is that group's
// (its sonar time, utime - sonar_age_s, equals the ring's utime: the pilot's map made by that
// group's SONAR_COMPLEMENT, whatever newer laser scan has moved the map's own utime on;
// README "Performance"). Prints one line
//   groups N matched M p50_ms A p99_ms B max_ms C
// and exits 1 if fewer than --min-groups groups were matched. Run it inside a private network
// namespace (tests/netns/in-netns.sh) with lasonic-complement and lasonic-pilot listening.
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <lasonic/sector_map_t.hpp>
#include <lasonic/sonar_ring_t.hpp>

#include "core/cli.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Listener {
  std::mutex mu;
  std::map<int64_t, Clock::time_point> first_map;  // sonar time of a sector map -> first arrival
  int64_t maps = 0;
  void onMap(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    const Clock::time_point now = Clock::now();
    lasonic::sector_map_t m;
    if (m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    std::lock_guard<std::mutex> lock(mu);
    ++maps;
    // The map's utime is the newest of its inputs (a laser scan's last reading can be newer than
    // the group that triggered it); its sonar time names the group.
    if (!std::isfinite(m.sonar_age_s) || m.sonar_age_s < 0) return;
    first_map.emplace(m.utime - std::llround(static_cast<double>(m.sonar_age_s) * 1e6), now);
  }
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<size_t>(std::min<double>(static_cast<double>(v.size() - 1), q * static_cast<double>(v.size())));
  return v[i];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lasonic-latency: SONAR_RING publish -> SECTOR_MAP arrival over live LCM"};
  std::string in_path, url = lasonic::kDefaultLcmUrl;
  double speed = 1.0, settle_s = 1.0;
  int64_t min_groups = 0;
  std::string samples_path;
  app.add_option("--in", in_path, "LCM log with the sensor channels (lasonic-sim's output)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--lcm-url", url, "LCM URL");
  app.add_option("--speed", speed, "play at this multiple of real time")->check(lasonic::FiniteNumberIn(1e-3, 1e3));
  app.add_option("--settle", settle_s, "seconds to wait for the last maps after the last group");
  app.add_option("--min-groups", min_groups, "exit 1 unless at least this many groups were matched");
  app.add_option("--samples", samples_path, "write each matched group's latency [ms] to this file");
  if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;

  lcm::LCM pub(url), sub(url);
  if (!pub.good() || !sub.good()) {
    std::cerr << "lasonic-latency: cannot open LCM with URL " << url << "\n";
    return 2;
  }
  Listener listener;
  sub.subscribe(lasonic::channels::SECTOR_MAP, &Listener::onMap, &listener);
  std::atomic<bool> stop{false};
  std::thread rx([&] {
    while (!stop) sub.handleTimeout(50);
  });

  const std::set<std::string> inputs = {lasonic::channels::ODOMETRY, lasonic::channels::LASER_SCAN,
                                        lasonic::channels::SONAR_GEOMETRY, lasonic::channels::SONAR_RING};
  std::map<int64_t, Clock::time_point> published;  // ring utime -> publish time
  lasonic::LogReader in(in_path);
  const Clock::time_point start = Clock::now() + std::chrono::milliseconds(500);  // subscribers ready
  std::optional<int64_t> t0;
  while (auto ev = in.next()) {
    if (!inputs.count(ev->channel)) continue;
    if (!t0) t0 = ev->timestamp;
    std::this_thread::sleep_until(start + std::chrono::microseconds(static_cast<int64_t>(
                                              static_cast<double>(ev->timestamp - *t0) / speed)));
    if (ev->channel == lasonic::channels::SONAR_RING) {
      lasonic::sonar_ring_t r;
      if (r.decode(ev->data.data(), 0, static_cast<int>(ev->data.size())) < 0) continue;
      published.emplace(r.utime, Clock::now());
    }
    pub.publish(ev->channel, ev->data.data(), static_cast<unsigned>(ev->data.size()));
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(settle_s));
  stop = true;
  rx.join();

  std::vector<double> ms;
  {
    std::lock_guard<std::mutex> lock(listener.mu);
    for (const auto& [utime, t_pub] : published) {
      const auto it = listener.first_map.find(utime);
      if (it == listener.first_map.end()) continue;
      ms.push_back(std::chrono::duration<double, std::milli>(it->second - t_pub).count());
    }
  }
  if (!samples_path.empty()) {
    if (FILE* f = std::fopen(samples_path.c_str(), "w")) {
      for (const double v : ms) std::fprintf(f, "%.4f\n", v);
      std::fclose(f);
    }
  }
  std::printf("groups %zu matched %zu p50_ms %.3f p99_ms %.3f max_ms %.3f\n", published.size(), ms.size(),
              quantile(ms, 0.5), quantile(ms, 0.99), ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()));
  return static_cast<int64_t>(ms.size()) >= min_groups ? 0 : 1;
}
