// lasonic-fuzz: bad input on every input channel of every live process (fuzz.sh, ./run soak).
//
//   lasonic-fuzz feed PIPE_URL SIM_URL NAV_URL COUNT SEED
//     Waits for the PROCESS_STATUS of every target, then publishes COUNT messages, deterministic
//     from SEED, spread over the targets' input channels:
//       PIPE_URL: ODOMETRY, LASER_SCAN, SONAR_RING (lasonic-complement), SONAR_COMPLEMENT,
//                 AGM_TACTICAL and AGM_LINES (lasonic-pilot; ODOMETRY and LASER_SCAN too)
//       SIM_URL:  SIM_STATE (lasonic-laser-driver, lasonic-sonar-driver)
//       NAV_URL:  ODOMETRY, SONAR_COMPLEMENT, RADAR_MAP, LASER_SCAN (lasonic-navigator)
//     Kinds: random bytes; a valid message cut short; bit flips in a valid message; a valid message
//     of another type; a count field claiming more elements than the bytes hold, negative, or
//     over the cap; a real array over the cap; valid messages with fields set to NaN, +-Inf,
//     negative, 1e30, unknown sensor ids and classes, times jumping back and forth (a looping log);
//     and plain valid messages. The feeder keeps at most WINDOW messages in flight per process
//     (from their 1 Hz PROCESS_STATUS; fewer than LCM queues per subscription), so no message is dropped and every message can be
//     accounted for. At the end it waits for every target to report all input received, then
//     checks, per process and channel: messages received == sent; decode_errors and oversize
//     counters == what the bytes say (classified here with Node's own rules); errors >= those;
//     the kinds of semantic garbage show up under their counters; every ring that decodes with a
//     plausible time answered by lasonic-complement (the pilot's SONAR_COMPLEMENT input) or
//     dropped for its time and counted. Prints "key value" lines.
//   lasonic-fuzz write LOG COUNT SEED [CHANNELS]
//     The same messages for the pipeline's channels, written to a log (for lasonic-replay:
//     deterministic, no network, fast); CHANNELS (comma-separated) instead of ODOMETRY,
//     LASER_SCAN, SONAR_RING, SONAR_COMPLEMENT may add RADAR_MAP, AGM_TACTICAL and AGM_LINES (the
//     navigator's and the remembering pilot's inputs, for `lasonic-replay --stages`). Prints sent.CH and
//     undecodable.CH (what Node cannot decode or finds over a cap) per channel.
//   lasonic-fuzz check PIPE_LOG [SIM_LOG [NAV_LOG]]   |   check-only CHANNELS LOG...
//     Every message on an output channel in the logs decodes, and its numbers are valid (finite
//     poses, SECTOR_MAP distances -1 or within [0, max_range], known classes and sources; the
//     laser driver's readings finite where flagged OK).
// Exit status: 0 ok, 1 check failed, 2 usage or I/O.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/process_status_t.hpp>
#include <lasonic/sector_map_t.hpp>
#include <lasonic/sim_state_t.hpp>

#include "complement_fixture.hpp"
#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "lcmio/time_reset.hpp"

using namespace lasonic;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// Messages in flight per process at most (as of its last heartbeat): below the queue LCM keeps
// per subscription (Node::kQueueCapacity), so that a process slower than the feed (the sonar
// driver under the sanitizers) is waited for instead of losing messages.
constexpr int64_t kWindow = 900;
static_assert(kWindow < Node::kQueueCapacity);

enum Url { kPipe = 0, kSim = 1, kNav = 2 };
struct Target {
  std::string process;
  Url url;
  std::vector<std::string> channels;
};
// The navigator listens on a URL of its own (NAV_URL): there only the fuzz feeds it (on PIPE_URL
// the complement's outputs would be its inputs too), and its AGM_TACTICAL and AGM_LINES never
// reach the pilot, whose AGM_TACTICAL and AGM_LINES inputs are fuzzed on PIPE_URL instead.
const std::vector<Target> kTargets = {
    {"lasonic-complement", kPipe, {channels::ODOMETRY, channels::LASER_SCAN, channels::SONAR_RING}},
    {"lasonic-pilot", kPipe,
     {channels::ODOMETRY, channels::LASER_SCAN, channels::SONAR_COMPLEMENT, channels::AGM_TACTICAL, channels::AGM_LINES}},
    {"lasonic-laser-driver", kSim, {channels::SIM_STATE}},
    {"lasonic-sonar-driver", kSim, {channels::SIM_STATE}},
    {"lasonic-navigator", kNav, {channels::ODOMETRY, channels::SONAR_COMPLEMENT, channels::RADAR_MAP, channels::LASER_SCAN}},
};

// ---- what Node will make of the bytes (lcmio/node.hpp: the cap check, then decode)
enum class Fate { Decodes, DecodeError, Oversize };
template <typename T>
Fate fateOf(const std::vector<uint8_t>& b) {
  if constexpr (HasWireArrays<T>::value) {
    const WireCheck c = checkWireArrays<T>(b.data(), b.size());
    if (c.result == WireCheck::TooMany) return Fate::Oversize;
    if (c.result == WireCheck::Truncated) return Fate::DecodeError;
  }
  T m;
  try {
    return m.decode(b.data(), 0, static_cast<int>(b.size())) < 0 ? Fate::DecodeError : Fate::Decodes;
  } catch (const std::exception&) {
    return Fate::DecodeError;
  }
}
Fate fateOn(const std::string& channel, const std::vector<uint8_t>& b) {
  if (channel == channels::ODOMETRY) return fateOf<odometry_t>(b);
  if (channel == channels::LASER_SCAN) return fateOf<laser_scan_t>(b);
  if (channel == channels::SONAR_RING) return fateOf<sonar_ring_t>(b);
  if (channel == channels::SONAR_COMPLEMENT) return fateOf<complement_t>(b);
  if (channel == channels::SIM_STATE) return fateOf<sim_state_t>(b);
  if (channel == channels::RADAR_MAP || channel == channels::AGM_LINES) return fateOf<line_map_t>(b);
  if (channel == channels::AGM_TACTICAL) return fateOf<grid_map_t>(b);
  return Fate::DecodeError;
}

template <typename T>
std::vector<uint8_t> bytes(T msg) {
  return encodeMsg(msg);
}

// ---- the generator
class Gen {
 public:
  explicit Gen(uint64_t seed) : rng_(seed) {}

  double nasty() {
    static const double v[] = {kNaN, kInf, -kInf, -1.0, 0.0, 1e30, -1e30, 1e-300, 5e6, -0.0};
    return v[pick(std::size(v))];
  }
  size_t pick(size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }
  int64_t time() {
    // Mostly moving forward, sometimes back (a looping log), sometimes absurd.
    const double r = std::uniform_real_distribution<double>(0, 1)(rng_);
    if (r < 0.80) t_ += std::uniform_int_distribution<int64_t>(0, 40'000)(rng_);
    else if (r < 0.90) t_ -= std::uniform_int_distribution<int64_t>(0, 3'000'000)(rng_);
    else if (r < 0.95) return std::uniform_int_distribution<int64_t>(std::numeric_limits<int64_t>::min(), -1)(rng_);
    else return std::uniform_int_distribution<int64_t>(0, std::numeric_limits<int64_t>::max())(rng_);
    if (t_ < 0 || t_ > 8'000'000) t_ = 1'000'000;  // the fuzz keeps to [0, 8] s (and absurd values)
    return t_;
  }
  std::mt19937_64& rng() { return rng_; }

  // A valid message of each type around time t.
  odometry_t odometry(int64_t t) {
    return fixture::odometryAt(fixture::still({2.0, 2.0, 0.0}), t);
  }
  laser_scan_t scan(int64_t t) {
    if (!scan_) scan_ = fixture::simulateScan(room(), fixture::still({2.0, 2.0, 0.0}), 0, 100'000);
    laser_scan_t s = *scan_;
    s.utime = t;
    return s;
  }
  sonar_ring_t ring(int64_t t) {
    const int g = static_cast<int>(pick(6));
    std::vector<int> ids;
    std::vector<double> ranges;
    for (int k = g; k < 24; k += 6) {
      ids.push_back(k);
      ranges.push_back(0.3 + 2.5 * std::uniform_real_distribution<double>(0, 1)(rng_));
    }
    return fixture::sonarGroup(t, g, ids, ranges);
  }
  complement_t complement(int64_t t) {
    complement_t c{};
    c.utime = t;
    c.group = static_cast<int16_t>(pick(6));
    c.tolerance = 0.125f;  // lasonic-complement's are 0.1: `check` tells them apart
    for (int k = 0; k < 4; ++k) {
      complement_reading_t r{};
      r.sensor_id = static_cast<int16_t>(c.group + 6 * k);
      r.cls = static_cast<int8_t>(pick(5));
      r.range = static_cast<float>(0.3 + 2.0 * std::uniform_real_distribution<double>(0, 1)(rng_));
      r.hypothetical_range = 2.2f;
      r.sensor_pose = {2.0 + 0.35 * std::cos(k * 1.57), 2.0 + 0.35 * std::sin(k * 1.57), k * 1.57};
      r.end_x = r.sensor_pose.x + r.range * std::cos(r.sensor_pose.theta);
      r.end_y = r.sensor_pose.y + r.range * std::sin(r.sensor_pose.theta);
      c.readings.push_back(r);
    }
    return c;
  }
  // The navigator's inputs from lasonic-complement (RADAR_MAP) and the pilot's from the navigator
  // (AGM_TACTICAL): the room's walls, and a tactical map holding them.
  line_map_t radarMap(int64_t t) {
    line_map_t m{};
    m.utime = t;
    m.source_utime = t - 100'000;
    m.robot_pose = {2.0, 2.0, 0.0};
    for (const auto& w : room().laser_visible) {
      line_segment_t l{};
      // Relative to the robot (the Radar Map's frame is the robot's at utime).
      l.x0 = w.a.x() - 2.0;
      l.y0 = w.a.y() - 2.0;
      l.x1 = w.b.x() - 2.0;
      l.y1 = w.b.y() - 2.0;
      l.npoints = 50;
      l.rms = 0.01f;
      l.source = line_segment_t::SOURCE_LASER;
      l.last_supported_utime = t;
      m.segments.push_back(l);
    }
    setLengths(m);
    return m;
  }
  grid_map_t tactical(int64_t t) {
    grid_map_t g{};
    g.utime = t;
    g.robot_pose = {2.0, 2.0, 0.0};
    g.cell_size = 0.1f;
    g.width = g.height = 60;  // 6 m around the 4 m room
    g.origin_x = g.origin_y = -1.0;
    g.gp_threshold = 5;
    const size_t n = static_cast<size_t>(g.width) * static_cast<size_t>(g.height);
    g.g.assign(n, 0);
    g.h.assign(n, 0);
    g.gp.assign(n, 0);
    for (int k = 10; k < 50; ++k)
      for (const size_t c : {static_cast<size_t>(10 * g.width + k), static_cast<size_t>(k * g.width + 50)}) {
        g.g[c] = 6;
        g.h[c] = 3;
        g.gp[c] = 8;
      }
    setLengths(g);
    return g;
  }
  sim_state_t simState(int64_t t) {
    sim_state_t s{};
    s.utime = t;
    s.seq = static_cast<int32_t>(t / 20'000);
    s.robot_pose = {1.2 + 1e-7 * static_cast<double>(t % 10'000'000), 1.2, 0.0};
    s.v = 0.3;
    return s;
  }

  // Semantic garbage: a valid message with some of its numbers made nasty.
  std::vector<uint8_t> semantic(const std::string& ch, int64_t t) {
    const int n = 1 + static_cast<int>(pick(3));
    if (ch == channels::ODOMETRY) {
      odometry_t o = odometry(t);
      double* f[] = {&o.pose.x, &o.pose.y, &o.pose.theta, &o.v, &o.omega};
      for (int i = 0; i < n; ++i) *f[pick(std::size(f))] = nasty();
      return bytes(o);
    }
    if (ch == channels::LASER_SCAN) {
      laser_scan_t s = scan(t);
      for (int i = 0; i < n; ++i) {
        if (s.ranges.empty()) break;
        switch (pick(8)) {
          case 0: s.ranges[pick(s.ranges.size())] = static_cast<float>(nasty()); break;
          case 1: s.flags[pick(s.flags.size())] = static_cast<int8_t>(pick(256) - 128); break;
          case 2: s.offset_us[pick(s.offset_us.size())] = -static_cast<int32_t>(pick(1'000'000)); break;
          case 3: s.angle_increment = nasty(); break;
          case 4: s.range_max = static_cast<float>(nasty()); break;
          case 5: s.mount.theta = nasty(); break;
          case 6: s.ranges.clear(); s.flags.clear(); s.offset_us.clear(); break;
          default: s.angle_min = nasty(); break;
        }
      }
      return bytes(s);
    }
    if (ch == channels::SONAR_RING) {
      sonar_ring_t r = ring(t);
      for (int i = 0; i < n; ++i) {
        const size_t k = pick(r.range.size());
        switch (pick(6)) {
          case 0: r.range[k] = static_cast<float>(nasty()); break;
          case 1: r.sensor_id[k] = static_cast<int16_t>(pick(65536) - 32768); break;
          case 2: r.mount[k].x = nasty(); break;
          case 3: r.num_sensors = static_cast<int16_t>(pick(65536) - 32768); break;
          case 4: r.range_max = static_cast<float>(nasty()); break;
          default: r.no_echo[k] = static_cast<int8_t>(pick(256) - 128); break;
        }
      }
      return bytes(r);
    }
    if (ch == channels::SONAR_COMPLEMENT) {
      complement_t c = complement(t);
      for (int i = 0; i < n; ++i) {
        complement_reading_t& r = c.readings[pick(c.readings.size())];
        switch (pick(6)) {
          case 0: r.cls = static_cast<int8_t>(pick(256) - 128); break;
          case 1: r.range = static_cast<float>(nasty()); break;
          case 2: r.end_x = nasty(); break;
          case 3: r.sensor_pose.theta = nasty(); break;
          case 4: r.sensor_id = static_cast<int16_t>(pick(65536) - 32768); break;
          default: r.cls = 0; r.end_y = nasty(); break;
        }
      }
      return bytes(c);
    }
    if (ch == channels::RADAR_MAP || ch == channels::AGM_LINES) {  // (the pilot reads both as lines)
      line_map_t m = radarMap(t);
      for (int i = 0; i < n; ++i) {
        line_segment_t& l = m.segments[pick(m.segments.size())];
        switch (pick(7)) {
          case 0: l.x0 = nasty(); break;
          case 1: l.y1 = nasty(); break;
          case 2: l.npoints = static_cast<int32_t>(pick(2'000)) - 1'000; break;
          case 3: l.rms = static_cast<float>(nasty()); break;
          case 4: l.last_supported_utime = time(); break;
          case 5: m.source_utime = time(); break;
          default: m.robot_pose.theta = nasty(); break;
        }
      }
      return bytes(m);
    }
    if (ch == channels::AGM_TACTICAL) {
      grid_map_t g = tactical(t);
      for (int i = 0; i < n; ++i) {
        switch (pick(8)) {
          case 0: g.cell_size = static_cast<float>(nasty()); break;
          case 1: g.origin_x = nasty(); break;
          case 2: g.width = static_cast<int32_t>(pick(200)) - 20; break;  // width * height != ncells
          case 3: g.gp_threshold = static_cast<int32_t>(pick(40)) - 20; break;
          case 4: g.g[pick(g.g.size())] = static_cast<int16_t>(pick(65536) - 32768); break;
          case 5: g.gp[pick(g.gp.size())] = static_cast<int32_t>(pick(200'000)) - 100'000; break;
          case 6: g.robot_pose.x = nasty(); break;
          default: g.height = 0; break;
        }
      }
      // Encoded as it is (encodeMsg would refuse a width * height that is not ncells).
      std::vector<uint8_t> b(static_cast<size_t>(g.getEncodedSize()));
      g.encode(b.data(), 0, static_cast<int>(b.size()));
      return b;
    }
    sim_state_t s = simState(t);
    for (int i = 0; i < n; ++i) {
      switch (pick(5)) {
        case 0: s.robot_pose.x = nasty(); break;
        case 1: s.v = nasty(); break;
        case 2: s.omega = nasty(); break;
        default: {
          mover_state_t m{};
          m.id = static_cast<int32_t>(pick(20)) - 5;
          m.x = nasty();
          m.y = 1.0;
          m.radius = nasty();
          s.movers.push_back(m);
        }
      }
    }
    return bytes(s);
  }

  std::vector<uint8_t> valid(const std::string& ch, int64_t t) {
    if (ch == channels::ODOMETRY) return bytes(odometry(t));
    if (ch == channels::LASER_SCAN) return bytes(scan(t));
    if (ch == channels::SONAR_RING) return bytes(ring(t));
    if (ch == channels::SONAR_COMPLEMENT) return bytes(complement(t));
    if (ch == channels::RADAR_MAP || ch == channels::AGM_LINES) return bytes(radarMap(t));
    if (ch == channels::AGM_TACTICAL) return bytes(tactical(t));
    return bytes(simState(t));
  }

  // One fuzz message for a channel.
  std::vector<uint8_t> next(const std::string& ch, std::string& kind) {
    const int64_t t = time();
    const double r = std::uniform_real_distribution<double>(0, 1)(rng_);
    if (r < 0.10) {
      kind = "random";
      std::vector<uint8_t> b(pick(600));
      for (auto& x : b) x = static_cast<uint8_t>(pick(256));
      // Half of them start with the channel's fingerprint: the decoder has to look further.
      if (b.size() >= 8 && chance(0.5)) {
        const std::vector<uint8_t> v = valid(ch, t);
        std::copy(v.begin(), v.begin() + 8, b.begin());
      }
      return b;
    }
    if (r < 0.20) {
      kind = "truncated";
      std::vector<uint8_t> b = valid(ch, t);
      b.resize(pick(b.size()));
      return b;
    }
    if (r < 0.40) {
      kind = "bitflip";
      std::vector<uint8_t> b = valid(ch, t);
      const size_t flips = 1 + pick(8);
      for (size_t i = 0; i < flips; ++i) b[pick(b.size())] ^= static_cast<uint8_t>(1u << pick(8));
      return b;
    }
    if (r < 0.45) {
      kind = "wrongtype";
      static const char* all[] = {channels::ODOMETRY, channels::LASER_SCAN, channels::SONAR_RING,
                                  channels::SONAR_COMPLEMENT, channels::SIM_STATE};
      std::string other = all[pick(std::size(all))];
      if (other == ch) other = ch == channels::ODOMETRY ? channels::LASER_SCAN : channels::ODOMETRY;
      return valid(other, t);
    }
    if (r < 0.50 && ch != channels::ODOMETRY) {
      kind = "claim";  // the count field rewritten: huge, negative, or a few more than present
      std::vector<uint8_t> b = valid(ch, t);
      int64_t off = 0;
      if (ch == channels::LASER_SCAN) off = wireShape<laser_scan_t>().count_offset;
      else if (ch == channels::SONAR_RING) off = wireShape<sonar_ring_t>().count_offset;
      else if (ch == channels::SONAR_COMPLEMENT) off = wireShape<complement_t>().count_offset;
      else if (ch == channels::RADAR_MAP || ch == channels::AGM_LINES) off = wireShape<line_map_t>().count_offset;
      else if (ch == channels::AGM_TACTICAL) off = wireShape<grid_map_t>().count_offset;
      else off = wireShape<sim_state_t>().count_offset;
      const int32_t claims[] = {std::numeric_limits<int32_t>::max(), -1, std::numeric_limits<int32_t>::min(),
                                1'000'000, 7, 100'001};
      const auto c = static_cast<uint32_t>(claims[pick(std::size(claims))]);
      for (int i = 0; i < 4; ++i) b[static_cast<size_t>(off) + static_cast<size_t>(i)] = static_cast<uint8_t>(c >> (24 - 8 * i));
      return b;
    }
    if (r < 0.90) {
      kind = "semantic";
      return semantic(ch, t);
    }
    kind = "valid";
    return valid(ch, t);
  }

  // A real array over the cap (all bytes present).
  std::vector<uint8_t> overCap(const std::string& ch, int64_t t) {
    if (ch == channels::LASER_SCAN) {
      laser_scan_t s = scan(t);
      s.ranges.assign(static_cast<size_t>(limits::kLaserReadings + 1), 1.f);
      s.flags.assign(s.ranges.size(), 0);
      s.offset_us.assign(s.ranges.size(), 0);
      return bytes(s);
    }
    if (ch == channels::SONAR_RING) {
      sonar_ring_t r = ring(t);
      const size_t n = static_cast<size_t>(limits::kSonarReadings + 1);
      r.sensor_id.assign(n, 0);
      r.range.assign(n, 1.f);
      r.no_echo.assign(n, 0);
      r.mount.assign(n, r.mount[0]);
      r.beam_width.assign(n, 0.5f);
      return bytes(r);
    }
    if (ch == channels::SONAR_COMPLEMENT) {
      complement_t c = complement(t);
      c.readings.assign(static_cast<size_t>(limits::kComplementReadings + 1), c.readings[0]);
      return bytes(c);
    }
    if (ch == channels::SIM_STATE) {
      sim_state_t s = simState(t);
      s.movers.assign(static_cast<size_t>(limits::kMovers + 1), mover_state_t{});
      return bytes(s);
    }
    if (ch == channels::RADAR_MAP || ch == channels::AGM_LINES) {
      line_map_t m = radarMap(t);
      m.segments.assign(static_cast<size_t>(limits::kLineSegments + 1), m.segments[0]);
      setLengths(m);
      return bytes(m);
    }
    // AGM_TACTICAL: a real grid over the cap would be 32 MB; its count claims cover the cap.
    return {};
  }

 private:
  static fixture::World room() {
    fixture::World w;
    w.laser_visible = {{{0, 0}, {4, 0}}, {{4, 0}, {4, 4}}, {{4, 4}, {0, 4}}, {{0, 4}, {0, 0}}};
    return w;
  }
  std::mt19937_64 rng_;
  int64_t t_ = 1'000'000;
  std::optional<laser_scan_t> scan_;
};

// ---- the feeder
struct Watch {
  std::map<std::string, process_status_t> newest;
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const process_status_t* s) { newest[s->process] = *s; }
  int64_t received(const std::string& process) const {
    const auto it = newest.find(process);
    if (it == newest.end()) return -1;
    int64_t n = 0;
    for (const auto& c : it->second.channels)
      if (c.direction == channel_stat_t::DIR_IN) n += c.messages;
    return n;
  }
  // What `process` reports having published on `channel` (0 before its first heartbeat).
  int64_t published(const std::string& process, const std::string& channel) const {
    const auto it = newest.find(process);
    if (it == newest.end()) return 0;
    for (const auto& c : it->second.channels)
      if (c.direction == channel_stat_t::DIR_OUT && c.channel == channel) return c.messages;
    return 0;
  }
  int64_t counter(const std::string& process, const std::string& name) const {
    const auto it = newest.find(process);
    if (it == newest.end()) return 0;
    for (size_t i = 0; i < it->second.counter_names.size() && i < it->second.counter_values.size(); ++i)
      if (it->second.counter_names[i] == name) return it->second.counter_values[i];
    return 0;
  }
};

struct Expect {
  std::map<std::string, int64_t> sent, decode_errors, oversize;  // per channel
  std::map<std::string, int64_t> kinds;
  // Rings that decode with a plausible time: each becomes one SONAR_COMPLEMENT from
  // lasonic-complement to the pilot, unless the complement drops it for its time (not newer than
  // the previous ring, or held back as far ahead of every input), which it counts.
  int64_t ring_decodes = 0;
};

int failures = 0;
void expect(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "lasonic-fuzz: FAIL: %s\n", what.c_str());
    ++failures;
  }
}

int feed(const std::string& pipe_url, const std::string& sim_url, const std::string& nav_url, int64_t count,
         uint64_t seed) {
  lcm::LCM pipe(pipe_url), sim(sim_url), nav(nav_url);
  if (!pipe.good() || !sim.good() || !nav.good()) {
    std::fprintf(stderr, "lasonic-fuzz: cannot open LCM\n");
    return 2;
  }
  lcm::LCM* const urls[] = {&pipe, &sim, &nav};
  Watch watch;
  for (lcm::LCM* l : urls) l->subscribe(channels::PROCESS_STATUS, &Watch::onStatus, &watch);
  auto spin = [&](int ms) {
    for (lcm::LCM* l : urls) {
      l->handleTimeout(ms / 3 + 1);
      while (l->handleTimeout(0) > 0) {
      }
    }
  };
  auto waitUntil = [&](double timeout_s, const std::function<bool()>& done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (!done()) {
      if (std::chrono::steady_clock::now() > until) return false;
      spin(50);
    }
    return true;
  };
  if (!waitUntil(15, [&] {
        for (const Target& t : kTargets)
          if (watch.received(t.process) < 0) return false;
        return true;
      })) {
    std::fprintf(stderr, "lasonic-fuzz: not every target sent a PROCESS_STATUS within 15 s\n");
    return 1;
  }
  // What each process had received before the fuzz (nothing, normally).
  std::map<std::string, int64_t> base;
  for (const Target& t : kTargets) base[t.process] = watch.received(t.process);

  Gen gen(seed);
  Expect ex;
  std::map<std::string, int64_t> expected_in;  // per process, including base
  for (const Target& t : kTargets) expected_in[t.process] = base[t.process];
  const std::vector<std::string> chans = {channels::ODOMETRY,         channels::LASER_SCAN, channels::SONAR_RING,
                                          channels::SONAR_COMPLEMENT, channels::SIM_STATE,  channels::RADAR_MAP,
                                          channels::AGM_TACTICAL,     channels::AGM_LINES};
  // The pilot also receives what lasonic-complement publishes (as of its last heartbeat).
  const auto expectedIn = [&](const std::string& process) {
    return expected_in[process] +
           (process == "lasonic-pilot" ? watch.published("lasonic-complement", channels::SONAR_COMPLEMENT) : 0);
  };
  const auto ringsAnswered = [&] { return watch.published("lasonic-complement", channels::SONAR_COMPLEMENT); };
  const auto ringsDropped = [&] {
    return watch.counter("lasonic-complement", "rejected.sonar_backwards") +
           watch.counter("lasonic-complement", std::string("time.held_ahead.") + channels::SONAR_RING);
  };
  const auto t_start = std::chrono::steady_clock::now();
  for (int64_t i = 0; i < count; ++i) {
    const std::string& ch = chans[gen.pick(chans.size())];
    std::string kind;
    std::vector<uint8_t> b;
    if (i % 25'000 == 12'345) {
      kind = "overcap";
      b = gen.overCap(ch, 1'000'000);
    }
    if (b.empty()) b = gen.next(ch, kind);
    // Published once on every URL where some target listens to the channel.
    bool on_url[3] = {false, false, false};
    for (const Target& t : kTargets)
      for (const std::string& c : t.channels)
        if (c == ch) on_url[t.url] = true;
    for (int u = 0; u < 3; ++u)
      if (on_url[u]) urls[u]->publish(ch, b.data(), static_cast<unsigned>(b.size()));
    ++ex.sent[ch];
    ++ex.kinds[kind];
    switch (fateOn(ch, b)) {
      case Fate::DecodeError: ++ex.decode_errors[ch]; break;
      case Fate::Oversize: ++ex.oversize[ch]; break;
      case Fate::Decodes:
        // lasonic-complement answers a ring with a plausible time with one SONAR_COMPLEMENT.
        if (ch == channels::SONAR_RING && [&] {
              sonar_ring_t r;
              r.decode(b.data(), 0, static_cast<int>(b.size()));
              return plausibleUtime(r.utime);
            }()) {
          ++ex.ring_decodes;
        }
        break;
    }
    for (const Target& t : kTargets)
      for (const std::string& c : t.channels)
        if (c == ch) ++expected_in[t.process];
    // Flow control: nobody more than kWindow messages behind (as of its last heartbeat).
    if (i % 64 == 0) spin(0);
    while (true) {
      int64_t lag = 0;
      for (const Target& t : kTargets) lag = std::max(lag, expectedIn(t.process) - watch.received(t.process));
      if (lag <= kWindow) break;
      spin(20);
    }
    if (b.size() > 100'000) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a big one: let it drain
  }
  const double feed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  const bool all_in = waitUntil(30, [&] {
    for (const Target& t : kTargets)
      if (watch.received(t.process) < expectedIn(t.process)) return false;
    return ringsAnswered() + ringsDropped() == ex.ring_decodes;  // (and the complement's heartbeat says so)
  });
  // Every ring that decoded with a plausible time was answered, or dropped for its time and counted.
  const int64_t answered = ringsAnswered();
  const int64_t dropped = ringsDropped();
  expect(answered + dropped == ex.ring_decodes,
         "lasonic-complement answered " + std::to_string(answered) + " and dropped " + std::to_string(dropped) +
             " of " + std::to_string(ex.ring_decodes) + " rings");
  // (The fuzz's times jump back and forth: over half of its rings come out of order.)
  expect(answered > 0, "lasonic-complement answered none of " + std::to_string(ex.ring_decodes) + " rings");
  std::printf("complement.rings_answered %lld\ncomplement.rings_dropped %lld\n", static_cast<long long>(answered),
              static_cast<long long>(dropped));
  std::printf("fuzz.messages %lld\nfuzz.seconds %.1f\nfuzz.rate_hz %.0f\n", static_cast<long long>(count), feed_s,
              static_cast<double>(count) / feed_s);
  for (const auto& [k, n] : ex.kinds) std::printf("kind.%s %lld\n", k.c_str(), static_cast<long long>(n));
  for (const auto& [c, n] : ex.sent)
    std::printf("sent.%s %lld decode_errors %lld oversize %lld\n", c.c_str(), static_cast<long long>(n),
                static_cast<long long>(ex.decode_errors[c]), static_cast<long long>(ex.oversize[c]));
  expect(all_in, "every target reported all its input received within 30 s");

  // Per process: received == sent, decode errors and oversize exactly, every error counted.
  for (const Target& t : kTargets) {
    const auto it = watch.newest.find(t.process);
    if (it == watch.newest.end()) continue;
    const process_status_t& s = it->second;
    std::map<std::string, int64_t> counters;
    for (size_t i = 0; i < s.counter_names.size() && i < s.counter_values.size(); ++i)
      counters[s.counter_names[i]] = s.counter_values[i];
    int64_t undecodable = 0;
    for (const std::string& c : t.channels) {
      int64_t in = -1, de = -1;
      for (const auto& cs : s.channels)
        if (cs.direction == channel_stat_t::DIR_IN && cs.channel == c) {
          in = cs.messages;
          de = cs.decode_errors;
        }
      const int64_t want =
          ex.sent[c] + (t.process == "lasonic-pilot" && c == channels::SONAR_COMPLEMENT ? answered : 0);
      expect(in == want, t.process + " " + c + ": received " + std::to_string(in) + " of " + std::to_string(want));
      expect(de == ex.decode_errors[c], t.process + " " + c + ": decode_errors " + std::to_string(de) + ", expected " +
                                            std::to_string(ex.decode_errors[c]));
      expect(counters["oversize." + c] == ex.oversize[c],
             t.process + " " + c + ": oversize " + std::to_string(counters["oversize." + c]) + ", expected " +
                 std::to_string(ex.oversize[c]));
      undecodable += ex.decode_errors[c] + ex.oversize[c];
    }
    int64_t rejected = 0;
    for (const auto& [k, v] : counters)
      if (k.rfind("rejected.", 0) == 0) rejected += v;
    std::printf("%s.errors %lld\n%s.rejected %lld\n%s.time_resets %lld\n%s.handler_failures %lld\n", t.process.c_str(),
                static_cast<long long>(s.errors), t.process.c_str(), static_cast<long long>(rejected), t.process.c_str(),
                static_cast<long long>(counters["time_resets"]), t.process.c_str(),
                static_cast<long long>([&] {
                  int64_t h = 0;
                  for (const auto& [k, v] : counters)
                    if (k.rfind("handler_failures.", 0) == 0) h += v;
                  return h;
                }()));
    expect(s.errors >= undecodable + rejected, t.process + ": errors below the bad inputs counted");
    expect(rejected > 0, t.process + ": no semantic garbage was rejected");
    for (const auto& [k, v] : counters)
      expect(k.rfind("handler_failures.", 0) != 0 && k != "publish_failures",
             t.process + ": " + k + " = " + std::to_string(v) + " (a handler threw or a publish failed)");
  }
  return failures == 0 ? 0 : 1;
}

// ---- check the outputs
bool finite(const pose2d_t& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta); }
bool distanceOk(float d, float limit) { return d == -1.0f || (std::isfinite(d) && d >= 0 && d <= limit + 1e-4f); }

// only: the channels to check (empty: all): in a log replayed with `lasonic-replay --stages`, a
// channel the other stages publish is the fuzz's input.
int check(const std::vector<std::string>& files, const std::set<std::string>& only = {}) {
  std::map<std::string, int64_t> n, bad;
  auto fail = [&](const std::string& ch, const std::string& why) {
    if (bad[ch]++ == 0) std::fprintf(stderr, "lasonic-fuzz: FAIL: %s: %s\n", ch.c_str(), why.c_str());
    ++failures;
  };
  try {
    for (size_t fi = 0; fi < files.size(); ++fi) {
      const bool sim_log = fi == 1;  // check PIPE_LOG SIM_LOG: LASER_SCAN there is the driver's
      // check PIPE_LOG SIM_LOG NAV_LOG: AGM_TACTICAL and AGM_LINES on PIPE_URL and RADAR_MAP on
      // NAV_URL are the fuzz's input, not a process's output.
      const bool three = files.size() == 3;
      LogReader log(files[fi]);
      while (auto ev = log.next()) {
        const std::string& ch = ev->channel;
        if (!only.empty() && !only.count(ch)) continue;
        if (three && fi == 0 && (ch == channels::AGM_TACTICAL || ch == channels::AGM_LINES)) continue;
        if (three && fi == 2 && ch != channels::AGM_TACTICAL && ch != channels::AGM_LINES &&
            ch != channels::CURRENT_SENSOR_MAP)
          continue;
        if (ch == channels::SECTOR_MAP) {
          ++n[ch];
          const auto m = decodeAs<sector_map_t>(ev->data);
          if (!m) { fail(ch, "does not decode"); continue; }
          const auto k = static_cast<size_t>(m->nsectors);
          if (m->distance.size() != k || m->source.size() != k || !finite(m->robot_pose) ||
              !std::isfinite(m->laser_age_s) || !std::isfinite(m->sonar_age_s) || !(m->max_range > 0)) {
            fail(ch, "bad header or pose");
            continue;
          }
          for (size_t i = 0; i < k; ++i)
            if (!distanceOk(m->distance[i], m->max_range) || !distanceOk(m->laser_distance[i], m->max_range) ||
                !distanceOk(m->sonar_distance[i], m->max_range) || m->source[i] < 0 ||
                m->source[i] > sector_map_t::SOURCE_REMEMBERED ||
                ((m->source[i] == sector_map_t::SOURCE_NONE) != (m->distance[i] == -1.0f)) ||
                (i < m->remembered_distance.size() && !distanceOk(m->remembered_distance[i], m->max_range)) ||
                // the remembered (tactical) source: never used while stale
                (m->source[i] == sector_map_t::SOURCE_REMEMBERED && m->remembered_stale != 0)) {
              fail(ch, "sector " + std::to_string(i) + " distance " + std::to_string(m->distance[i]));
              break;
            }
        } else if (ch == channels::RADAR_MAP || ch == channels::AGM_LINES || ch == channels::CURRENT_SENSOR_MAP) {
          ++n[ch];
          const auto m = decodeAs<line_map_t>(ev->data);
          if (!m) { fail(ch, "does not decode"); continue; }
          for (const auto& l : m->segments)
            if (!std::isfinite(l.x0) || !std::isfinite(l.y0) || !std::isfinite(l.x1) || !std::isfinite(l.y1) ||
                !std::isfinite(l.rms)) {
              fail(ch, "non-finite segment (event " + std::to_string(ev->timestamp) + ")");
              break;
            }
        } else if (ch == channels::SONAR_COMPLEMENT && ev->timestamp > 0) {
          // Our own fuzz is on this channel too: only the complement's output decodes with a
          // known tolerance of 0.1 (ours: 0.1 too) -- so check every decodable one for classes.
          const auto m = decodeAs<complement_t>(ev->data);
          if (!m) continue;
          ++n[ch];
          // The fuzz's own complements have tolerance 0.125 (no 8 bit flips make it 0.1).
          if (m->tolerance != 0.1f) continue;
          for (const auto& r : m->readings)
            if (r.cls < 0 || r.cls > complement_reading_t::CLASS_SEEN_BEFORE ||
                ((r.cls == complement_reading_t::CLASS_COMPLEMENTARY ||
                  r.cls == complement_reading_t::CLASS_OUTSIDE_VIEW ||
                  r.cls == complement_reading_t::CLASS_SEEN_BEFORE) &&
                 (!std::isfinite(r.range) || !std::isfinite(r.end_x) || !std::isfinite(r.end_y) || !finite(r.sensor_pose)))) {
              fail(ch, "lasonic-complement published a reading with an unknown class or a non-finite value");
              break;
            }
        } else if (ch == channels::LASER_SCAN && sim_log) {
          const auto m = decodeAs<laser_scan_t>(ev->data);
          if (!m) {
            fail(ch, "a driver's scan does not decode");
            continue;
          }
          ++n["driver.LASER_SCAN"];
          for (size_t i = 0; i < m->ranges.size(); ++i)
            if (m->flags[i] == laser_scan_t::FLAG_OK && !(std::isfinite(m->ranges[i]) && m->ranges[i] >= 0)) {
              fail(ch, "a driver's reading is not finite");
              break;
            }
        } else if (ch == channels::AGM_OPERATIONAL || ch == channels::AGM_TACTICAL) {
          ++n[ch];
          const auto m = decodeAs<grid_map_t>(ev->data);
          if (!m || static_cast<int64_t>(m->width) * m->height != m->ncells || !std::isfinite(m->origin_x) ||
              !std::isfinite(m->origin_y) || !(m->cell_size > 0) || !finite(m->robot_pose))
            fail(ch, "bad grid");
          else
            for (int32_t c = 0; c < m->ncells; ++c)
              if (m->g[static_cast<size_t>(c)] < 0 || m->h[static_cast<size_t>(c)] < 0 || m->gp[static_cast<size_t>(c)] < 0) {
                fail(ch, "negative weight in cell " + std::to_string(c));
                break;
              }
        }
      }
    }
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-fuzz: %s\n", e.what());
    return 2;
  }
  for (const auto& [ch, k] : n) std::printf("out.%s %lld\n", ch.c_str(), static_cast<long long>(k));
  return failures == 0 ? 0 : 1;
}

}  // namespace

// The pipeline channels' fuzz written to a log, for lasonic-replay: deterministic and fast.
// Prints per channel the messages sent and those Node cannot decode or finds over a cap
// ("sent.CH N", "undecodable.CH N").
int write(const std::string& file, int64_t count, uint64_t seed,
          const std::vector<std::string>& chans = {channels::ODOMETRY, channels::LASER_SCAN, channels::SONAR_RING,
                                                   channels::SONAR_COMPLEMENT}) {
  Gen gen(seed);
  std::map<std::string, int64_t> sent, undecodable;
  try {
    LogWriter out(file);
    for (int64_t i = 0; i < count; ++i) {
      const std::string& ch = chans[gen.pick(chans.size())];
      std::string kind;
      std::vector<uint8_t> b = i % 25'000 == 12'345 ? gen.overCap(ch, 1'000'000) : gen.next(ch, kind);
      ++sent[ch];
      undecodable[ch] += fateOn(ch, b) != Fate::Decodes;
      out.writeRaw(ch, i, b);
    }
  } catch (const LogError& e) {
    std::fprintf(stderr, "lasonic-fuzz: %s\n", e.what());
    return 2;
  }
  for (const auto& [ch, k] : sent)
    std::printf("sent.%s %lld\nundecodable.%s %lld\n", ch.c_str(), static_cast<long long>(k), ch.c_str(),
                static_cast<long long>(undecodable[ch]));
  return 0;
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  for (size_t a = 0; a <= s.size();) {
    const size_t b = std::min(s.find(',', a), s.size());
    if (b > a) out.push_back(s.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "write" && argc == 5)
    return write(argv[2], std::strtoll(argv[3], nullptr, 10), std::strtoull(argv[4], nullptr, 10));
  if (mode == "write" && argc == 6) {
    const auto chans = splitList(argv[5]);
    for (const auto& c : chans)
      if (c != channels::ODOMETRY && c != channels::LASER_SCAN && c != channels::SONAR_RING &&
          c != channels::SONAR_COMPLEMENT && c != channels::RADAR_MAP && c != channels::AGM_TACTICAL &&
          c != channels::AGM_LINES) {
        std::fprintf(stderr, "lasonic-fuzz: write: no fuzz for channel '%s'\n", c.c_str());
        return 2;
      }
    if (chans.empty()) return 2;
    return write(argv[2], std::strtoll(argv[3], nullptr, 10), std::strtoull(argv[4], nullptr, 10), chans);
  }
  if (mode == "check-only" && argc >= 4) {
    const auto only = splitList(argv[2]);
    return check(std::vector<std::string>(argv + 3, argv + argc), std::set<std::string>(only.begin(), only.end()));
  }
  if (mode == "feed" && argc == 7)
    return feed(argv[2], argv[3], argv[4], std::strtoll(argv[5], nullptr, 10), std::strtoull(argv[6], nullptr, 10));
  if (mode == "check" && argc == 5) return check({argv[2], argv[3], argv[4]});
  if (mode == "check" && argc == 4) return check({argv[2], argv[3]});
  if (mode == "check" && argc == 3) return check({argv[2]});
  std::fprintf(stderr, "usage: lasonic-fuzz feed PIPE_URL SIM_URL NAV_URL COUNT SEED | write LOG COUNT SEED [CHANNELS] |\n"
               "       check PIPE_LOG [SIM_LOG [NAV_LOG]] | check-only CHANNELS LOG...   (CHANNELS: comma-separated)\n");
  return 2;
}
