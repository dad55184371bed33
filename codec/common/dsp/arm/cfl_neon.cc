// SPDX-License-Identifier: BSD-2-Clause
// NEON chroma-from-luma kernels. Every value fits 16 bits: a 2x2 luma sum is at most
// 1020, its deviation from the mean within +-1020, and alpha * ac + 16 within +-16336,
// so 16-bit lanes compute the plain kernels' integers exactly.
#include <arm_neon.h>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

void cfl_luma_ac_8x8_neon(const uint8_t* luma, ptrdiff_t stride, int16_t* ac) {
  uint16x8_t rows[8];
  uint16x8_t total = vdupq_n_u16(0);  // at most 8 x 1020 per lane
  for (int y = 0; y < 8; ++y) {
    const uint8_t* top = luma + 2 * y * stride;
    rows[y] = vaddq_u16(vpaddlq_u8(vld1q_u8(top)), vpaddlq_u8(vld1q_u8(top + stride)));
    total = vaddq_u16(total, rows[y]);
  }
  const int16x8_t mean = vdupq_n_s16(static_cast<int16_t>((vaddlvq_u16(total) + 32) >> 6));
  for (int y = 0; y < 8; ++y) vst1q_s16(ac + 8 * y, vsubq_s16(vreinterpretq_s16_u16(rows[y]), mean));
}

void cfl_predict_8x8_neon(const int16_t* ac, int dc, int alpha, uint8_t* out) {
  const int16x8_t base = vdupq_n_s16(static_cast<int16_t>(dc));
  for (int y = 0; y < 8; y += 2) {
    int16x8_t v[2];
    for (int r = 0; r < 2; ++r) {
      // vrshr: (x + 16) >> 5.
      const int16x8_t scaled = vmulq_n_s16(vld1q_s16(ac + 8 * (y + r)), static_cast<int16_t>(alpha));
      v[r] = vaddq_s16(base, vrshrq_n_s16(scaled, 5));
    }
    vst1q_u8(out + 8 * y, vcombine_u8(vqmovun_s16(v[0]), vqmovun_s16(v[1])));
  }
}

}  // namespace

void init_cfl_neon(DspTable* table) {
  table->cfl_luma_ac_8x8 = cfl_luma_ac_8x8_neon;
  table->cfl_predict_8x8 = cfl_predict_8x8_neon;
}

}  // namespace svc::codec::dsp
