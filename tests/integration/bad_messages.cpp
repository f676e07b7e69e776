// lasonic-bad-messages: helper of the bad-message integration test (bad_messages.sh).
//   lasonic-bad-messages feed URL   wait for a PROCESS_STATUS of lasonic-complement and
//                                   lasonic-pilot, then publish, in order:
//                                   (a) random bytes on ODOMETRY, LASER_SCAN, SONAR_RING and
//                                       SONAR_COMPLEMENT (4 each), (b) one valid message cut short
//                                       on each, (c) one valid message of the wrong type on each;
//                                   (d) semantic garbage (1.0 .. 2.0 s): ODOMETRY with a NaN pose and
//                                       going backwards, LASER_SCANs with NaN / negative / 1e9
//                                       ranges and an unknown flag, no readings, a negative offset,
//                                       a NaN range_max, a zero angle_increment, one going
//                                       backwards; SONAR_COMPLEMENT with a NaN end point, class 42,
//                                       a negative range, a 1e30 m range, an end point 1e30 away, one going
//                                       backwards; a SONAR_RING with ranges NaN / -1 / 1e9 and
//                                       sensor ids -1 / 99 (num_sensors 24); then waits until
//                                       both processes' PROCESS_STATUS show all of it received
//                                       (bounded), so nothing of it reaches the pilot late;
//                                   (e) a valid stream (10.0 .. 11.5 s): the robot standing in a
//                                       4 m square room with a round obstacle the laser cannot see
//                                       1 m ahead: ODOMETRY at 50 Hz, 7 LASER_SCANs, 37 sonar groups.
//                                   Then waits until both processes' PROCESS_STATUS show every
//                                   message received (bounded).
//   lasonic-bad-messages check LOG  check the lcm-logger log: the counters and last_error of both
//                                   processes' last PROCESS_STATUS, and that RADAR_MAP,
//                                   SONAR_COMPLEMENT and SECTOR_MAP came out of the valid stream with
//                                   finite values; prints "key value" lines
// Exit status: 0 ok, 1 check failed (or the processes never consumed the input), 2 usage or I/O.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/process_status_t.hpp>
#include <lasonic/sector_map_t.hpp>

#include "complement_fixture.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/lengths.hpp"
#include "lcmio/node.hpp"

using namespace lasonic;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kComplement = "lasonic-complement";
const char* const kPilot = "lasonic-pilot";

// Per channel: 4 random blobs + 1 truncated + 1 wrong type.
constexpr int kDecodeErrorsPerChannel = 6;
constexpr int64_t kValidStart = 10'000'000, kValidEnd = 11'500'000;
constexpr int64_t kScanPeriod = 200'000, kScanDuration = 100'000;
constexpr int64_t kSonarStart = 10'300'000, kSonarEnd = 11'400'000, kGroupPeriod = 30'000;

// The valid stream's world: a 4 m square room, the robot in its centre facing +x, a round
// obstacle the laser does not see 1 m ahead (its near side 0.45 m from the robot's boundary).
fixture::World room() {
  fixture::World w;
  w.laser_visible = {{{0, 0}, {4, 0}}, {{4, 0}, {4, 4}}, {{4, 4}, {0, 4}}, {{0, 4}, {0, 0}}};
  w.laser_invisible_circles = {{{3.0, 2.0}, 0.2}};
  return w;
}
const geom::Pose2 kRobot{2.0, 2.0, 0.0};

struct Sent {
  std::map<std::string, int> count;  // per channel, everything published
};

template <typename T>
void send(lcm::LCM& lcm, Sent& sent, const char* channel, T msg) {
  setLengths(msg);
  lcm.publish(channel, &msg);
  ++sent.count[channel];
  std::this_thread::sleep_for(std::chrono::milliseconds(2));  // no burst for the UDP buffers
}
void sendRaw(lcm::LCM& lcm, Sent& sent, const char* channel, const std::vector<uint8_t>& bytes) {
  lcm.publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size()));
  ++sent.count[channel];
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
}
template <typename T>
std::vector<uint8_t> encode(T msg) {
  setLengths(msg);
  std::vector<uint8_t> b(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

odometry_t odometry(int64_t t) { return fixture::odometryAt(fixture::still(kRobot), t); }
laser_scan_t scan(int64_t t) { return fixture::simulateScan(room(), fixture::still(kRobot), t, kScanDuration); }
sonar_ring_t validRing(int64_t t) { return fixture::sonarGroup(t, 0, {0, 6, 12, 18}, {1.0, 1.0, 1.0, 1.0}); }
complement_reading_t reading(int8_t cls, double range, double x, double y) {
  complement_reading_t r{};
  r.sensor_id = 0;
  r.cls = cls;
  r.range = static_cast<float>(range);
  r.hypothetical_range = 2.0f;
  r.sensor_pose = {2.3, 2.0, 0.0};
  r.end_x = x;
  r.end_y = y;
  r.beam_width = 0.5236f;  // 30 deg
  return r;
}

// Collects the newest PROCESS_STATUS of each process.
struct StatusWatch {
  std::map<std::string, process_status_t> newest;
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const process_status_t* s) { newest[s->process] = *s; }
  int64_t received(const std::string& process, const std::string& channel) const {
    const auto it = newest.find(process);
    if (it == newest.end()) return -1;
    for (const auto& c : it->second.channels)
      if (c.channel == channel && c.direction == channel_stat_t::DIR_IN) return c.messages;
    return 0;
  }
};

// Handles messages until done() or the timeout; true if done.
template <typename Done>
bool waitFor(lcm::LCM& lcm, double timeout_s, Done done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    lcm.handleTimeout(100);
  }
  return true;
}

// A small tactical grid (the pilot's remembered source listens to AGM_TACTICAL).
grid_map_t tacticalGrid(int64_t utime) {
  grid_map_t g{};
  g.utime = utime;
  g.width = g.height = 4;
  g.cell_size = 0.1f;
  g.gp_threshold = 5;
  g.g.assign(16, 0);
  g.h.assign(16, 0);
  g.gp.assign(16, 0);
  setLengths(g);
  return g;
}

// A navigator's line map of one line (the pilot moves remembered cells onto AGM_LINES).
line_map_t agmLines(int64_t utime, double x0) {
  line_map_t l{};
  l.utime = utime;
  line_segment_t seg{};
  seg.x0 = x0;
  seg.y0 = 0.0;
  seg.x1 = 1.0;
  seg.y1 = 1.0;
  seg.source = line_segment_t::SOURCE_SONAR;
  l.segments.push_back(seg);
  setLengths(l);
  return l;
}

void garbage(lcm::LCM& lcm, Sent& sent) {
  std::mt19937 rng(20240607);
  std::uniform_int_distribution<int> byte(0, 255);
  const char* const channels_in[] = {channels::ODOMETRY, channels::LASER_SCAN, channels::SONAR_RING,
                                     channels::SONAR_COMPLEMENT, channels::AGM_TACTICAL, channels::AGM_LINES};
  // (a) random bytes (a random fingerprint never matches: 2^-64).
  for (const char* ch : channels_in) {
    for (size_t len : {1u, 7u, 64u, 300u}) {
      std::vector<uint8_t> b(len);
      for (auto& x : b) x = static_cast<uint8_t>(byte(rng));
      sendRaw(lcm, sent, ch, b);
    }
  }
  // (b) a valid message of the channel's type, cut short (right fingerprint, half a body).
  complement_t comp{};
  comp.utime = 900'000;
  comp.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, 1.0, 3.0, 2.0));
  const std::map<std::string, std::vector<uint8_t>> valid = {
      {channels::ODOMETRY, encode(odometry(900'000))},
      {channels::LASER_SCAN, encode(scan(900'000))},
      {channels::SONAR_RING, encode(validRing(900'000))},
      {channels::SONAR_COMPLEMENT, encode(comp)},
      {channels::AGM_TACTICAL, encode(tacticalGrid(900'000))},
      {channels::AGM_LINES, encode(agmLines(900'000, 0.0))},
  };
  for (const char* ch : channels_in) {
    std::vector<uint8_t> b = valid.at(ch);
    b.resize(b.size() / 2);
    sendRaw(lcm, sent, ch, b);
  }
  // (c) a valid message of another type.
  sendRaw(lcm, sent, channels::ODOMETRY, valid.at(channels::LASER_SCAN));
  sendRaw(lcm, sent, channels::LASER_SCAN, valid.at(channels::ODOMETRY));
  sendRaw(lcm, sent, channels::SONAR_RING, valid.at(channels::SONAR_COMPLEMENT));
  sendRaw(lcm, sent, channels::SONAR_COMPLEMENT, valid.at(channels::SONAR_RING));
  sendRaw(lcm, sent, channels::AGM_TACTICAL, valid.at(channels::ODOMETRY));
  sendRaw(lcm, sent, channels::AGM_LINES, valid.at(channels::AGM_TACTICAL));
}

void semanticGarbage(lcm::LCM& lcm, Sent& sent) {
  // ODOMETRY: valid 1.0 .. 2.0 s, then a NaN pose, then one going backwards.
  for (int64_t t = 1'000'000; t <= 2'000'000; t += 20'000) send(lcm, sent, channels::ODOMETRY, odometry(t));
  odometry_t o = odometry(2'020'000);
  o.pose.theta = kNaN;
  send(lcm, sent, channels::ODOMETRY, o);
  send(lcm, sent, channels::ODOMETRY, odometry(1'500'000));

  // LASER_SCAN.
  laser_scan_t s = scan(1'100'000);
  s.ranges[0] = static_cast<float>(kNaN);
  s.ranges[1] = -1.0f;
  s.ranges[2] = 1e9f;
  for (int i = 0; i < 3; ++i) s.flags[static_cast<size_t>(i)] = laser_scan_t::FLAG_OK;
  s.flags[3] = 7;  // unknown flag
  send(lcm, sent, channels::LASER_SCAN, s);  // 3 laser_range + 1 laser_flag
  s = scan(1'200'000);
  s.ranges.clear();
  s.flags.clear();
  s.offset_us.clear();
  send(lcm, sent, channels::LASER_SCAN, s);  // nranges = 0: laser_scan
  s = scan(1'300'000);
  s.offset_us[10] = -5'000;
  send(lcm, sent, channels::LASER_SCAN, s);  // laser_offset
  s = scan(1'400'000);
  s.range_max = static_cast<float>(kNaN);
  s.ranges[20] = 1e9f;
  s.flags[20] = laser_scan_t::FLAG_OK;
  send(lcm, sent, channels::LASER_SCAN, s);  // NaN range_max: laser_scan
  s = scan(1'500'000);
  s.angle_increment = 0;
  send(lcm, sent, channels::LASER_SCAN, s);  // laser_scan
  send(lcm, sent, channels::LASER_SCAN, scan(1'250'000));  // laser_backwards

  // AGM_LINES straight to the pilot: a NaN end point, then a valid one, then one going backwards.
  send(lcm, sent, channels::AGM_LINES, agmLines(1'560'000, kNaN));  // agm_lines
  send(lcm, sent, channels::AGM_LINES, agmLines(1'570'000, 0.0));
  send(lcm, sent, channels::AGM_LINES, agmLines(1'540'000, 0.0));  // agm_lines_backwards

  // SONAR_COMPLEMENT straight to the pilot (before the ring below, whose complement is newer).
  complement_t c{};
  c.utime = 1'550'000;
  c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, 1.0, kNaN, 2.0));  // complement_nan
  c.readings.push_back(reading(42, 1.0, 3.0, 2.0));                                         // complement_class
  c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, -1.0, 3.0, 2.0));  // complement_range
  c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, 1e30, 3.0, 2.0));  // complement_range
  c.readings.push_back(reading(complement_reading_t::CLASS_COMPLEMENTARY, 1.0, 1e30, -1e30));  // complement_range
  send(lcm, sent, channels::SONAR_COMPLEMENT, c);
  c.utime = 1'500'000;
  c.readings.clear();
  send(lcm, sent, channels::SONAR_COMPLEMENT, c);  // complement_backwards

  // SONAR_RING to the complement: 3 bad ranges, 2 bad ids, one good reading.
  sonar_ring_t r = fixture::sonarGroup(1'600'000, 0, {0, 6, 12, 1, 2, 18}, {kNaN, 1.0, 1.0, 1.0, 1.0, 1.0});
  r.range[1] = -1.0f;
  r.range[2] = 1e9f;
  r.sensor_id[3] = -1;
  r.sensor_id[4] = 99;
  send(lcm, sent, channels::SONAR_RING, r);
}

void validStream(lcm::LCM& lcm, Sent& sent) {
  const auto world = room();
  const auto ring = fixture::trueRing(world, kRobot);
  int64_t next_scan = kValidStart, next_group = kSonarStart;
  int group = 0;
  for (int64_t t = kValidStart; t <= kValidEnd; t += 20'000) {
    send(lcm, sent, channels::ODOMETRY, odometry(t));
    // Each input once the odometry covers all of it.
    while (next_scan + kScanDuration + 20'000 <= t) {
      send(lcm, sent, channels::LASER_SCAN, scan(next_scan));
      next_scan += kScanPeriod;
    }
    while (next_group <= kSonarEnd && next_group + 20'000 <= t) {
      const int g = group % 6;
      std::vector<int> ids;
      std::vector<double> ranges;
      for (int k = g; k < 24; k += 6) {
        ids.push_back(k);
        ranges.push_back(ring[static_cast<size_t>(k)]);
      }
      send(lcm, sent, channels::SONAR_RING, fixture::sonarGroup(next_group, g, ids, ranges));
      next_group += kGroupPeriod;
      ++group;
    }
  }
}

int feed(const std::string& url) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "lasonic-bad-messages: cannot open LCM %s\n", url.c_str());
    return 2;
  }
  StatusWatch watch;
  lcm.subscribe(channels::PROCESS_STATUS, &StatusWatch::onStatus, &watch);
  // Subscriptions are made before the first heartbeat.
  if (!waitFor(lcm, 10, [&] { return watch.newest.count(kComplement) && watch.newest.count(kPilot); })) {
    std::fprintf(stderr, "lasonic-bad-messages: no PROCESS_STATUS from %s and %s within 10 s\n", kComplement, kPilot);
    return 1;
  }
  Sent sent;
  garbage(lcm, sent);
  semanticGarbage(lcm, sent);
  const int direct_complements = sent.count[channels::SONAR_COMPLEMENT];
  // Everything sent so far consumed: every message seen by both, and the complement's output of
  // every ring by the pilot (the heartbeat after the last message shows it).
  const auto consumed = [&](const char* phase) {
    const std::vector<std::tuple<const char*, const char*, int>> want = {
        {kComplement, channels::ODOMETRY, sent.count[channels::ODOMETRY]},
        {kComplement, channels::LASER_SCAN, sent.count[channels::LASER_SCAN]},
        {kComplement, channels::SONAR_RING, sent.count[channels::SONAR_RING]},
        {kPilot, channels::ODOMETRY, sent.count[channels::ODOMETRY]},
        {kPilot, channels::LASER_SCAN, sent.count[channels::LASER_SCAN]},
        // Rings that decode become one SONAR_COMPLEMENT each.
        {kPilot, channels::SONAR_COMPLEMENT,
         direct_complements + sent.count[channels::SONAR_RING] - kDecodeErrorsPerChannel},
    };
    const bool ok = waitFor(lcm, 15, [&] {
      for (const auto& [proc, ch, n] : want)
        if (watch.received(proc, ch) < n) return false;
      return true;
    });
    for (const auto& [proc, ch, n] : want)
      std::printf("%s%s.received.%s %lld (of %d)\n", phase, proc, ch, static_cast<long long>(watch.received(proc, ch)), n);
    if (!ok)
      std::fprintf(stderr, "lasonic-bad-messages: the processes did not report all input received within 15 s (%s)\n",
                   phase);
    return ok;
  };
  // The bad phase is consumed before the valid stream starts: the pilot also hears the bad
  // phase's rings through lasonic-complement, and one of them arriving once the valid stream has
  // begun would make a SECTOR_MAP stamped with the valid stream's time (a loaded machine is
  // enough to delay it).
  if (!consumed("bad_phase.")) return 1;
  validStream(lcm, sent);
  for (const auto& [ch, n] : sent.count) std::printf("sent.%s %d\n", ch.c_str(), n);
  if (!consumed("")) return 1;
  return 0;
}

// ---- check

int failures = 0;
void expect(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "lasonic-bad-messages: FAIL: %s\n", what.c_str());
    ++failures;
  }
}
bool finite(const pose2d_t& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta); }
// A SECTOR_MAP distance: -1 (none) or a finite value in [0, limit].
bool distanceOk(float d, float limit) { return d == -1.0f || (std::isfinite(d) && d >= 0 && d <= limit + 1e-4f); }

void checkStatus(const std::string& process, const std::map<std::string, process_status_t>& status,
                 const std::map<std::string, int64_t>& want, const std::string& error_mentions) {
  const auto it = status.find(process);
  expect(it != status.end(), "a PROCESS_STATUS of " + process);
  if (it == status.end()) return;
  const process_status_t& s = it->second;
  std::map<std::string, int64_t> counters;
  for (size_t i = 0; i < s.counter_names.size() && i < s.counter_values.size(); ++i)
    counters[s.counter_names[i]] = s.counter_values[i];
  for (const auto& [k, v] : counters) std::printf("%s.%s %lld\n", process.c_str(), k.c_str(), static_cast<long long>(v));
  std::printf("%s.errors %lld\n%s.last_error %s\n", process.c_str(), static_cast<long long>(s.errors),
              process.c_str(), s.last_error.c_str());
  int64_t expected_errors = 0;
  for (const auto& [k, v] : want) {
    const auto c = counters.find(k);
    const int64_t got = c == counters.end() ? 0 : c->second;
    expect(got == v, process + ": counter " + k + " = " + std::to_string(got) + ", expected " + std::to_string(v));
    if (k.rfind("decode_errors.", 0) == 0 || k.rfind("rejected.", 0) == 0 ||
        (k.size() > 5 && k.compare(k.size() - 5, 5, ".lost") == 0))
      expected_errors += v;
  }
  // Nothing else went wrong (the final status, sent on SIGTERM, may count the interrupted wait).
  const auto lf = counters.find("lcm_failures");
  const int64_t lcm_failures = lf == counters.end() ? 0 : lf->second;
  expect(s.errors - lcm_failures == expected_errors, process + ": errors = " + std::to_string(s.errors) +
                                                        ", expected exactly the " + std::to_string(expected_errors) +
                                                        " bad inputs");
  expect(s.last_error.find(error_mentions) != std::string::npos,
         process + ": last_error '" + s.last_error + "' does not name " + error_mentions);
  // Decode errors are also in the channel statistics.
  for (const auto& c : s.channels) {
    if (c.direction != channel_stat_t::DIR_IN) continue;
    expect(c.decode_errors == kDecodeErrorsPerChannel,
           process + ": channel " + c.channel + " decode_errors = " + std::to_string(c.decode_errors));
  }
}

int check(const std::string& file) {
  std::map<std::string, process_status_t> status;
  std::map<std::string, int> count, valid_count;  // all / from the valid stream (utime >= 10 s)
  int complementary = 0, invalid_late = 0, radar_segments = 0;
  sector_map_t last_map{};
  try {
    LogReader log(file);
    while (auto rec = log.next()) {
      const std::string& ch = rec->channel;
      ++count[ch];
      if (ch == channels::PROCESS_STATUS) {
        const auto s = decodeAs<process_status_t>(rec->data);
        expect(s.has_value(), "PROCESS_STATUS decodes");
        if (s) status[s->process] = *s;
      } else if (ch == channels::RADAR_MAP) {
        const auto m = decodeAs<line_map_t>(rec->data);
        expect(m.has_value(), "RADAR_MAP decodes");
        if (!m) continue;
        expect(finite(m->robot_pose), "RADAR_MAP.robot_pose finite");
        for (const auto& l : m->segments)
          expect(std::isfinite(l.x0) && std::isfinite(l.y0) && std::isfinite(l.x1) && std::isfinite(l.y1) &&
                     std::isfinite(l.rms),
                 "RADAR_MAP segment finite");
        if (m->utime >= kValidStart) {
          ++valid_count[ch];
          radar_segments = m->nsegments;
        }
      } else if (ch == channels::SONAR_COMPLEMENT) {
        const auto m = decodeAs<complement_t>(rec->data);
        if (!m || m->utime < kValidStart) continue;  // our own garbage, or the bad phase
        ++valid_count[ch];
        expect(!m->radar_map_stale || m->utime < kSonarStart + 200'000, "SONAR_COMPLEMENT has a fresh Radar Map");
        for (const auto& r : m->readings) {
          expect(r.cls >= complement_reading_t::CLASS_COMPLEMENTARY && r.cls <= complement_reading_t::CLASS_SEEN_BEFORE,
                 "SONAR_COMPLEMENT class in range");
          if (r.cls == complement_reading_t::CLASS_INVALID) ++invalid_late;
          if (r.cls != complement_reading_t::CLASS_COMPLEMENTARY) continue;
          ++complementary;
          expect(std::isfinite(r.range) && r.range >= 0 && std::isfinite(r.end_x) && std::isfinite(r.end_y) &&
                     finite(r.sensor_pose),
                 "complementary reading finite");
        }
      } else if (ch == channels::SECTOR_MAP) {
        const auto m = decodeAs<sector_map_t>(rec->data);
        expect(m.has_value(), "SECTOR_MAP decodes");
        if (!m) continue;
        const auto n = static_cast<size_t>(m->nsectors);
        expect(n == 48 && m->distance.size() == n && m->source.size() == n && m->laser_distance.size() == n &&
                   m->sonar_distance.size() == n,
               "SECTOR_MAP has 48 sectors");
        expect(finite(m->robot_pose) && std::isfinite(m->laser_age_s) && std::isfinite(m->sonar_age_s),
               "SECTOR_MAP pose and ages finite");
        for (size_t k = 0; k < m->distance.size() && k < m->source.size(); ++k) {
          const bool none = m->source[k] == sector_map_t::SOURCE_NONE;
          if (!distanceOk(m->distance[k], m->max_range) || none != (m->distance[k] == -1.0f) ||
              !distanceOk(m->laser_distance[k], m->max_range) || !distanceOk(m->sonar_distance[k], m->max_range)) {
            expect(false, "SECTOR_MAP utime " + std::to_string(m->utime) + " sector " + std::to_string(k) +
                              ": distance " + std::to_string(m->distance[k]) + " (laser " +
                              std::to_string(m->laser_distance[k]) + ", sonar " +
                              std::to_string(m->sonar_distance[k]) + ", source " + std::to_string(m->source[k]) +
                              "): neither -1 with source NONE nor in [0, max_range]");
            break;
          }
        }
        if (m->utime >= kValidStart) {
          ++valid_count[ch];
          last_map = *m;
        }
      } else if (ch == channels::AGM_OPERATIONAL) {
        const auto m = decodeAs<grid_map_t>(rec->data);
        expect(m.has_value(), "AGM_OPERATIONAL decodes");
        if (m && m->utime >= kValidStart) ++valid_count[ch];
      }
    }
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-bad-messages: %s\n", e.what());
    return 2;
  }
  for (const auto& [ch, n] : count) std::printf("%s %d\n", ch.c_str(), n);
  for (const auto& [ch, n] : valid_count) std::printf("valid.%s %d\n", ch.c_str(), n);

  // (a)-(d) counted; nothing else went wrong.
  const int64_t d = kDecodeErrorsPerChannel;
  checkStatus(kComplement, status,
              {{"decode_errors.ODOMETRY", d},
               {"decode_errors.LASER_SCAN", d},
               {"decode_errors.SONAR_RING", d},
               {"rejected.odometry_nan", 1},
               {"rejected.odometry_backwards", 1},
               {"rejected.laser_range", 3},
               {"rejected.laser_flag", 1},
               {"rejected.laser_offset", 1},
               {"rejected.laser_scan", 3},
               {"rejected.laser_backwards", 1},
               {"rejected.sonar_range", 3},
               {"rejected.sonar_id", 2},
               {"class.invalid", 5}},
              "SONAR_RING.sensor_id[4] = 99");
  checkStatus(kPilot, status,
              {{"decode_errors.ODOMETRY", d},
               {"decode_errors.LASER_SCAN", d},
               {"decode_errors.SONAR_COMPLEMENT", d},
               {"decode_errors.AGM_TACTICAL", d},
               {"decode_errors.AGM_LINES", d},
               {"rejected.agm_lines", 1},
               {"rejected.agm_lines_backwards", 1},
               {"rejected.odometry_nan", 1},
               {"rejected.odometry_backwards", 1},
               {"rejected.laser_range", 3},
               {"rejected.laser_flag", 1},
               {"rejected.laser_offset", 1},
               {"rejected.laser_scan", 3},
               {"rejected.laser_backwards", 1},
               {"rejected.complement_nan", 1},
               {"rejected.complement_class", 1},
               {"rejected.complement_range", 3},  // -1 m, 1e30 m, and an end point 1e30 m away
               {"rejected.complement_backwards", 1},
               // the 8 s between the bad phase and the valid stream: both sensors had been
               // delivering (their last at 1.6 s), an outage each, reported at the first map after
               {"laser.lost", 1},
               {"sonar.lost", 1}},
              "no SONAR_COMPLEMENT since utime 1600000");

  // (e) the valid stream still produced everything, with the values expected.
  expect(valid_count[channels::RADAR_MAP] == 7, "7 RADAR_MAP from the valid stream");
  expect(radar_segments >= 4, "the last RADAR_MAP holds the room's 4 walls");
  expect(valid_count[channels::SONAR_COMPLEMENT] == 37, "37 SONAR_COMPLEMENT from the valid stream");
  expect(complementary >= 5 && invalid_late == 0, "complementary readings (the obstacle), none invalid");
  // ... plus the ones ODOMETRY makes while no sensor does (map_max_interval_s: before the
  // first group, scans come only every 0.2 s).
  const auto pilot_status = status.find(kPilot);
  int64_t on_odometry = 0;
  if (pilot_status != status.end())
    for (size_t i = 0; i < pilot_status->second.counter_names.size(); ++i)
      if (pilot_status->second.counter_names[i] == "sector_map.on_odometry")
        on_odometry = pilot_status->second.counter_values[i];
  std::printf("valid.on_odometry_maps_at_most %lld\n", static_cast<long long>(on_odometry));
  expect(valid_count[channels::SECTOR_MAP] >= 7 + 37 && valid_count[channels::SECTOR_MAP] <= 7 + 37 + on_odometry,
         "a SECTOR_MAP per valid scan and group (and the odometry-made ones)");
  expect(valid_count[channels::AGM_OPERATIONAL] >= 2, "AGM_OPERATIONAL from the valid stream");
  if (last_map.nsectors == 48) {
    // The wall 2 m to the left (laser): 2 - 0.35; the obstacle ahead (sonar): 1 - 0.2 - 0.35.
    float sonar_ahead = -1;
    for (size_t k = 22; k <= 25; ++k)
      if (last_map.sonar_distance[k] >= 0 && (sonar_ahead < 0 || last_map.sonar_distance[k] < sonar_ahead))
        sonar_ahead = last_map.sonar_distance[k];
    std::printf("last.laser_distance[36] %.3f\nlast.sonar_ahead %.3f\n", last_map.laser_distance[36], sonar_ahead);
    expect(std::abs(last_map.laser_distance[36] - 1.65f) < 0.05f, "last SECTOR_MAP: laser wall 1.65 m to the left");
    expect(sonar_ahead > 0.3f && sonar_ahead < 0.6f, "last SECTOR_MAP: sonar obstacle ~0.45 m ahead");
    expect(!last_map.laser_stale && !last_map.sonar_stale, "last SECTOR_MAP: neither source stale");
  }
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (argc == 3 && mode == "feed") return feed(argv[2]);
  if (argc == 3 && mode == "check") return check(argv[2]);
  std::fprintf(stderr, "usage: lasonic-bad-messages feed URL | check LOG\n");
  return 2;
}
