// lasonic-complement-check: helper of the complement integration test (complement.sh).
//   lasonic-complement-check publish URL   publish the paper's Fig. 4 fixture: ODOMETRY, one
//                                          LASER_SCAN, the 24-sonar ring in six firing groups
//                                          (two specular readings, one beyond the limit, one NaN)
//   lasonic-complement-check log FILE      check lasonic-complement's outputs in an LCM log
// Exit status: 0 ok, 1 the outputs are wrong, 2 usage or I/O error.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <thread>

#include <lasonic/complement_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/process_status_t.hpp>

#include "complement_fixture.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"

using namespace lasonic;

namespace {

// Fig. 4 sensors (see tests/unit/test_complement.cpp): door, obstacle, two specular, beyond
// the limit, a NaN, and three that see only a wall.
constexpr int kDoor = 6, kObstacle = 21, kSpecular1 = 3, kSpecular2 = 15, kBeyond = 9, kNaN = 10;
const int kWalls[] = {0, 12, 18};
constexpr int64_t kFiring0 = 150'000, kGroupPeriod = 30'000;

template <typename T>
void send(lcm::LCM& lcm, const char* channel, T msg) {
  setLengths(msg);
  lcm.publish(channel, &msg);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));  // no burst for the UDP buffers
}

int publish(const std::string& url) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "lasonic-complement-check: cannot open LCM %s\n", url.c_str());
    return 2;
  }
  const auto world = fixture::fig4Room();
  const auto traj = fixture::still(fixture::fig4RobotPose());
  for (int64_t t = 0; t <= 400'000; t += 20'000) send(lcm, channels::ODOMETRY, fixture::odometryAt(traj, t));
  send(lcm, channels::LASER_SCAN, fixture::simulateScan(world, traj, 0, 100'000));
  std::vector<double> real = fixture::trueRing(world, traj(0));
  real[kSpecular1] = real[kSpecular2] = 2.15;
  real[kBeyond] = 2.8;
  real[kNaN] = std::numeric_limits<double>::quiet_NaN();
  for (int g = 0; g < 6; ++g) {
    std::vector<int> ids;
    std::vector<double> ranges;
    for (int k = g; k < 24; k += 6) {
      ids.push_back(k);
      ranges.push_back(real[static_cast<size_t>(k)]);
    }
    send(lcm, channels::SONAR_RING, fixture::sonarGroup(kFiring0 + g * kGroupPeriod, g, ids, ranges));
  }
  return 0;
}

int fail(const std::string& why) {
  std::fprintf(stderr, "lasonic-complement-check: FAIL: %s\n", why.c_str());
  return 1;
}

int checkLog(const std::string& file) {
  std::map<std::string, int> count;
  std::map<int, int> cls;  // sensor id -> class
  int segments = -1;
  std::map<std::string, int64_t> counters;
  try {
    for (const auto& rec : LogReader::readAll(file)) {
      ++count[rec.channel];
      if (rec.channel == channels::RADAR_MAP) {
        const auto m = decodeAs<line_map_t>(rec.data);
        if (!m) return fail("RADAR_MAP does not decode");
        segments = m->nsegments;
      } else if (rec.channel == channels::SONAR_HYPOTHESIS) {
        const auto h = decodeAs<hypothetical_scan_t>(rec.data);
        if (!h || h->radar_map_stale) return fail("SONAR_HYPOTHESIS does not decode or is stale");
      } else if (rec.channel == channels::SONAR_COMPLEMENT) {
        const auto c = decodeAs<complement_t>(rec.data);
        if (!c || c->radar_map_stale) return fail("SONAR_COMPLEMENT does not decode or is stale");
        for (const auto& r : c->readings) cls[r.sensor_id] = r.cls;
      } else if (rec.channel == channels::PROCESS_STATUS) {
        const auto s = decodeAs<process_status_t>(rec.data);
        if (s && s->process == "lasonic-complement")
          for (size_t i = 0; i < s->counter_names.size(); ++i) counters[s->counter_names[i]] = s->counter_values[i];
      }
    }
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-complement-check: %s\n", e.what());
    return 2;
  }
  for (const auto& [ch, n] : count) std::printf("%s %d\n", ch.c_str(), n);
  for (const auto& [k, v] : counters) std::printf("complement.%s %lld\n", k.c_str(), static_cast<long long>(v));
  if (count[channels::RADAR_MAP] != 1 || segments != 5) return fail("expected one RADAR_MAP of 5 segments");
  if (count[channels::SONAR_HYPOTHESIS] != 6 || count[channels::SONAR_COMPLEMENT] != 6)
    return fail("expected 6 SONAR_HYPOTHESIS and 6 SONAR_COMPLEMENT");
  if (cls.size() != 24) return fail("expected a class for each of the 24 sensors");
  auto expect = [&](int k, int8_t c, const char* what) {
    if (cls[k] != c) throw std::runtime_error(std::string(what) + ": sensor " + std::to_string(k) +
                                              " has class " + std::to_string(cls[k]));
  };
  try {
    expect(kDoor, complement_reading_t::CLASS_COMPLEMENTARY, "glass door");
    expect(kObstacle, complement_reading_t::CLASS_COMPLEMENTARY, "round obstacle");
    expect(kSpecular1, complement_reading_t::CLASS_FALSE, "specular");
    expect(kSpecular2, complement_reading_t::CLASS_FALSE, "specular");
    expect(kBeyond, complement_reading_t::CLASS_UNVERIFIABLE, "beyond the limit");
    expect(kNaN, complement_reading_t::CLASS_INVALID, "NaN range");
    for (int k : kWalls) expect(k, complement_reading_t::CLASS_REDUNDANT, "wall");
  } catch (const std::runtime_error& e) {
    return fail(e.what());
  }
  if (counters["class.complementary"] < 2 || counters["rejected.sonar_range"] != 1)
    return fail("PROCESS_STATUS counters do not show the classes and the rejected NaN");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "publish" && argc == 3) return publish(argv[2]);
  if (mode == "log" && argc == 3) return checkLog(argv[2]);
  std::fprintf(stderr, "usage: lasonic-complement-check publish URL | log FILE\n");
  return 2;
}
