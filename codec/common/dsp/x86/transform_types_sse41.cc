// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 integer inverses of the intra transform types (for the rectangular blocks
// DCT_DCT too, docs/codec.md 5.5.3): matrix_inverse_sse41.h's arithmetic (the encoder's
// float forward transforms are codec/encoder/dsp/x86/forward_transform_types_sse41.cc).
#include <smmintrin.h>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/inverse_add.h"
#include "codec/common/dsp/transform_type_basis.h"
#include "codec/common/dsp/x86/add_clipped_sse2.h"
#include "codec/common/dsp/x86/matrix_inverse_sse41.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

// A direction's matrix (DST-VII when `dst`, else the DCT) in the inverse's layouts.
template <int N>
const InverseMatrixPairs<N>& matrix_pairs(bool dst) {
  static const InverseMatrixPairs<N> dct(type_matrix<N>(false).m), dst_pairs(type_matrix<N>(true).m);
  return dst ? dst_pairs : dct;
}

template <int W, int H>
void inverse_typed(int type, const int16_t* coefficients, int16_t* samples) {
  const bool rows_dst = (type & 1) != 0, columns_dst = (type & 2) != 0;
  inverse_matrix_transform<W, H>(matrix_pairs<W>(rows_dst), type_row_shift(rows_dst), matrix_pairs<H>(columns_dst),
                                 type_column_shift(W, H, columns_dst), coefficients, samples);
}

}  // namespace

void init_transform_types_sse41(DspTable* table) {
  set_typed_inverse<4, 4, inverse_typed<4, 4>, add_clipped_sse2<4, 4>>(table);
  set_typed_inverse<8, 8, inverse_typed<8, 8>, add_clipped_sse2<8, 8>>(table);
  set_typed_inverse<16, 16, inverse_typed<16, 16>, add_clipped_sse2<16, 16>>(table);
  set_typed_inverse<16, 8, inverse_typed<16, 8>, add_clipped_sse2<16, 8>>(table);
  set_typed_inverse<8, 16, inverse_typed<8, 16>, add_clipped_sse2<8, 16>>(table);
  set_typed_inverse<16, 4, inverse_typed<16, 4>, add_clipped_sse2<16, 4>>(table);
  set_typed_inverse<4, 16, inverse_typed<4, 16>, add_clipped_sse2<4, 16>>(table);
  set_typed_inverse<8, 4, inverse_typed<8, 4>, add_clipped_sse2<8, 4>>(table);
  set_typed_inverse<4, 8, inverse_typed<4, 8>, add_clipped_sse2<4, 8>>(table);
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
