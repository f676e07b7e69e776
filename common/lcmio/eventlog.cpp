#include "lcmio/eventlog.hpp"

namespace lasonic {

LogReader::LogReader(const std::string& path) : path_(path) {
  log_ = std::make_unique<lcm::LogFile>(path, "r");
  if (!log_->good()) throw LogError(path + ": cannot open LCM log for reading");
}

std::optional<LogRecord> LogReader::next() {
  const lcm::LogEvent* ev = log_->readNextEvent();
  if (!ev) return std::nullopt;
  LogRecord r;
  r.timestamp = ev->timestamp;
  r.channel = ev->channel;
  const auto* p = static_cast<const uint8_t*>(ev->data);
  r.data.assign(p, p + ev->datalen);
  return r;
}

std::vector<LogRecord> LogReader::readAll(const std::string& path) {
  LogReader r(path);
  std::vector<LogRecord> out;
  while (auto e = r.next()) out.push_back(std::move(*e));
  return out;
}

LogWriter::LogWriter(const std::string& path) : path_(path) {
  log_ = std::make_unique<lcm::LogFile>(path, "w");
  if (!log_->good()) throw LogError(path + ": cannot open LCM log for writing");
}

void LogWriter::writeRaw(const std::string& channel, int64_t timestamp, const std::vector<uint8_t>& data) {
  lcm::LogEvent ev;
  ev.eventnum = events_;
  ev.timestamp = timestamp;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(data.size());
  ev.data = const_cast<uint8_t*>(data.data());
  if (log_->writeEvent(&ev) != 0) throw LogError(path_ + ": write failed");
  ++events_;
}

}  // namespace lasonic
