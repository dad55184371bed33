// SPDX-License-Identifier: BSD-2-Clause
// Plain float forward transforms of the intra transform types other than DCT_DCT and of
// the rectangular blocks (docs/codec.md 5.5.2, 5.5.3): separable transforms whose row pass
// (horizontal) and column pass (vertical) each take the DCT or the DST-VII basis of
// forward_type_basis.h, the transposes of the shared table's integer inverses.
#include <cmath>

#include "codec/encoder/dsp/encoder_dsp_init.h"
#include "codec/encoder/dsp/forward_type_basis.h"

namespace svc::codec::dsp {

template <int N>
TypeFloatBasis<N>::TypeFloatBasis(bool dst) {
  const TypeMatrix<N>& matrix = type_matrix<N>(dst);
  const double scale = (dst ? 1 << kDstExtraShift : 1) * 64.0 * std::sqrt(static_cast<double>(N));
  for (int k = 0; k < N; ++k) {
    for (int n = 0; n < N; ++n) b[k][n] = static_cast<float>(matrix.m[k][n] / scale);
  }
}

template <int N>
const TypeFloatBasis<N>& type_float_basis(bool dst) {
  static const TypeFloatBasis<N> dct(false), dst_basis(true);
  return dst ? dst_basis : dct;
}
template const TypeFloatBasis<4>& type_float_basis<4>(bool);
template const TypeFloatBasis<8>& type_float_basis<8>(bool);
template const TypeFloatBasis<16>& type_float_basis<16>(bool);

namespace {

// Rows with the horizontal basis, then columns with the vertical one; each sum
// accumulates in increasing sample order (the SIMD variants keep this order). W x H
// blocks, W samples a row.
template <int W, int H>
void forward_typed(int type, const float* samples, float* coefficients) {
  const TypeFloatBasis<W>& rows = type_float_basis<W>((type & 1) != 0);
  const TypeFloatBasis<H>& columns = type_float_basis<H>((type & 2) != 0);
  const float scale = type_forward_scale(W, H);
  float tmp[W * H];
  for (int y = 0; y < H; ++y) {
    for (int u = 0; u < W; ++u) {
      float sum = 0;
      for (int x = 0; x < W; ++x) sum += rows.b[u][x] * samples[W * y + x];
      tmp[W * y + u] = sum;
    }
  }
  for (int u = 0; u < W; ++u) {
    for (int v = 0; v < H; ++v) {
      float sum = 0;
      for (int y = 0; y < H; ++y) sum += columns.b[v][y] * tmp[W * y + u];
      coefficients[W * v + u] = sum * scale;
    }
  }
}

}  // namespace

void init_forward_transform_types_c(EncoderDspTable* table) {
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
