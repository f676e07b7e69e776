#pragma once
// Durations in the messages' clock: every timestamp is an int64 count of microseconds, and every
// configured duration or rate is converted to one here, rounded to the nearest microsecond. A
// truncating cast would make a computed duration (2.5 periods of a 15 Hz scanner, 1/15 s) up to
// 1 µs short of itself, so an event exactly that old would fall outside its own window.

#include <cmath>
#include <cstdint>

namespace lasonic {

// `s` seconds in microseconds, rounded to the nearest. Callers pass a validated (finite,
// bounded) duration; the configuration's ranges keep it far below int64's limit.
inline int64_t secondsToUs(double s) { return static_cast<int64_t>(std::llround(s * 1e6)); }

// One period of a rate `hz` > 0 in microseconds, rounded to the nearest.
inline int64_t periodUs(double hz) { return static_cast<int64_t>(std::llround(1e6 / hz)); }

}  // namespace lasonic
