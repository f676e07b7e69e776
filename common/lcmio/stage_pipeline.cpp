#include "lcmio/stage_pipeline.hpp"

#include <pthread.h>

#include <thread>
#include <utility>

namespace lasonic {

namespace {
constexpr size_t kQueueChunks = 8;  // chunks a queue holds before its producer waits
size_t channelHash(const std::string& channel) { return std::hash<std::string>{}(channel); }
}  // namespace

bool StagePipeline::ChunkQueue::push(Chunk&& c, const std::atomic<bool>& failed) {
  std::unique_lock<std::mutex> lock(m_);
  cv_.wait(lock, [&] { return q_.size() < kQueueChunks || closed_; });
  if (closed_ || failed) return false;
  q_.push_back(std::move(c));
  lock.unlock();
  cv_.notify_all();
  return true;
}

std::optional<StagePipeline::Chunk> StagePipeline::ChunkQueue::pop(const std::atomic<bool>& failed) {
  std::unique_lock<std::mutex> lock(m_);
  cv_.wait(lock, [&] { return !q_.empty() || closed_; });
  if (failed || q_.empty()) return std::nullopt;
  Chunk c = std::move(q_.front());
  q_.pop_front();
  lock.unlock();
  cv_.notify_all();
  return c;
}

void StagePipeline::ChunkQueue::close() {
  {
    const std::lock_guard<std::mutex> lock(m_);
    closed_ = true;
  }
  cv_.notify_all();
}

void StagePipeline::Chunk::reset() {
  inputs.clear();
  input_bytes.clear();
  calls.clear();
  outs.clear();
  bytes.clear();
  owned.clear();
  for (auto& from : calls_from) from.clear();
}

StagePipeline::Chunk StagePipeline::takeChunk() {
  const std::lock_guard<std::mutex> lock(spare_m_);
  if (spare_chunks_.empty()) return Chunk{};
  Chunk c = std::move(spare_chunks_.back());
  spare_chunks_.pop_back();
  return c;
}

void StagePipeline::recycle(Chunk&& chunk) {
  chunk.reset();
  const std::lock_guard<std::mutex> lock(spare_m_);
  // (At most as many as can be on their way at once: the queues' and one per thread.)
  if (spare_chunks_.size() < (kQueueChunks + 1) * threads_.size()) spare_chunks_.push_back(std::move(chunk));
}

StagePipeline::StagePipeline(int threads) {
  if (threads < 1) throw std::invalid_argument("StagePipeline: threads must be >= 1");
  for (int i = 0; i < threads; ++i) threads_.push_back(std::make_unique<Thread>());
}

StagePipeline::~StagePipeline() = default;

void StagePipeline::beginStage(int thread) {
  if (stage_thread_ >= 0) throw std::logic_error("StagePipeline::beginStage: the previous stage was not ended");
  if (thread < 0 || thread >= threads()) throw std::out_of_range("StagePipeline::beginStage: no thread " + std::to_string(thread));
  stage_thread_ = thread;
  stage_first_ = bus(thread)->subscriptions();
}

void StagePipeline::endStage() {
  if (stage_thread_ < 0) throw std::logic_error("StagePipeline::endStage without beginStage");
  const int t = stage_thread_;
  Thread& own = *threads_[static_cast<size_t>(t)];
  const size_t end = own.bus->subscriptions();
  own.global_of.resize(end, SIZE_MAX);
  for (size_t i = stage_first_; i < end; ++i) {
    const size_t g = globals_++;
    own.global_of[i] = g;
    if (t == lastThread()) continue;  // no later thread needs what it publishes
    Thread* thp = &own;
    own.bus->capture(i, [thp, g](size_t, const std::string& delivered, std::deque<LocalBus::Message>& q,
                                 size_t first) {
      Chunk& c = *thp->chunk;
      c.calls.push_back({g, channelHash(delivered), c.outs.size(), q.size() - first});
      for (size_t j = first; j < q.size(); ++j) {
        const std::string& name = q[j].name();
        const size_t at = c.bytes.size();
        c.bytes.insert(c.bytes.end(), name.begin(), name.end());
        if (thp->bus->wanted(q[j])) {  // delivered here too: a copy
          c.bytes.insert(c.bytes.end(), q[j].data.begin(), q[j].data.end());
          c.outs.push_back({at, name.size(), at + name.size(), q[j].data.size(), SIZE_MAX});
        } else {  // (a grid map for a later thread's pilot): taken, not copied
          c.outs.push_back({at, name.size(), 0, q[j].data.size(), c.owned.size()});
          c.owned.push_back(std::move(q[j].data));
        }
      }
    });
    // Its proxy on every later thread, at this point of the order.
    for (int u = t + 1; u < threads(); ++u) {
      Thread* later = threads_[static_cast<size_t>(u)].get();
      const size_t k = later->proxies.size();
      const bool last = u == lastThread();
      later->proxies.push_back({g, t, own.bus->patternOf(i), 0});
      later->bus->subscribe(own.bus->patternOf(i), [later, k, last](const lcm::ReceiveBuffer*, const std::string& channel) {
        Thread::Proxy& p = later->proxies[k];
        Chunk& c = *later->chunk;
        const size_t calls_end = c.calls_from[static_cast<size_t>(p.from_thread)][later->unit + 1];
        while (p.cursor < calls_end && c.calls[p.cursor].global != p.global) ++p.cursor;
        if (p.cursor >= calls_end || c.calls[p.cursor].channel_hash != channelHash(channel))
          throw PipelineError("StagePipeline: subscription '" + p.pattern + "' got " + channel +
                              " here but not on its stage's own thread: a stage takes messages from a stage on a "
                              "later thread");
        const Chunk::Call& call = c.calls[p.cursor++];
        for (size_t o = call.first_out; o < call.first_out + call.outs; ++o) {
          const Chunk::Out& out = c.outs[o];
          later->channel.assign(reinterpret_cast<const char*>(c.bytes.data() + out.channel_at), out.channel_len);
          if (out.owned == SIZE_MAX) later->bus->publish(later->channel, c.bytes.data() + out.data_at, out.data_len);
          else if (last) later->bus->publish(later->channel, std::move(c.owned[out.owned]));  // its last use
          else later->bus->publish(later->channel, c.owned[out.owned].data(), out.data_len);
        }
      });
    }
  }
  stage_thread_ = -1;
}

void StagePipeline::process(Thread& th, int index, const std::function<void(int64_t)>& on_last) {
  Chunk& c = *th.chunk;
  const Chunk::Input& in = c.inputs[th.unit];
  for (Thread::Proxy& p : th.proxies) p.cursor = c.calls_from[static_cast<size_t>(p.from_thread)][th.unit];
  th.input_channel.assign(reinterpret_cast<const char*>(c.input_bytes.data() + in.at), in.channel_len);
  const uint8_t* data = c.input_bytes.data() + in.at + in.channel_len;
  if (index == lastThread()) {
    if (on_last) on_last(in.timestamp);
    th.bus->publish(th.input_channel, data, in.data_len);
  } else if (th.bus->wanted(th.input_channel)) {  // (a message nobody here takes changes nothing here)
    th.bus->publish(th.input_channel, data, in.data_len);
  }
  th.bus->handleAll();
  for (const Thread::Proxy& p : th.proxies) {
    const size_t calls_end = c.calls_from[static_cast<size_t>(p.from_thread)][th.unit + 1];
    for (size_t i = p.cursor; i < calls_end; ++i)
      if (c.calls[i].global == p.global)
        throw PipelineError("StagePipeline: subscription '" + p.pattern +
                            "' got fewer messages here than on its stage's own thread: a stage takes messages "
                            "from a stage on a later thread");
  }
}

void StagePipeline::fail(std::exception_ptr e) {
  {
    const std::lock_guard<std::mutex> lock(error_m_);
    if (!error_) error_ = std::move(e);
  }
  failed_ = true;
  for (auto& t : threads_) t->in.close();
}

void StagePipeline::work(int index, const std::function<std::optional<InputView>()>& next,
                         const std::function<void(int64_t)>& on_last) {
  try {
    Thread& th = *threads_[static_cast<size_t>(index)];
    for (bool end = false; !end && !failed_;) {
      Chunk chunk;
      if (index == 0) {
        chunk = takeChunk();
        chunk.inputs.reserve(kChunk);
        while (chunk.inputs.size() < kChunk) {
          const std::optional<InputView> in = next();
          if (!in) {
            end = true;
            break;
          }
          const size_t at = chunk.input_bytes.size();
          chunk.input_bytes.insert(chunk.input_bytes.end(), in->channel.begin(), in->channel.end());
          chunk.input_bytes.insert(chunk.input_bytes.end(), in->data, in->data + in->size);
          chunk.inputs.push_back({in->timestamp, at, in->channel.size(), in->size});
        }
        if (chunk.inputs.empty()) break;
        chunk.calls_from.resize(threads_.size());
      } else {
        std::optional<Chunk> c = th.in.pop(failed_);
        if (!c) break;
        chunk = std::move(*c);
      }
      th.chunk = &chunk;
      std::vector<size_t>& from = chunk.calls_from[static_cast<size_t>(index)];
      from.reserve(chunk.inputs.size() + 1);
      for (th.unit = 0; th.unit < chunk.inputs.size() && !failed_; ++th.unit) {
        from.push_back(chunk.calls.size());
        process(th, index, on_last);
      }
      from.push_back(chunk.calls.size());
      th.chunk = nullptr;
      if (index == lastThread()) recycle(std::move(chunk));
      else if (!threads_[static_cast<size_t>(index) + 1]->in.push(std::move(chunk), failed_)) break;
    }
  } catch (...) {
    fail(std::current_exception());
  }
  if (index < lastThread()) threads_[static_cast<size_t>(index) + 1]->in.close();
}

void StagePipeline::run(const std::function<std::optional<InputView>()>& next,
                        const std::function<void(int64_t)>& on_last) {
  if (stage_thread_ >= 0) throw std::logic_error("StagePipeline::run: a stage was not ended");
  for (int t = 0; t < lastThread(); ++t) {  // only stages and proxies on the earlier threads' buses
    const Thread& th = *threads_[static_cast<size_t>(t)];
    size_t own = 0;
    for (const size_t g : th.global_of) own += g != SIZE_MAX;
    if (own + th.proxies.size() != th.bus->subscriptions())
      throw std::logic_error("StagePipeline::run: thread " + std::to_string(t) +
                             " has subscriptions outside a stage (allowed on the last thread only)");
  }
  std::vector<std::thread> workers;
  for (int t = 0; t < lastThread(); ++t)
    workers.emplace_back([this, t, &next, &on_last] {
      pthread_setname_np(pthread_self(), ("pipeline-" + std::to_string(t)).c_str());  // for top -H, perf
      work(t, next, on_last);
    });
  work(lastThread(), next, on_last);
  for (std::thread& w : workers) w.join();
  if (error_) std::rethrow_exception(error_);
}

}  // namespace lasonic
