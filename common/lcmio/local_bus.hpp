#pragma once
// LocalBus: an in-process message bus with the delivery order of LCM's memq:// provider, for
// offline replay (several stages in one process). A published message is queued; handle()
// delivers queued messages first in, first out, each to every subscription whose pattern matches
// its channel, in the order of subscribing -- LCM's rules (patterns are regular expressions
// matched against the whole channel name). Messages published by a handler join the end of the
// queue. Unlike memq://, no pipe is written and read per message (two system calls, most of the
// replay's time on small messages), and a publisher that encodes into one of the bus's buffers
// (takeBuffer) hands it over without a copy; buffers are reused, never zero-filled.
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

  // pattern: a regular expression matched against the whole channel name (as LCM's subscribe).
  void subscribe(const std::string& pattern, Handler handler);
  // Queues a copy of the bytes. Returns 0 (as lcm::LCM::publish on success).
  int publish(const std::string& channel, const void* data, size_t size);
  // Queues these bytes (no copy). Returns 0.
  int publish(const std::string& channel, Bytes&& bytes);
  // An empty buffer to encode into (a delivered message's, its capacity kept), for publish.
  Bytes takeBuffer();
  // Delivers one queued message; returns 1, or 0 if the queue was empty.
  int handleOne();
  // Delivers until the queue is empty (including what the handlers publish); returns the count.
  int64_t handleAll();
  bool empty() const { return queue_.empty(); }

 private:
  struct Subscription {
    std::regex pattern;
    Handler handler;
  };
  struct Message {
    std::string channel;
    Bytes data;
  };
  const std::vector<size_t>& subscribersOf(const std::string& channel);

  std::vector<Subscription> subs_;
  std::unordered_map<std::string, std::vector<size_t>> by_channel_;  // cache; cleared on subscribe
  std::deque<Message> queue_;
  std::vector<Bytes> spare_;  // buffers of delivered messages, reused
};

}  // namespace lasonic
