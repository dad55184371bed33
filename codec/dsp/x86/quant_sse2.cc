// SSE2 quantizer: the plain kernel's float operations (|c| * inverse_step + rounding,
// then truncation) four lanes at a time, in the same order and without fused
// multiply-add, so every level equals the plain kernel's.
#include <emmintrin.h>

#include "codec/dsp/dsp_init.h"

#pragma GCC target("sse2")

namespace svc::codec::dsp {
namespace {

int quantize_8x8_sse2(const float* coefficients, const float* inverse_step, float rounding_dc, float rounding_ac,
                      int16_t* levels) {
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 max_level = _mm_set1_ps(4095.0f);
  const __m128i max_level_int = _mm_set1_epi32(4095);
  const __m128 zero = _mm_setzero_ps();
  int nonzero = 0;
  for (int i = 0; i < 64; i += 8) {
    __m128i halves[2];
    for (int h = 0; h < 2; ++h) {
      const __m128 c = _mm_loadu_ps(coefficients + i + 4 * h);
      const __m128 rounding = i + h == 0 ? _mm_setr_ps(rounding_dc, rounding_ac, rounding_ac, rounding_ac)
                                         : _mm_set1_ps(rounding_ac);
      const __m128 magnitude =
          _mm_add_ps(_mm_mul_ps(_mm_and_ps(c, abs_mask), _mm_loadu_ps(inverse_step + i + 4 * h)), rounding);
      const __m128i saturated = _mm_castps_si128(_mm_cmpge_ps(magnitude, max_level));
      __m128i level = _mm_or_si128(_mm_and_si128(saturated, max_level_int),
                                   _mm_andnot_si128(saturated, _mm_cvttps_epi32(magnitude)));
      const __m128i negative = _mm_castps_si128(_mm_cmplt_ps(c, zero));
      level = _mm_sub_epi32(_mm_xor_si128(level, negative), negative);  // conditional negate
      halves[h] = level;
    }
    const __m128i packed = _mm_packs_epi32(halves[0], halves[1]);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(levels + i), packed);
    const int zero_mask = _mm_movemask_epi8(_mm_cmpeq_epi16(packed, _mm_setzero_si128()));
    nonzero += 8 - __builtin_popcount(static_cast<unsigned>(zero_mask)) / 2;
  }
  return nonzero;
}

}  // namespace

void init_quant_sse2(DspTable* table) { table->quantize_8x8 = quantize_8x8_sse2; }

}  // namespace svc::codec::dsp
