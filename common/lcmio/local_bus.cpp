#include "lcmio/local_bus.hpp"

#include <utility>

namespace lasonic {

void LocalBus::subscribe(const std::string& pattern, Handler handler) {
  subs_.push_back({std::regex(pattern), std::move(handler)});
  by_channel_.clear();
}

const std::vector<size_t>& LocalBus::subscribersOf(const std::string& channel) {
  auto it = by_channel_.find(channel);
  if (it != by_channel_.end()) return it->second;
  std::vector<size_t> idx;
  for (size_t i = 0; i < subs_.size(); ++i)
    if (std::regex_match(channel, subs_[i].pattern)) idx.push_back(i);
  return by_channel_.emplace(channel, std::move(idx)).first->second;
}

LocalBus::Bytes LocalBus::takeBuffer() {
  Bytes bytes;
  if (!spare_.empty()) {
    bytes = std::move(spare_.back());
    spare_.pop_back();
    bytes.clear();
  }
  return bytes;
}

int LocalBus::publish(const std::string& channel, const void* data, size_t size) {
  Bytes bytes = takeBuffer();
  const auto* p = static_cast<const uint8_t*>(data);
  bytes.assign(p, p + size);
  return publish(channel, std::move(bytes));
}

int LocalBus::publish(const std::string& channel, Bytes&& bytes) {
  queue_.push_back({channel, std::move(bytes)});
  return 0;
}

int LocalBus::handleOne() {
  if (queue_.empty()) return 0;
  Message m = std::move(queue_.front());
  queue_.pop_front();
  lcm::ReceiveBuffer rbuf{};
  rbuf.data = m.data.data();
  rbuf.data_size = static_cast<uint32_t>(m.data.size());
  rbuf.recv_utime = 0;
  // By index: a handler may subscribe (which clears the cache), as with LCM the new
  // subscription sees the next message.
  const std::vector<size_t> subs = subscribersOf(m.channel);
  for (const size_t i : subs) subs_[i].handler(&rbuf, m.channel);
  spare_.push_back(std::move(m.data));
  return 1;
}

int64_t LocalBus::handleAll() {
  int64_t n = 0;
  while (handleOne() > 0) ++n;
  return n;
}

}  // namespace lasonic
