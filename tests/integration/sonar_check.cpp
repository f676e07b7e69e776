// lasonic-sonar-check: helper of the sonar driver's integration test (sonar_driver.sh).
//   lasonic-sonar-check garbage URL CHANNEL N   publish N undecodable messages on CHANNEL
//   lasonic-sonar-check log FILE                check the sonar channels of an LCM log and print
//                                               "key value" lines (counts, cause proportions,
//                                               the driver's last decode_errors / rejected counts)
// Exit status: 0 ok, 1 the log's sonar messages are inconsistent, 2 usage or I/O error.
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <lasonic/process_status_t.hpp>
#include <lasonic/sonar_geometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

#include "lcmio/eventlog.hpp"

using namespace lasonic;

namespace {

int garbage(const std::string& url, const std::string& channel, int n) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "lasonic-sonar-check: cannot open LCM %s\n", url.c_str());
    return 2;
  }
  // Too short for any lasonic type's fingerprint and fields.
  const char bytes[] = "not an lcm message";
  for (int i = 0; i < n; ++i) lcm.publish(channel, bytes, sizeof bytes);
  return 0;
}

int fail(const std::string& why) {
  std::fprintf(stderr, "lasonic-sonar-check: %s\n", why.c_str());
  return 1;
}

int checkLog(const std::string& file) {
  std::map<std::string, int64_t> count;
  std::map<int, int64_t> causes;
  std::map<int32_t, sonar_ring_t> rings;  // by seq, until its truth arrives
  int64_t readings = 0, decode_errors = -1, rejected = 0, time_resets = 0;
  int num_groups = -1, num_sensors = -1;
  try {
    LogReader log(file);
    while (auto rec = log.next()) {
      ++count[rec->channel];
      if (rec->channel == "SONAR_GEOMETRY") {
        const auto g = decodeAs<sonar_geometry_t>(rec->data);
        if (!g) return fail("SONAR_GEOMETRY does not decode");
        num_groups = g->num_groups;
        num_sensors = g->num_sensors;
      } else if (rec->channel == "SONAR_RING") {
        const auto r = decodeAs<sonar_ring_t>(rec->data);
        if (!r) return fail("SONAR_RING does not decode");
        if (num_groups > 0 && (r->group != r->seq % num_groups || r->num_sensors != num_sensors))
          return fail("SONAR_RING seq " + std::to_string(r->seq) + ": group or num_sensors disagree with SONAR_GEOMETRY");
        for (int i = 0; i < r->nreadings; ++i)
          if (r->sensor_id[i] < 0 || r->sensor_id[i] >= r->num_sensors || !(r->range[i] >= 0) ||
              r->range[i] > r->range_max)
            return fail("SONAR_RING seq " + std::to_string(r->seq) + ": bad sensor id or range");
        rings[r->seq] = *r;
      } else if (rec->channel == "SONAR_TRUTH") {
        const auto t = decodeAs<sonar_truth_t>(rec->data);
        if (!t) return fail("SONAR_TRUTH does not decode");
        const auto it = rings.find(t->seq);
        if (it == rings.end()) return fail("SONAR_TRUTH seq " + std::to_string(t->seq) + " has no SONAR_RING before it");
        const sonar_ring_t& r = it->second;
        if (r.utime != t->utime || r.group != t->group || r.nreadings != t->nreadings)
          return fail("SONAR_TRUTH seq " + std::to_string(t->seq) + " disagrees with its SONAR_RING");
        for (int i = 0; i < t->nreadings; ++i) {
          if (t->causes[i].sensor_id != r.sensor_id[i]) return fail("SONAR_TRUTH sensor ids differ from SONAR_RING");
          ++causes[t->causes[i].cause];
        }
        readings += t->nreadings;
        rings.erase(it);
      } else if (rec->channel == "PROCESS_STATUS") {
        const auto s = decodeAs<process_status_t>(rec->data);
        if (!s || s->process != "lasonic-sonar-driver") continue;
        for (const channel_stat_t& c : s->channels)
          if (c.channel == "SIM_STATE") decode_errors = c.decode_errors;
        for (int i = 0; i < s->ncounters; ++i)
          if (s->counter_names[i] == "rejected.sim_state") rejected = s->counter_values[i];
          else if (s->counter_names[i] == "time_resets") time_resets = s->counter_values[i];
      }
    }
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-sonar-check: %s\n", e.what());
    return 2;
  }
  for (const char* ch : {"SIM_STATE", "SONAR_GEOMETRY", "SONAR_RING", "SONAR_TRUTH", "PROCESS_STATUS"})
    std::printf("%s %lld\n", ch, static_cast<long long>(count[ch]));
  std::printf("readings %lld\n", static_cast<long long>(readings));
  const char* names[] = {"direct", "specular_long", "no_echo", "crosstalk", "foreign"};
  for (int c = 0; c < 5; ++c)
    std::printf("cause.%s %.4f\n", names[c], readings ? static_cast<double>(causes[c]) / static_cast<double>(readings) : 0.0);
  std::printf("driver.decode_errors.SIM_STATE %lld\n", static_cast<long long>(decode_errors));
  std::printf("driver.rejected.sim_state %lld\n", static_cast<long long>(rejected));
  std::printf("driver.time_resets %lld\n", static_cast<long long>(time_resets));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> a(argv + 1, argv + argc);
  if (a.size() == 4 && a[0] == "garbage") return garbage(a[1], a[2], std::atoi(a[3].c_str()));
  if (a.size() == 2 && a[0] == "log") return checkLog(a[1]);
  std::fprintf(stderr, "usage: lasonic-sonar-check garbage URL CHANNEL N | log FILE\n");
  return 2;
}
