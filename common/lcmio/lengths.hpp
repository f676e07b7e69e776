#pragma once
// LCM 1.3.1 does not check array length fields on encode: a wrong count silently writes
// garbage. Every message with arrays is finalised here, in one place, from the vectors' sizes,
// and parallel arrays are checked to agree (a programming error -> std::logic_error).
// Node::publish and LogWriter::write call setLengths() for every message.
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include <lasonic/complement_t.hpp>
#include <lasonic/grid_map_t.hpp>
#include <lasonic/hypothetical_scan_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/laser_truth_t.hpp>
#include <lasonic/line_map_t.hpp>
#include <lasonic/process_status_t.hpp>
#include <lasonic/sector_map_t.hpp>
#include <lasonic/sim_state_t.hpp>
#include <lasonic/sonar_geometry_t.hpp>
#include <lasonic/sonar_ring_t.hpp>
#include <lasonic/sonar_truth_t.hpp>

namespace lasonic {

void setLengths(laser_scan_t& m);
void setLengths(sonar_ring_t& m);
void setLengths(sonar_geometry_t& m);
void setLengths(line_map_t& m);
void setLengths(hypothetical_scan_t& m);
void setLengths(complement_t& m);
void setLengths(grid_map_t& m);
void setLengths(sector_map_t& m);
void setLengths(process_status_t& m);
void setLengths(sim_state_t& m);
void setLengths(sonar_truth_t& m);
void setLengths(laser_truth_t& m);
// Types without arrays.
template <typename T> void setLengths(T&) {}

// ---- Incoming arrays: caps and a check before decoding.
//
// LCM 1.3.1's generated decode() resizes each array to the count a message claims *before* it
// checks that the bytes are there: a 30-byte message claiming 2^31 laser readings makes the
// receiver allocate and zero 8 GB, or throw std::bad_alloc out of LCM's C callback (abort). So
// every input type with arrays has a cap on its element count (one limit per quantity, here),
// and checkWireArrays() reads the count from the raw bytes and compares it with the cap and with
// the bytes present before anything is decoded. Each cap is far above any real sensor and far
// below what would hurt a process.
namespace limits {
inline constexpr int64_t kLaserReadings = 100'000;   // a 0.01 deg 360 deg scanner has 36 000
inline constexpr int64_t kSonarReadings = 1'024;     // per firing group; real rings: 8 .. 48 sensors
inline constexpr int64_t kComplementReadings = kSonarReadings;  // one per sonar reading
inline constexpr int64_t kMovers = 10'000;           // moving obstacles in a simulated world
inline constexpr int64_t kLineSegments = 100'000;    // a Radar Map has at most readings/2 segments
inline constexpr int64_t kGridCells = 4'000'000;     // a grid map window: 2000 x 2000 cells (100 m at 5 cm)
}  // namespace limits

// WireArrays<T>: for a type whose arrays all share one count field, the last fixed-size field
// before them, and nothing after the arrays: its cap and how to give it one element per array
// (to measure the layout; a unit test checks the count sits where it is measured to).
template <typename T> struct WireArrays;
template <> struct WireArrays<laser_scan_t> {
  static constexpr int64_t kMax = limits::kLaserReadings;
  static void one(laser_scan_t& m) { m.ranges = {0}; m.flags = {0}; m.offset_us = {0}; }
};
template <> struct WireArrays<sonar_ring_t> {
  static constexpr int64_t kMax = limits::kSonarReadings;
  static void one(sonar_ring_t& m) { m.sensor_id = {0}; m.range = {0}; m.no_echo = {0}; m.mount.resize(1); m.beam_width = {0}; }
};
template <> struct WireArrays<complement_t> {
  static constexpr int64_t kMax = limits::kComplementReadings;
  static void one(complement_t& m) { m.readings.resize(1); }
};
template <> struct WireArrays<sim_state_t> {
  static constexpr int64_t kMax = limits::kMovers;
  static void one(sim_state_t& m) { m.movers.resize(1); }
};
template <> struct WireArrays<line_map_t> {
  static constexpr int64_t kMax = limits::kLineSegments;
  static void one(line_map_t& m) { m.segments.resize(1); }
};
template <> struct WireArrays<grid_map_t> {
  static constexpr int64_t kMax = limits::kGridCells;
  static void one(grid_map_t& m) { m.width = m.height = 1; m.g = {0}; m.h = {0}; m.gp = {0}; m.heard = {0}; }
};

template <typename T, typename = void> struct HasWireArrays : std::false_type {};
template <typename T> struct HasWireArrays<T, std::void_t<decltype(WireArrays<T>::kMax)>> : std::true_type {};

struct WireShape {
  int64_t count_offset = 0;  // bytes from the start of the message (fingerprint included)
  int64_t fixed = 0;         // bytes of a message with no elements
  int64_t per_element = 0;   // bytes one element adds (one entry in every array)
};
struct WireCheck {
  enum Result { Ok, NotThisType, Truncated, TooMany } result = Ok;
  int64_t claimed = 0;  // the count the message claims
};

namespace detail {
WireCheck checkWire(const void* data, size_t size, int64_t hash, const WireShape& shape, int64_t cap);
}

// The layout of T's encoding, measured once from the generated code.
template <typename T>
const WireShape& wireShape() {
  static const WireShape shape = [] {
    T none{}, one{};
    WireArrays<T>::one(one);
    setLengths(none);
    setLengths(one);
    WireShape s;
    s.fixed = none.getEncodedSize();
    s.count_offset = s.fixed - 4;
    s.per_element = one.getEncodedSize() - s.fixed;
    return s;
  }();
  return shape;
}

// NotThisType: the fingerprint is not T's (decode() refuses it without allocating);
// Truncated: a negative count, or fewer bytes than the count needs; TooMany: over the cap.
template <typename T>
WireCheck checkWireArrays(const void* data, size_t size) {
  return detail::checkWire(data, size, T::getHash(), wireShape<T>(), WireArrays<T>::kMax);
}

}  // namespace lasonic
