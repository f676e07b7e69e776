#include "core/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdlib>

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
  spdlog::set_level(spdlog::level::from_str(lvl));
}

}  // namespace lasonic
