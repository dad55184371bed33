// SPDX-License-Identifier: BSD-2-Clause
// SSE2 motion-compensation kernels: the rounding of 14-bit intermediates to samples
// (single and bidirectional), each equal to its plain kernel in mc.cc bit for bit.
#include <emmintrin.h>

#include <cstring>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse2")

namespace svc::codec::dsp {
namespace {

inline __m128i load_int16x8(const int16_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }

// (in + 8192 + 32) >> 6 is ((in + 32) >> 6) + 128 (8192 = 128 * 64), which cannot
// overflow int16; packus clips to 0..255.
inline __m128i put8(__m128i in) {
  return _mm_add_epi16(_mm_srai_epi16(_mm_add_epi16(in, _mm_set1_epi16(32)), 6), _mm_set1_epi16(128));
}

void put_intermediate_sse2(const int16_t* in, int count, uint8_t* out) {
  int i = 0;
  for (; i + 16 <= count; i += 16) {
    const __m128i packed = _mm_packus_epi16(put8(load_int16x8(in + i)), put8(load_int16x8(in + i + 8)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), packed);
  }
  for (; i + 8 <= count; i += 8) {  // rows of 8-sample blocks
    const __m128i row = put8(load_int16x8(in + i));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(row, row));
  }
  for (; i + 4 <= count; i += 4) {  // rows of the warped mode's 4x4 chroma blocks
    const __m128i row = put8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(in + i)));
    const int32_t bytes = _mm_cvtsi128_si32(_mm_packus_epi16(row, row));
    std::memcpy(out + i, &bytes, 4);
  }
  if (i < count) put_intermediate_c(in + i, count - i, out + i);
}

// Four 32-bit sums a + b + 64 of interleaved pairs (pmaddwd with ones), shifted by 7.
inline __m128i average4(__m128i pairs) {
  const __m128i sums = _mm_add_epi32(_mm_madd_epi16(pairs, _mm_set1_epi16(1)), _mm_set1_epi32(64));
  return _mm_srai_epi32(sums, 7);
}

// (a + b + 16384 + 64) >> 7 = ((a + b + 64) >> 7) + 128, in 32 bits.
inline __m128i average8(__m128i a, __m128i b) {
  const __m128i low = average4(_mm_unpacklo_epi16(a, b)), high = average4(_mm_unpackhi_epi16(a, b));
  return _mm_add_epi16(_mm_packs_epi32(low, high), _mm_set1_epi16(128));
}

void average_intermediate_sse2(const int16_t* a, const int16_t* b, int count, uint8_t* out) {
  int i = 0;
  for (; i + 16 <= count; i += 16) {
    const __m128i low = average8(load_int16x8(a + i), load_int16x8(b + i));
    const __m128i high = average8(load_int16x8(a + i + 8), load_int16x8(b + i + 8));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(low, high));
  }
  for (; i + 8 <= count; i += 8) {
    const __m128i row = average8(load_int16x8(a + i), load_int16x8(b + i));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(row, row));
  }
  if (i < count) average_intermediate_c(a + i, b + i, count - i, out + i);
}

}  // namespace

void init_mc_sse2(DspTable* table) {
  table->put_intermediate = put_intermediate_sse2;
  table->average_intermediate = average_intermediate_sse2;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
