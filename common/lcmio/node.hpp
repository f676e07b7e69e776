#pragma once
// Node: what a lasonic process uses to talk over LCM (in the spirit of Drake's DrakeLcm): typed
// publish/subscribe with decode errors counted and never thrown, handler exceptions caught and
// counted, a 1 Hz PROCESS_STATUS heartbeat. Its jobs live in small parts:
//   lcmio/status.hpp   StatusBoard (counters, errors, channel rates -> PROCESS_STATUS), Heartbeat
//   lcmio/signals.hpp  SIGINT/SIGTERM -> a shutdown flag
//   lcmio/lengths.hpp  array lengths on publish; array caps checked before decoding
//   lcmio/process.hpp  a live process's main (command line, config, logging, exit codes)
//
// Handlers are std::function (LCM 1.3.1's C++ API has no lambda subscribe; a small typed
// subscription object forwards to them).
#include <lasonic/channels.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "lcmio/lengths.hpp"
#include "lcmio/local_bus.hpp"
#include "lcmio/signals.hpp"
#include "lcmio/status.hpp"
#include "lcmio/wire.hpp"

namespace lasonic {

// Default URL: ttl=0 keeps multicast on the host; the larger receive buffer is needed for
// grid maps (~90 kB per message).
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

// The LCM URL cannot be used (LCM 1.3.1 prints its own reason to stderr and reports !good()).
class LcmUrlError : public std::runtime_error {
 public:
  explicit LcmUrlError(const std::string& what) : std::runtime_error(what) {}
};

class Node {
 public:
  // Messages LCM queues per subscription while a handler runs. LCM's default, 30, silently drops
  // the rest of a burst (measured: a pilot busy with a laser scan lost SONAR_COMPLEMENT messages
  // of a fuzzing burst). Bursts happen (a logger replaying, a network hiccup released); a
  // process that keeps up at its steady rate clears 1000 queued messages in well under a second.
  static constexpr int kQueueCapacity = 1000;

  struct Options {
    bool heartbeat = true;        // publish PROCESS_STATUS at 1 Hz (off for offline replay)
    bool install_signal_handlers = true;
  };

  // Creates its own LCM instance; throws LcmUrlError if the URL does not work.
  Node(std::string process_name, const std::string& lcm_url);
  Node(std::string process_name, const std::string& lcm_url, Options opts);
  // Shares an LCM instance (offline replay runs several stages on one memq:// instance).
  Node(std::string process_name, std::shared_ptr<lcm::LCM> lcm, Options opts);
  // Shares an in-process LocalBus (offline replay: LCM's memq:// order without its system calls).
  // Such a Node has no LCM instance; spinOnce/run are for LCM nodes (the bus's owner drives it).
  Node(std::string process_name, std::shared_ptr<LocalBus> bus, Options opts);
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  // Before decoding, a message of a type with arrays is checked against its cap
  // (lcmio/lengths.hpp): too many elements -> counted under oversize.<CHANNEL>; a count the
  // bytes do not hold -> decode_errors.<CHANNEL>, like any message that does not decode.
  template <typename T>
  void subscribe(const std::string& channel, std::function<void(const T&)> handler);

  // Finalises array lengths, encodes and publishes. Never throws: failures are counted.
  template <typename T>
  void publish(const std::string& channel, T& msg);

  // Counters shown in PROCESS_STATUS.
  void count(std::string_view counter, int64_t n = 1) { status_.count(counter, n); }
  int64_t counter(const std::string& name) const { return status_.counter(name); }
  // Bad input or a failure: counted under `counter` and in `errors`, logged (rate-limited),
  // kept as last_error. The process goes on.
  void reportError(const std::string& counter, const std::string& message) { status_.reportError(counter, message); }
  // Newest message time processed (shown in PROCESS_STATUS).
  void noteMessageTime(int64_t utime) { status_.noteMessageTime(utime); }

  // Handles messages until SIGINT/SIGTERM or stop(); heartbeats on the way. Returns 0.
  int run();
  // One wait of at most timeout_ms; returns the number of messages handled (0 or 1).
  int spinOnce(int timeout_ms);
  void stop() { stop_requested_ = true; }
  static bool shutdownRequested() { return shutdown::requested(); }

  void publishStatus();
  const std::string& name() const { return status_.name(); }
  lcm::LCM& lcm() { return *lcm_; }  // LCM nodes only
  int64_t errors() const { return status_.errors(); }
  const StatusBoard& status() const { return status_; }

 private:
  struct SubscriptionBase {
    virtual ~SubscriptionBase() = default;
    void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) { dispatch(rbuf, channel); }
    virtual void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel) = 0;
  };
  template <typename T>
  struct TypedSubscription : SubscriptionBase {
    Node* node;
    std::function<void(const T&)> handler;
    // For the types lcmio/wire decodes itself (grid maps, laser scans): decoded into again for
    // every message, its arrays keep their memory, so a message as large as the last one costs no
    // allocation and no zero-filling. (Not for the others: LCM's generated decode leaves an array
    // whose count is 0 as it was, the previous message's; fastDecode empties it.)
    std::conditional_t<HasFastDecode<T>::value, T, char> reused{};
    void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel) override;
  };

  void init();
  void maybeHeartbeat();
  void handlerFailed(const std::string& channel, const char* what);
  void decodeFailed(const std::string& channel, const char* type, size_t bytes, const std::string& why);
  void oversize(const std::string& channel, const char* type, int64_t claimed, int64_t cap);

  std::shared_ptr<lcm::LCM> lcm_;   // exactly one of lcm_ and bus_ is set
  std::shared_ptr<LocalBus> bus_;
  LocalBus::Bytes lcm_encoded_;     // publish buffer of an LCM node (types with a fast encode)
  Options opts_;
  StatusBoard status_;
  Heartbeat heartbeat_;
  std::vector<std::unique_ptr<SubscriptionBase>> subs_;
  bool stop_requested_ = false;
};

template <typename T>
void Node::TypedSubscription<T>::dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  node->status_.received(channel);
  const auto size = static_cast<size_t>(rbuf->data_size);
  if constexpr (HasWireArrays<T>::value) {
    const WireCheck c = checkWireArrays<T>(rbuf->data, size);
    if (c.result == WireCheck::TooMany) {
      node->oversize(channel, T::getTypeName(), c.claimed, WireArrays<T>::kMax);
      return;
    }
    if (c.result == WireCheck::Truncated) {
      node->decodeFailed(channel, T::getTypeName(), size,
                         "claims " + std::to_string(c.claimed) + " elements that the bytes do not hold");
      return;
    }
  }
  T fresh;
  T& msg = [&]() -> T& {
    if constexpr (HasFastDecode<T>::value) return reused;
    else return fresh;
  }();
  int decoded = -1;
  try {
    decoded = wireDecode(msg, rbuf->data, static_cast<int>(size));
  } catch (const std::exception& e) {  // e.g. std::bad_alloc: never out of LCM's C callback
    node->decodeFailed(channel, T::getTypeName(), size, e.what());
    return;
  }
  if (decoded < 0) {
    node->decodeFailed(channel, T::getTypeName(), size, "wrong type or corrupt");
    return;
  }
  try {
    handler(msg);
  } catch (const std::exception& e) {
    node->handlerFailed(channel, e.what());
  } catch (...) {
    node->handlerFailed(channel, "unknown exception");
  }
}

template <typename T>
void Node::subscribe(const std::string& channel, std::function<void(const T&)> handler) {
  auto sub = std::make_unique<TypedSubscription<T>>();
  sub->node = this;
  sub->handler = std::move(handler);
  status_.declareInput(channel);
  if (bus_) {
    SubscriptionBase* base = sub.get();
    bus_->subscribe(channel, [base](const lcm::ReceiveBuffer* rbuf, const std::string& ch) { base->onMessage(rbuf, ch); });
  } else {
    lcm::Subscription* s =
        lcm_->subscribe(channel, &SubscriptionBase::onMessage, static_cast<SubscriptionBase*>(sub.get()));
    if (s) s->setQueueCapacity(kQueueCapacity);
  }
  subs_.push_back(std::move(sub));
}

template <typename T>
void Node::publish(const std::string& channel, T& msg) {
  try {
    setLengths(msg);
    int rc = -1;
    if (bus_) {  // as lcm::LCM::publish: encode, then hand over the bytes
      const int size = msg.getEncodedSize();
      LocalBus::Bytes bytes = bus_->takeBuffer(static_cast<size_t>(size));  // encoded in place, handed over without a copy
      bytes.resize(static_cast<size_t>(size));
      if (wireEncode(msg, bytes.data(), size) == size) rc = bus_->publish(channel, std::move(bytes));
    } else if constexpr (HasFastEncode<T>::value) {  // the same bytes as lcm::LCM::publish(channel, &msg)
      const int size = msg.getEncodedSize();
      lcm_encoded_.resize(static_cast<size_t>(size));
      if (wireEncode(msg, lcm_encoded_.data(), size) == size)
        rc = lcm_->publish(channel, lcm_encoded_.data(), static_cast<unsigned int>(size));
    } else {
      rc = lcm_->publish(channel, &msg);
    }
    if (rc != 0) {
      reportError("publish_failures", channel + ": publish failed");
      return;
    }
    status_.sent(channel);
  } catch (const std::exception& e) {
    reportError("publish_failures", channel + ": " + e.what());
  }
}

}  // namespace lasonic
