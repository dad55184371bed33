// SPDX-License-Identifier: BSD-2-Clause
// NEON integer inverse 4x4 and 16x16 DCTs (arithmetic in matrix_transform_neon.h). The
// float forward transforms have no NEON variant: GCC contracts the plain kernels'
// products and sums into fused multiply-adds on AArch64, an order a variant cannot
// promise to reproduce.
#include "codec/common/dsp/arm/matrix_transform_neon.h"
#include "codec/common/dsp/dct_4_16_basis.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/inverse_add.h"

namespace svc::codec::dsp {
namespace {

void inverse_dct_4x4_neon(const int16_t* coefficients, int16_t* samples) {
  inverse_by_matrices<4, 4>(kDct4Matrix.m, kIdct4RowShift, kDct4Matrix.m, kIdct4ColumnShift, coefficients, samples);
}

void inverse_dct_16x16_neon(const int16_t* coefficients, int16_t* samples) {
  inverse_by_matrices<16, 16>(kDct16Matrix.m, kIdct16RowShift, kDct16Matrix.m, kIdct16ColumnShift, coefficients,
                              samples);
}

}  // namespace

void init_transform_4_16_neon(DspTable* table) {
  set_dct_inverse<4, inverse_dct_4x4_neon, add_clipped_c<4, 4>>(table);
  set_dct_inverse<16, inverse_dct_16x16_neon, add_clipped_c<16, 16>>(table);
}

}  // namespace svc::codec::dsp
