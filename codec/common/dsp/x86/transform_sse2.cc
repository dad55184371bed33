// SPDX-License-Identifier: BSD-2-Clause
// SSE2 8x8 integer inverse DCT, exact against the plain kernel (the encoder's float
// forward DCT is codec/encoder/dsp/x86/forward_transform_sse2.cc). Both passes run on eight
// transforms at once with pmaddwd (16-bit inputs, 32-bit sums) on transposed blocks.
// The row pass always fits 32 bits; the column pass does when every row-pass output fits
// 16 bits (then |sum| <= 43284 * 32768 < 2^31), which holds for nearly all blocks;
// otherwise that block's column pass runs in 64-bit scalar arithmetic as in the plain
// kernel. Integer sums do not depend on the order of addition, so the results agree.
#include <emmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/idct_basis.h"
#include "codec/common/dsp/inverse_add.h"
#include "codec/common/dsp/x86/add_clipped_sse2.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse2")

namespace svc::codec::dsp {
namespace {

void transpose_8x8_epi16(__m128i r[8]) {
  const __m128i a0 = _mm_unpacklo_epi16(r[0], r[1]), a1 = _mm_unpackhi_epi16(r[0], r[1]);
  const __m128i a2 = _mm_unpacklo_epi16(r[2], r[3]), a3 = _mm_unpackhi_epi16(r[2], r[3]);
  const __m128i a4 = _mm_unpacklo_epi16(r[4], r[5]), a5 = _mm_unpackhi_epi16(r[4], r[5]);
  const __m128i a6 = _mm_unpacklo_epi16(r[6], r[7]), a7 = _mm_unpackhi_epi16(r[6], r[7]);
  const __m128i b0 = _mm_unpacklo_epi32(a0, a2), b1 = _mm_unpackhi_epi32(a0, a2);
  const __m128i b2 = _mm_unpacklo_epi32(a1, a3), b3 = _mm_unpackhi_epi32(a1, a3);
  const __m128i b4 = _mm_unpacklo_epi32(a4, a6), b5 = _mm_unpackhi_epi32(a4, a6);
  const __m128i b6 = _mm_unpacklo_epi32(a5, a7), b7 = _mm_unpackhi_epi32(a5, a7);
  r[0] = _mm_unpacklo_epi64(b0, b4);
  r[1] = _mm_unpackhi_epi64(b0, b4);
  r[2] = _mm_unpacklo_epi64(b1, b5);
  r[3] = _mm_unpackhi_epi64(b1, b5);
  r[4] = _mm_unpacklo_epi64(b2, b6);
  r[5] = _mm_unpackhi_epi64(b2, b6);
  r[6] = _mm_unpacklo_epi64(b3, b7);
  r[7] = _mm_unpackhi_epi64(b3, b7);
}

// pmaddwd weights: the low 16 bits multiply the first of a pair, the high the second.
inline __m128i weight_pair(int first, int second) {
  return _mm_set1_epi32(static_cast<int>((static_cast<uint32_t>(second) << 16) | static_cast<uint16_t>(first)));
}

// One 1-D inverse of eight transforms: in[u] holds frequency u of each (one per lane);
// out_low[x] / out_high[x] hold sample x of lanes 0-3 / 4-7, rounded and shifted.
template <int kShift>
void idct_pass(const __m128i in[8], __m128i out_low[8], __m128i out_high[8]) {
  const __m128i round = _mm_set1_epi32(1 << (kShift - 1));
  const __m128i p02[2] = {_mm_unpacklo_epi16(in[0], in[2]), _mm_unpackhi_epi16(in[0], in[2])};
  const __m128i p46[2] = {_mm_unpacklo_epi16(in[4], in[6]), _mm_unpackhi_epi16(in[4], in[6])};
  const __m128i p13[2] = {_mm_unpacklo_epi16(in[1], in[3]), _mm_unpackhi_epi16(in[1], in[3])};
  const __m128i p57[2] = {_mm_unpacklo_epi16(in[5], in[7]), _mm_unpackhi_epi16(in[5], in[7])};
  for (int x = 0; x < 4; ++x) {
    const __m128i w02 = weight_pair(kIdctBasis[0][x], kIdctBasis[2][x]);
    const __m128i w46 = weight_pair(kIdctBasis[4][x], kIdctBasis[6][x]);
    const __m128i w13 = weight_pair(kIdctBasis[1][x], kIdctBasis[3][x]);
    const __m128i w57 = weight_pair(kIdctBasis[5][x], kIdctBasis[7][x]);
    for (int half = 0; half < 2; ++half) {
      const __m128i even =
          _mm_add_epi32(_mm_add_epi32(_mm_madd_epi16(p02[half], w02), _mm_madd_epi16(p46[half], w46)), round);
      const __m128i odd = _mm_add_epi32(_mm_madd_epi16(p13[half], w13), _mm_madd_epi16(p57[half], w57));
      __m128i* out = half == 0 ? out_low : out_high;
      out[x] = _mm_srai_epi32(_mm_add_epi32(even, odd), kShift);
      out[7 - x] = _mm_srai_epi32(_mm_sub_epi32(even, odd), kShift);
    }
  }
}

bool dc_only(const __m128i block[8]) {
  __m128i any = _mm_srli_si128(block[0], 2);  // row 0 without the DC
  for (int v = 1; v < 8; ++v) any = _mm_or_si128(any, block[v]);
  return _mm_movemask_epi8(_mm_cmpeq_epi16(any, _mm_setzero_si128())) == 0xffff;
}

void inverse_dct_8x8_sse2(const int16_t* coefficients, int16_t* samples) {
  __m128i block[8];
  for (int v = 0; v < 8; ++v) block[v] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(coefficients + 8 * v));
  if (dc_only(block)) {  // common in decoded faces; the passes below give this same value
    const int row = (kIdctBasis[0][0] * coefficients[0] + (1 << (kIdctRowShift - 1))) >> kIdctRowShift;
    const int value = static_cast<int>((int64_t{kIdctBasis[0][0]} * row + (int64_t{1} << (kIdctColumnShift - 1))) >>
                                       kIdctColumnShift);
    const __m128i fill = _mm_set1_epi16(static_cast<int16_t>(value));
    for (int y = 0; y < 8; ++y) _mm_storeu_si128(reinterpret_cast<__m128i*>(samples + 8 * y), fill);
    return;
  }
  transpose_8x8_epi16(block);  // block[u]: frequency u of every row
  __m128i low[8], high[8];
  idct_pass<kIdctRowShift>(block, low, high);  // low/high[x]: column x of the row pass, by row
  __m128i fits = _mm_set1_epi32(-1);
  for (int x = 0; x < 8; ++x) {
    block[x] = _mm_packs_epi32(low[x], high[x]);
    const __m128i back_low = _mm_srai_epi32(_mm_unpacklo_epi16(block[x], block[x]), 16);
    const __m128i back_high = _mm_srai_epi32(_mm_unpackhi_epi16(block[x], block[x]), 16);
    fits =
        _mm_and_si128(fits, _mm_and_si128(_mm_cmpeq_epi32(back_low, low[x]), _mm_cmpeq_epi32(back_high, high[x])));
  }
  if (_mm_movemask_epi8(fits) != 0xffff) {  // some row-pass output needs more than 16 bits
    alignas(16) int32_t columns[8][8];
    for (int x = 0; x < 8; ++x) {
      _mm_store_si128(reinterpret_cast<__m128i*>(columns[x]), low[x]);
      _mm_store_si128(reinterpret_cast<__m128i*>(columns[x] + 4), high[x]);
    }
    idct_column_pass_scalar(columns, samples);
    return;
  }
  transpose_8x8_epi16(block);  // block[v]: row v of the row pass
  idct_pass<kIdctColumnShift>(block, low, high);
  for (int y = 0; y < 8; ++y) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(samples + 8 * y), _mm_packs_epi32(low[y], high[y]));
  }
}

}  // namespace

void init_transform_sse2(DspTable* table) {
  set_dct_inverse<8, inverse_dct_8x8_sse2, add_clipped_sse2<8, 8>>(table);
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
