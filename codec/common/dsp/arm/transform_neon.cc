// SPDX-License-Identifier: BSD-2-Clause
// NEON 8x8 integer inverse DCT, exact against the plain kernel. Both passes run on eight
// transforms at once (one per lane, on transposed blocks) with 16-bit inputs and 32-bit
// sums. The row pass always fits 32 bits; the column pass does when every row-pass output
// fits 16 bits (then |sum| <= 43284 * 32768 < 2^31), which holds for nearly all blocks;
// otherwise that block's column pass runs in 64-bit scalar arithmetic as in the plain
// kernel. Integer sums do not depend on the order of addition, so the results agree.
// The float forward DCT has no NEON variant: GCC contracts the plain kernel's products
// and sums into fused multiply-adds on AArch64, an order a variant cannot promise to
// reproduce.
#include <arm_neon.h>

#include "codec/common/dsp/arm/transpose_neon.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/idct_basis.h"
#include "codec/common/dsp/inverse_add.h"

namespace svc::codec::dsp {
namespace {

// One 1-D inverse of eight transforms: in[u] holds frequency u of each (one per lane);
// low[x] / high[x] hold sample x of lanes 0-3 / 4-7, rounded and shifted.
template <int kShift>
void idct_pass(const int16x8_t in[8], int32x4_t low[8], int32x4_t high[8]) {
  for (int x = 0; x < 4; ++x) {
    int32x4_t even[2] = {vdupq_n_s32(1 << (kShift - 1)), vdupq_n_s32(1 << (kShift - 1))};
    int32x4_t odd[2] = {vdupq_n_s32(0), vdupq_n_s32(0)};
    for (int u = 0; u < 8; u += 2) {
      even[0] = vmlal_n_s16(even[0], vget_low_s16(in[u]), static_cast<int16_t>(kIdctBasis[u][x]));
      even[1] = vmlal_high_n_s16(even[1], in[u], static_cast<int16_t>(kIdctBasis[u][x]));
      odd[0] = vmlal_n_s16(odd[0], vget_low_s16(in[u + 1]), static_cast<int16_t>(kIdctBasis[u + 1][x]));
      odd[1] = vmlal_high_n_s16(odd[1], in[u + 1], static_cast<int16_t>(kIdctBasis[u + 1][x]));
    }
    low[x] = vshrq_n_s32(vaddq_s32(even[0], odd[0]), kShift);
    high[x] = vshrq_n_s32(vaddq_s32(even[1], odd[1]), kShift);
    low[7 - x] = vshrq_n_s32(vsubq_s32(even[0], odd[0]), kShift);
    high[7 - x] = vshrq_n_s32(vsubq_s32(even[1], odd[1]), kShift);
  }
}

bool dc_only(const int16x8_t block[8]) {
  int16x8_t any = vsetq_lane_s16(0, block[0], 0);
  for (int v = 1; v < 8; ++v) any = vorrq_s16(any, block[v]);
  return vmaxvq_u16(vreinterpretq_u16_s16(any)) == 0;
}

bool fits_16_bits(const int32x4_t low[8], const int32x4_t high[8]) {
  int32x4_t most = vmaxq_s32(low[0], high[0]), least = vminq_s32(low[0], high[0]);
  for (int x = 1; x < 8; ++x) {
    most = vmaxq_s32(most, vmaxq_s32(low[x], high[x]));
    least = vminq_s32(least, vminq_s32(low[x], high[x]));
  }
  return vmaxvq_s32(most) <= 32767 && vminvq_s32(least) >= -32768;
}

void inverse_dct_8x8_neon(const int16_t* coefficients, int16_t* samples) {
  int16x8_t block[8];
  for (int v = 0; v < 8; ++v) block[v] = vld1q_s16(coefficients + 8 * v);
  if (dc_only(block)) {  // common in decoded faces; the passes below give this same value
    const int row = (kIdctBasis[0][0] * coefficients[0] + (1 << (kIdctRowShift - 1))) >> kIdctRowShift;
    const int value = static_cast<int>((int64_t{kIdctBasis[0][0]} * row + (int64_t{1} << (kIdctColumnShift - 1))) >>
                                       kIdctColumnShift);
    const int16x8_t fill = vdupq_n_s16(static_cast<int16_t>(value));
    for (int y = 0; y < 8; ++y) vst1q_s16(samples + 8 * y, fill);
    return;
  }
  transpose_8x8(block);  // block[u]: frequency u of every row
  int32x4_t low[8], high[8];
  idct_pass<kIdctRowShift>(block, low, high);  // low/high[x]: column x of the row pass, by row
  if (!fits_16_bits(low, high)) {
    int32_t columns[8][8];
    for (int x = 0; x < 8; ++x) {
      vst1q_s32(columns[x], low[x]);
      vst1q_s32(columns[x] + 4, high[x]);
    }
    idct_column_pass_scalar(columns, samples);
    return;
  }
  for (int x = 0; x < 8; ++x) block[x] = vcombine_s16(vmovn_s32(low[x]), vmovn_s32(high[x]));
  transpose_8x8(block);  // block[v]: row v of the row pass
  idct_pass<kIdctColumnShift>(block, low, high);
  // Narrowing keeps the low 16 bits, as the plain kernel's cast (the values fit anyway).
  for (int y = 0; y < 8; ++y) vst1q_s16(samples + 8 * y, vcombine_s16(vmovn_s32(low[y]), vmovn_s32(high[y])));
}

}  // namespace

void init_transform_neon(DspTable* table) { set_dct_inverse<8, inverse_dct_8x8_neon, add_clipped_c<8, 8>>(table); }

}  // namespace svc::codec::dsp
