#include "lcmio/node.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <stdexcept>
#include <thread>

#include <lasonic/process_status_t.hpp>

namespace lasonic {
namespace {
std::atomic<bool> g_shutdown{false};
extern "C" void onSignal(int) { g_shutdown = true; }

int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
}  // namespace

Node::Node(std::string process_name, const std::string& lcm_url)
    : Node(std::move(process_name), lcm_url, Options{}) {}

Node::Node(std::string process_name, const std::string& lcm_url, Options opts)
    : name_(std::move(process_name)), lcm_(std::make_shared<lcm::LCM>(lcm_url)), opts_(opts) {
  if (!lcm_->good()) throw std::runtime_error("cannot initialise LCM with URL '" + lcm_url + "'");
  init();
}

Node::Node(std::string process_name, std::shared_ptr<lcm::LCM> lcm, Options opts)
    : name_(std::move(process_name)), lcm_(std::move(lcm)), opts_(opts) {
  if (!lcm_ || !lcm_->good()) throw std::runtime_error("LCM instance is not usable");
  init();
}

Node::~Node() = default;

void Node::init() {
  start_ = last_status_ = std::chrono::steady_clock::now();
  if (opts_.install_signal_handlers) {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
  }
}

bool Node::shutdownRequested() { return g_shutdown.load(); }

void Node::count(const std::string& counter, int64_t n) { counters_[counter] += n; }

int64_t Node::counter(const std::string& name) const {
  auto it = counters_.find(name);
  return it == counters_.end() ? 0 : it->second;
}

void Node::reportError(const std::string& counter, const std::string& message) {
  ++counters_[counter];
  ++errors_;
  last_error_ = message;
  // At most one log line per counter and second: a flood of bad input must not flood the log.
  const auto now = std::chrono::steady_clock::now();
  auto it = last_logged_.find(counter);
  if (it == last_logged_.end() || now - it->second > std::chrono::seconds(1)) {
    last_logged_[counter] = now;
    spdlog::warn("{} [{} so far: {}]", message, counter, counters_[counter]);
  }
}

void Node::handlerFailed(const std::string& channel, const char* what) {
  reportError("handler_failures." + channel, channel + ": handler failed: " + what);
}

void Node::noteMessageTime(int64_t utime) {
  if (utime > last_msg_utime_) last_msg_utime_ = utime;
}

int Node::spinOnce(int timeout_ms) {
  const int r = lcm_->handleTimeout(timeout_ms);
  maybeHeartbeat();
  return r > 0 ? 1 : 0;
}

int Node::run() {
  spdlog::info("{} running", name_);
  while (!g_shutdown && !stop_requested_) {
    // A signal interrupts the wait (EINTR): that is shutdown, not an LCM failure.
    if (lcm_->handleTimeout(100) < 0 && !g_shutdown) {
      reportError("lcm_failures", "LCM handle failed");
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    maybeHeartbeat();
  }
  publishStatus();
  spdlog::info("{} stopping: {} errors", name_, errors_);
  return 0;
}

void Node::maybeHeartbeat() {
  if (!opts_.heartbeat) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_status_ >= std::chrono::seconds(1)) publishStatus();
}

void Node::publishStatus() {
  if (!opts_.heartbeat) return;
  const auto now = std::chrono::steady_clock::now();
  const double dt = std::chrono::duration<double>(now - last_status_).count();
  last_status_ = now;
  process_status_t st;
  st.utime = wallUtime();
  st.process = name_;
  char host[256] = {0};
  gethostname(host, sizeof(host) - 1);
  st.host = host;
  st.pid = static_cast<int32_t>(getpid());
  st.uptime_s = std::chrono::duration<double>(now - start_).count();
  st.last_msg_utime = last_msg_utime_;
  auto add = [&](std::map<std::string, ChannelStats>& m, int8_t dir) {
    for (auto& [ch, s] : m) {
      channel_stat_t c;
      c.channel = ch;
      c.direction = dir;
      c.messages = s.messages;
      c.rate_hz = dt > 0 ? static_cast<float>(static_cast<double>(s.messages - s.at_last_status) / dt) : 0.f;
      c.decode_errors = s.decode_errors;
      s.at_last_status = s.messages;
      st.channels.push_back(c);
    }
  };
  add(in_, channel_stat_t::DIR_IN);
  add(out_, channel_stat_t::DIR_OUT);
  for (const auto& [k, v] : counters_) {
    st.counter_names.push_back(k);
    st.counter_values.push_back(v);
  }
  st.errors = errors_;
  st.last_error = last_error_;
  publish(channels::PROCESS_STATUS, st);
}

}  // namespace lasonic
