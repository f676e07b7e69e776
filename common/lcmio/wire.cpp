#include "lcmio/wire.hpp"

#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lasonic {

namespace {

// Eight (four) elements at a time with SSE2 (part of x86-64's baseline): the bytes of each
// element swapped, as the generated code writes them one by one.
void putBe16(uint8_t* out, const int16_t* v, size_t n) {
  size_t i = 0;
#if defined(__SSE2__)
  for (; i + 8 <= n; i += 8) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v + i));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * i), _mm_or_si128(_mm_slli_epi16(x, 8), _mm_srli_epi16(x, 8)));
  }
#endif
  for (; i < n; ++i) {
    const auto u = static_cast<uint16_t>(v[i]);
    out[2 * i] = static_cast<uint8_t>(u >> 8);
    out[2 * i + 1] = static_cast<uint8_t>(u);
  }
}

void putBe32(uint8_t* out, const int32_t* v, size_t n) {
  size_t i = 0;
#if defined(__SSE2__)
  for (; i + 4 <= n; i += 4) {
    __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v + i));
    x = _mm_shufflehi_epi16(_mm_shufflelo_epi16(x, 0xB1), 0xB1);  // the two halves of each element swapped
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 4 * i), _mm_or_si128(_mm_slli_epi16(x, 8), _mm_srli_epi16(x, 8)));
  }
#endif
  for (; i < n; ++i) {
    const uint32_t u = __builtin_bswap32(static_cast<uint32_t>(v[i]));
    std::memcpy(out + 4 * i, &u, 4);
  }
}

}  // namespace

int fastEncode(const grid_map_t& m, void* buf, int maxlen) {
  const int32_t n = m.ncells;
  // What the generated encode would not do the same way here (a short buffer, arrays shorter
  // than ncells): left to it.
  if (n < 0 || m.g.size() < static_cast<size_t>(n) || m.h.size() < static_cast<size_t>(n) ||
      m.gp.size() < static_cast<size_t>(n))
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
  const int head_size = head.getEncodedSize();
  const int64_t size = int64_t{head_size} + int64_t{n} * 8;
  if (size > maxlen) return m.encode(buf, 0, maxlen);
  if (head.encode(buf, 0, maxlen) != head_size) return m.encode(buf, 0, maxlen);
  auto* out = static_cast<uint8_t*>(buf);
  const uint32_t be_n = __builtin_bswap32(static_cast<uint32_t>(n));
  std::memcpy(out + head_size - 4, &be_n, 4);
  out += head_size;
  putBe16(out, m.g.data(), static_cast<size_t>(n));
  putBe16(out + 2 * static_cast<size_t>(n), m.h.data(), static_cast<size_t>(n));
  putBe32(out + 4 * static_cast<size_t>(n), m.gp.data(), static_cast<size_t>(n));
  return static_cast<int>(size);
}

}  // namespace lasonic
