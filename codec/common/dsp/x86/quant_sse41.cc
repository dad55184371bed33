// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 dequantization, four coefficients a step in 32-bit lanes: |level| is capped at
// 4096 and scale is at most 2^18, so the product and the rounding fit 31 bits, as in the
// plain kernel (the encoder's quantization is codec/encoder/dsp/x86/quantize_sse41.cc).
#include <smmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

// Four coefficients from four sign-extended levels.
__m128i dequantize_four(__m128i level, const int32_t* scale) {
  const __m128i magnitude = _mm_min_epi32(_mm_abs_epi32(level), _mm_set1_epi32(4096));
  const __m128i product = _mm_mullo_epi32(magnitude, _mm_loadu_si128(reinterpret_cast<const __m128i*>(scale)));
  const __m128i value = _mm_srai_epi32(_mm_add_epi32(product, _mm_set1_epi32(128)), 8);
  // Saturation: 2047 for positive levels, 2048 (before the sign) for negative ones.
  const __m128i limit = _mm_sub_epi32(_mm_set1_epi32(2047), _mm_srai_epi32(level, 31));
  return _mm_sign_epi32(_mm_min_epi32(value, limit), level);
}

void dequantize_8x8_sse41(const int16_t* levels, const int32_t* scale, int16_t* coefficients) {
  for (int i = 0; i < 64; i += 8) {
    const __m128i packed = _mm_loadu_si128(reinterpret_cast<const __m128i*>(levels + i));
    const __m128i low = dequantize_four(_mm_cvtepi16_epi32(packed), scale + i);
    const __m128i high = dequantize_four(_mm_cvtepi16_epi32(_mm_srli_si128(packed, 8)), scale + i + 4);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(coefficients + i), _mm_packs_epi32(low, high));
  }
}

}  // namespace

void init_quant_sse41(DspTable* table) { table->dequantize_8x8 = dequantize_8x8_sse41; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
