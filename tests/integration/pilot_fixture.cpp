// lasonic-pilot-fixture: helper of the pilot's integration test (pilot.sh).
//   lasonic-pilot-fixture feed URL   publish a scripted input: ODOMETRY (robot standing at (1, 2)
//                                    facing +x, 0..1.5 s), two undecodable SONAR_COMPLEMENT
//                                    messages, one LASER_SCAN (one return 1 m to the left) and 34
//                                    firing groups (0.30..1.29 s, one complementary echo at
//                                    (2.05, 2.05), 1 m ahead; group 5 also carries a NaN reading
//                                    and an unknown class)
//   lasonic-pilot-fixture check LOG  check the pilot's SECTOR_MAP / AGM_OPERATIONAL /
//                                    PROCESS_STATUS in an lcm-logger log; print "key value" lines
// Exit status: 0 ok, 1 check failed, 2 usage or I/O error.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/odometry_t.hpp>
#include <lasonic/process_status_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "lcmio/eventlog.hpp"
#include "lcmio/lengths.hpp"

using namespace lasonic;

namespace {

constexpr double kPi = 3.14159265358979323846;

template <typename T>
void send(lcm::LCM& lcm, const char* channel, T& msg) {
  setLengths(msg);
  lcm.publish(channel, &msg);
  // Paced so that no datagram is lost in a socket buffer.
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

complement_reading_t reading(int8_t cls, double x, double y) {
  complement_reading_t r{};
  r.cls = cls;
  r.range = 1.0f;
  r.hypothetical_range = 2.2f;
  r.end_x = x;
  r.end_y = y;
  r.beam_width = 0.5236f;  // 30 deg
  return r;
}

int feed(const std::string& url) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "lasonic-pilot-fixture: cannot open LCM %s\n", url.c_str());
    return 2;
  }
  for (int64_t t = 0; t <= 1'500'000; t += 20'000) {
    odometry_t o{};
    o.utime = t;
    o.pose = {1.0, 2.0, 0.0};
    send(lcm, "ODOMETRY", o);
  }
  const char junk[] = "not an lcm message";
  for (int i = 0; i < 2; ++i) lcm.publish("SONAR_COMPLEMENT", junk, sizeof junk);

  laser_scan_t s{};
  s.utime = 100'000;
  s.angle_min = -kPi;
  s.angle_increment = 2 * kPi / 720;
  s.range_min = 0.05f;
  s.range_max = 15.0f;
  for (int i = 0; i < 720; ++i) {
    s.ranges.push_back(0.0f);
    s.flags.push_back(static_cast<int8_t>(i == 540 ? 0 : 1));  // FLAG_OK only at +90 deg
    s.offset_us.push_back(i * 200'000 / 720);
  }
  s.ranges[540] = 1.0f;
  send(lcm, "LASER_SCAN", s);

  int group = 0;
  for (int64_t t = 300'000; t < 1'300'000; t += 30'000, ++group) {
    complement_t c{};
    c.utime = t;
    c.group = static_cast<int16_t>(group % 6);
    c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, 2.05, 2.05));
    if (group == 5) {
      c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY,
                                   std::numeric_limits<double>::quiet_NaN(), 1.0));
      c.readings.push_back(reading(9, 1.0, 1.0));
    }
    send(lcm, "SONAR_COMPLEMENT", c);
  }
  return 0;
}

int failures = 0;
void expect(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "lasonic-pilot-fixture: FAIL: %s\n", what.c_str());
    ++failures;
  }
}
bool near(double a, double b) { return std::abs(a - b) < 1e-4; }

int check(const std::string& file) {
  std::vector<sector_map_t> maps;
  std::vector<grid_map_t> grids;
  process_status_t status{};
  bool have_status = false;
  try {
    LogReader log(file);
    while (auto rec = log.next()) {
      if (rec->channel == "SECTOR_MAP") {
        const auto m = decodeAs<sector_map_t>(rec->data);
        expect(m.has_value(), "SECTOR_MAP decodes");
        if (m) maps.push_back(*m);
      } else if (rec->channel == "AGM_OPERATIONAL") {
        const auto m = decodeAs<grid_map_t>(rec->data);
        expect(m.has_value(), "AGM_OPERATIONAL decodes");
        if (m) grids.push_back(*m);
      } else if (rec->channel == "PROCESS_STATUS") {
        const auto m = decodeAs<process_status_t>(rec->data);
        if (m && m->process == "lasonic-pilot") {
          status = *m;
          have_status = true;
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lasonic-pilot-fixture: %s\n", e.what());
    return 2;
  }
  std::printf("SECTOR_MAP %zu\nAGM_OPERATIONAL %zu\n", maps.size(), grids.size());
  // One map per laser scan and per firing group; the AGM at 2 Hz of message time.
  expect(maps.size() == 35, "35 SECTOR_MAP messages (1 laser scan + 34 groups)");
  expect(grids.size() == 2, "2 AGM_OPERATIONAL messages (0.30 s and 0.81 s)");
  if (maps.size() == 35) {
    const sector_map_t& first = maps.front();
    expect(first.nsectors == 48, "48 sectors");
    expect(near(first.distance[36], 0.65) && first.source[36] == sector_map_t::SOURCE_LASER,
           "first map: laser 0.65 m to the left (sector 36)");
    expect(first.sonar_stale == 1 && first.sonar_age_s == -1.0f, "first map: sonar never heard (stale, age -1)");
    const sector_map_t& last = maps.back();
    std::printf("last.distance[24] %.4f\nlast.source[24] %d\nlast.laser_stale %d\n", last.distance[24],
                last.source[24], last.laser_stale);
    expect(near(last.distance[24], 0.65) && last.source[24] == sector_map_t::SOURCE_SONAR,
           "last map: sonar 0.65 m ahead (sector 24)");
    expect(last.source[23] == sector_map_t::SOURCE_SONAR_COPIED && last.source[25] == sector_map_t::SOURCE_SONAR_COPIED,
           "last map: sonar value copied into sectors 23 and 25");
    expect(last.laser_stale == 1 && near(last.distance[36], 0.65), "last map: laser stale, its value held");
    expect(last.utime == 1'290'000, "last map at the last group's time");
  }
  if (grids.size() == 2) {
    const grid_map_t& g = grids[1];
    std::printf("agm.utime %lld\nagm.g_echo %d\n", static_cast<long long>(g.utime), g.g[5060]);
    expect(g.utime == 810'000, "second AGM at 0.81 s");
    expect(g.width == 100 && g.height == 100 && g.ncells == 10000, "AGM 100 x 100");
    expect(near(g.origin_x, -4.0) && near(g.origin_y, -3.0), "AGM window centred on the robot's cell");
    expect(g.g[5060] == 18 && g.gp[5060] == 18 && g.h[5060] == 0, "echo cell G = Gp = 18, H = 0");
  }
  expect(have_status, "a PROCESS_STATUS of lasonic-pilot");
  if (have_status) {
    std::printf("errors %lld\n", static_cast<long long>(status.errors));
    int64_t nan = -1, cls = -1, decode = -1, lcm_failures = 0;
    for (size_t i = 0; i < status.counter_names.size(); ++i) {
      if (status.counter_names[i] == "rejected.complement_nan") nan = status.counter_values[i];
      if (status.counter_names[i] == "rejected.complement_class") cls = status.counter_values[i];
      if (status.counter_names[i] == "decode_errors.SONAR_COMPLEMENT") decode = status.counter_values[i];
      if (status.counter_names[i] == "lcm_failures") lcm_failures = status.counter_values[i];
    }
    expect(nan == 1 && cls == 1 && decode == 2, "bad input counted: 1 NaN reading, 1 unknown class, 2 undecodable");
    // The final status, sent on SIGTERM, may count the interrupted wait as an lcm_failure.
    expect(status.errors - lcm_failures == 4, "4 input errors in PROCESS_STATUS");
  }
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (argc == 3 && mode == "feed") return feed(argv[2]);
  if (argc == 3 && mode == "check") return check(argv[2]);
  std::fprintf(stderr, "usage: lasonic-pilot-fixture feed URL | check LOG\n");
  return 2;
}
