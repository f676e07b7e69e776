#pragma once
// LCM event-log (lcm-logger format) reading and writing for the offline tools.
//
// The format is LCM's (lcm/eventlog.c): per event a sync word 0xEDA1DA01, event number and
// timestamp (int64), channel and data lengths (int32), all big-endian, then the channel name and
// the data. Read and written here with large buffers rather than through lcm::LogFile, whose
// reader seeks back after every event (one lseek and one buffer refill per event: most of
// lasonic-replay's time on small messages). The reader keeps LCM 1.3.1's rules exactly: it
// scans for the sync word; a channel length outside 1..999 or a negative data length, a short
// read, or anything but a sync word or the end of the file after an event's data end the log.
// Unlike LCM it says so, once, naming the file and the byte (stopReason()), and it does not
// buffer an event longer than the rest of the file.
#include <lcm/lcm-cpp.hpp>

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "lcmio/lengths.hpp"
#include "lcmio/local_bus.hpp"
#include "lcmio/wire.hpp"

namespace lasonic {

class LogError : public std::runtime_error {
 public:
  explicit LogError(const std::string& w) : std::runtime_error(w) {}
};

// An event as it lies in LogReader's buffer: valid until the reader's next call.
struct LogRecordView {
  int64_t timestamp = 0;
  std::string_view channel;
  const uint8_t* data = nullptr;
  size_t size = 0;
};

struct LogRecord {
  int64_t timestamp = 0;  // [us] as stored in the log (for our logs: the message's own time)
  std::string channel;
  std::vector<uint8_t> data;
};

// nullopt for bytes that are not a T. Like Node, array counts are checked against the bytes
// and the caps first (lcmio/lengths.hpp): a corrupt log must not make a tool allocate gigabytes
// or abort on std::length_error out of LCM's generated decode().
template <typename T>
std::optional<T> decodeAs(const std::vector<uint8_t>& data) {
  if constexpr (HasWireArrays<T>::value) {
    if (checkWireArrays<T>(data.data(), data.size()).result != WireCheck::Ok &&
        checkWireArrays<T>(data.data(), data.size()).result != WireCheck::NotThisType)
      return std::nullopt;
  }
  T msg;
  try {
    if (wireDecode(msg, data.data(), static_cast<int>(data.size())) < 0) return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return msg;
}

template <typename T>
std::vector<uint8_t> encodeMsg(T& msg) {
  setLengths(msg);
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  if (wireEncode(msg, buf.data(), static_cast<int>(buf.size())) < 0)
    throw std::logic_error("LCM encode failed");
  return buf;
}

class LogReader {
 public:
  explicit LogReader(const std::string& path);  // throws LogError
  // Next event, or nullopt at the end of the log.
  std::optional<LogRecord> next();
  // The same without copying the event out of the reader's buffer.
  std::optional<LogRecordView> nextView();
  // All events of the log, in order.
  static std::vector<LogRecord> readAll(const std::string& path);
  // Bytes read from the file so far (for progress reports).
  int64_t bytesRead() const { return file_offset_ - static_cast<int64_t>(end_ - pos_); }
  // Size of a regular file (when opened, or as found when an event seemed to run past it); 0 for
  // a pipe.
  int64_t fileSize() const { return file_size_; }
  // Events returned so far.
  int64_t events() const { return events_; }
  // Why the log ended before the end of the file (a cut or corrupt event; also warned about on
  // stderr with the file's name and the byte), or empty when it ended at the end of the file.
  const std::string& stopReason() const { return stop_reason_; }

 private:
  bool fill(size_t need);  // at least `need` unread bytes buffered; false at the end of the file
  bool refreshFileSize(int64_t need);  // the file's size now; whether it holds `need` bytes
  void stop(const std::string& reason, int64_t at);  // at: the byte where the log stops making sense
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> f_;
  std::string path_;
  std::vector<uint8_t> buf_;
  size_t pos_ = 0, end_ = 0;
  int64_t file_offset_ = 0, file_size_ = 0;
  int64_t events_ = 0;
  bool regular_ = false;
  std::string stop_reason_;
};

// Events are gathered in a buffer of about a megabyte; a full buffer is handed to a writer thread
// and the next one filled meanwhile, so the file system's work (a third of lasonic-replay's time
// when it ran in line) overlaps the caller's. The bytes and their order are those of the calls.
// A failed write is reported by the next call that hands over a buffer, or by flush().
// writeOwned takes a large event's data whole instead of copying it (lasonic-replay's grid maps:
// 19 MB of a 60 s fig7_lab replay's 26 MB); written in place (writev), the buffer goes back
// through the give-back function on the caller's thread once it is written.
class LogWriter {
 public:
  explicit LogWriter(const std::string& path);  // throws LogError
  ~LogWriter();                                 // flushes; a failure is reported on stderr
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;
  void writeRaw(const std::string& channel, int64_t timestamp, const uint8_t* data, size_t size);
  void writeRaw(const std::string& channel, int64_t timestamp, const std::vector<uint8_t>& data);
  // The same bytes as writeRaw; data of kOwnedMin bytes or more is kept, not copied, and handed
  // to the give-back function (if set) once written, from a later call on the caller's thread.
  void writeOwned(const std::string& channel, int64_t timestamp, LocalBus::Bytes&& data);
  void setGiveBack(std::function<void(LocalBus::Bytes&&)> give_back) { give_back_ = std::move(give_back); }
  static constexpr size_t kOwnedMin = 16384;
  template <typename T>
  void write(const std::string& channel, int64_t timestamp, T& msg) {
    writeRaw(channel, timestamp, encodeMsg(msg));
  }
  int64_t events() const { return events_; }
  // Writes the buffered events to the file and waits until they are written (throws LogError on
  // failure).
  void flush();

 private:
  // What is handed to the writer thread: bytes, and data kept whole, in the order of `pieces`.
  struct Chunk {
    struct Piece {
      size_t owned;       // index in `owned`, or SIZE_MAX: bytes[at, at + len)
      size_t at, len;
    };
    std::vector<uint8_t> bytes;
    std::vector<LocalBus::Bytes> owned;
    std::vector<Piece> pieces;
    bool empty() const { return pieces.empty() && bytes.empty(); }
  };
  void header(const std::string& channel, int64_t timestamp, size_t size);  // into buf_.bytes
  void handOver();  // buf_ to the writer thread (after it has written the previous buffer)
  void writerLoop();
  bool writeChunk(Chunk& c);  // (on the writer thread) false on failure
  [[noreturn]] void throwFailed();

  std::FILE* f_ = nullptr;
  std::string path_;
  Chunk buf_;  // being filled by the caller
  size_t buf_size_ = 0;  // bytes in buf_ (its own and those of its kept buffers)
  size_t covered_ = 0;   // buf_.bytes up to here are in buf_.pieces
  int64_t events_ = 0;
  std::function<void(LocalBus::Bytes&&)> give_back_;
  std::mutex m_;
  std::condition_variable cv_;
  Chunk writing_;  // being written by the writer thread (while pending_)
  bool pending_ = false, stop_ = false, failed_ = false;
  bool failure_thrown_ = false;  // a caller has been told (the destructor need not say it again)
  std::thread writer_;
};

}  // namespace lasonic
