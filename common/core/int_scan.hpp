#pragma once
// forEachAtLeast(v, len, threshold, f): f(k) for every k in [0, len) with v[k] >= threshold, in
// ascending order. Grids are mostly empty, so groups of four below the threshold are passed over
// with one SSE2 comparison (part of x86-64's baseline); the calls are exactly those of the plain
// loop. threshold must be above INT32_MIN.
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lasonic {

template <typename F>
void forEachAtLeast(const int32_t* v, size_t len, int32_t threshold, F&& f) {
  size_t k = 0;
#if defined(__SSE2__)
  const __m128i below = _mm_set1_epi32(threshold - 1);
  for (; k + 4 <= len; k += 4) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(v + k));
    if (_mm_movemask_epi8(_mm_cmpgt_epi32(x, below)) == 0) continue;
    for (size_t j = k; j < k + 4; ++j)
      if (v[j] >= threshold) f(j);
  }
#endif
  for (; k < len; ++k)
    if (v[k] >= threshold) f(k);
}

}  // namespace lasonic
