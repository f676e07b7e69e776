#include "lcmio/local_bus.hpp"

#include <utility>

namespace lasonic {

size_t LocalBus::subscribe(const std::string& pattern, Handler handler) {
  subs_.push_back({pattern, std::regex(pattern), std::move(handler), {}});
  ++generation_;
  return subs_.size() - 1;
}

void LocalBus::capture(size_t subscription, Capture capture) { subs_.at(subscription).capture = std::move(capture); }

LocalBus::Channel* LocalBus::channelOf(const std::string& name) {
  auto it = channels_.find(name);
  if (it == channels_.end()) {
    it = channels_.emplace(name, Channel{}).first;
    it->second.name = &it->first;
  }
  return &it->second;
}

const std::vector<size_t>& LocalBus::subscribersOf(Channel* c) {
  if (c->generation != generation_) {
    c->subs.clear();
    for (size_t i = 0; i < subs_.size(); ++i)
      if (std::regex_match(*c->name, subs_[i].pattern)) c->subs.push_back(i);
    c->generation = generation_;
  }
  return c->subs;
}

LocalBus::Bytes LocalBus::takeBuffer(size_t size) {
  Bytes bytes;
  if (size >= kLarge && !spare_large_.empty()) {
    // The newest that is big enough (else the newest: it grows once).
    size_t k = spare_large_.size() - 1;
    for (size_t i = spare_large_.size(); i-- > 0;)
      if (spare_large_[i].capacity() >= size) {
        k = i;
        break;
      }
    bytes = std::move(spare_large_[k]);
    spare_large_.erase(spare_large_.begin() + static_cast<std::ptrdiff_t>(k));
  } else if (!spare_.empty()) {
    bytes = std::move(spare_.back());
    spare_.pop_back();
  }
  bytes.clear();
  return bytes;
}

void LocalBus::giveBack(Bytes&& bytes) {
  if (bytes.capacity() >= kLarge) {
    if (spare_large_.size() < kMaxSpareLarge) spare_large_.push_back(std::move(bytes));
  } else if (bytes.capacity() > 0 && spare_.size() < kMaxSpare) {
    spare_.push_back(std::move(bytes));
  }
}

int LocalBus::publish(const std::string& channel, const void* data, size_t size) {
  Bytes bytes = takeBuffer(size);
  const auto* p = static_cast<const uint8_t*>(data);
  bytes.assign(p, p + size);
  return publish(channel, std::move(bytes));
}

int LocalBus::publish(const std::string& channel, Bytes&& bytes) {
  queue_.push_back({channelOf(channel), std::move(bytes)});
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
  // A copy: a handler may subscribe (which changes the channel's list); as with LCM, the new
  // subscription sees the next message.
  const std::string& name = m.name();
  const std::vector<size_t>& current = subscribersOf(m.channel);
  subs_scratch_.assign(current.begin(), current.end());
  for (const size_t i : subs_scratch_) {
    if (!subs_[i].capture) {
      subs_[i].handler(&rbuf, name);
      continue;
    }
    const size_t first = queue_.size();
    subs_[i].handler(&rbuf, name);
    subs_[i].capture(i, name, queue_, first);
  }
  if (sink_) {
    sink_(name, std::move(m.data));
    return 1;
  }
  // Kept for reuse, up to a bound: buffers published from elsewhere (another thread's copies)
  // would otherwise pile up here.
  giveBack(std::move(m.data));
  return 1;
}

int64_t LocalBus::handleAll() {
  int64_t n = 0;
  while (handleOne() > 0) ++n;
  return n;
}

}  // namespace lasonic
