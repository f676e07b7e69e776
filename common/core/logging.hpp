#pragma once
#include <spdlog/common.h>

#include <optional>
#include <string>

namespace lasonic {
// Console logger named after the process; level from "trace".."off" (env LASONIC_LOG_LEVEL
// overrides; an unknown name is warned about and logs at info).
void setupLogging(const std::string& process_name, const std::string& level = "info");
// trace, debug, info, warn (warning), error (err), critical, off, in any case; nullopt otherwise.
std::optional<spdlog::level::level_enum> parseLogLevel(std::string name);
}  // namespace lasonic
