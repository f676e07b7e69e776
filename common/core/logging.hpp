#pragma once
#include <string>

namespace lasonic {
// Console logger named after the process; level from "trace".."off" (env LASONIC_LOG_LEVEL overrides).
void setupLogging(const std::string& process_name, const std::string& level = "info");
}  // namespace lasonic
