// SPDX-License-Identifier: BSD-2-Clause
// The plain 8x8 integer inverse DCT with its zero-row and DC-only shortcuts, the
// bitstream's contract: its output must equal codec/common/dct.cc's matrix product. The
// float forward transform is the encoder's (codec/encoder/dsp/forward_transform.cc).
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/idct_basis.h"
#include "codec/common/dsp/inverse_add.h"

namespace svc::codec::dsp {
namespace {

// One 1-D inverse over in[0], in[stride], ... writing out[0..7] with rounding shift,
// accumulating in Acc (int for rows, int64_t for columns).
template <typename Acc, typename In>
inline void idct_1d(const In* in, int stride, int shift, int* out) {
  const Acc f0 = in[0], f1 = in[stride], f2 = in[2 * stride], f3 = in[3 * stride];
  const Acc f4 = in[4 * stride], f5 = in[5 * stride], f6 = in[6 * stride], f7 = in[7 * stride];
  const Acc rounding = Acc{1} << (shift - 1);
  for (int x = 0; x < 4; ++x) {
    const Acc even =
        kIdctBasis[0][x] * f0 + kIdctBasis[2][x] * f2 + kIdctBasis[4][x] * f4 + kIdctBasis[6][x] * f6 + rounding;
    const Acc odd = kIdctBasis[1][x] * f1 + kIdctBasis[3][x] * f3 + kIdctBasis[5][x] * f5 + kIdctBasis[7][x] * f7;
    out[x] = static_cast<int>((even + odd) >> shift);
    out[7 - x] = static_cast<int>((even - odd) >> shift);
  }
}

void inverse_dct_8x8_c(const int16_t* coefficients, int16_t* samples) {
  bool dc_only = true;
  for (int i = 1; i < 64 && dc_only; ++i) dc_only = coefficients[i] == 0;
  if (dc_only) {
    // The general path below yields this same value at every position.
    const int row = (kIdctBasis[0][0] * coefficients[0] + (1 << (kIdctRowShift - 1))) >> kIdctRowShift;
    const int value = static_cast<int>((int64_t{kIdctBasis[0][0]} * row + (int64_t{1} << (kIdctColumnShift - 1))) >>
                                       kIdctColumnShift);
    for (int i = 0; i < 64; ++i) samples[i] = static_cast<int16_t>(value);
    return;
  }
  int tmp[64];
  for (int v = 0; v < 8; ++v) {
    const int16_t* row = coefficients + 8 * v;
    bool zero = true;
    for (int u = 0; u < 8 && zero; ++u) zero = row[u] == 0;
    if (zero) {
      for (int x = 0; x < 8; ++x) tmp[8 * v + x] = 0;  // what idct_1d gives for zeros
      continue;
    }
    idct_1d<int>(row, 1, kIdctRowShift, tmp + 8 * v);
  }
  for (int x = 0; x < 8; ++x) {
    int column[8];
    idct_1d<int64_t>(tmp + x, 8, kIdctColumnShift, column);
    for (int y = 0; y < 8; ++y) samples[8 * y + x] = static_cast<int16_t>(column[y]);
  }
}

}  // namespace

void init_transform_c(DspTable* table) { set_dct_inverse<8, inverse_dct_8x8_c, add_clipped_c<8, 8>>(table); }

}  // namespace svc::codec::dsp
