// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 4x4 and 16x16 integer inverse DCTs: matrix_inverse_sse41.h's arithmetic (the
// encoder's float forward transforms are codec/encoder/dsp/x86/forward_transform_4_16_sse41.cc).
#include <smmintrin.h>

#include "codec/common/dsp/dct_4_16_basis.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/inverse_add.h"
#include "codec/common/dsp/x86/add_clipped_sse2.h"
#include "codec/common/dsp/x86/matrix_inverse_sse41.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

void inverse_dct_4x4_sse41(const int16_t* coefficients, int16_t* samples) {
  static const InverseMatrixPairs<4> pairs(kDct4Matrix.m);
  inverse_matrix_transform<4, 4>(pairs, kIdct4RowShift, pairs, kIdct4ColumnShift, coefficients, samples);
}

void inverse_dct_16x16_sse41(const int16_t* coefficients, int16_t* samples) {
  static const InverseMatrixPairs<16> pairs(kDct16Matrix.m);
  inverse_matrix_transform<16, 16>(pairs, kIdct16RowShift, pairs, kIdct16ColumnShift, coefficients, samples);
}

}  // namespace

void init_transform_4_16_sse41(DspTable* table) {
  set_dct_inverse<4, inverse_dct_4x4_sse41, add_clipped_sse2<4, 4>>(table);
  set_dct_inverse<16, inverse_dct_16x16_sse41, add_clipped_sse2<16, 16>>(table);
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
