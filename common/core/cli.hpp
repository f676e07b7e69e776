#pragma once
// One rule for every executable's command line (README "Processes: start-up, exit codes,
// status"): --help prints the help and exits 0, --version prints the build (core/version.hpp)
// and exits 0; any other command-line error (an unknown option, a missing required one, a value
// out of range, a missing input file) prints CLI11's reason on one line after the tool's name
// and exits 2, like a bad configuration. CLI11's own codes (105, 106, 109, ...) would tell a
// script nothing the table does not.
//   if (const auto rc = lasonic::parseCommandLine(app, argc, argv)) return *rc;
#include <CLI/CLI.hpp>

#include "core/version.hpp"

#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

namespace lasonic {

inline constexpr int kExitBadCommandLine = 2;

// A number option that must be finite and within [lo, hi]:
//   app.add_option("--max-time", s, "...")->check(lasonic::FiniteNumberIn(0, 1e6));
// CLI::Range and CLI::NonNegativeNumber let "nan" through (every comparison with NaN is false),
// and an unbounded one lets "inf" or 1e300 through, which a conversion to a clock's integer
// count turns into anything.
inline CLI::Validator FiniteNumberIn(double lo, double hi) {
  std::ostringstream range;
  range << "[" << lo << " - " << hi << "]";
  return CLI::Validator(
      [lo, hi, range = range.str()](std::string& input) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(input, v)) return "value " + input + " is not a number";
        if (!std::isfinite(v)) return "value " + input + " is not a finite number";
        if (v < lo || v > hi) return "value " + input + " not in range " + range;
        return {};
      },
      "FINITE in " + range.str(), "FiniteNumberIn");
}

inline std::optional<int> parseCommandLine(CLI::App& app, int argc, const char* const* argv) {
  app.set_version_flag("--version", std::string(versionString()),
                       "Print the build (version, git revision, build type) and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help or --version: printed
    // One line naming the tool, as every start-up error (a log or a launcher shows it as it is).
    std::string name = argc > 0 && argv[0] ? argv[0] : "lasonic";
    if (const auto slash = name.rfind('/'); slash != std::string::npos) name = name.substr(slash + 1);
    std::cerr << name << ": " << e.what() << " (" << name << " --help lists the options)\n";
    return kExitBadCommandLine;
  }
  return std::nullopt;
}

}  // namespace lasonic
