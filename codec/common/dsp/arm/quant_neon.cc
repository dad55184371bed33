// SPDX-License-Identifier: BSD-2-Clause
// NEON dequantization: four levels a step in 32-bit lanes. |level| is capped at 4096 and
// scale is at most 2^18, so the product and the rounding fit 31 bits, as in the plain
// kernel.
#include <arm_neon.h>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

// Four coefficients from four sign-extended levels.
int32x4_t dequantize_four(int32x4_t level, const int32_t* scale) {
  const int32x4_t magnitude = vminq_s32(vabsq_s32(level), vdupq_n_s32(4096));
  const int32x4_t value = vshrq_n_s32(vmlaq_s32(vdupq_n_s32(128), magnitude, vld1q_s32(scale)), 8);
  // Saturation: 2047 for positive levels, 2048 (before the sign) for negative ones; the
  // comparison's all-ones lanes are -1.
  const uint32x4_t negative = vcltzq_s32(level);
  const int32x4_t limited = vminq_s32(value, vsubq_s32(vdupq_n_s32(2047), vreinterpretq_s32_u32(negative)));
  return vbslq_s32(negative, vnegq_s32(limited), limited);
}

void dequantize_8x8_neon(const int16_t* levels, const int32_t* scale, int16_t* coefficients) {
  for (int i = 0; i < 64; i += 8) {
    const int16x8_t packed = vld1q_s16(levels + i);
    const int32x4_t low = dequantize_four(vmovl_s16(vget_low_s16(packed)), scale + i);
    const int32x4_t high = dequantize_four(vmovl_s16(vget_high_s16(packed)), scale + i + 4);
    vst1q_s16(coefficients + i, vcombine_s16(vmovn_s32(low), vmovn_s32(high)));
  }
}

}  // namespace

void init_quant_neon(DspTable* table) { table->dequantize_8x8 = dequantize_8x8_neon; }

}  // namespace svc::codec::dsp
