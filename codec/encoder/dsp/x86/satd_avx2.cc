// SPDX-License-Identifier: BSD-2-Clause
// AVX2 16x16 Hadamard SATD: the two 8x8 quadrants of eight rows side by side, one per
// 128-bit lane (every AVX2 unpack works within lanes, so the SSE transpose carries over).
// Values stay within 16 bits as in the SSE4.1 8x8 (satd_sse41.cc).
#include <immintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"

SVC_TARGET_BEGIN("avx2")

namespace svc::codec::dsp {
namespace {

void butterflies(__m256i* v) {
  for (int span = 1; span < 8; span *= 2) {
    for (int i = 0; i < 8; i += 2 * span) {
      for (int j = i; j < i + span; ++j) {
        const __m256i a = v[j], b = v[j + span];
        v[j] = _mm256_add_epi16(a, b);
        v[j + span] = _mm256_sub_epi16(a, b);
      }
    }
  }
}

void transpose_lanes_8x8_epi16(__m256i* v) {
  __m256i a[8], b[8];
  for (int i = 0; i < 4; ++i) {
    a[2 * i] = _mm256_unpacklo_epi16(v[2 * i], v[2 * i + 1]);
    a[2 * i + 1] = _mm256_unpackhi_epi16(v[2 * i], v[2 * i + 1]);
  }
  for (int i = 0; i < 2; ++i) {
    for (int h = 0; h < 2; ++h) {
      b[4 * i + 2 * h] = _mm256_unpacklo_epi32(a[4 * i + h], a[4 * i + 2 + h]);
      b[4 * i + 2 * h + 1] = _mm256_unpackhi_epi32(a[4 * i + h], a[4 * i + 2 + h]);
    }
  }
  for (int i = 0; i < 4; ++i) {
    v[2 * i] = _mm256_unpacklo_epi64(b[i], b[4 + i]);
    v[2 * i + 1] = _mm256_unpackhi_epi64(b[i], b[4 + i]);
  }
}

int satd_16x16_avx2(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  const __m256i ones = _mm256_set1_epi16(1);
  __m256i sum = _mm256_setzero_si256();
  for (int half = 0; half < 2; ++half) {
    __m256i v[8];
    for (int y = 0; y < 8; ++y) {
      const int row = 8 * half + y;
      const __m256i s =
          _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(source + row * source_stride)));
      const __m256i p =
          _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(prediction + 16 * row)));
      v[y] = _mm256_sub_epi16(s, p);
    }
    butterflies(v);
    transpose_lanes_8x8_epi16(v);
    butterflies(v);
    for (int y = 0; y < 8; ++y) sum = _mm256_add_epi32(sum, _mm256_madd_epi16(_mm256_abs_epi16(v[y]), ones));
  }
  __m128i total = _mm_add_epi32(_mm256_castsi256_si128(sum), _mm256_extracti128_si256(sum, 1));
  total = _mm_add_epi32(total, _mm_shuffle_epi32(total, _MM_SHUFFLE(1, 0, 3, 2)));
  total = _mm_add_epi32(total, _mm_shuffle_epi32(total, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtsi128_si32(total);
}

}  // namespace

void init_satd_avx2(EncoderDspTable* table) { table->satd_16x16 = satd_16x16_avx2; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
