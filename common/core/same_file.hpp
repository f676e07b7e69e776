#pragma once
// Whether a tool's output file would overwrite one of its inputs (README "Processes: start-up,
// exit codes, status"): lasonic-sim --out naming its scenario, lasonic-render --out its log,
// lasonic-replay --out its --in.
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
