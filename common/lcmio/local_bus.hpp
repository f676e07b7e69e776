#pragma once
// LocalBus: an in-process message bus with the delivery order of LCM's memq:// provider, for
// offline replay (several stages in one process). A published message is queued; handle()
// delivers queued messages first in, first out, each to every subscription whose pattern matches
// its channel, in the order of subscribing -- LCM's rules (patterns are regular expressions
// matched against the whole channel name). Messages published by a handler join the end of the
// queue. Unlike memq://, no pipe is written and read per message (two system calls, most of the
// replay's time on small messages) and nothing is copied but the encoded bytes.
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <deque>
#include <functional>
#include <regex>
#include <string>
#include <unordered_map>
#include <vector>

namespace lasonic {

class LocalBus {
 public:
  using Handler = std::function<void(const lcm::ReceiveBuffer* rbuf, const std::string& channel)>;

  // pattern: a regular expression matched against the whole channel name (as LCM's subscribe).
  void subscribe(const std::string& pattern, Handler handler);
  // Queues a copy of the bytes. Returns 0 (as lcm::LCM::publish on success).
  int publish(const std::string& channel, const void* data, size_t size);
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
    std::vector<uint8_t> data;
  };
  const std::vector<size_t>& subscribersOf(const std::string& channel);

  std::vector<Subscription> subs_;
  std::unordered_map<std::string, std::vector<size_t>> by_channel_;  // cache; cleared on subscribe
  std::deque<Message> queue_;
  std::vector<std::vector<uint8_t>> spare_;  // buffers of delivered messages, reused
};

}  // namespace lasonic
