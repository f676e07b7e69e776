#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "lcmio/eventlog.hpp"
#include "lcmio/node.hpp"
#include "lcmio/time_reset.hpp"
#include "scratch_dir.hpp"

#include <lasonic/odometry_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/process_status_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/sector_map_t.hpp>

using namespace lasonic;

TEST(Lengths, SetFromVectorsAndCheckParallelArrays) {
  laser_scan_t s{};
  s.ranges = {1, 2, 3};
  s.flags = {0, 0, 1};
  s.offset_us = {0, 10, 20};
  s.nranges = 99;  // stale count must be replaced
  setLengths(s);
  EXPECT_EQ(s.nranges, 3);
  s.flags.pop_back();
  EXPECT_THROW(setLengths(s), std::logic_error);
}

TEST(Node, TypedPubSubOverMemq) {
  Node node("test", "memq://", Node::Options{false, false});
  int got = 0;
  double x = 0;
  node.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t& m) {
    ++got;
    x = m.pose.x;
  });
  odometry_t o{};
  o.utime = 5;
  o.pose.x = 1.25;
  node.publish("ODOMETRY", o);
  while (node.spinOnce(0) > 0) {
  }
  EXPECT_EQ(got, 1);
  EXPECT_DOUBLE_EQ(x, 1.25);
}

TEST(Node, DecodeErrorsAreCountedNotThrown) {
  Node node("test", "memq://", Node::Options{false, false});
  int got = 0;
  node.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t&) { ++got; });
  const uint8_t junk[5] = {1, 2, 3, 4, 5};
  node.lcm().publish("ODOMETRY", junk, sizeof(junk));
  // A laser scan on the odometry channel: wrong fingerprint.
  laser_scan_t wrong{};
  node.publish("ODOMETRY", wrong);
  while (node.spinOnce(0) > 0) {
  }
  EXPECT_EQ(got, 0);
  EXPECT_EQ(node.counter("decode_errors.ODOMETRY"), 2);
  EXPECT_EQ(node.errors(), 2);
}

TEST(Node, HandlerExceptionsAreCaught) {
  Node node("test", "memq://", Node::Options{false, false});
  node.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t&) { throw std::runtime_error("boom"); });
  odometry_t o{};
  node.publish("ODOMETRY", o);
  EXPECT_NO_THROW(while (node.spinOnce(0) > 0){});
  EXPECT_EQ(node.counter("handler_failures.ODOMETRY"), 1);
}

TEST(EventLog, WriteThenReadBack) {
  const lasonic::fixture::ScratchDir scratch;
  const std::string path = scratch.file("lasonic_test_eventlog.lcmlog");
  {
    LogWriter w(path);
    for (int i = 0; i < 3; ++i) {
      odometry_t o{};
      o.utime = i * 1000;
      o.pose.y = i;
      w.write("ODOMETRY", o.utime, o);
    }
  }
  const auto events = LogReader::readAll(path);
  ASSERT_EQ(events.size(), 3u);
  auto o = decodeAs<odometry_t>(events[2].data);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->utime, 2000);
  EXPECT_EQ(events[2].timestamp, 2000);
  EXPECT_FALSE(decodeAs<laser_scan_t>(events[0].data));
  EXPECT_THROW(LogReader("/nonexistent/x.lcmlog"), LogError);
}

// ---- array caps before decoding (lcmio/lengths.hpp)

namespace {
// A message's bytes with its count field overwritten (big-endian int32 at the measured offset).
template <typename T>
std::vector<uint8_t> withClaimedCount(T msg, int32_t claimed) {
  std::vector<uint8_t> b = encodeMsg(msg);
  const auto off = static_cast<size_t>(wireShape<T>().count_offset);
  const auto u = static_cast<uint32_t>(claimed);
  for (int i = 0; i < 4; ++i) b[off + static_cast<size_t>(i)] = static_cast<uint8_t>(u >> (24 - 8 * i));
  return b;
}
template <typename T>
void expectCountAtMeasuredOffset() {
  T m{};
  WireArrays<T>::one(m);
  const std::vector<uint8_t> b = encodeMsg(m);
  const auto off = static_cast<size_t>(wireShape<T>().count_offset);
  ASSERT_LT(off + 4, b.size() + 1);
  const int32_t count = static_cast<int32_t>((uint32_t{b[off]} << 24) | (uint32_t{b[off + 1]} << 16) |
                                             (uint32_t{b[off + 2]} << 8) | uint32_t{b[off + 3]});
  EXPECT_EQ(count, 1) << T::getTypeName();
  EXPECT_EQ(static_cast<int64_t>(b.size()), wireShape<T>().fixed + wireShape<T>().per_element) << T::getTypeName();
  EXPECT_EQ(checkWireArrays<T>(b.data(), b.size()).result, WireCheck::Ok) << T::getTypeName();
}
}  // namespace

TEST(WireArrays, CountSitsWhereMeasuredForEveryCheckedType) {
  expectCountAtMeasuredOffset<laser_scan_t>();
  expectCountAtMeasuredOffset<sonar_ring_t>();
  expectCountAtMeasuredOffset<complement_t>();
  expectCountAtMeasuredOffset<sim_state_t>();
  expectCountAtMeasuredOffset<line_map_t>();
  expectCountAtMeasuredOffset<grid_map_t>();
}

TEST(WireArrays, ClaimsBeyondTheBytesOrTheCapAreRefusedBeforeDecoding) {
  laser_scan_t s{};
  s.ranges = {1, 2};
  s.flags = {0, 0};
  s.offset_us = {0, 1};
  EXPECT_EQ(checkWireArrays<laser_scan_t>(encodeMsg(s).data(), encodeMsg(s).size()).result, WireCheck::Ok);
  const auto huge = withClaimedCount(s, 2'000'000'000);
  EXPECT_EQ(checkWireArrays<laser_scan_t>(huge.data(), huge.size()).result, WireCheck::TooMany);
  const auto three = withClaimedCount(s, 3);  // bytes for 2
  EXPECT_EQ(checkWireArrays<laser_scan_t>(three.data(), three.size()).result, WireCheck::Truncated);
  const auto negative = withClaimedCount(s, -1);
  EXPECT_EQ(checkWireArrays<laser_scan_t>(negative.data(), negative.size()).result, WireCheck::Truncated);
  odometry_t o{};
  const auto other = encodeMsg(o);
  EXPECT_EQ(checkWireArrays<laser_scan_t>(other.data(), other.size()).result, WireCheck::NotThisType);
  // Exactly at the cap with the bytes present: accepted.
  laser_scan_t big{};
  big.ranges.assign(static_cast<size_t>(limits::kLaserReadings), 1.f);
  big.flags.assign(big.ranges.size(), 0);
  big.offset_us.assign(big.ranges.size(), 0);
  const auto at_cap = encodeMsg(big);
  EXPECT_EQ(checkWireArrays<laser_scan_t>(at_cap.data(), at_cap.size()).result, WireCheck::Ok);
  big.ranges.push_back(1.f);
  big.flags.push_back(0);
  big.offset_us.push_back(0);
  const auto over = encodeMsg(big);
  EXPECT_EQ(checkWireArrays<laser_scan_t>(over.data(), over.size()).result, WireCheck::TooMany);
}

TEST(Node, HugeClaimedArraysAreCountedNotAllocated) {
  Node node("test", "memq://", Node::Options{false, false});
  int got = 0;
  node.subscribe<laser_scan_t>("LASER_SCAN", [&](const laser_scan_t&) { ++got; });
  laser_scan_t s{};
  s.ranges = {1};
  s.flags = {0};
  s.offset_us = {0};
  // Without the check, decode() would resize to 2^31-1 readings (~19 GB) before noticing.
  const auto huge = withClaimedCount(s, 2'147'483'647);
  const auto lying = withClaimedCount(s, 1000);
  const auto negative = withClaimedCount(s, -5);
  node.lcm().publish("LASER_SCAN", huge.data(), static_cast<unsigned>(huge.size()));
  node.lcm().publish("LASER_SCAN", lying.data(), static_cast<unsigned>(lying.size()));
  node.lcm().publish("LASER_SCAN", negative.data(), static_cast<unsigned>(negative.size()));
  node.publish("LASER_SCAN", s);
  while (node.spinOnce(0) > 0) {
  }
  EXPECT_EQ(got, 1);
  EXPECT_EQ(node.counter("oversize.LASER_SCAN"), 1);
  EXPECT_EQ(node.counter("decode_errors.LASER_SCAN"), 2);
  EXPECT_EQ(node.errors(), 3);
}

TEST(Node, AnUnusableUrlThrowsLcmUrlError) {
  EXPECT_THROW(Node("test", "bogus://nothing", Node::Options{false, false}), LcmUrlError);
  EXPECT_THROW(Node("test", "udpm://999.1.1.1:7667", Node::Options{false, false}), LcmUrlError);
}

TEST(StatusBoard, SnapshotCarriesCountersErrorsAndChannels) {
  StatusBoard b("p");
  b.declareInput("IN");
  b.received("IN");
  b.received("IN");
  b.decodeError("IN");
  b.sent("OUT");
  b.count("x", 3);
  b.reportError("rejected.y", "Y is bad");
  b.noteMessageTime(42);
  b.noteMessageTime(7);  // older: the newest stays
  const process_status_t st = b.snapshot();
  EXPECT_EQ(st.process, "p");
  EXPECT_EQ(st.errors, 1);
  EXPECT_EQ(st.last_error, "Y is bad");
  EXPECT_EQ(st.last_msg_utime, 42);
  ASSERT_EQ(st.channels.size(), 2u);
  EXPECT_EQ(st.channels[0].channel, "IN");
  EXPECT_EQ(st.channels[0].messages, 2);
  EXPECT_EQ(st.channels[0].decode_errors, 1);
  EXPECT_EQ(int{st.channels[1].direction}, int{channel_stat_t::DIR_OUT});
  ASSERT_EQ(st.counter_names.size(), 2u);
  EXPECT_EQ(st.counter_names[0], "rejected.y");
  EXPECT_EQ(st.counter_values[1], 3);
}

TEST(TimeReset, PerChannelJumpsOfMoreThanASecond) {
  TimeReset c;
  EXPECT_FALSE(c.jumpedBack("A", 5'000'000));
  EXPECT_FALSE(c.jumpedBack("B", 1'000'000));  // another channel may lag behind
  EXPECT_FALSE(c.jumpedBack("A", 4'500'000));  // late, not a restart
  EXPECT_TRUE(c.jumpedBack("A", 3'000'000));   // 2 s back: restarted
  // After a reset every channel starts afresh: B's old time does not count any more.
  EXPECT_FALSE(c.jumpedBack("B", 100'000));
  EXPECT_FALSE(c.jumpedBack("A", 3'020'000));
  EXPECT_TRUE(plausibleUtime(0));
  EXPECT_FALSE(plausibleUtime(-1));
  EXPECT_FALSE(plausibleUtime(kMaxUtime + 1));
}

TEST(TimeReset, AStrayTimeFarAheadIsHeldAndDroppedNotARestart) {
  using A = TimeReset::Admission;
  TimeReset c;
  EXPECT_EQ(c.admit("ODO", 10'000'000).kind, A::Ok);
  EXPECT_EQ(c.admit("LASER", 9'900'000).kind, A::Ok);
  // One odometry message stamped an hour ahead: held, not used.
  const A held = c.admit("ODO", 3'610'000'000);
  EXPECT_EQ(held.kind, A::HeldAhead);
  EXPECT_EQ(held.reference, 10'000'000);
  // The next one is back at the common time: the held one was a stray, and nothing restarts.
  const A back = c.admit("ODO", 10'020'000);
  EXPECT_EQ(back.kind, A::Ok);
  ASSERT_TRUE(back.stray.has_value());
  EXPECT_EQ(*back.stray, 3'610'000'000);
  EXPECT_EQ(back.stray_reference, 10'000'000);
  EXPECT_EQ(c.admit("LASER", 10'000'000).kind, A::Ok);
  EXPECT_FALSE(c.admit("ODO", 10'040'000).stray.has_value());  // reported once
}

TEST(TimeReset, AClockThatSteppedForwardIsTakenFromItsSecondMessage) {
  using A = TimeReset::Admission;
  TimeReset c;
  EXPECT_EQ(c.admit("ODO", 10'000'000).kind, A::Ok);
  EXPECT_EQ(c.admit("ODO", 15'000'000).kind, A::HeldAhead);  // 5 s on: a stray, or a step?
  const A next = c.admit("ODO", 15'020'000);                 // it goes on from there: a step
  EXPECT_EQ(next.kind, A::Ok);
  EXPECT_FALSE(next.stray.has_value());
  ASSERT_TRUE(next.stepped_from.has_value());
  EXPECT_EQ(*next.stepped_from, 10'000'000);
  EXPECT_EQ(c.admit("LASER", 15'030'000).kind, A::Ok);  // the other inputs follow
  // A channel that starts late but in step with the others is not held.
  EXPECT_EQ(c.admit("SONAR", 15'040'000).kind, A::Ok);
  // Restarts are still restarts, and forget what was held.
  EXPECT_EQ(c.admit("ODO", 30'000'000).kind, A::HeldAhead);
  EXPECT_EQ(c.admit("LASER", 1'000'000).kind, A::Restarted);
  const A after = c.admit("ODO", 1'020'000);
  EXPECT_EQ(after.kind, A::Ok);
  EXPECT_FALSE(after.stray.has_value());
}

TEST(TimeReset, TwoInterleavedTimelinesKeepTheOneTakenAndReportTheOther) {
  using A = TimeReset::Admission;
  TimeReset c;
  int restarts = 0, strays = 0;
  for (int k = 0; k < 50; ++k) {
    const int64_t dt = 20'000 * k;
    for (const int64_t t : {100'000'000 + dt, 50'000'000 + dt}) {  // two logs played together
      const A a = c.admit("ODO", t);
      restarts += a.kind == A::Restarted ? 1 : 0;
      strays += a.stray ? 1 : 0;
    }
  }
  EXPECT_EQ(restarts, 1);  // the second log's first message; then its timeline is kept
  EXPECT_EQ(strays, 49);   // every later message of the first one, reported
}

namespace {
// T::decode, out of line (inlined into a test, GCC warns about the generated decode's fingerprint).
template <typename T>
[[gnu::noinline]] int generatedDecode(T& m, const uint8_t* bytes, int len) {
  return m.decode(bytes, 0, len);
}
}  // namespace

// The fast encode of grid maps (lcmio/wire.hpp) must give exactly the generated code's bytes:
// any cell count (the SSE2 blocks and the scalar tail), every value range, odd header values.
TEST(Wire, GridMapFastEncodeIsTheGeneratedEncodeByteForByte) {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (const int n : {0, 1, 3, 4, 5, 7, 8, 9, 15, 16, 17, 100, 10000}) {
    grid_map_t m{};
    m.utime = static_cast<int64_t>(next());
    m.robot_pose = {-1.25, 3.5e10, -0.0};
    m.origin_x = -std::numeric_limits<double>::infinity();
    m.origin_y = std::numeric_limits<double>::quiet_NaN();
    m.cell_size = 0.05f;
    m.width = n;
    m.height = 1;
    m.gp_threshold = -7;
    for (int i = 0; i < n; ++i) {
      const uint64_t r = next();
      m.g.push_back(static_cast<int16_t>(r));
      m.h.push_back(static_cast<int16_t>(r >> 16));
      m.gp.push_back(static_cast<int32_t>(r >> 32));
      m.heard.push_back(static_cast<int8_t>(r >> 29));  // every byte value, not only HEARD_*
    }
    if (n > 2) m.g[1] = std::numeric_limits<int16_t>::min(), m.gp[2] = std::numeric_limits<int32_t>::min();
    setLengths(m);
    const int size = m.getEncodedSize();
    std::vector<uint8_t> want(static_cast<size_t>(size)), got(static_cast<size_t>(size), 0xAB);
    ASSERT_EQ(m.encode(want.data(), 0, size), size);
    ASSERT_EQ(wireEncode(m, got.data(), size), size) << n << " cells";
    EXPECT_EQ(got, want) << n << " cells";
    // A buffer too short: the generated encode's answer.
    if (n > 0) {
      EXPECT_EQ(wireEncode(m, got.data(), size - 1), m.encode(want.data(), 0, size - 1));
    }
    // Decoding: the generated decode's message and return value, also for bytes that are not a
    // whole grid map (cut short, a wrong fingerprint, a count the bytes do not hold, negative).
    const auto sameDecode = [](const std::vector<uint8_t>& bytes, int len, const char* what) {
      grid_map_t a{}, b{};
      const int ra = generatedDecode(a, bytes.data(), len);
      const int rb = wireDecode(b, bytes.data(), len);
      EXPECT_EQ(rb, ra) << what;
      if (ra < 0) return;
      std::vector<uint8_t> ea(static_cast<size_t>(ra)), eb(static_cast<size_t>(ra));
      a.encode(ea.data(), 0, ra);
      b.encode(eb.data(), 0, ra);
      EXPECT_EQ(eb, ea) << what;
      EXPECT_EQ(b.g.size(), a.g.size()) << what;
      EXPECT_EQ(b.heard, a.heard) << what;
    };
    sameDecode(want, size, "whole");
    sameDecode(want, size - 1, "one byte short");
    sameDecode(want, 40, "cut in the fields");
    std::vector<uint8_t> bad = want;
    bad[3] ^= 1;
    sameDecode(bad, size, "fingerprint");
    bad = want;
    const size_t count_at = static_cast<size_t>(size) - 9 * static_cast<size_t>(n) - 4;
    bad[count_at + 3] += 1;  // one cell more than the bytes hold
    sameDecode(bad, size, "count + 1");
    bad[count_at] = 0xFF;  // negative: the generated decode throws (Node checks the count first)
    grid_map_t a{}, b{};
    EXPECT_ANY_THROW(generatedDecode(a, bad.data(), size));
    EXPECT_ANY_THROW(wireDecode(b, bad.data(), size));
  }
}

// The laser scan's fast decode: the generated decode's message and return value for whole
// scans of 0..1000 readings (NaN, infinite and negative ranges, every flag byte, negative
// offsets) and for bytes that are not a whole scan (cut short anywhere, a wrong fingerprint, a
// count the bytes do not hold, a negative count).
TEST(Wire, LaserScanFastDecodeIsTheGeneratedDecode) {
  uint64_t state = 0x2545F4914F6CDD1Dull;
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  const auto same = [](const laser_scan_t& a, const laser_scan_t& b) {
    const auto bytes = [](const laser_scan_t& m) {
      std::vector<uint8_t> v(static_cast<size_t>(m.getEncodedSize()));
      m.encode(v.data(), 0, static_cast<int>(v.size()));
      return v;
    };
    return a.nranges == b.nranges && a.ranges.size() == b.ranges.size() && a.flags.size() == b.flags.size() &&
           a.offset_us.size() == b.offset_us.size() && bytes(a) == bytes(b);
  };
  for (const int n : {0, 1, 3, 4, 5, 7, 8, 9, 15, 16, 17, 360, 720, 1000}) {
    laser_scan_t m{};
    m.utime = static_cast<int64_t>(next());
    m.seq = static_cast<int32_t>(next());
    m.mount = {0.2, -0.0, std::numeric_limits<double>::quiet_NaN()};
    m.angle_min = -2.35;
    m.angle_increment = 0.0065;
    m.range_min = 0.02f;
    m.range_max = std::numeric_limits<float>::infinity();
    for (int i = 0; i < n; ++i) {
      const uint64_t r = next();
      uint32_t bits = static_cast<uint32_t>(r);
      float f;
      std::memcpy(&f, &bits, 4);  // any float: NaN payloads, infinities, negative, subnormal
      m.ranges.push_back(f);
      m.flags.push_back(static_cast<int8_t>(r >> 32));
      m.offset_us.push_back(static_cast<int32_t>(r >> 40) - (1 << 22));
    }
    setLengths(m);
    const int size = m.getEncodedSize();
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    ASSERT_EQ(m.encode(bytes.data(), 0, size), size);
    const auto sameDecode = [&](const std::vector<uint8_t>& b, int len, const std::string& what) {
      laser_scan_t x{}, y{};
      const int rx = generatedDecode(x, b.data(), len);
      const int ry = wireDecode(y, b.data(), len);
      ASSERT_EQ(ry, rx) << what << ", " << n << " readings";
      if (rx >= 0) {
        EXPECT_TRUE(same(x, y)) << what << ", " << n << " readings";
      }
      // Into a message that held an earlier scan (Node decodes into the same one each time).
      laser_scan_t z{};
      z.nranges = 1000;
      z.ranges.assign(1000, 1.5f);
      z.flags.assign(1000, 1);
      z.offset_us.assign(1000, 7);
      const int rz = wireDecode(z, b.data(), len);
      ASSERT_EQ(rz, rx) << what << ", " << n << " readings, into a used message";
      if (rx >= 0) {
        EXPECT_TRUE(same(x, z)) << what << ", " << n << " readings, into a used message";
      }
    };
    sameDecode(bytes, size, "whole");
    for (int cut = 1; cut <= 9; ++cut) sameDecode(bytes, size - cut, "cut by " + std::to_string(cut));
    sameDecode(bytes, 40, "cut in the fields");
    std::vector<uint8_t> bad = bytes;
    bad[3] ^= 1;
    sameDecode(bad, size, "fingerprint");
    bad = bytes;
    const size_t count_at = static_cast<size_t>(size) - 9 * static_cast<size_t>(n) - 4;
    bad[count_at + 3] += 1;  // one reading more than the bytes hold
    sameDecode(bad, size, "count + 1");
    bad[count_at] = 0xFF;  // negative: the generated decode throws (Node checks the count first)
    laser_scan_t a{}, b{};
    EXPECT_ANY_THROW(generatedDecode(a, bad.data(), size));
    EXPECT_ANY_THROW(wireDecode(b, bad.data(), size));
  }
}

// Node decodes grid maps and laser scans into the same message each time: a map without cells
// after one with cells arrives without them (LCM's generated decode alone would leave them).
TEST(Node, ReusedMessagesCarryNothingOver) {
  auto bus = std::make_shared<LocalBus>();
  Node node("test", bus, Node::Options{false, false});
  std::vector<size_t> cells;
  node.subscribe<grid_map_t>("GRID", [&cells](const grid_map_t& m) {
    cells.push_back(m.g.size() + m.h.size() + m.gp.size() + m.heard.size());
  });
  grid_map_t full{};
  full.width = full.height = 10;
  full.g.assign(100, 3);
  full.h.assign(100, 4);
  full.gp.assign(100, 5);
  grid_map_t empty{};
  node.publish("GRID", full);
  node.publish("GRID", empty);
  node.publish("GRID", full);
  bus->handleAll();
  EXPECT_EQ(cells, (std::vector<size_t>{400, 0, 400}));  // (`heard` left empty: setLengths fills it)
}

// The sector map's fast encode: the generated encode's bytes and return value for 0..3600
// sectors with any float bits (NaN payloads, -0, infinities), every source byte, the scalar
// fields at extreme values; for a buffer one byte short, the generated encode's answer.
TEST(Wire, SectorMapFastEncodeIsTheGeneratedEncodeByteForByte) {
  uint64_t state = 0x853C49E6748FEA9Bull;
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  const auto anyFloat = [&next]() {
    const auto bits = static_cast<uint32_t>(next());
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  };
  for (const int n : {0, 1, 3, 4, 5, 7, 8, 9, 48, 360, 3600}) {
    sector_map_t m{};
    m.utime = static_cast<int64_t>(next());
    m.robot_pose = {-1.25, 3.5e10, std::numeric_limits<double>::quiet_NaN()};
    m.robot_radius = anyFloat();
    m.max_range = -0.0f;
    m.laser_stale = static_cast<int8_t>(next());
    m.sonar_stale = -128;
    m.laser_age_s = anyFloat();
    m.sonar_age_s = std::numeric_limits<float>::infinity();
    m.remembered_stale = 127;
    m.remembered_age_s = anyFloat();
    for (int i = 0; i < n; ++i) {
      m.distance.push_back(anyFloat());
      m.source.push_back(static_cast<int8_t>(next()));
      m.laser_distance.push_back(anyFloat());
      m.sonar_distance.push_back(anyFloat());
      m.remembered_distance.push_back(anyFloat());
    }
    setLengths(m);
    const int size = m.getEncodedSize();
    std::vector<uint8_t> want(static_cast<size_t>(size)), got(static_cast<size_t>(size), 0xAB);
    ASSERT_EQ(m.encode(want.data(), 0, size), size);
    ASSERT_EQ(wireEncode(m, got.data(), size), size) << n << " sectors";
    EXPECT_EQ(got, want) << n << " sectors";
    // A buffer too short: the generated encode's answer.
    EXPECT_EQ(wireEncode(m, got.data(), size - 1), m.encode(want.data(), 0, size - 1)) << n << " sectors";
  }
}

TEST(Wire, NodePublishesTheSameBytesAsLcm) {
  grid_map_t m{};
  m.width = m.height = 3;
  m.cell_size = 0.1f;
  m.g = {1, -2, 3, 4, 5, 6, 7, 8, 32767};
  m.h = {0, 1, 2, 3, 4, 5, 6, 7, -32768};
  m.gp = {9, 8, 7, 6, 5, 4, 3, 2, -1};
  m.heard = {0, 1, 2, 3, 0, 1, 2, 3, -128};
  setLengths(m);
  std::vector<uint8_t> want(static_cast<size_t>(m.getEncodedSize()));
  ASSERT_EQ(m.encode(want.data(), 0, static_cast<int>(want.size())), static_cast<int>(want.size()));
  auto bus = std::make_shared<LocalBus>();
  std::vector<uint8_t> got;
  bus->subscribe("AGM_TACTICAL", [&got](const lcm::ReceiveBuffer* rbuf, const std::string&) {
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    got.assign(p, p + rbuf->data_size);
  });
  Node node("test", bus, Node::Options{false, false});
  node.publish("AGM_TACTICAL", m);
  ASSERT_EQ(bus->handleAll(), 1);
  EXPECT_EQ(got, want);
}
