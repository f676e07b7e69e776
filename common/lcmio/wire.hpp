#pragma once
// Exact fast encoding and decoding of the large messages (and decoding of LASER_SCAN, encoding
// of SECTOR_MAP). LCM's generated encode writes every element of an
// int16/int32 array byte by byte, big-endian; for a grid map (three arrays of 10,000 cells, at
// 2 Hz from two processes) that was the biggest single cost of lasonic-replay. wireEncode gives
// the very bytes of T::encode (the generated types are unchanged; tests/unit/test_lcmio.cpp
// compares the two), writing the arrays a whole element at a time; wireDecode is T::decode
// (the same message, the same return value) reading them so.
#include <cstdint>
#include <type_traits>

#include <lasonic/grid_map_t.hpp>
#include <lasonic/laser_scan_t.hpp>
#include <lasonic/sector_map_t.hpp>

namespace lasonic {

template <typename T>
struct HasFastEncode : std::false_type {};
template <>
struct HasFastEncode<grid_map_t> : std::true_type {};
template <>
struct HasFastEncode<sector_map_t> : std::true_type {};  // (one per firing group and scan)
template <typename T>
struct HasFastDecode : std::false_type {};
template <>
struct HasFastDecode<grid_map_t> : std::true_type {};
template <>
struct HasFastDecode<laser_scan_t> : std::true_type {};  // (720 readings, two stages per scan)

// The bytes of m.encode(buf, 0, maxlen) and its return value (m's lengths already set).
int fastEncode(const grid_map_t& m, void* buf, int maxlen);
int fastEncode(const sector_map_t& m, void* buf, int maxlen);
// m.decode(buf, 0, maxlen): its return value and, where it succeeds, its message.
int fastDecode(grid_map_t& m, const void* buf, int maxlen);
int fastDecode(laser_scan_t& m, const void* buf, int maxlen);

template <typename T>
int wireEncode(const T& m, void* buf, int maxlen) {
  if constexpr (HasFastEncode<T>::value)
    return fastEncode(m, buf, maxlen);
  else
    return m.encode(buf, 0, maxlen);
}

template <typename T>
int wireDecode(T& m, const void* buf, int maxlen) {
  if constexpr (HasFastDecode<T>::value)
    return fastDecode(m, buf, maxlen);
  else
    return m.decode(buf, 0, maxlen);
}

}  // namespace lasonic
