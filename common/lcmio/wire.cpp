#include "lcmio/wire.hpp"

#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lasonic {

namespace {

// n elements of 2 (4) bytes from src to dst with their bytes reversed (big-endian <-> the
// machine's order; the same operation both ways), eight (four) at a time with SSE2 (part of
// x86-64's baseline), as the generated code moves them one byte at a time.
void swap16(void* dst, const void* src, size_t n) {
  auto* out = static_cast<uint8_t*>(dst);
  const auto* in = static_cast<const uint8_t*>(src);
  size_t i = 0;
#if defined(__SSE2__)
  for (; i + 8 <= n; i += 8) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + 2 * i));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * i), _mm_or_si128(_mm_slli_epi16(x, 8), _mm_srli_epi16(x, 8)));
  }
#endif
  for (; i < n; ++i) {
    out[2 * i] = in[2 * i + 1];
    out[2 * i + 1] = in[2 * i];
  }
}

void swap32(void* dst, const void* src, size_t n) {
  auto* out = static_cast<uint8_t*>(dst);
  const auto* in = static_cast<const uint8_t*>(src);
  size_t i = 0;
#if defined(__SSE2__)
  for (; i + 4 <= n; i += 4) {
    __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + 4 * i));
    x = _mm_shufflehi_epi16(_mm_shufflelo_epi16(x, 0xB1), 0xB1);  // the two halves of each element swapped
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 4 * i), _mm_or_si128(_mm_slli_epi16(x, 8), _mm_srli_epi16(x, 8)));
  }
#endif
  for (; i < n; ++i) {
    uint32_t u;
    std::memcpy(&u, in + 4 * i, 4);
    u = __builtin_bswap32(u);
    std::memcpy(out + 4 * i, &u, 4);
  }
}

// The encoded size of a grid map without cells: its last four bytes are ncells.
int gridMapHeadSize() {
  static const int size = grid_map_t{}.getEncodedSize();
  return size;
}

// A sector map without sectors: its fields up to nsectors, then laser_stale .. sonar_age_s
// (10 bytes), then remembered_stale and remembered_age_s (5 bytes).
int sectorMapEmptySize() {
  static const int size = sector_map_t{}.getEncodedSize();
  return size;
}

int laserScanHeadSize() {
  static const int size = laser_scan_t{}.getEncodedSize();
  return size;
}

}  // namespace

int fastEncode(const grid_map_t& m, void* buf, int maxlen) {
  const int32_t n = m.ncells;
  // What the generated encode would not do the same way here (a short buffer, arrays shorter
  // than ncells): left to it.
  if (n < 0 || m.g.size() < static_cast<size_t>(n) || m.h.size() < static_cast<size_t>(n) ||
      m.gp.size() < static_cast<size_t>(n) || m.heard.size() < static_cast<size_t>(n))
    return m.encode(buf, 0, maxlen);
  // The fields before the arrays by the generated code: the message without its cells, whose
  // encoding ends with ncells (0 there, patched).
  grid_map_t head;
  head.utime = m.utime;
  head.robot_pose = m.robot_pose;
  head.origin_x = m.origin_x;
  head.origin_y = m.origin_y;
  head.cell_size = m.cell_size;
  head.width = m.width;
  head.height = m.height;
  head.gp_threshold = m.gp_threshold;
  head.ncells = 0;
  const int head_size = gridMapHeadSize();
  const int64_t size = int64_t{head_size} + int64_t{n} * 9;
  if (size > maxlen) return m.encode(buf, 0, maxlen);
  if (head.encode(buf, 0, maxlen) != head_size) return m.encode(buf, 0, maxlen);
  auto* out = static_cast<uint8_t*>(buf);
  const uint32_t be_n = __builtin_bswap32(static_cast<uint32_t>(n));
  std::memcpy(out + head_size - 4, &be_n, 4);
  out += head_size;
  swap16(out, m.g.data(), static_cast<size_t>(n));
  swap16(out + 2 * static_cast<size_t>(n), m.h.data(), static_cast<size_t>(n));
  swap32(out + 4 * static_cast<size_t>(n), m.gp.data(), static_cast<size_t>(n));
  if (n > 0) std::memcpy(out + 8 * static_cast<size_t>(n), m.heard.data(), static_cast<size_t>(n));
  return static_cast<int>(size);
}

int fastEncode(const sector_map_t& m, void* buf, int maxlen) {
  const int32_t n = m.nsectors;
  const auto count = static_cast<size_t>(n);
  // What the generated encode would not do the same way here (a short buffer, arrays shorter
  // than nsectors): left to it.
  if (n < 0 || m.distance.size() < count || m.source.size() < count || m.laser_distance.size() < count ||
      m.sonar_distance.size() < count || m.remembered_distance.size() < count)
    return m.encode(buf, 0, maxlen);
  const int empty_size = sectorMapEmptySize();
  const int64_t size = int64_t{empty_size} + int64_t{n} * 17;
  if (size > maxlen) return m.encode(buf, 0, maxlen);
  // The scalar fields by the generated code, from the map without sectors (nsectors 0,
  // patched), then spliced around the arrays.
  sector_map_t head;
  head.utime = m.utime;
  head.robot_pose = m.robot_pose;
  head.robot_radius = m.robot_radius;
  head.max_range = m.max_range;
  head.nsectors = 0;
  head.laser_stale = m.laser_stale;
  head.sonar_stale = m.sonar_stale;
  head.laser_age_s = m.laser_age_s;
  head.sonar_age_s = m.sonar_age_s;
  head.remembered_stale = m.remembered_stale;
  head.remembered_age_s = m.remembered_age_s;
  uint8_t fields[128];
  if (static_cast<size_t>(empty_size) > sizeof fields || head.encode(fields, 0, empty_size) != empty_size)
    return m.encode(buf, 0, maxlen);
  const auto first = static_cast<size_t>(empty_size - 15);  // through nsectors
  auto* out = static_cast<uint8_t*>(buf);
  std::memcpy(out, fields, first);
  const uint32_t be_n = __builtin_bswap32(static_cast<uint32_t>(n));
  std::memcpy(out + first - 4, &be_n, 4);
  out += first;
  swap32(out, m.distance.data(), count);
  out += 4 * count;
  if (count > 0) std::memcpy(out, m.source.data(), count);  // (no sectors: source.data() may be null)
  out += count;
  swap32(out, m.laser_distance.data(), count);
  out += 4 * count;
  swap32(out, m.sonar_distance.data(), count);
  out += 4 * count;
  std::memcpy(out, fields + first, 10);
  out += 10;
  swap32(out, m.remembered_distance.data(), count);
  out += 4 * count;
  std::memcpy(out, fields + first + 10, 5);
  return static_cast<int>(size);
}

namespace {
// The fields before a message's one array count (the last 4 bytes of its head_size-byte head) by
// the generated code (the fingerprint checked there), from a copy whose count reads 0. Returns
// the count, or 0 when the generated decode must do all: no elements, a negative count, fewer
// bytes than n elements of element_bytes, or a head the generated code does not accept.
template <typename Msg>
int32_t decodeHead(Msg& m, const void* buf, int maxlen, int head_size, int element_bytes) {
  if (maxlen < head_size) return 0;
  const auto* in = static_cast<const uint8_t*>(buf);
  uint32_t be_n;
  std::memcpy(&be_n, in + head_size - 4, 4);
  const auto n = static_cast<int32_t>(__builtin_bswap32(be_n));
  if (n <= 0 || int64_t{head_size} + int64_t{n} * element_bytes > int64_t{maxlen}) return 0;
  uint8_t head[128];
  if (static_cast<size_t>(head_size) > sizeof head) return 0;
  std::memcpy(head, in, static_cast<size_t>(head_size));
  std::memset(head + head_size - 4, 0, 4);
  if (m.decode(head, 0, head_size) != head_size) return 0;
  return n;
}

// The generated decode, into emptied arrays: it leaves an array whose count is 0 as it was (the
// previous message's, where Node decodes into the same message each time).
template <typename Msg, typename... Arrays>
int generatedDecodeEmptied(Msg& m, const void* buf, int maxlen, Arrays&... arrays) {
  (arrays.clear(), ...);
  return m.decode(buf, 0, maxlen);
}
}  // namespace

int fastDecode(grid_map_t& m, const void* buf, int maxlen) {
  const int head_size = gridMapHeadSize();
  const int32_t n = decodeHead(m, buf, maxlen, head_size, 9);
  if (n <= 0) return generatedDecodeEmptied(m, buf, maxlen, m.g, m.h, m.gp, m.heard);
  m.ncells = n;
  const auto cells = static_cast<size_t>(n);
  m.g.resize(cells);
  m.h.resize(cells);
  m.gp.resize(cells);
  m.heard.resize(cells);
  const auto* in = static_cast<const uint8_t*>(buf) + head_size;
  swap16(m.g.data(), in, cells);
  swap16(m.h.data(), in + 2 * cells, cells);
  swap32(m.gp.data(), in + 4 * cells, cells);
  std::memcpy(m.heard.data(), in + 8 * cells, cells);
  return head_size + n * 9;
}

int fastDecode(laser_scan_t& m, const void* buf, int maxlen) {
  // As fastDecode(grid_map_t&): the generated encoding ends its head with nranges; the three
  // arrays a whole element at a time.
  const int head_size = laserScanHeadSize();
  const int32_t n = decodeHead(m, buf, maxlen, head_size, 9);
  if (n <= 0) return generatedDecodeEmptied(m, buf, maxlen, m.ranges, m.flags, m.offset_us);
  m.nranges = n;
  const auto count = static_cast<size_t>(n);
  m.ranges.resize(count);
  m.flags.resize(count);
  m.offset_us.resize(count);
  const auto* in = static_cast<const uint8_t*>(buf) + head_size;
  swap32(m.ranges.data(), in, count);
  std::memcpy(m.flags.data(), in + 4 * count, count);
  swap32(m.offset_us.data(), in + 5 * count, count);
  return head_size + n * 9;
}

}  // namespace lasonic
