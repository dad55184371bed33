// SPDX-License-Identifier: BSD-2-Clause
// The add half of the SSE2 and SSE4.1 inverse_transform_add kernels: dst =
// clip(prediction + residual, 0, 255) over a W x H block (W = 4, 8 or 16), the
// saturating 16-bit add and the unsigned pack doing the clip (inverse_add.h's
// add_clipped_c bit for bit). Internal linkage, as every file built for its own
// instruction set instantiates its own copy.
#pragma once

#include <emmintrin.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace svc::codec::dsp {
namespace {

template <int W, int H>
inline void add_clipped_sse2(const int16_t* residual, const uint8_t* prediction, ptrdiff_t prediction_stride,
                             uint8_t* dst, ptrdiff_t dst_stride) {
  static_assert(W == 4 || W == 8 || W == 16);
  const __m128i zero = _mm_setzero_si128();
  for (int y = 0; y < H; ++y) {
    const int16_t* r = residual + W * y;
    const uint8_t* p = prediction + y * prediction_stride;
    uint8_t* d = dst + y * dst_stride;
    if constexpr (W == 16) {
      const __m128i pred = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
      const __m128i low =
          _mm_adds_epi16(_mm_unpacklo_epi8(pred, zero), _mm_loadu_si128(reinterpret_cast<const __m128i*>(r)));
      const __m128i high =
          _mm_adds_epi16(_mm_unpackhi_epi8(pred, zero), _mm_loadu_si128(reinterpret_cast<const __m128i*>(r + 8)));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(d), _mm_packus_epi16(low, high));
    } else if constexpr (W == 8) {
      const __m128i pred = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
      const __m128i sum =
          _mm_adds_epi16(_mm_unpacklo_epi8(pred, zero), _mm_loadu_si128(reinterpret_cast<const __m128i*>(r)));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(d), _mm_packus_epi16(sum, sum));
    } else {
      int32_t word;
      std::memcpy(&word, p, 4);
      const __m128i sum = _mm_adds_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(word), zero),
                                         _mm_loadl_epi64(reinterpret_cast<const __m128i*>(r)));
      word = _mm_cvtsi128_si32(_mm_packus_epi16(sum, sum));
      std::memcpy(d, &word, 4);
    }
  }
}

}  // namespace
}  // namespace svc::codec::dsp
