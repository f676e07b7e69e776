#pragma once
// LocalBus: an in-process message bus with the delivery order of LCM's memq:// provider, for
// offline replay (several stages in one process). A published message is queued; handle()
// delivers queued messages first in, first out, each to every subscription whose pattern matches
// its channel, in the order of subscribing -- LCM's rules (patterns are regular expressions
// matched against the whole channel name). Messages published by a handler join the end of the
// queue. Unlike memq://, no pipe is written and read per message (two system calls, most of the
// replay's time on small messages), and a publisher that encodes into one of the bus's buffers
// (takeBuffer) hands it over without a copy; buffers are reused, never zero-filled. Channel names
// are kept once per bus (a queued message points at its channel's entry, which also caches the
// matching subscriptions), so publishing allocates nothing once the buffers have grown.
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <new>
#include <regex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace lasonic {

// An allocator whose value-initialisation is default-initialisation: resize() of a byte buffer
// leaves the new bytes as they are (they are written next) instead of zeroing them.
template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

class LocalBus {
 public:
  using Handler = std::function<void(const lcm::ReceiveBuffer* rbuf, const std::string& channel)>;
  using Bytes = std::vector<uint8_t, DefaultInitAllocator<uint8_t>>;
  struct Channel;  // a channel name and the subscriptions matching it
  struct Message {
    Channel* channel;
    Bytes data;
    const std::string& name() const;
  };
  // Told, after a captured subscription's handler returned, what it published while it ran:
  // queue[first, queue.size()); it may take the data of a message that no subscription wants
  // (wanted()). (Used by StagePipeline to hand a stage's outputs to another thread.)
  using Capture = std::function<void(size_t subscription, const std::string& delivered_channel,
                                     std::deque<Message>& queue, size_t first)>;

  // pattern: a regular expression matched against the whole channel name (as LCM's subscribe).
  // Returns the subscription's index (0, 1, ... in the order of subscribing).
  size_t subscribe(const std::string& pattern, Handler handler);
  size_t subscriptions() const { return subs_.size(); }
  const std::string& patternOf(size_t subscription) const { return subs_.at(subscription).pattern_text; }
  // What the handler of `subscription` publishes is reported to `capture` after each delivery.
  void capture(size_t subscription, Capture capture);
  // Given every message after its subscriptions, with its buffer to keep (a recorder: it sees the
  // messages in the order a subscription to ".*" made last would, and need not copy them).
  using Sink = std::function<void(const std::string& channel, Bytes&& data)>;
  void setSink(Sink sink) { sink_ = std::move(sink); }
  // Queues a copy of the bytes. Returns 0 (as lcm::LCM::publish on success).
  int publish(const std::string& channel, const void* data, size_t size);
  // Queues these bytes (no copy). Returns 0.
  int publish(const std::string& channel, Bytes&& bytes);
  // An empty buffer to encode `size` bytes into (a delivered message's, its capacity kept), for
  // publish. Large buffers (grid maps) are kept apart and go to large messages: a 300-byte
  // SONAR_RING taking an 80 kB buffer would leave the next grid map to allocate and first-touch
  // its own.
  Bytes takeBuffer(size_t size = 0);
  // A buffer for later takeBuffer() calls (kept up to a bound, else freed).
  void giveBack(Bytes&& bytes);
  // Delivers one queued message; returns 1, or 0 if the queue was empty.
  int handleOne();
  // Delivers until the queue is empty (including what the handlers publish); returns the count.
  int64_t handleAll();
  bool empty() const { return queue_.empty(); }
  // Whether a message on `channel` would reach any subscription.
  bool wanted(const std::string& channel) { return !subscribersOf(channelOf(channel)).empty(); }
  bool wanted(const Message& m) { return !subscribersOf(m.channel).empty(); }

 private:
  struct Subscription {
    std::string pattern_text;
    std::regex pattern;
    Handler handler;
    Capture capture;  // empty: not captured
  };
  Channel* channelOf(const std::string& name);
  const std::vector<size_t>& subscribersOf(Channel* c);

  std::vector<Subscription> subs_;
  std::unordered_map<std::string, Channel> channels_;  // never erased: queued messages point here
  uint64_t generation_ = 1;                            // of the subscriptions; bumped on subscribe
  std::deque<Message> queue_;
  std::vector<size_t> subs_scratch_;  // the delivered message's subscriptions
  Sink sink_;
  std::vector<Bytes> spare_;        // buffers of delivered messages, reused (at most kMaxSpare)
  std::vector<Bytes> spare_large_;  // those of kLarge bytes or more (at most kMaxSpareLarge)
  static constexpr size_t kMaxSpare = 64, kMaxSpareLarge = 16;
  static constexpr size_t kLarge = 16384;
};

struct LocalBus::Channel {
  const std::string* name = nullptr;  // the map's key
  std::vector<size_t> subs;            // matching subscriptions, valid if generation is the bus's
  uint64_t generation = 0;
};

inline const std::string& LocalBus::Message::name() const { return *channel->name; }

}  // namespace lasonic
