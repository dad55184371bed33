// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 quantization, four coefficients a step in 32-bit lanes, rounding as the plain
// kernel does: one float multiply, one float add, then truncation (no fused
// multiply-add).
#include <smmintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

// Four levels: trunc(min(|c| inverse_step + rounding, 4095)) with the sign of c.
__m128i quantize_four(__m128 coefficients, const float* inverse_step, __m128 rounding) {
  const __m128 sign_bit = _mm_set1_ps(-0.0f);
  const __m128 magnitude =
      _mm_add_ps(_mm_mul_ps(_mm_andnot_ps(sign_bit, coefficients), _mm_loadu_ps(inverse_step)), rounding);
  // min keeps 4095 for any magnitude at or above it, as the plain kernel's comparison does.
  const __m128i level = _mm_cvttps_epi32(_mm_min_ps(magnitude, _mm_set1_ps(4095.0f)));
  const __m128i negative = _mm_castps_si128(_mm_cmplt_ps(coefficients, _mm_setzero_ps()));
  return _mm_sub_epi32(_mm_xor_si128(level, negative), negative);
}

int quantize_8x8_sse41(const float* coefficients, const float* inverse_step, float rounding_dc, float rounding_ac,
                       int16_t* levels) {
  const __m128 rounding_ac4 = _mm_set1_ps(rounding_ac);
  __m128i zeros = _mm_setzero_si128();  // per 16-bit lane
  for (int i = 0; i < 64; i += 8) {
    const __m128 first_rounding = i == 0 ? _mm_setr_ps(rounding_dc, rounding_ac, rounding_ac, rounding_ac)
                                         : rounding_ac4;
    const __m128i low = quantize_four(_mm_loadu_ps(coefficients + i), inverse_step + i, first_rounding);
    const __m128i high = quantize_four(_mm_loadu_ps(coefficients + i + 4), inverse_step + i + 4, rounding_ac4);
    const __m128i packed = _mm_packs_epi32(low, high);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(levels + i), packed);
    zeros = _mm_sub_epi16(zeros, _mm_cmpeq_epi16(packed, _mm_setzero_si128()));  // a zero level adds 1
  }
  const __m128i pairs = _mm_madd_epi16(zeros, _mm_set1_epi16(1));
  const __m128i quads = _mm_add_epi32(pairs, _mm_shuffle_epi32(pairs, 0x4E));
  return 64 - _mm_cvtsi128_si32(_mm_add_epi32(quads, _mm_shuffle_epi32(quads, 0xB1)));
}

}  // namespace

void init_quantize_sse41(EncoderDspTable* table) { table->quantize_8x8 = quantize_8x8_sse41; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
