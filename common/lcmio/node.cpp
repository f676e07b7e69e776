#include "lcmio/node.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include <lasonic/process_status_t.hpp>

namespace lasonic {

Node::Node(std::string process_name, const std::string& lcm_url)
    : Node(std::move(process_name), lcm_url, Options{}) {}

Node::Node(std::string process_name, const std::string& lcm_url, Options opts)
    : lcm_(std::make_shared<lcm::LCM>(lcm_url)), opts_(opts), status_(std::move(process_name)) {
  if (!lcm_->good())
    throw LcmUrlError("cannot open LCM with URL '" + lcm_url +
                      "' (LCM's reason is printed above; see the README, \"Deploying on two computers\")");
  init();
}

Node::Node(std::string process_name, std::shared_ptr<lcm::LCM> lcm, Options opts)
    : lcm_(std::move(lcm)), opts_(opts), status_(std::move(process_name)) {
  if (!lcm_ || !lcm_->good()) throw LcmUrlError("LCM instance is not usable");
  init();
}

Node::Node(std::string process_name, std::shared_ptr<LocalBus> bus, Options opts)
    : bus_(std::move(bus)), opts_(opts), status_(std::move(process_name)) {
  if (!bus_) throw LcmUrlError("no LocalBus given");
  init();
}

Node::~Node() = default;

void Node::init() {
  if (opts_.install_signal_handlers) shutdown::installHandlers();
}

void Node::handlerFailed(const std::string& channel, const char* what) {
  reportError("handler_failures." + channel, channel + ": handler failed: " + what);
}

void Node::decodeFailed(const std::string& channel, const char* type, size_t bytes, const std::string& why) {
  status_.decodeError(channel);
  reportError("decode_errors." + channel, channel + ": message does not decode as " + type + " (" +
                                              std::to_string(bytes) + " bytes; " + why + ")");
}

void Node::oversize(const std::string& channel, const char* type, int64_t claimed, int64_t cap) {
  reportError("oversize." + channel, channel + ": " + type + " with " + std::to_string(claimed) +
                                         " elements (cap " + std::to_string(cap) + "): dropped undecoded");
}

int Node::spinOnce(int timeout_ms) {
  const int r = bus_ ? bus_->handleOne() : lcm_->handleTimeout(timeout_ms);
  maybeHeartbeat();
  return r > 0 ? 1 : 0;
}

int Node::run() {
  spdlog::info("{} running", name());
  while (bus_ && !shutdown::requested() && !stop_requested_ && bus_->handleOne() > 0) maybeHeartbeat();
  while (lcm_ && !shutdown::requested() && !stop_requested_) {
    // A signal interrupts the wait (EINTR): that is shutdown, not an LCM failure.
    if (lcm_->handleTimeout(100) < 0 && !shutdown::requested()) {
      reportError("lcm_failures", "LCM handle failed");
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    maybeHeartbeat();
  }
  publishStatus();
  spdlog::info("{} stopping: {} errors", name(), errors());
  return 0;
}

void Node::maybeHeartbeat() {
  if (opts_.heartbeat && heartbeat_.due()) publishStatus();
}

void Node::publishStatus() {
  if (!opts_.heartbeat) return;
  heartbeat_.reset();
  process_status_t st = status_.snapshot();
  publish(channels::PROCESS_STATUS, st);
}

}  // namespace lasonic
