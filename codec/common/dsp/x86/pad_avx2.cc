// SPDX-License-Identifier: BSD-2-Clause
// AVX2 bilinear sampling of cube padding's border: eight samples per step, their 2 x 2
// blocks fetched with two gathers. A 4-byte gather at the block's top-left sample holds
// the top pair in its low half; one 2 bytes before the bottom-left sample holds the
// bottom pair in its high half, so neither reads outside the block's two rows. pmaddubsw
// applies the column weights (each row sum at most 16 x 255), pmaddwd the row weights,
// which is the plain kernel's arithmetic exactly.
#include <immintrin.h>

#include <cstring>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("avx2")

namespace svc::codec::dsp {
namespace {

// The blocks at `offsets` as dwords (p00, p01, p10, p11); lanes outside `lanes` are
// neither read nor set.
__m256i gather_blocks(const uint8_t* plane, ptrdiff_t stride, __m256i offsets, __m256i lanes) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i top = _mm256_mask_i32gather_epi32(zero, reinterpret_cast<const int*>(plane), offsets, lanes, 1);
  const __m256i bottom =
      _mm256_mask_i32gather_epi32(zero, reinterpret_cast<const int*>(plane + stride - 2), offsets, lanes, 1);
  return _mm256_blend_epi16(top, bottom, 0xAA);
}

// The eight samples, 0..255 in 32-bit lanes.
__m256i filter_blocks(__m256i blocks, __m256i w) {
  const __m256i column_pairs = _mm256_setr_epi8(0, 1, 0, 1, 4, 5, 4, 5, 8, 9, 8, 9, 12, 13, 12, 13, 0, 1, 0, 1, 4,
                                                5, 4, 5, 8, 9, 8, 9, 12, 13, 12, 13);
  const __m256i row_words = _mm256_setr_epi8(2, -1, 3, -1, 6, -1, 7, -1, 10, -1, 11, -1, 14, -1, 15, -1, 2, -1, 3,
                                             -1, 6, -1, 7, -1, 10, -1, 11, -1, 14, -1, 15, -1);
  const __m256i rows = _mm256_maddubs_epi16(blocks, _mm256_shuffle_epi8(w, column_pairs));
  const __m256i sums = _mm256_madd_epi16(rows, _mm256_shuffle_epi8(w, row_words));
  return _mm256_srli_epi32(_mm256_add_epi32(sums, _mm256_set1_epi32(128)), 8);
}

// The low byte of each 32-bit lane, in order.
__m128i low_bytes(__m256i samples) {
  const __m256i bytes =
      _mm256_shuffle_epi8(samples, _mm256_setr_epi8(0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, 0,
                                                    4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1));
  return _mm_unpacklo_epi32(_mm256_castsi256_si128(bytes), _mm256_extracti128_si256(bytes, 1));
}

void pad_sample_run_avx2(const uint8_t* plane, ptrdiff_t stride, const uint32_t* index,
                         const BilinearWeights* weights, int count, uint8_t* out) {
  const __m256i all = _mm256_set1_epi32(-1);
  int k = 0;
  for (; k + 8 <= count; k += 8) {
    const __m256i offsets = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index + k));
    const __m256i w = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(weights + k));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + k),
                     low_bytes(filter_blocks(gather_blocks(plane, stride, offsets, all), w)));
  }
  if (k == count) return;
  // The last 1..7 samples as a masked step: runs of every length occur (the corners of
  // a border), so a scalar tail would cost more than the full steps.
  const int rest = count - k;
  const __m256i lanes = _mm256_cmpgt_epi32(_mm256_set1_epi32(rest), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i offsets = _mm256_maskload_epi32(reinterpret_cast<const int*>(index + k), lanes);
  const __m256i w = _mm256_maskload_epi32(reinterpret_cast<const int*>(weights + k), lanes);
  uint8_t samples[8];
  _mm_storel_epi64(reinterpret_cast<__m128i*>(samples),
                   low_bytes(filter_blocks(gather_blocks(plane, stride, offsets, lanes), w)));
  std::memcpy(out + k, samples, static_cast<size_t>(rest));
}

}  // namespace

void init_pad_avx2(DspTable* table) { table->pad_sample_run = pad_sample_run_avx2; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
