// SPDX-License-Identifier: BSD-2-Clause
// Plain color-conversion row kernels (formulas in color_formulas.h).
#include "codec/common/dsp/color_formulas.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {

using namespace color;

void rgb_to_luma_row_c(const uint8_t* rgb, int width, uint8_t* y) {
  for (int x = 0; x < width; ++x) y[x] = luma(rgb[3 * x], rgb[3 * x + 1], rgb[3 * x + 2]);
}

void rgb_to_chroma_row_c(const uint8_t* row0, const uint8_t* row1, int width, uint8_t* cb, uint8_t* cr) {
  const int cw = (width + 1) / 2;
  for (int cx = 0; cx < cw; ++cx) {
    const int x0 = 2 * cx * 3, x1 = std::min(2 * cx + 1, width - 1) * 3;
    const int r = row0[x0] + row0[x1] + row1[x0] + row1[x1];
    const int g = row0[x0 + 1] + row0[x1 + 1] + row1[x0 + 1] + row1[x1 + 1];
    const int b = row0[x0 + 2] + row0[x1 + 2] + row1[x0 + 2] + row1[x1 + 2];
    // Linear, so the sum of four pixels' unscaled chroma is the unscaled chroma of the sum.
    cb[cx] = chroma_from_sum4(cb_unscaled(r, g, b));
    cr[cx] = chroma_from_sum4(cr_unscaled(r, g, b));
  }
}

void ycbcr_to_rgb_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgb) {
  for (int x = 0; x < width; ++x) to_rgb(y[x], cb[x >> 1], cr[x >> 1], rgb + 3 * x);
}

void ycbcr_to_rgba_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* rgba) {
  for (int x = 0; x < width; ++x) {
    to_rgb(y[x], cb[x >> 1], cr[x >> 1], rgba + 4 * x);
    rgba[4 * x + 3] = 255;
  }
}

void ycbcr_to_bgra_row_c(const uint8_t* y, const uint8_t* cb, const uint8_t* cr, int width, uint8_t* bgra) {
  for (int x = 0; x < width; ++x) {
    uint8_t rgb[3];
    to_rgb(y[x], cb[x >> 1], cr[x >> 1], rgb);
    bgra[4 * x] = rgb[2];
    bgra[4 * x + 1] = rgb[1];
    bgra[4 * x + 2] = rgb[0];
    bgra[4 * x + 3] = 255;
  }
}

void init_color_c(DspTable* table) {
  table->rgb_to_luma_row = rgb_to_luma_row_c;
  table->rgb_to_chroma_row = rgb_to_chroma_row_c;
  table->ycbcr_to_rgb_row = ycbcr_to_rgb_row_c;
  table->ycbcr_to_rgba_row = ycbcr_to_rgba_row_c;
  table->ycbcr_to_bgra_row = ycbcr_to_bgra_row_c;
}

}  // namespace svc::codec::dsp
