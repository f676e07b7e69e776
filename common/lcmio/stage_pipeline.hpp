#pragma once
// StagePipeline: stages that would share one LocalBus (lasonic-replay: complement, pilot,
// navigator) run on several threads instead, and every stage still sees exactly the messages, in
// exactly the order, that it would see on the one bus -- so the output is the same, byte for
// byte, with one thread or several.
//
// How. The threads form a chain, each with its own LocalBus. Stages are made in the one bus's
// order, each on the bus of its thread; for every subscription of a stage on thread t, a proxy
// subscription with the same pattern is made on every later thread's bus at that point of the
// order. For each input event, every thread publishes the event on its bus (unless nothing there
// takes it) and delivers until the queue is empty (as the one bus would). On thread t, what each of its stages' handlers published
// during each delivery is recorded with the event, which then goes down the chain; on a later
// thread the proxy publishes the recorded messages when the same delivery reaches it -- where the
// stage's own handler would have published them on the one bus.
//
// Condition: a stage takes no messages from a stage on a later thread (the pilot, which reads
// the navigator's AGM_TACTICAL, must run on the navigator's thread or after it). A breach shows
// as a proxy with no recorded delivery, or one for another channel; the run then ends with a
// PipelineError naming the pattern, never with a different output.
//
// Work moves between threads in chunks of events through bounded queues, so a fast thread
// waits for a slow one instead of buffering the whole log. A chunk holds its input events in one
// byte array, and the last thread hands a finished chunk back to the first with its storage:
// no allocation per event, and none made on one thread and freed on the other (which has the
// two wait on each other's allocator lock).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lcmio/local_bus.hpp"

namespace lasonic {

class PipelineError : public std::logic_error {
 public:
  explicit PipelineError(const std::string& w) : std::logic_error(w) {}
};

class StagePipeline {
 public:
  // An input event; channel and data are valid until the next call of the function that gave it.
  struct InputView {
    int64_t timestamp = 0;
    std::string_view channel;
    const uint8_t* data = nullptr;
    size_t size = 0;
  };

  explicit StagePipeline(int threads);  // threads >= 1
  StagePipeline(const StagePipeline&) = delete;
  StagePipeline& operator=(const StagePipeline&) = delete;
  ~StagePipeline();

  int threads() const { return static_cast<int>(threads_.size()); }
  const std::shared_ptr<LocalBus>& bus(int thread) const { return threads_.at(static_cast<size_t>(thread))->bus; }
  int lastThread() const { return threads() - 1; }

  // Make a stage's subscriptions on bus(thread) between these two calls, stages in the one
  // bus's order. Subscriptions made outside a stage are allowed on the last thread's bus only
  // (e.g. a recorder, after all stages).
  void beginStage(int thread);
  void endStage();

  // Runs to the end of the input: `next` (called on the first thread) gives the input events
  // (copied before it is called again); `on_last` (may be empty) is called with an event's
  // timestamp on the last thread before the event is delivered there. The last thread is the
  // calling thread. Rethrows the first exception of any thread.
  void run(const std::function<std::optional<InputView>()>& next, const std::function<void(int64_t)>& on_last);

 private:
  // A chunk of input events with what the stages of the threads it has passed published, in a
  // few flat arrays (allocations per chunk, not per event or message).
  struct Chunk {
    struct Out {  // one published message: channel name in `bytes`, data in `bytes` or `owned`
      size_t channel_at, channel_len, data_at, data_len;
      size_t owned;  // index in `owned`, or SIZE_MAX
    };
    struct Call {  // one delivery to a captured subscription: the messages its handler published
      size_t global;          // the subscription's id in the one bus's order
      size_t channel_hash;    // of the delivered message's channel
      size_t first_out, outs;
    };
    struct Input {  // an input event: its channel name, then its data, in `input_bytes` from `at`
      int64_t timestamp;
      size_t at, channel_len, data_len;
    };
    std::vector<Input> inputs;
    std::vector<uint8_t> input_bytes;
    std::vector<Call> calls;
    std::vector<Out> outs;
    std::vector<uint8_t> bytes;
    std::vector<LocalBus::Bytes> owned;  // messages nobody on their own thread wanted, taken over whole
    // calls_from[t][u]: where thread t's calls for input u begin in `calls` (u = inputs.size():
    // where they end).
    std::vector<std::vector<size_t>> calls_from;
    void reset();  // empty, its storage kept
  };
  class ChunkQueue {
   public:
    bool push(Chunk&& c, const std::atomic<bool>& failed);  // false when the run failed
    std::optional<Chunk> pop(const std::atomic<bool>& failed);
    void close();

   private:
    std::mutex m_;
    std::condition_variable cv_;
    std::deque<Chunk> q_;
    bool closed_ = false;
  };
  struct Thread {
    std::shared_ptr<LocalBus> bus = std::make_shared<LocalBus>();
    std::vector<size_t> global_of;  // local subscription index -> global id (own stages' only)
    struct Proxy {
      size_t global;
      int from_thread;  // the stage's own thread
      std::string pattern;
      size_t cursor = 0;  // next call to look at in the chunk
    };
    std::vector<Proxy> proxies;
    Chunk* chunk = nullptr;  // being processed
    size_t unit = 0;         // its input being processed
    std::string channel;     // scratch: a recorded channel name
    std::string input_channel;  // scratch: the input event's channel name
    ChunkQueue in;           // from the previous thread (unused on the first)
  };

  void process(Thread& th, int index, const std::function<void(int64_t)>& on_last);
  void work(int index, const std::function<std::optional<InputView>()>& next, const std::function<void(int64_t)>& on_last);
  Chunk takeChunk();            // one the last thread is done with, or a new one
  void recycle(Chunk&& chunk);  // (on the last thread) kept for takeChunk, up to a bound
  void fail(std::exception_ptr e);

  std::vector<std::unique_ptr<Thread>> threads_;
  int stage_thread_ = -1;
  size_t stage_first_ = 0;
  size_t globals_ = 0;
  std::atomic<bool> failed_{false};
  std::mutex error_m_;
  std::exception_ptr error_;
  std::mutex spare_m_;
  std::vector<Chunk> spare_chunks_;
  static constexpr size_t kChunk = 256;  // events per hand-over
};

}  // namespace lasonic
