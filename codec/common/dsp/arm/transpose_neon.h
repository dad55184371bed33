// SPDX-License-Identifier: BSD-2-Clause
// An 8x8 transpose of 16-bit lanes, shared by the NEON inverse DCT and the encoder's
// SATD (internal linkage).
#pragma once

#include <arm_neon.h>

namespace svc::codec::dsp {
namespace {

inline void transpose_8x8(int16x8_t r[8]) {
  int16x8_t a[8];
  for (int i = 0; i < 4; ++i) {
    a[2 * i] = vtrn1q_s16(r[2 * i], r[2 * i + 1]);
    a[2 * i + 1] = vtrn2q_s16(r[2 * i], r[2 * i + 1]);
  }
  int32x4_t b[8];  // b[4 h + c]: columns c and c + 4 of rows 4h..4h+3, c = 0..3
  for (int h = 0; h < 2; ++h) {
    for (int odd = 0; odd < 2; ++odd) {
      const int32x4_t x = vreinterpretq_s32_s16(a[4 * h + odd]), y = vreinterpretq_s32_s16(a[4 * h + 2 + odd]);
      b[4 * h + odd] = vtrn1q_s32(x, y);
      b[4 * h + 2 + odd] = vtrn2q_s32(x, y);
    }
  }
  for (int c = 0; c < 4; ++c) {
    const int64x2_t top = vreinterpretq_s64_s32(b[c]), bottom = vreinterpretq_s64_s32(b[4 + c]);
    r[c] = vreinterpretq_s16_s64(vzip1q_s64(top, bottom));
    r[c + 4] = vreinterpretq_s16_s64(vzip2q_s64(top, bottom));
  }
}

}  // namespace
}  // namespace svc::codec::dsp
