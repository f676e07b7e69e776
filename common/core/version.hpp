#pragma once
// Which build this is (README "Processes: start-up, exit codes, status"): every executable's
// --version prints it, so that the builds on the computers of one robot can be compared before
// their processes talk (an LCM type changed on one side only is a decode error on the other).
namespace lasonic {

// "lasonic 0.1.0 (git 01cc602a1b2c, Release)": the project's version, the source tree's git
// revision when it was built ("-dirty" with uncommitted changes; "unknown" outside a git
// checkout) and the CMake build type. Generated at every build by common/core/version.cmake.
const char* versionString();

}  // namespace lasonic
