// SPDX-License-Identifier: BSD-2-Clause
// Plain 4x4 and 16x16 integer inverse DCTs with HEVC's matrices, the bitstream's
// contract: their output must equal codec/common/dct.cc's matrix products. The float
// forward transforms are the encoder's (codec/encoder/dsp/forward_transform_4_16.cc).
#include <algorithm>
#include <cstdint>

#include "codec/common/dsp/dct_4_16_basis.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/inverse_add.h"

namespace svc::codec::dsp {
namespace {

template <int N>
void inverse_dct(const HevcDctMatrix<N>& matrix, int row_shift, int column_shift, const int16_t* coefficients,
                 int16_t* samples) {
  int32_t tmp[N * N];
  for (int v = 0; v < N; ++v) {
    for (int x = 0; x < N; ++x) {
      int32_t sum = int32_t{1} << (row_shift - 1);
      for (int u = 0; u < N; ++u) sum += matrix.m[u][x] * coefficients[N * v + u];
      tmp[N * v + x] = sum >> row_shift;
    }
  }
  for (int x = 0; x < N; ++x) {
    for (int y = 0; y < N; ++y) {
      int32_t sum = int32_t{1} << (column_shift - 1);
      for (int v = 0; v < N; ++v) sum += matrix.m[v][y] * tmp[N * v + x];
      samples[N * y + x] = static_cast<int16_t>(std::clamp(sum >> column_shift, -32768, 32767));
    }
  }
}

}  // namespace

void inverse_dct_4x4_c(const int16_t* coefficients, int16_t* samples) {
  inverse_dct(kDct4Matrix, kIdct4RowShift, kIdct4ColumnShift, coefficients, samples);
}
void inverse_dct_16x16_c(const int16_t* coefficients, int16_t* samples) {
  inverse_dct(kDct16Matrix, kIdct16RowShift, kIdct16ColumnShift, coefficients, samples);
}

void init_transform_4_16_c(DspTable* table) {
  set_dct_inverse<4, inverse_dct_4x4_c, add_clipped_c<4, 4>>(table);
  set_dct_inverse<16, inverse_dct_16x16_c, add_clipped_c<16, 16>>(table);
}

}  // namespace svc::codec::dsp
