#pragma once
// One rule for every executable's command line (README "Processes: start-up, exit codes,
// status"): --help prints the help and exits 0; any other command-line error (an unknown
// option, a missing required one, a value out of range, a missing input file) prints CLI11's
// reason and exits 2, like a bad configuration. CLI11's own codes (105, 106, 109, ...) would
// tell a script nothing the table does not.
//   if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
#include <CLI/CLI.hpp>

#include <optional>

namespace lasonic {

inline constexpr int kExitBadCommandLine = 2;

inline std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadCommandLine;  // app.exit prints help or the reason
  }
  return std::nullopt;
}

}  // namespace lasonic
