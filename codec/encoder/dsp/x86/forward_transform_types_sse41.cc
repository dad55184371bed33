// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 float forward transforms of the intra transform types (for the rectangular
// blocks DCT_DCT too, docs/codec.md 5.5.3): four outputs of a row at once (lanes over the
// frequency u), every sum in the plain kernel's order, so they round exactly as the plain
// code does (no fused multiply-add).
#include <smmintrin.h>

#include "codec/common/dsp/x86/target.h"
#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/forward_type_basis.h"
#include "codec/encoder/dsp/x86/transposed_basis.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

template <int N>
const TransposedBasis<N>& transposed_basis(bool dst) {
  static const TransposedBasis<N> dct(type_float_basis<N>(false)), dst_basis(type_float_basis<N>(true));
  return dst ? dst_basis : dct;
}

template <int W, int H>
void forward_typed(int type, const float* samples, float* coefficients) {
  const TransposedBasis<W>& rows = transposed_basis<W>((type & 1) != 0);
  const TypeFloatBasis<H>& columns = type_float_basis<H>((type & 2) != 0);
  alignas(16) float tmp[W * H];
  for (int y = 0; y < H; ++y) {
    for (int u = 0; u < W; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int x = 0; x < W; ++x) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_load_ps(&rows.bt[x][u]), _mm_set1_ps(samples[W * y + x])));
      }
      _mm_store_ps(tmp + W * y + u, sum);
    }
  }
  const __m128 factor = _mm_set1_ps(type_forward_scale(W, H));
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; u += 4) {
      __m128 sum = _mm_setzero_ps();
      for (int y = 0; y < H; ++y) {
        sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(columns.b[v][y]), _mm_load_ps(tmp + W * y + u)));
      }
      _mm_storeu_ps(coefficients + W * v + u, _mm_mul_ps(sum, factor));
    }
  }
}

}  // namespace

void init_forward_transform_types_sse41(EncoderDspTable* table) {
  table->forward_typed_4x4 = forward_typed<4, 4>;
  table->forward_typed_8x8 = forward_typed<8, 8>;
  table->forward_typed_16x16 = forward_typed<16, 16>;
  table->forward_typed_16x8 = forward_typed<16, 8>;
  table->forward_typed_8x16 = forward_typed<8, 16>;
  table->forward_typed_16x4 = forward_typed<16, 4>;
  table->forward_typed_4x16 = forward_typed<4, 16>;
  table->forward_typed_8x4 = forward_typed<8, 4>;
  table->forward_typed_4x8 = forward_typed<4, 8>;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
