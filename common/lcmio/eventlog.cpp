#include "lcmio/eventlog.hpp"

#include <pthread.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>
#include <iostream>

namespace lasonic {

namespace {
constexpr uint32_t kSync = 0xEDA1DA01u;  // LCM's event-log sync word
constexpr size_t kReadChunk = 1 << 17;  // (the buffer: twice that, a quarter of a megabyte)
// A megabyte: a quarter of one gave the writer thread four times the wake-ups, on two cores each
// a switch away from a busy stage thread (lasonic-replay 2400x -> 2200x on a 600 s log).
constexpr size_t kWriteChunk = 1 << 20;

uint32_t be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
uint64_t be64(const uint8_t* p) { return (uint64_t{be32(p)} << 32) | be32(p + 4); }
}  // namespace

LogReader::LogReader(const std::string& path) : path_(path) {
  f_.reset(std::fopen(path.c_str(), "rb"));
  if (!f_) throw LogError(path + ": cannot open LCM log for reading");
  // A regular file's size bounds its events; a pipe or FIFO (`--in <(...)`) has none, and is read
  // to its end as LCM reads it.
  struct stat st {};
  regular_ = ::fstat(::fileno(f_.get()), &st) == 0 && S_ISREG(st.st_mode);
  if (regular_) file_size_ = static_cast<int64_t>(st.st_size);
  std::setvbuf(f_.get(), nullptr, _IONBF, 0);  // buffered here
}

bool LogReader::fill(size_t need) {
  if (end_ - pos_ >= need) return true;
  if (pos_ > 0) {  // keep the unread bytes at the front
    std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
    end_ -= pos_;
    pos_ = 0;
  }
  // (Grown at least twofold: an event a little larger than any before is no new buffer.)
  if (buf_.size() < need + kReadChunk) buf_.resize(std::max(need + kReadChunk, 2 * buf_.size()));
  while (end_ < need) {
    const size_t got = std::fread(buf_.data() + end_, 1, buf_.size() - end_, f_.get());
    if (got == 0) return false;
    end_ += got;
    file_offset_ += static_cast<int64_t>(got);
  }
  return true;
}

std::optional<LogRecord> LogReader::next() {
  const std::optional<LogRecordView> v = nextView();
  if (!v) return std::nullopt;
  LogRecord r;
  r.timestamp = v->timestamp;
  r.channel.assign(v->channel);
  r.data.assign(v->data, v->data + v->size);
  return r;
}

bool LogReader::refreshFileSize(int64_t need) {
  // (A log still being written has grown since it was opened.)
  struct stat st {};
  if (::fstat(::fileno(f_.get()), &st) == 0) file_size_ = static_cast<int64_t>(st.st_size);
  return file_size_ >= need;
}

void LogReader::stop(const std::string& reason, int64_t at) {
  // Said once per reading, with where: a log cut short by a power loss or a killed lcm-logger is
  // still worth reading up to there, but never silently (the tools go on with the events before it).
  std::cerr << "warning: " << path_ << ": the log ends at byte " << at;
  if (regular_) std::cerr << " of " << file_size_;
  std::cerr << " (" << reason << "); " << events_ << " events read before it\n";
  stop_reason_ = reason;
  pos_ = end_;
}

std::optional<LogRecordView> LogReader::nextView() {
  if (!stop_reason_.empty()) return std::nullopt;
  // The sync word, byte by byte (skipping anything before it), as LCM does.
  uint32_t magic = 0;
  const int64_t scan_start = bytesRead();
  do {
    if (!fill(1)) {
      if (bytesRead() > scan_start)
        stop(std::to_string(bytesRead() - scan_start) + " bytes at the end that hold no event's sync word", scan_start);
      return std::nullopt;
    }
    magic = (magic << 8) | buf_[pos_++];
  } while (magic != kSync);
  const int64_t at = bytesRead() - 4;  // where this event starts
  if (!fill(24)) {
    stop("an event's header cut short", at);
    return std::nullopt;
  }
  const uint8_t* h = buf_.data() + pos_;
  LogRecordView r;
  r.timestamp = static_cast<int64_t>(be64(h + 8));
  const auto channellen = static_cast<int32_t>(be32(h + 16));
  const auto datalen = static_cast<int32_t>(be32(h + 20));
  pos_ += 24;
  if (channellen <= 0 || channellen >= 1000) {
    stop("an event with an invalid channel length, " + std::to_string(channellen), at);
    return std::nullopt;
  }
  if (datalen < 0) {
    stop("an event with an invalid data length, " + std::to_string(datalen), at);
    return std::nullopt;
  }
  const size_t body = static_cast<size_t>(channellen) + static_cast<size_t>(datalen);
  // An event longer than what is left of the file is a cut or corrupt one: said before buffering
  // it (a corrupt length near 2^31 would otherwise make the reader allocate 2 GB first).
  if (regular_ && bytesRead() + static_cast<int64_t>(body) > file_size_ &&
      !refreshFileSize(bytesRead() + static_cast<int64_t>(body))) {
    stop("an event of " + std::to_string(body) + " bytes, more than the " + std::to_string(file_size_ - bytesRead()) +
         " left in the file: cut short or corrupt", at);
    return std::nullopt;
  }
  if (!fill(body)) {
    stop("an event's data cut short", at);
    return std::nullopt;
  }
  // The next event's sync word buffered too (if there is one) before pointing into the buffer,
  // which fill() may move.
  const bool more = fill(body + 4);
  r.channel = std::string_view(reinterpret_cast<const char*>(buf_.data() + pos_), static_cast<size_t>(channellen));
  r.data = buf_.data() + pos_ + channellen;
  r.size = static_cast<size_t>(datalen);
  pos_ += body;
  // After the data: the next event's sync word or the end of the file; anything else ends the log,
  // this event included (as LCM's reader does: its length may be what is corrupt).
  if (more && be32(buf_.data() + pos_) != kSync) {
    stop("no sync word after an event's data: the event dropped", at);
    return std::nullopt;
  }
  ++events_;
  return r;
}

std::vector<LogRecord> LogReader::readAll(const std::string& path) {
  LogReader r(path);
  std::vector<LogRecord> out;
  while (auto e = r.next()) out.push_back(std::move(*e));
  return out;
}

LogWriter::LogWriter(const std::string& path) : path_(path) {
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_) throw LogError(path + ": cannot open LCM log for writing");
  std::setvbuf(f_, nullptr, _IONBF, 0);  // buffered here
  // Both buffers made once (a chunk and the event that fills it): the second one grown by
  // doubling as it was filled cost a copy and a page fault per page of each size on the way.
  buf_.bytes.reserve(2 * kWriteChunk);
  writing_.bytes.reserve(2 * kWriteChunk);
  writer_ = std::thread([this] {
    pthread_setname_np(pthread_self(), "log-writer");  // for top -H, perf
    writerLoop();
  });
}

LogWriter::~LogWriter() {
  const bool told = failure_thrown_;
  try {
    flush();
  } catch (const LogError& e) {
    if (!told) std::cerr << e.what() << "\n";  // (a failure the caller was told of is not said twice)
  }
  {
    const std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  writer_.join();
  if (std::fclose(f_) != 0) std::cerr << path_ << ": closing the LCM log failed\n";
}

bool LogWriter::writeChunk(Chunk& c) {
  if (c.pieces.empty()) return std::fwrite(c.bytes.data(), 1, c.bytes.size(), f_) == c.bytes.size();
  // The pieces in order, as few system calls as the iovec limit allows; a short write goes on
  // from where it stopped.
  std::vector<iovec> iov;
  iov.reserve(c.pieces.size() + 1);
  size_t covered = 0;  // bytes up to here are in a piece
  for (const Chunk::Piece& p : c.pieces) {
    uint8_t* base = p.owned == SIZE_MAX ? c.bytes.data() + p.at : c.owned[p.owned].data();
    if (p.owned == SIZE_MAX) covered = p.at + p.len;
    if (p.len > 0) iov.push_back({base, p.len});
  }
  if (covered < c.bytes.size()) iov.push_back({c.bytes.data() + covered, c.bytes.size() - covered});
  const int fd = fileno(f_);
  size_t first = 0;
  while (first < iov.size()) {
    const int count = static_cast<int>(std::min<size_t>(iov.size() - first, IOV_MAX));
    const ssize_t n = ::writev(fd, iov.data() + first, count);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    auto left = static_cast<size_t>(n);
    while (first < iov.size() && left >= iov[first].iov_len) left -= iov[first++].iov_len;
    if (left > 0) {
      iov[first].iov_base = static_cast<uint8_t*>(iov[first].iov_base) + left;
      iov[first].iov_len -= left;
    }
  }
  return true;
}

void LogWriter::writerLoop() {
  std::unique_lock<std::mutex> lock(m_);
  for (;;) {
    cv_.wait(lock, [this] { return pending_ || stop_; });
    if (!pending_) return;  // stop_, nothing left to write
    lock.unlock();
    const bool ok = writeChunk(writing_);
    writing_.bytes.clear();
    writing_.pieces.clear();  // (the owned buffers go back from the caller's thread: handOver)
    lock.lock();
    failed_ = failed_ || !ok;
    pending_ = false;
    cv_.notify_all();
  }
}

void LogWriter::handOver() {
  std::unique_lock<std::mutex> lock(m_);
  cv_.wait(lock, [this] { return !pending_; });
  if (failed_) throwFailed();
  if (buf_.empty()) return;
  std::swap(buf_, writing_);  // buf_ is now the written (cleared) chunk, its capacity kept
  buf_size_ = 0;
  covered_ = 0;
  pending_ = true;
  lock.unlock();
  cv_.notify_all();
  for (LocalBus::Bytes& b : buf_.owned)
    if (give_back_) give_back_(std::move(b));
  buf_.owned.clear();
}

void LogWriter::flush() {
  handOver();
  std::unique_lock<std::mutex> lock(m_);
  cv_.wait(lock, [this] { return !pending_; });
  if (failed_) throwFailed();
}

void LogWriter::throwFailed() {
  failure_thrown_ = true;
  throw LogError(path_ + ": write failed");
}

void LogWriter::header(const std::string& channel, int64_t timestamp, size_t size) {
  if (size > 0x7fffffff) throw LogError(path_ + ": event on channel '" + channel + "' too large for an LCM log");
  // The event header (big-endian), made apart and appended at once (not byte by byte).
  uint8_t h[28];
  const auto be = [&h](size_t at, uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) h[at + static_cast<size_t>(i)] = static_cast<uint8_t>(v >> (8 * (bytes - 1 - i)));
  };
  be(0, kSync, 4);
  be(4, static_cast<uint64_t>(events_), 8);
  be(12, static_cast<uint64_t>(timestamp), 8);
  be(20, channel.size(), 4);
  be(24, size, 4);
  buf_.bytes.insert(buf_.bytes.end(), h, h + sizeof h);
  buf_.bytes.insert(buf_.bytes.end(), channel.begin(), channel.end());
  buf_size_ += sizeof h + channel.size();
  ++events_;
}

void LogWriter::writeRaw(const std::string& channel, int64_t timestamp, const uint8_t* data, size_t size) {
  header(channel, timestamp, size);
  buf_.bytes.insert(buf_.bytes.end(), data, data + size);
  buf_size_ += size;
  if (buf_size_ >= kWriteChunk) handOver();
}

void LogWriter::writeOwned(const std::string& channel, int64_t timestamp, LocalBus::Bytes&& data) {
  if (data.size() < kOwnedMin) {
    writeRaw(channel, timestamp, data.data(), data.size());
    if (give_back_) give_back_(std::move(data));
    return;
  }
  header(channel, timestamp, data.size());
  // The bytes since the previous kept buffer (or the start), then this one.
  buf_.pieces.push_back({SIZE_MAX, covered_, buf_.bytes.size() - covered_});
  covered_ = buf_.bytes.size();
  buf_.pieces.push_back({buf_.owned.size(), 0, data.size()});
  buf_size_ += data.size();
  buf_.owned.push_back(std::move(data));
  if (buf_size_ >= kWriteChunk) handOver();
}

void LogWriter::writeRaw(const std::string& channel, int64_t timestamp, const std::vector<uint8_t>& data) {
  writeRaw(channel, timestamp, data.data(), data.size());
}

}  // namespace lasonic
