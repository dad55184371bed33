// SPDX-License-Identifier: BSD-2-Clause
// NEON SADs of the encoder's motion search, each equal to its plain kernel in sad.cc bit
// for bit: against a packed prediction and against the rounded-up average of two blocks.
#include <arm_neon.h>

#include "codec/encoder/dsp/encoder_dsp_init.h"

namespace svc::codec::dsp {
namespace {

// 16-bit lanes hold at most 16 rows x 2 x 255.
int sad_16x16_neon(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  uint16x8_t sum = vdupq_n_u16(0);
  for (int y = 0; y < 16; ++y) {
    const uint8x16_t s = vld1q_u8(source + y * source_stride), p = vld1q_u8(prediction + 16 * y);
    sum = vabal_high_u8(vabal_u8(sum, vget_low_u8(s), vget_low_u8(p)), s, p);
  }
  return static_cast<int>(vaddlvq_u16(sum));
}

int sad_average_neon(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* a, const uint8_t* b,
                     ptrdiff_t reference_stride, int width, int height) {
  uint16x8_t sum = vdupq_n_u16(0);
  if (width == 16) {
    for (int y = 0; y < height; ++y) {
      const uint8x16_t average = vrhaddq_u8(vld1q_u8(a + y * reference_stride), vld1q_u8(b + y * reference_stride));
      const uint8x16_t s = vld1q_u8(source + y * source_stride);
      sum = vabal_high_u8(vabal_u8(sum, vget_low_u8(s), vget_low_u8(average)), s, average);
    }
    return static_cast<int>(vaddlvq_u16(sum));
  }
  for (int y = 0; y < height; ++y) {
    const uint8x8_t average = vrhadd_u8(vld1_u8(a + y * reference_stride), vld1_u8(b + y * reference_stride));
    sum = vabal_u8(sum, vld1_u8(source + y * source_stride), average);
  }
  return static_cast<int>(vaddlvq_u16(sum));
}

}  // namespace

void init_sad_neon(EncoderDspTable* table) {
  table->sad_average = sad_average_neon;
  table->sad_16x16 = sad_16x16_neon;
}

}  // namespace svc::codec::dsp
