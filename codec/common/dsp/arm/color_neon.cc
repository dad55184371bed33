// SPDX-License-Identifier: BSD-2-Clause
// NEON color rows: vld3/vst3 move between packed RGB and planes (vst4 writes RGBA and
// BGRA), and the arithmetic is the plain kernels' integer formulas (color_formulas.h)
// with the same constants, in 32-bit lanes wherever a constant does not fit 16 bits;
// saturating narrows are the clamps.
#include <arm_neon.h>

#include "codec/common/dsp/color_formulas.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

using namespace color;

// Y of 8 pixels: the weights fit unsigned 16 bits and the sums 32 (they total 65536).
uint8x8_t luma_8(uint16x8_t r, uint16x8_t g, uint16x8_t b) {
  uint32x4_t low = vmull_n_u16(vget_low_u16(r), kYR);
  uint32x4_t high = vmull_high_n_u16(r, kYR);
  low = vmlal_n_u16(low, vget_low_u16(g), kYG);
  high = vmlal_high_n_u16(high, g, kYG);
  low = vmlal_n_u16(low, vget_low_u16(b), kYB);
  high = vmlal_high_n_u16(high, b, kYB);
  return vqmovn_u16(vcombine_u16(vrshrn_n_u32(low, 16), vrshrn_n_u32(high, 16)));  // (sum + 32768) >> 16
}

void rgb_to_luma_row_neon(const uint8_t* rgb, int width, uint8_t* y) {
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const uint8x16x3_t p = vld3q_u8(rgb + 3 * x);
    const uint8x8_t low =
        luma_8(vmovl_u8(vget_low_u8(p.val[0])), vmovl_u8(vget_low_u8(p.val[1])), vmovl_u8(vget_low_u8(p.val[2])));
    const uint8x8_t high = luma_8(vmovl_high_u8(p.val[0]), vmovl_high_u8(p.val[1]), vmovl_high_u8(p.val[2]));
    vst1q_u8(y + x, vcombine_u8(low, high));
  }
  if (x < width) rgb_to_luma_row_c(rgb + 3 * x, width - x, y + x);
}

// Four chroma samples from the 2x2 sums (at most 1020) of r, g, b, as chroma_from_sum4.
int32x4_t chroma_4(int32x4_t r, int32x4_t g, int32x4_t b, int wr, int wg, int wb) {
  const int32x4_t sum = vmlaq_n_s32(vmlaq_n_s32(vmulq_n_s32(r, wr), g, wg), b, wb);
  return vshrq_n_s32(vaddq_s32(sum, vdupq_n_s32((1 << 17) + (128 << 18))), 18);
}

uint8x8_t chroma_8(const int16x8_t (&sum)[3], int wr, int wg, int wb) {
  int32x4_t half[2][3];
  for (int c = 0; c < 3; ++c) {
    half[0][c] = vmovl_s16(vget_low_s16(sum[c]));
    half[1][c] = vmovl_high_s16(sum[c]);
  }
  const int32x4_t low = chroma_4(half[0][0], half[0][1], half[0][2], wr, wg, wb);
  const int32x4_t high = chroma_4(half[1][0], half[1][1], half[1][2], wr, wg, wb);
  return vqmovn_u16(vcombine_u16(vqmovun_s32(low), vqmovun_s32(high)));
}

void rgb_to_chroma_row_neon(const uint8_t* row0, const uint8_t* row1, int width, uint8_t* cb, uint8_t* cr) {
  int x = 0;
  for (; x + 16 <= width; x += 16) {
    const uint8x16x3_t p0 = vld3q_u8(row0 + 3 * x), p1 = vld3q_u8(row1 + 3 * x);
    int16x8_t sum[3];  // 2x2 sums per channel
    for (int c = 0; c < 3; ++c)
      sum[c] = vreinterpretq_s16_u16(vaddq_u16(vpaddlq_u8(p0.val[c]), vpaddlq_u8(p1.val[c])));
    vst1_u8(cb + x / 2, chroma_8(sum, kCbR, kCbG, kCbB));
    vst1_u8(cr + x / 2, chroma_8(sum, kCrR, kCrG, kCrB));
  }
  if (x < width) rgb_to_chroma_row_c(row0 + 3 * x, row1 + 3 * x, width - x, cb + x / 2, cr + x / 2);  // x is even
}

// (w0 d0 + w1 d1 + 32768) >> 16 of 8 chroma samples, in 32 bits (the weights reach 17).
int16x8_t chroma_term(int16x8_t d0, int w0, int16x8_t d1, int w1) {
  const int32x4_t low = vmlaq_n_s32(vmulq_n_s32(vmovl_s16(vget_low_s16(d0)), w0), vmovl_s16(vget_low_s16(d1)), w1);
  const int32x4_t high = vmlaq_n_s32(vmulq_n_s32(vmovl_high_s16(d0), w0), vmovl_high_s16(d1), w1);
  return vcombine_s16(vmovn_s32(vrshrq_n_s32(low, 16)), vmovn_s32(vrshrq_n_s32(high, 16)));
}

// Adds a chroma term (one per two pixels) to 16 luma samples and clamps to bytes.
uint8x16_t channel(uint8x16_t y, int16x8_t term) {
  const int16x8_t low = vaddq_s16(vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(y))), vzip1q_s16(term, term));
  const int16x8_t high = vaddq_s16(vreinterpretq_s16_u16(vmovl_high_u8(y)), vzip2q_s16(term, term));
  return vcombine_u8(vqmovun_s16(low), vqmovun_s16(high));
}

// R, G and B of 16 pixels at y[0..15] with chroma cb[0..7], cr[0..7].
uint8x16x3_t ycbcr_to_rgb_16(const uint8_t* y, const uint8_t* cb, const uint8_t* cr) {
  const int16x8_t bias = vdupq_n_s16(128);
  const int16x8_t dcb = vsubq_s16(vreinterpretq_s16_u16(vmovl_u8(vld1_u8(cb))), bias);
  const int16x8_t dcr = vsubq_s16(vreinterpretq_s16_u16(vmovl_u8(vld1_u8(cr))), bias);
  const uint8x16_t luma = vld1q_u8(y);
  uint8x16x3_t planes;
  planes.val[0] = channel(luma, chroma_term(dcr, kRCr, dcr, 0));
  planes.val[1] = channel(luma, chroma_term(dcb, kGCb, dcr, kGCr));
  planes.val[2] = channel(luma, chroma_term(dcb, kBCb, dcb, 0));
  return planes;
}

void store_rgb_16(const uint8x16x3_t& planes, uint8_t* rgb) { vst3q_u8(rgb, planes); }

void store_rgba_16(const uint8x16x3_t& planes, uint8_t* rgba) {
  vst4q_u8(rgba, uint8x16x4_t{{planes.val[0], planes.val[1], planes.val[2], vdupq_n_u8(255)}});
}

void store_bgra_16(const uint8x16x3_t& planes, uint8_t* bgra) {
  vst4q_u8(bgra, uint8x16x4_t{{planes.val[2], planes.val[1], planes.val[0], vdupq_n_u8(255)}});
}

using PixelStore16 = void (*)(const uint8x16x3_t& planes, uint8_t* out);
using ColorRow = void (*)(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* out);

// A row of kBytes-byte pixels: groups of 16 converted here and written by `store`, the
// rest by the plain kernel `tail` of the same layout.
template <PixelStore16 store, int kBytes, ColorRow tail>
void ycbcr_row_16(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* out) {
  int x = 0;
  for (; x + 16 <= width; x += 16) store(ycbcr_to_rgb_16(y + x, cb + x / 2, cr + x / 2), out + kBytes * x);
  if (x < width) tail(y + x, cb + x / 2, cr + x / 2, width - x, out + kBytes * x);  // x is even
}

}  // namespace

void init_color_neon(DspTable* table) {
  table->rgb_to_luma_row = rgb_to_luma_row_neon;
  table->rgb_to_chroma_row = rgb_to_chroma_row_neon;
  table->ycbcr_to_rgb_row = ycbcr_row_16<store_rgb_16, 3, ycbcr_to_rgb_row_c>;
  table->ycbcr_to_rgba_row = ycbcr_row_16<store_rgba_16, 4, ycbcr_to_rgba_row_c>;
  table->ycbcr_to_bgra_row = ycbcr_row_16<store_bgra_16, 4, ycbcr_to_bgra_row_c>;
}

}  // namespace svc::codec::dsp
