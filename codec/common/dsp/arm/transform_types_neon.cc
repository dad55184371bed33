// SPDX-License-Identifier: BSD-2-Clause
// NEON integer inverses of the intra transform types (for 16x8 and 8x16 blocks DCT_DCT too; arithmetic in
// matrix_transform_neon.h). The float forward transforms have no NEON variant, for the
// reason transform_4_16_neon.cc gives.
#include "codec/common/dsp/arm/matrix_transform_neon.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/inverse_add.h"
#include "codec/common/dsp/transform_type_basis.h"

namespace svc::codec::dsp {
namespace {

template <int W, int H>
void inverse_typed_neon(int type, const int16_t* coefficients, int16_t* samples) {
  const bool rows_dst = (type & 1) != 0, columns_dst = (type & 2) != 0;
  inverse_by_matrices<W, H>(type_matrix<W>(rows_dst).m, type_row_shift(rows_dst), type_matrix<H>(columns_dst).m,
                            type_column_shift(W, H, columns_dst), coefficients, samples);
}

}  // namespace

void init_transform_types_neon(DspTable* table) {
  set_typed_inverse<4, 4, inverse_typed_neon<4, 4>, add_clipped_c<4, 4>>(table);
  set_typed_inverse<8, 8, inverse_typed_neon<8, 8>, add_clipped_c<8, 8>>(table);
  set_typed_inverse<16, 16, inverse_typed_neon<16, 16>, add_clipped_c<16, 16>>(table);
  set_typed_inverse<16, 8, inverse_typed_neon<16, 8>, add_clipped_c<16, 8>>(table);
  set_typed_inverse<8, 16, inverse_typed_neon<8, 16>, add_clipped_c<8, 16>>(table);
  set_typed_inverse<16, 4, inverse_typed_neon<16, 4>, add_clipped_c<16, 4>>(table);
  set_typed_inverse<4, 16, inverse_typed_neon<4, 16>, add_clipped_c<4, 16>>(table);
  set_typed_inverse<8, 4, inverse_typed_neon<8, 4>, add_clipped_c<8, 4>>(table);
  set_typed_inverse<4, 8, inverse_typed_neon<4, 8>, add_clipped_c<4, 8>>(table);
}

}  // namespace svc::codec::dsp
