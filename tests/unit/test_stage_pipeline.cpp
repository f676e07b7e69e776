// StagePipeline: stages spread over threads see exactly what they would see on one LocalBus.
// Three toy stages shaped like lasonic-replay's (an upstream stage, a downstream one that reads a
// middle one's output, and the middle one), each publishing what depends on the whole order of
// what it received, so that any difference in delivery order shows in the recorded output.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lcmio/stage_pipeline.hpp"

using namespace lasonic;

namespace {

using Record = std::pair<std::string, std::vector<uint8_t>>;

// A running hash of every (channel, bytes) delivered, in order: its value depends on the order.
struct Chain {
  uint64_t h = 1469598103934665603ull;
  void add(const std::string& channel, const lcm::ReceiveBuffer* rbuf) {
    for (const char c : channel) h = (h ^ static_cast<uint8_t>(c)) * 1099511628211ull;
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    for (uint32_t i = 0; i < rbuf->data_size; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  std::vector<uint8_t> bytes() const {
    std::vector<uint8_t> b(8);
    for (int i = 0; i < 8; ++i) b[static_cast<size_t>(i)] = static_cast<uint8_t>(h >> (8 * i));
    return b;
  }
};

void publish(LocalBus& bus, const std::string& channel, const std::vector<uint8_t>& b) {
  bus.publish(channel, b.data(), b.size());
}

// Like the complement stage: takes the inputs, publishes X for each (and XX for every third).
struct Upstream {
  Chain chain;
  int n = 0;
  explicit Upstream(LocalBus& bus, bool throw_at_100 = false) {
    bus.subscribe("IN", [this, &bus, throw_at_100](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
      chain.add(ch, rbuf);
      if (throw_at_100 && n == 100) throw std::runtime_error("upstream failed at input 100");
      publish(bus, "X", chain.bytes());
      if (++n % 3 == 0) publish(bus, "XX", chain.bytes());
    });
  }
};

// Like the navigator: takes inputs and X, publishes N on every fifth delivery. With
// `reads_downstream` it also takes D (the downstream stage's output): not allowed from an earlier
// thread.
struct Middle {
  Chain chain;
  int n = 0;
  Middle(LocalBus& bus, bool reads_downstream = false) {
    const auto handler = [this, &bus](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
      chain.add(ch, rbuf);
      if (++n % 5 == 0) publish(bus, "N", chain.bytes());
    };
    bus.subscribe("IN", handler);
    bus.subscribe("X.*", handler);
    if (reads_downstream) bus.subscribe("D", handler);
  }
};

// Like the pilot: takes inputs, X and N, publishes D for each.
struct Downstream {
  Chain chain;
  explicit Downstream(LocalBus& bus) {
    bus.subscribe("IN|X|N", [this, &bus](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
      chain.add(ch, rbuf);
      publish(bus, "D", chain.bytes());
    });
  }
};

// 5000 inputs (more chunks than can be on their way at once, so that chunks come back and are
// used again, and a partial one), some on a channel no stage takes. Each view points into storage
// that the next call overwrites, as lasonic-replay's log reader's do.
std::function<std::optional<StagePipeline::InputView>()> inputs() {
  auto data = std::make_shared<std::vector<uint8_t>>();
  return [i = 0, data]() mutable -> std::optional<StagePipeline::InputView> {
    if (i == 5000) return std::nullopt;
    data->assign(static_cast<size_t>(1 + i % 5), static_cast<uint8_t>(i));
    const StagePipeline::InputView in{1000 * i, i % 7 == 3 ? "OTHER" : "IN", data->data(), data->size()};
    ++i;
    return in;
  };
}

struct Options {
  std::map<std::string, int> thread_of;  // "up", "down", "mid"
  bool throw_at_100 = false;
  bool mid_reads_downstream = false;
  bool subscribe_outside_stage = false;
};

// Runs inputs() and returns what a recorder on the last thread saw, with the input time of each.
std::vector<std::pair<int64_t, Record>> runPipeline(const Options& o) {
  int threads = 1;
  for (const auto& [name, t] : o.thread_of) threads = std::max(threads, t + 1);
  StagePipeline p(threads);
  std::optional<Upstream> up;
  std::optional<Downstream> down;
  std::optional<Middle> mid;
  // The one bus's order: upstream, downstream, middle (as lasonic-replay: complement, pilot, navigator).
  p.beginStage(o.thread_of.at("up"));
  up.emplace(*p.bus(o.thread_of.at("up")), o.throw_at_100);
  p.endStage();
  p.beginStage(o.thread_of.at("down"));
  down.emplace(*p.bus(o.thread_of.at("down")));
  p.endStage();
  p.beginStage(o.thread_of.at("mid"));
  mid.emplace(*p.bus(o.thread_of.at("mid")), o.mid_reads_downstream);
  p.endStage();
  if (o.subscribe_outside_stage) p.bus(0)->subscribe("IN", [](const lcm::ReceiveBuffer*, const std::string&) {});
  std::vector<std::pair<int64_t, Record>> seen;
  int64_t now = 0;
  p.bus(p.lastThread())->subscribe(".*", [&](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
    const auto* d = static_cast<const uint8_t*>(rbuf->data);
    seen.push_back({now, {ch, std::vector<uint8_t>(d, d + rbuf->data_size)}});
  });
  p.run(inputs(), [&now](int64_t timestamp) { now = timestamp; });
  return seen;
}

}  // namespace

TEST(StagePipeline, EveryThreadLayoutRecordsWhatOneBusRecords) {
  const auto one = runPipeline({{{"up", 0}, {"down", 0}, {"mid", 0}}});
  ASSERT_GT(one.size(), 3000u);
  size_t n_msgs = 0;
  for (const auto& [t, r] : one) n_msgs += r.first == "N";
  EXPECT_GT(n_msgs, 100u);  // the middle stage's output reaches the downstream one
  const std::vector<std::map<std::string, int>> layouts = {
      {{"up", 0}, {"mid", 0}, {"down", 1}},  // lasonic-replay on two threads
      {{"up", 0}, {"mid", 1}, {"down", 1}},
      {{"up", 0}, {"mid", 1}, {"down", 2}},  // one thread per stage
      {{"up", 1}, {"mid", 1}, {"down", 1}},  // all on the second of two threads
  };
  for (const auto& layout : layouts) {
    const auto many = runPipeline({layout});
    ASSERT_EQ(many.size(), one.size()) << "layout up " << layout.at("up") << " mid " << layout.at("mid");
    for (size_t k = 0; k < one.size(); ++k) {
      ASSERT_EQ(many[k], one[k]) << "message " << k << " (" << one[k].second.first << ") differs, layout up "
                                 << layout.at("up") << " mid " << layout.at("mid") << " down " << layout.at("down");
    }
  }
}

// The check is not vacuous: a different order of stages on one bus records something else.
TEST(StagePipeline, TheRecordDependsOnTheOrder) {
  const auto one = runPipeline({{{"up", 0}, {"down", 0}, {"mid", 0}}});
  // Same stages, the middle one made before the downstream one: N reaches it earlier.
  StagePipeline q(1);
  std::optional<Upstream> up;
  std::optional<Middle> mid;
  std::optional<Downstream> d2;
  q.beginStage(0);
  up.emplace(*q.bus(0));
  mid.emplace(*q.bus(0));
  d2.emplace(*q.bus(0));
  q.endStage();
  std::vector<Record> seen;
  q.bus(0)->subscribe(".*", [&](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
    const auto* d = static_cast<const uint8_t*>(rbuf->data);
    seen.push_back({ch, std::vector<uint8_t>(d, d + rbuf->data_size)});
  });
  q.run(inputs(), {});
  ASSERT_EQ(seen.size(), one.size());
  bool differs = false;
  for (size_t k = 0; k < seen.size(); ++k) differs = differs || seen[k] != one[k].second;
  EXPECT_TRUE(differs);
}

// A stage on an earlier thread that takes a later thread's output would see less than on one
// bus: the run ends with an error that names the subscription, instead of a different output.
TEST(StagePipeline, AStageReadingALaterThreadIsAnError) {
  Options o{{{"up", 0}, {"mid", 0}, {"down", 1}}};
  o.mid_reads_downstream = true;
  try {
    runPipeline(o);
    FAIL() << "no error";
  } catch (const PipelineError& e) {
    EXPECT_NE(std::string(e.what()).find("'D'"), std::string::npos) << e.what();
  }
  // On one thread the same stages are fine.
  o.thread_of = {{"up", 0}, {"mid", 0}, {"down", 0}};
  EXPECT_GT(runPipeline(o).size(), 3000u);
}

// An exception in a stage on any thread ends the run (no thread left waiting) and is rethrown.
TEST(StagePipeline, AnExceptionOnAnyThreadIsRethrown) {
  for (const auto& layout : std::vector<std::map<std::string, int>>{
           {{"up", 0}, {"mid", 0}, {"down", 0}}, {{"up", 0}, {"mid", 1}, {"down", 2}}, {{"up", 1}, {"mid", 1}, {"down", 2}}}) {
    Options o{layout};
    o.throw_at_100 = true;
    try {
      runPipeline(o);
      FAIL() << "no error, up on thread " << layout.at("up");
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "upstream failed at input 100");
    }
  }
}

TEST(StagePipeline, SubscriptionsOutsideAStageOnlyOnTheLastThread) {
  Options o{{{"up", 0}, {"mid", 0}, {"down", 1}}};
  o.subscribe_outside_stage = true;
  EXPECT_THROW(runPipeline(o), std::logic_error);
}
