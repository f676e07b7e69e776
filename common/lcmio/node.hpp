#pragma once
// Node: the small interface every lasonic process uses over LCM (in the spirit of Drake's
// DrakeLcm): typed publish/subscribe, decode errors counted and never thrown, handler
// exceptions caught and counted, a 1 Hz PROCESS_STATUS heartbeat, clean SIGINT/SIGTERM exit.
//
// Handlers are std::function (LCM 1.3.1's C++ API has no lambda subscribe; a small typed
// subscription object forwards to them).
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "lcmio/lengths.hpp"

namespace lasonic {

// Fixed channel names (DESIGN.md).
namespace channels {
inline constexpr const char* ODOMETRY = "ODOMETRY";
inline constexpr const char* LASER_SCAN = "LASER_SCAN";
inline constexpr const char* SONAR_RING = "SONAR_RING";
inline constexpr const char* SONAR_GEOMETRY = "SONAR_GEOMETRY";
inline constexpr const char* SIM_STATE = "SIM_STATE";
inline constexpr const char* SONAR_TRUTH = "SONAR_TRUTH";
inline constexpr const char* LASER_TRUTH = "LASER_TRUTH";
inline constexpr const char* RADAR_MAP = "RADAR_MAP";
inline constexpr const char* SONAR_HYPOTHESIS = "SONAR_HYPOTHESIS";
inline constexpr const char* SONAR_COMPLEMENT = "SONAR_COMPLEMENT";
inline constexpr const char* AGM_OPERATIONAL = "AGM_OPERATIONAL";
inline constexpr const char* SECTOR_MAP = "SECTOR_MAP";
inline constexpr const char* AGM_TACTICAL = "AGM_TACTICAL";
inline constexpr const char* AGM_LINES = "AGM_LINES";
inline constexpr const char* CURRENT_SENSOR_MAP = "CURRENT_SENSOR_MAP";
inline constexpr const char* PROCESS_STATUS = "PROCESS_STATUS";
}  // namespace channels

// Default URL: ttl=0 keeps multicast on the host; the larger receive buffer is needed for
// grid maps (~80 kB per message).
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

class Node {
 public:
  struct Options {
    bool heartbeat = true;        // publish PROCESS_STATUS at 1 Hz (off for offline replay)
    bool install_signal_handlers = true;
  };

  // Creates its own LCM instance; throws std::runtime_error if the URL does not work.
  Node(std::string process_name, const std::string& lcm_url);
  Node(std::string process_name, const std::string& lcm_url, Options opts);
  // Shares an LCM instance (offline replay runs several stages on one memq:// instance).
  Node(std::string process_name, std::shared_ptr<lcm::LCM> lcm, Options opts);
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  template <typename T>
  void subscribe(const std::string& channel, std::function<void(const T&)> handler);

  // Finalises array lengths, encodes and publishes. Never throws: failures are counted.
  template <typename T>
  void publish(const std::string& channel, T& msg);

  // Counters shown in PROCESS_STATUS.
  void count(const std::string& counter, int64_t n = 1);
  int64_t counter(const std::string& name) const;
  // Bad input or a failure: counted under `counter` and in `errors`, logged (rate-limited),
  // kept as last_error. The process goes on.
  void reportError(const std::string& counter, const std::string& message);
  // Newest message time processed (shown in PROCESS_STATUS).
  void noteMessageTime(int64_t utime);

  // Handles messages until SIGINT/SIGTERM or stop(); heartbeats on the way. Returns 0.
  int run();
  // One wait of at most timeout_ms; returns the number of messages handled (0 or 1).
  int spinOnce(int timeout_ms);
  void stop() { stop_requested_ = true; }
  static bool shutdownRequested();

  void publishStatus();
  const std::string& name() const { return name_; }
  lcm::LCM& lcm() { return *lcm_; }
  int64_t errors() const { return errors_; }

 private:
  struct ChannelStats {
    int64_t messages = 0;
    int64_t at_last_status = 0;
    int64_t decode_errors = 0;
  };
  struct SubscriptionBase {
    virtual ~SubscriptionBase() = default;
    void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) { dispatch(rbuf, channel); }
    virtual void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel) = 0;
  };
  template <typename T>
  struct TypedSubscription : SubscriptionBase {
    Node* node;
    std::function<void(const T&)> handler;
    void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel) override;
  };

  void init();
  void maybeHeartbeat();
  void handlerFailed(const std::string& channel, const char* what);

  std::string name_;
  std::shared_ptr<lcm::LCM> lcm_;
  Options opts_;
  std::vector<std::unique_ptr<SubscriptionBase>> subs_;
  std::map<std::string, ChannelStats> in_, out_;
  std::map<std::string, int64_t> counters_;
  int64_t errors_ = 0;
  std::string last_error_;
  int64_t last_msg_utime_ = 0;
  bool stop_requested_ = false;
  std::chrono::steady_clock::time_point start_, last_status_;
  std::map<std::string, std::chrono::steady_clock::time_point> last_logged_;
};

template <typename T>
void Node::TypedSubscription<T>::dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  ChannelStats& st = node->in_[channel];
  ++st.messages;
  T msg;
  if (msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) {
    ++st.decode_errors;
    node->reportError("decode_errors." + channel,
                      channel + ": message does not decode as lasonic::" + T::getTypeName() +
                          " (" + std::to_string(rbuf->data_size) + " bytes; wrong type or corrupt)");
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
  in_[channel];
  lcm_->subscribe(channel, &SubscriptionBase::onMessage, static_cast<SubscriptionBase*>(sub.get()));
  subs_.push_back(std::move(sub));
}

template <typename T>
void Node::publish(const std::string& channel, T& msg) {
  try {
    setLengths(msg);
    if (lcm_->publish(channel, &msg) != 0) {
      reportError("publish_failures", channel + ": publish failed");
      return;
    }
    ++out_[channel].messages;
  } catch (const std::exception& e) {
    reportError("publish_failures", channel + ": " + e.what());
  }
}

}  // namespace lasonic
