#include "core/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <cstdlib>
#include <utility>

namespace lasonic {

void setupLogging(const std::string& process_name, const std::string& level) {
  auto logger = spdlog::stderr_color_mt(process_name);
  spdlog::set_default_logger(logger);
  // Microseconds (%f), as LCM stamps what it receives: a line then orders against the messages of
  // an lcm-logger log; milliseconds leave a message logged within the line's millisecond on
  // either side of it.
  spdlog::set_pattern("[%Y-%m-%d %H:%M:%S.%f] [%n] [%^%l%$] %v");
  std::string lvl = level;
  if (const char* env = std::getenv("LASONIC_LOG_LEVEL")) lvl = env;
  const auto parsed = parseLogLevel(lvl);
  spdlog::set_level(parsed.value_or(spdlog::level::info));
  // spdlog reads a name it does not know as "off", which would hide every later warning and
  // error: say so, and log at info.
  if (!parsed)
    spdlog::warn("LASONIC_LOG_LEVEL: unknown level '{}' (trace, debug, info, warn, error, critical, off): logging at info",
                 lvl);
}

std::optional<spdlog::level::level_enum> parseLogLevel(std::string name) {
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  static const std::pair<const char*, spdlog::level::level_enum> kNames[] = {
      {"trace", spdlog::level::trace}, {"debug", spdlog::level::debug},       {"info", spdlog::level::info},
      {"warn", spdlog::level::warn},   {"warning", spdlog::level::warn},      {"error", spdlog::level::err},
      {"err", spdlog::level::err},     {"critical", spdlog::level::critical}, {"off", spdlog::level::off}};
  for (const auto& [n, l] : kNames)
    if (name == n) return l;
  return std::nullopt;
}

}  // namespace lasonic
