#pragma once
// LCM event-log (lcm-logger format) reading and writing for the offline tools.
#include <lcm/lcm-cpp.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lcmio/lengths.hpp"

namespace lasonic {

class LogError : public std::runtime_error {
 public:
  explicit LogError(const std::string& w) : std::runtime_error(w) {}
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
    if (msg.decode(data.data(), 0, static_cast<int>(data.size())) < 0) return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return msg;
}

template <typename T>
std::vector<uint8_t> encodeMsg(T& msg) {
  setLengths(msg);
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  if (msg.encode(buf.data(), 0, static_cast<int>(buf.size())) < 0)
    throw std::logic_error("LCM encode failed");
  return buf;
}

class LogReader {
 public:
  explicit LogReader(const std::string& path);  // throws LogError
  // Next event, or nullopt at the end of the log.
  std::optional<LogRecord> next();
  // All events of the log, in order.
  static std::vector<LogRecord> readAll(const std::string& path);

 private:
  std::unique_ptr<lcm::LogFile> log_;
  std::string path_;
};

class LogWriter {
 public:
  explicit LogWriter(const std::string& path);  // throws LogError
  void writeRaw(const std::string& channel, int64_t timestamp, const std::vector<uint8_t>& data);
  template <typename T>
  void write(const std::string& channel, int64_t timestamp, T& msg) {
    writeRaw(channel, timestamp, encodeMsg(msg));
  }
  int64_t events() const { return events_; }

 private:
  std::unique_ptr<lcm::LogFile> log_;
  std::string path_;
  int64_t events_ = 0;
};

}  // namespace lasonic
