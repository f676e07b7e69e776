#pragma once
// Physical constants the simulator and the method share (one value, so they cannot drift apart).

namespace lasonic {

constexpr double kSpeedOfSound = 343.0;  // [m/s] in air at 20 °C

// Round trip of an echo from a target at `range` [m], in seconds: how long a transducer listens
// for echoes up to that range.
inline double timeOfFlight(double range) { return 2.0 * range / kSpeedOfSound; }

}  // namespace lasonic
