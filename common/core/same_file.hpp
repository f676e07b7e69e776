#pragma once
// Whether a tool's output file would overwrite one of its inputs (README "Scenario format",
// *Physical bounds*): lasonic-sim --out naming its scenario, lasonic-render --out its log,
// lasonic-replay --out its --in or a --config, lasonic-eval's --json, --samples or
// --tactical-samples its log, scenario or a --config, lasonic-lossy-relay --out-log its --in-log.
#include <filesystem>
#include <string>
#include <system_error>

namespace lasonic {

// True if `out` and `input` both exist and are the same file (however spelt: relative, through
// a link). An output that does not exist yet overwrites nothing.
inline bool sameExistingFile(const std::string& out, const std::string& input) {
  std::error_code ec;
  const bool same = std::filesystem::equivalent(out, input, ec);
  return !ec && same;
}

}  // namespace lasonic
