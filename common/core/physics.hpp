#pragma once
// Physical constants the simulator and the method share (one value, so they cannot drift apart).

namespace lasonic {

constexpr double kSpeedOfSound = 343.0;  // [m/s] in air at 20 °C

}  // namespace lasonic
