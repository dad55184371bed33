// SPDX-License-Identifier: BSD-2-Clause
// Plain kernels of the intra transform types other than DCT_DCT (docs/codec.md 5.5.2):
// separable transforms whose row pass (horizontal) and column pass (vertical) each take
// the DCT or the DST-VII matrix of transform_type_basis.h. These integer inverses are the
// bitstream's contract and must equal codec/common/dct.cc's matrix product; the float
// forward transforms are the encoder's (codec/encoder/dsp/forward_transform_types.cc).
#include <algorithm>
#include <cstdint>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/inverse_add.h"
#include "codec/common/dsp/transform_type_basis.h"

namespace svc::codec::dsp {
namespace {

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
  set_typed_inverse<4, 4, inverse_typed<4, 4>, add_clipped_c<4, 4>>(table);
  set_typed_inverse<8, 8, inverse_typed<8, 8>, add_clipped_c<8, 8>>(table);
  set_typed_inverse<16, 16, inverse_typed<16, 16>, add_clipped_c<16, 16>>(table);
  set_typed_inverse<16, 8, inverse_typed<16, 8>, add_clipped_c<16, 8>>(table);
  set_typed_inverse<8, 16, inverse_typed<8, 16>, add_clipped_c<8, 16>>(table);
  set_typed_inverse<16, 4, inverse_typed<16, 4>, add_clipped_c<16, 4>>(table);
  set_typed_inverse<4, 16, inverse_typed<4, 16>, add_clipped_c<4, 16>>(table);
  set_typed_inverse<8, 4, inverse_typed<8, 4>, add_clipped_c<8, 4>>(table);
  set_typed_inverse<4, 8, inverse_typed<4, 8>, add_clipped_c<4, 8>>(table);
}

}  // namespace svc::codec::dsp
