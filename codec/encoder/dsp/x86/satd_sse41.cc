// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 Hadamard SATDs of the encoder's first-stage estimates (16x16: four 8x8). The 8x8 transform
// keeps every value in 16 bits (residuals of at most 255 grow by 8 per 1-D pass:
// |value| <= 16320), so it equals the plain sum; the 4x4 transforms two rows per
// register.
#include <smmintrin.h>

#include <cstring>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"

SVC_TARGET_BEGIN("sse4.1")

#include "codec/common/dsp/x86/transpose_sse2.h"

namespace svc::codec::dsp {
namespace {

void butterflies(__m128i* v) {
  for (int span = 1; span < 8; span *= 2) {
    for (int i = 0; i < 8; i += 2 * span) {
      for (int j = i; j < i + span; ++j) {
        const __m128i a = v[j], b = v[j + span];
        v[j] = _mm_add_epi16(a, b);
        v[j + span] = _mm_sub_epi16(a, b);
      }
    }
  }
}

int satd_8x8_strided(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction,
                     ptrdiff_t prediction_stride) {
  __m128i v[8];
  for (int y = 0; y < 8; ++y) {
    const __m128i s =
        _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(source + y * source_stride)));
    const __m128i p =
        _mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(prediction + prediction_stride * y)));
    v[y] = _mm_sub_epi16(s, p);
  }
  butterflies(v);
  transpose_8x8_epi16(v);
  butterflies(v);
  __m128i sum = _mm_setzero_si128();
  const __m128i ones = _mm_set1_epi16(1);
  for (int y = 0; y < 8; ++y) sum = _mm_add_epi32(sum, _mm_madd_epi16(_mm_abs_epi16(v[y]), ones));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(1, 0, 3, 2)));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtsi128_si32(sum);
}

int satd_8x8_sse41(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  return satd_8x8_strided(source, source_stride, prediction, 8);
}

int satd_16x16_sse41(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int q = 0; q < 4; ++q) {
    const int x = 8 * (q & 1), y = 8 * (q >> 1);
    sum += satd_8x8_strided(source + y * source_stride + x, source_stride, prediction + 16 * y + x, 16);
  }
  return sum;
}

// 4x4 Hadamard on two rows per register. The SATD sums the magnitudes of all sixteen
// coefficients, so the butterflies may produce them in any order.
inline void hadamard_pairs(__m128i* a, __m128i* b) {
  const __m128i sum = _mm_add_epi16(*a, *b), difference = _mm_sub_epi16(*a, *b);
  const __m128i low = _mm_unpacklo_epi64(sum, difference), high = _mm_unpackhi_epi64(sum, difference);
  *a = _mm_add_epi16(low, high);
  *b = _mm_sub_epi16(low, high);
}

int satd_4x4_sse41(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  auto row_pair = [&](int y) {
    int s0, s1, p0, p1;
    std::memcpy(&s0, source + y * source_stride, 4);
    std::memcpy(&s1, source + (y + 1) * source_stride, 4);
    std::memcpy(&p0, prediction + 4 * y, 4);
    std::memcpy(&p1, prediction + 4 * y + 4, 4);
    const __m128i s = _mm_cvtepu8_epi16(_mm_unpacklo_epi32(_mm_cvtsi32_si128(s0), _mm_cvtsi32_si128(s1)));
    const __m128i p = _mm_cvtepu8_epi16(_mm_unpacklo_epi32(_mm_cvtsi32_si128(p0), _mm_cvtsi32_si128(p1)));
    return _mm_sub_epi16(s, p);
  };
  __m128i a = row_pair(0), b = row_pair(2);  // rows 0 | 1 and 2 | 3
  hadamard_pairs(&a, &b);                    // four transformed rows, two per register
  const __m128i x = _mm_unpacklo_epi16(a, _mm_srli_si128(a, 8)), y = _mm_unpacklo_epi16(b, _mm_srli_si128(b, 8));
  __m128i c = _mm_unpacklo_epi32(x, y), d = _mm_unpackhi_epi32(x, y);  // columns 0 | 1 and 2 | 3
  hadamard_pairs(&c, &d);
  const __m128i ones = _mm_set1_epi16(1);
  __m128i sum = _mm_add_epi32(_mm_madd_epi16(_mm_abs_epi16(c), ones), _mm_madd_epi16(_mm_abs_epi16(d), ones));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(1, 0, 3, 2)));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtsi128_si32(sum);
}

}  // namespace

void init_satd_sse41(EncoderDspTable* table) {
  table->satd_4x4 = satd_4x4_sse41;
  table->satd_8x8 = satd_8x8_sse41;
  table->satd_16x16 = satd_16x16_sse41;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
