#include "lcmio/status.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

namespace lasonic {
namespace {
int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
}  // namespace

StatusBoard::StatusBoard(std::string process_name)
    : name_(std::move(process_name)), start_(std::chrono::steady_clock::now()), last_snapshot_(start_) {}

void StatusBoard::count(std::string_view counter, int64_t n) {
  auto it = counters_.find(counter);
  if (it == counters_.end()) it = counters_.emplace(std::string(counter), 0).first;
  it->second += n;
}

int64_t StatusBoard::counter(const std::string& name) const {
  auto it = counters_.find(name);
  return it == counters_.end() ? 0 : it->second;
}

void StatusBoard::reportError(const std::string& counter, const std::string& message) {
  ++counters_[counter];
  ++errors_;
  last_error_ = message;
  const auto now = std::chrono::steady_clock::now();
  auto it = last_logged_.find(counter);
  if (it == last_logged_.end() || now - it->second > std::chrono::seconds(1)) {
    last_logged_[counter] = now;
    spdlog::warn("{} [{} so far: {}]", message, counter, counters_[counter]);
  }
}

void StatusBoard::noteMessageTime(int64_t utime) {
  if (utime > last_msg_utime_) last_msg_utime_ = utime;
}

process_status_t StatusBoard::snapshot() {
  const auto now = std::chrono::steady_clock::now();
  const double dt = std::chrono::duration<double>(now - last_snapshot_).count();
  last_snapshot_ = now;
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
  return st;
}

}  // namespace lasonic
