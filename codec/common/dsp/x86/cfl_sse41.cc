// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 chroma-from-luma kernels. Every value fits 16 bits: a 2x2 luma sum is at most
// 1020, its deviation from the mean within +-1020, and alpha * ac + 16 within +-16336,
// so 16-bit lanes compute the plain kernels' integers exactly.
#include <smmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

// The eight 2x2 sums of one chroma row from two 16-sample luma rows.
__m128i pair_sums(const uint8_t* top, const uint8_t* bottom) {
  const __m128i ones = _mm_set1_epi8(1);
  const __m128i t = _mm_maddubs_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(top)), ones);
  const __m128i b = _mm_maddubs_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bottom)), ones);
  return _mm_add_epi16(t, b);
}

void cfl_luma_ac_8x8_sse41(const uint8_t* luma, ptrdiff_t stride, int16_t* ac) {
  __m128i rows[8];
  __m128i total = _mm_setzero_si128();
  for (int y = 0; y < 8; ++y) {
    const uint8_t* top = luma + 2 * y * stride;
    rows[y] = pair_sums(top, top + stride);
    total = _mm_add_epi32(total, _mm_madd_epi16(rows[y], _mm_set1_epi16(1)));
  }
  total = _mm_add_epi32(total, _mm_shuffle_epi32(total, _MM_SHUFFLE(1, 0, 3, 2)));
  total = _mm_add_epi32(total, _mm_shuffle_epi32(total, _MM_SHUFFLE(2, 3, 0, 1)));
  const __m128i mean = _mm_set1_epi16(static_cast<int16_t>((_mm_cvtsi128_si32(total) + 32) >> 6));
  for (int y = 0; y < 8; ++y) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(ac + 8 * y), _mm_sub_epi16(rows[y], mean));
  }
}

void cfl_predict_8x8_sse41(const int16_t* ac, int dc, int alpha, uint8_t* out) {
  const __m128i scale = _mm_set1_epi16(static_cast<int16_t>(alpha));
  const __m128i rounding = _mm_set1_epi16(16);
  const __m128i base = _mm_set1_epi16(static_cast<int16_t>(dc));
  for (int y = 0; y < 8; y += 2) {
    __m128i v[2];
    for (int r = 0; r < 2; ++r) {
      const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ac + 8 * (y + r)));
      v[r] = _mm_add_epi16(base, _mm_srai_epi16(_mm_add_epi16(_mm_mullo_epi16(a, scale), rounding), 5));
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 8 * y), _mm_packus_epi16(v[0], v[1]));
  }
}

}  // namespace

void init_cfl_sse41(DspTable* table) {
  table->cfl_luma_ac_8x8 = cfl_luma_ac_8x8_sse41;
  table->cfl_predict_8x8 = cfl_predict_8x8_sse41;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
