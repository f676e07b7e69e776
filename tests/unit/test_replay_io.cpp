// The replay's fast parts against LCM's own: LogReader/LogWriter against lcm::LogFile (the same
// bytes, the same events, also for corrupt logs), LocalBus against memq:// (the same delivery
// order, also when handlers publish), ReplayMeter's progress rate.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <lasonic/odometry_t.hpp>

#include "lcmio/eventlog.hpp"
#include "lcmio/local_bus.hpp"
#include "lcmio/node.hpp"
#include "lcmio/replay_meter.hpp"
#include "scratch_dir.hpp"

using namespace lasonic;
namespace fs = std::filesystem;

namespace {

// A file NAME in the test program's scratch directory, removed when it exits.
std::string tmpPath(const std::string& name) {
  static const lasonic::fixture::ScratchDir d{"lasonic-test-replay-io"};
  return d.file(name);
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
}

struct Ev {
  int64_t t;
  std::string channel;
  std::vector<uint8_t> data;
};

std::vector<Ev> sampleEvents() {
  std::vector<Ev> ev;
  for (int i = 0; i < 300; ++i) {
    std::vector<uint8_t> d(static_cast<size_t>((i * 37) % 5000));  // 0 .. 4999 bytes, one empty
    for (size_t k = 0; k < d.size(); ++k) d[k] = static_cast<uint8_t>(k * 7 + static_cast<size_t>(i));
    ev.push_back({int64_t{1000} * i - 5, i % 3 ? "ODOMETRY" : "SONAR_RING", d});
  }
  ev.push_back({-1, std::string(999, 'C'), {1, 2, 3}});  // the longest channel LCM reads
  return ev;
}

// Events as lcm::LogFile reads them.
std::vector<LogRecord> readWithLcm(const std::string& path) {
  std::vector<LogRecord> out;
  lcm::LogFile f(path, "r");
  if (!f.good()) return out;
  while (const lcm::LogEvent* e = f.readNextEvent()) {
    const auto* p = static_cast<const uint8_t*>(e->data);
    out.push_back({e->timestamp, e->channel, std::vector<uint8_t>(p, p + e->datalen)});
  }
  return out;
}

void expectSame(const std::vector<LogRecord>& a, const std::vector<LogRecord>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].timestamp, b[i].timestamp) << what << " event " << i;
    EXPECT_EQ(a[i].channel, b[i].channel) << what << " event " << i;
    EXPECT_TRUE(a[i].data == b[i].data) << what << " event " << i;
  }
}

}  // namespace

TEST(ReplayIo, LogWriterWritesWhatLcmWrites) {
  const std::string ours = tmpPath("ours.lcmlog"), theirs = tmpPath("theirs.lcmlog");
  {
    LogWriter w(ours);
    lcm::LogFile l(theirs, "w");
    for (const Ev& e : sampleEvents()) {
      w.writeRaw(e.channel, e.t, e.data);
      lcm::LogEvent le;
      le.timestamp = e.t;
      le.channel = e.channel;
      le.datalen = static_cast<int32_t>(e.data.size());
      le.data = const_cast<uint8_t*>(e.data.data());
      ASSERT_EQ(l.writeEvent(&le), 0);
    }
  }
  const std::string a = slurp(ours);
  EXPECT_GT(a.size(), 700000u);
  EXPECT_TRUE(a == slurp(theirs)) << "LogWriter's bytes differ from lcm::LogFile's";
}

// Large events taken whole (writeOwned) are written in their place among copied ones, with the
// bytes lcm::LogFile writes, and every taken buffer comes back through the give-back function.
TEST(ReplayIo, LogWriterWritesTakenBuffersInPlace) {
  const std::string ours = tmpPath("owned.lcmlog"), theirs = tmpPath("owned_lcm.lcmlog");
  size_t taken = 0, given_back = 0;
  {
    LogWriter w(ours);
    w.setGiveBack([&](LocalBus::Bytes&& b) {
      ++given_back;
      EXPECT_GT(b.capacity(), 0u);
    });
    lcm::LogFile l(theirs, "w");
    for (int i = 0; i < 200; ++i) {
      // Grid-map sized events between small ones, some back to back, some a chunk's end apart.
      const size_t size = i % 3 == 0 ? 80000 + static_cast<size_t>(i) : static_cast<size_t>((i * 53) % 3000);
      LocalBus::Bytes d(size);
      for (size_t k = 0; k < size; ++k) d[k] = static_cast<uint8_t>(k * 13 + static_cast<size_t>(i));
      lcm::LogEvent le;
      le.timestamp = 1000 * i;
      le.channel = i % 3 == 0 ? "AGM_TACTICAL" : "SECTOR_MAP";
      le.datalen = static_cast<int32_t>(size);
      le.data = d.data();
      ASSERT_EQ(l.writeEvent(&le), 0);
      taken += size >= LogWriter::kOwnedMin;
      if (i % 2) {
        w.writeOwned(le.channel, le.timestamp, std::move(d));
      } else {
        w.writeRaw(le.channel, le.timestamp, d.data(), d.size());
        taken -= size >= LogWriter::kOwnedMin;
      }
    }
    w.flush();
    // All but those of the last chunk written are back (they come back at the next hand-over).
    EXPECT_GT(taken, 20u);
    EXPECT_GT(given_back, 20u);
  }
  const std::string a = slurp(ours);
  EXPECT_GT(a.size(), 5000000u);
  EXPECT_TRUE(a == slurp(theirs)) << "LogWriter's bytes differ from lcm::LogFile's";
}

TEST(ReplayIo, LogReaderReadsWhatLcmReadsAlsoWhenCorrupt) {
  const std::string path = tmpPath("r.lcmlog");
  {
    LogWriter w(path);
    for (const Ev& e : sampleEvents()) w.writeRaw(e.channel, e.t, e.data);
  }
  const std::string good = slurp(path);
  ASSERT_EQ(LogReader::readAll(path).size(), sampleEvents().size());
  // Corruptions: junk before the first sync word, a truncated event, junk between events (LCM
  // stops: "Invalid header after log data"), bad lengths, an empty file, a lone sync word.
  const size_t second = good.find("\xED\xA1\xDA\x01", 4);
  ASSERT_NE(second, std::string::npos);
  std::string bad_channel_len = good;
  bad_channel_len[20] = '\x7f';
  std::string neg_data_len = good;
  neg_data_len[24] = '\xff';
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"junk before", std::string("xyz\xED\xA1", 5) + good},
      {"truncated", good.substr(0, good.size() - 17)},
      {"truncated header", good.substr(0, second + 10)},
      {"junk between", good.substr(0, second) + "junk" + good.substr(second)},
      {"channel length", bad_channel_len},
      {"data length", neg_data_len},
      {"empty", ""},
      {"sync only", "\xED\xA1\xDA\x01"},
  };
  for (const auto& [what, bytes] : cases) {
    spit(path, bytes);
    const auto lcm_events = readWithLcm(path);
    const auto ours = LogReader::readAll(path);
    expectSame(ours, lcm_events, what);
  }
  // And where LCM stops silently, ours says why (stopReason, and a warning on stderr); a whole
  // log, or one with junk only before its first event, ends without one.
  const auto stopReason = [&](const std::string& bytes) {
    spit(path, bytes);
    LogReader r(path);
    testing::internal::CaptureStderr();
    while (r.nextView()) {
    }
    const std::string warned = testing::internal::GetCapturedStderr();
    EXPECT_EQ(warned.empty(), r.stopReason().empty()) << warned;
    return r.stopReason();
  };
  EXPECT_EQ(stopReason(good), "");
  EXPECT_EQ(stopReason(""), "");
  EXPECT_NE(stopReason(good.substr(0, good.size() - 17)).find("cut short"), std::string::npos);
  EXPECT_NE(stopReason(good.substr(0, second) + "junk" + good.substr(second)).find("no sync word after"), std::string::npos);
  EXPECT_NE(stopReason(bad_channel_len).find("invalid channel length"), std::string::npos);
  EXPECT_NE(stopReason(good + "ab").find("2 bytes at the end"), std::string::npos);
  EXPECT_NE(stopReason(std::string(5000, 'x')).find("5000 bytes at the end"), std::string::npos);
  // A data length near 2^31 in the second event: the first event is read, and the reader stops
  // without buffering 2 GB (LCM's reader allocates it first, so it is not compared here).
  std::string huge = good;
  huge[second + 24] = '\x7f';
  huge[second + 25] = '\xff';
  spit(path, huge);
  {
    LogReader r(path);
    testing::internal::CaptureStderr();
    int n = 0;
    while (r.nextView()) ++n;
    testing::internal::GetCapturedStderr();
    EXPECT_EQ(n, 1);
    EXPECT_NE(r.stopReason().find("more than the"), std::string::npos) << r.stopReason();
  }
}

TEST(ReplayIo, LocalBusDeliversInMemqOrder) {
  // Two "stages": A answers every IN with A_OUT and, every third, a second message; B answers
  // A_OUT with B_OUT; a recorder on ".*" sees everything. The sequences must be identical.
  const auto run = [](auto& publish, auto& subscribe, auto& drain) {
    std::vector<std::string> seen;
    int n = 0;
    subscribe("IN", [&, n](const std::string&, const std::string& d) mutable {
      publish("A_OUT", d + "a");
      if (++n % 3 == 0) publish("A_EXTRA", d + "x");
    });
    subscribe("A_OUT", [&](const std::string&, const std::string& d) { publish("B_OUT", d + "b"); });
    subscribe(".*", [&](const std::string& ch, const std::string& d) { seen.push_back(ch + ":" + d); });
    subscribe("A_.*", [&](const std::string& ch, const std::string&) { seen.push_back("match " + ch); });
    for (int i = 0; i < 10; ++i) {
      publish("IN", std::to_string(i));
      drain();
    }
    return seen;
  };
  using Fn = std::function<void(const std::string&, const std::string&)>;

  lcm::LCM memq("memq://");
  std::vector<std::unique_ptr<Fn>> keep;
  struct Forward {
    Fn* f;
    void handle(const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
      (*f)(ch, std::string(static_cast<const char*>(rbuf->data), rbuf->data_size));
    }
  };
  std::vector<std::unique_ptr<Forward>> fw;
  auto lcm_pub = [&](const std::string& ch, const std::string& d) { memq.publish(ch, d.data(), static_cast<unsigned>(d.size())); };
  auto lcm_sub = [&](const std::string& ch, Fn f) {
    keep.push_back(std::make_unique<Fn>(std::move(f)));
    fw.push_back(std::make_unique<Forward>(Forward{keep.back().get()}));
    memq.subscribe(ch, &Forward::handle, fw.back().get());
  };
  auto lcm_drain = [&] {
    while (memq.handleTimeout(0) > 0) {
    }
  };
  const auto expected = run(lcm_pub, lcm_sub, lcm_drain);

  LocalBus bus;
  auto bus_pub = [&](const std::string& ch, const std::string& d) { bus.publish(ch, d.data(), d.size()); };
  auto bus_sub = [&](const std::string& ch, Fn f) {
    bus.subscribe(ch, [f](const lcm::ReceiveBuffer* rbuf, const std::string& c) {
      f(c, std::string(static_cast<const char*>(rbuf->data), rbuf->data_size));
    });
  };
  auto bus_drain = [&] { bus.handleAll(); };
  const auto got = run(bus_pub, bus_sub, bus_drain);

  EXPECT_GT(expected.size(), 40u);
  EXPECT_EQ(got, expected);
}

// Delivered messages' buffers are reused by size: a grid map's for the next grid map, not for
// a sonar ring (which would leave the next grid map to allocate its own).
TEST(ReplayIo, LocalBusReusesLargeBuffersForLargeMessages) {
  LocalBus bus;
  const std::vector<uint8_t> grid(80000, 7), ring(300, 1);
  bus.publish("AGM", grid.data(), grid.size());
  for (int i = 0; i < 10; ++i) bus.publish("RING", ring.data(), ring.size());
  EXPECT_EQ(bus.handleAll(), 11);
  // The small ones take the small buffers, however many there are.
  for (int i = 0; i < 20; ++i) EXPECT_LT(bus.takeBuffer(ring.size()).capacity(), 16384u) << i;
  LocalBus::Bytes big = bus.takeBuffer(grid.size());
  EXPECT_GE(big.capacity(), grid.size());
  EXPECT_TRUE(big.empty());
  // Taken: the next large one has none to reuse.
  EXPECT_EQ(bus.takeBuffer(grid.size()).capacity(), 0u);
  // Given back, it is there again.
  bus.giveBack(std::move(big));
  EXPECT_GE(bus.takeBuffer(grid.size()).capacity(), grid.size());
}

// The sink gets every message after its subscriptions, in delivery order, with the buffer.
TEST(ReplayIo, LocalBusSinkTakesEveryMessageLast) {
  LocalBus bus;
  std::vector<std::string> seen;
  bus.subscribe("A", [&](const lcm::ReceiveBuffer*, const std::string& ch) {
    seen.push_back("sub " + ch);
    const uint8_t b = 2;
    bus.publish("B", &b, 1);  // delivered after A, so sunk after A
  });
  bus.setSink([&](const std::string& ch, LocalBus::Bytes&& data) {
    seen.push_back("sink " + ch + " " + std::to_string(data.size()));
  });
  const uint8_t a[3] = {1, 2, 3};
  bus.publish("A", a, sizeof a);
  bus.publish("C", a, 2);  // nobody subscribes: sunk all the same
  EXPECT_EQ(bus.handleAll(), 3);
  EXPECT_EQ(seen, (std::vector<std::string>{"sub A", "sink A 3", "sink C 2", "sink B 1"}));
}

TEST(ReplayIo, NodeOnLocalBusDecodesAndCounts) {
  auto bus = std::make_shared<LocalBus>();
  Node a("a", bus, Node::Options{false, false});
  Node b("b", bus, Node::Options{false, false});
  std::vector<int64_t> got;
  b.subscribe<odometry_t>("ODOMETRY", [&](const odometry_t& m) { got.push_back(m.utime); });
  odometry_t o{};
  o.utime = 42;
  a.publish("ODOMETRY", o);
  const uint8_t junk[3] = {1, 2, 3};
  bus->publish("ODOMETRY", junk, sizeof junk);
  EXPECT_EQ(bus->handleAll(), 2);
  EXPECT_EQ(got, std::vector<int64_t>{42});
  EXPECT_EQ(b.counter("decode_errors.ODOMETRY"), 1);
}

TEST(ReplayIo, MeterPrintsAtMostEveryTenthAndSecond) {
  using C = ReplayMeter::Clock;
  const C::time_point t0{};
  ReplayMeter m(1000, t0);
  int lines = 0;
  // 1000 bytes read over 100 events within 0.5 s of wall time: no line (too soon).
  for (int i = 1; i <= 100; ++i) lines += !m.update(i * 1'000'000, i * 10, t0 + std::chrono::milliseconds(5 * i)).empty();
  EXPECT_EQ(lines, 0);
  // A slow run: 10 s per tenth -> a line per tenth, ten in all.
  ReplayMeter slow(1000, t0);
  lines = 0;
  for (int i = 1; i <= 100; ++i) lines += !slow.update(i * 1'000'000, i * 10, t0 + std::chrono::seconds(i)).empty();
  EXPECT_EQ(lines, 10);
  EXPECT_NEAR(slow.logSeconds(), 99.0, 1e-9);
  EXPECT_NE(slow.summary(t0 + std::chrono::seconds(100)).find("real-time factor 1,"), std::string::npos)
      << slow.summary(t0 + std::chrono::seconds(100));
  // A log looped twice (lcm-logger recording lcm-logplayer -l): two passes of 9 s, not one of 9.
  ReplayMeter looped(1000, t0);
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 1; i <= 10; ++i) looped.update(i * 1'000'000 - (i == 5 ? 1'300'000 : 0), 1, t0);  // one 0.3 s late
  EXPECT_NEAR(looped.logSeconds(), 18.0, 1e-9);
}

// The writer thread's failures reach the caller: a full device makes flush() throw, naming the
// file, and the destructor after it neither throws nor hangs.
TEST(ReplayIo, LogWriterReportsAFailedWrite) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  LogWriter w("/dev/full");
  const std::vector<uint8_t> data(4096, 7);
  try {
    for (int i = 0; i < 1000; ++i) w.writeRaw("CH", i, data);  // 4 MB: buffers handed over on the way
    w.flush();
    FAIL() << "no error writing to /dev/full";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
  // The same where large events are written in place (writev).
  LogWriter v("/dev/full");
  try {
    for (int i = 0; i < 100; ++i) v.writeOwned("AGM", i, LocalBus::Bytes(80000, 7));  // 8 MB
    v.flush();
    FAIL() << "no error writing taken buffers to /dev/full";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
}
