// Plain kernels of the intra transform types other than DCT_DCT (docs/codec.md 7.2):
// separable transforms whose row pass (horizontal) and column pass (vertical) each take
// the DCT or the DST-VII matrix of transform_type_basis.h. The float forward transforms
// serve the encoder; the integer inverses are the bitstream's contract and must equal
// codec/dct.cc's matrix product.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/transform_type_basis.h"

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

template <int W, int H>
void inverse_typed(int type, const int16_t* coefficients, int16_t* samples) {
  const bool rows_dst = (type & 1) != 0, columns_dst = (type & 2) != 0;
  const TypeMatrix<W>& rows = type_matrix<W>(rows_dst);
  const TypeMatrix<H>& columns = type_matrix<H>(columns_dst);
  const int row_shift = type_row_shift(rows_dst), column_shift = type_column_shift(W, H, columns_dst);
  int32_t tmp[W * H];
  for (int v = 0; v < H; ++v) {
    for (int x = 0; x < W; ++x) {
      int32_t sum = int32_t{1} << (row_shift - 1);
      for (int u = 0; u < W; ++u) sum += rows.m[u][x] * coefficients[W * v + u];
      tmp[W * v + x] = sum >> row_shift;
    }
  }
  for (int x = 0; x < W; ++x) {
    for (int y = 0; y < H; ++y) {
      int32_t sum = int32_t{1} << (column_shift - 1);
      for (int v = 0; v < H; ++v) sum += columns.m[v][y] * tmp[W * v + x];
      samples[W * y + x] = static_cast<int16_t>(std::clamp(sum >> column_shift, -32768, 32767));
    }
  }
}

}  // namespace

void init_transform_types_c(DspTable* table) {
  table->forward_typed_4x4 = forward_typed<4, 4>;
  table->forward_typed_8x8 = forward_typed<8, 8>;
  table->forward_typed_16x16 = forward_typed<16, 16>;
  table->forward_typed_16x8 = forward_typed<16, 8>;
  table->forward_typed_8x16 = forward_typed<8, 16>;
  table->forward_typed_16x4 = forward_typed<16, 4>;
  table->forward_typed_4x16 = forward_typed<4, 16>;
  table->forward_typed_8x4 = forward_typed<8, 4>;
  table->forward_typed_4x8 = forward_typed<4, 8>;
  table->inverse_typed_4x4 = inverse_typed<4, 4>;
  table->inverse_typed_8x8 = inverse_typed<8, 8>;
  table->inverse_typed_16x16 = inverse_typed<16, 16>;
  table->inverse_typed_16x8 = inverse_typed<16, 8>;
  table->inverse_typed_8x16 = inverse_typed<8, 16>;
  table->inverse_typed_16x4 = inverse_typed<16, 4>;
  table->inverse_typed_4x16 = inverse_typed<4, 16>;
  table->inverse_typed_8x4 = inverse_typed<8, 4>;
  table->inverse_typed_4x8 = inverse_typed<4, 8>;
}

}  // namespace svc::codec::dsp
