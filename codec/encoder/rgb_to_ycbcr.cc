// SPDX-License-Identifier: BSD-2-Clause
// Full-range BT.601 (JFIF) conversion of whole input images to YCbCr 4:2:0 through the
// dsp row kernels, and the per-pixel references they are tested against.
#include "codec/encoder/rgb_to_ycbcr.h"

#include <algorithm>

#include "codec/common/dsp/color_formulas.h"
#include "codec/common/dsp/dsp.h"

namespace svc::codec {
namespace {

using namespace dsp::color;

ImageYCbCr420 allocate(int width, int height) {
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  const size_t cw = static_cast<size_t>((width + 1) / 2), ch = static_cast<size_t>((height + 1) / 2);
  image.y.resize(static_cast<size_t>(width) * static_cast<size_t>(height));
  image.cb.resize(cw * ch);
  image.cr.resize(cw * ch);
  return image;
}

}  // namespace

YCbCr rgb_to_ycbcr_pixel(uint8_t r, uint8_t g, uint8_t b) {
  return {luma(r, g, b), chroma_from_sum4(4 * cb_unscaled(r, g, b)), chroma_from_sum4(4 * cr_unscaled(r, g, b))};
}

ImageYCbCr420 rgb_to_ycbcr420(const uint8_t* rgb, int width, int height) {
  if (width <= 0 || height <= 0) return ImageYCbCr420{};
  const dsp::DspTable& dsp = dsp::get_dsp();
  ImageYCbCr420 image = allocate(width, height);
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  const size_t stride = static_cast<size_t>(width) * 3;
  for (int y = 0; y < height; ++y) {
    dsp.rgb_to_luma_row(rgb + static_cast<size_t>(y) * stride, width,
                        image.y.data() + static_cast<size_t>(y) * width);
  }
  for (int cy = 0; cy < ch; ++cy) {
    const uint8_t* row0 = rgb + static_cast<size_t>(2 * cy) * stride;
    const uint8_t* row1 = rgb + static_cast<size_t>(std::min(2 * cy + 1, height - 1)) * stride;
    dsp.rgb_to_chroma_row(row0, row1, width, image.cb.data() + static_cast<size_t>(cy) * cw,
                          image.cr.data() + static_cast<size_t>(cy) * cw);
  }
  return image;
}

ImageYCbCr420 rgb_to_ycbcr420_reference(const uint8_t* rgb, int width, int height) {
  if (width <= 0 || height <= 0) return ImageYCbCr420{};
  ImageYCbCr420 image = allocate(width, height);
  const int cw = (width + 1) / 2;
  auto pixel = [&](int x, int y) {
    x = std::min(x, width - 1);
    y = std::min(y, height - 1);
    return rgb + (static_cast<size_t>(y) * width + x) * 3;
  };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint8_t* p = pixel(x, y);
      image.y[static_cast<size_t>(y) * width + x] = luma(p[0], p[1], p[2]);
      if ((x | y) & 1) continue;
      int cb = 0, cr = 0;
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
          const uint8_t* q = pixel(x + dx, y + dy);
          cb += cb_unscaled(q[0], q[1], q[2]);
          cr += cr_unscaled(q[0], q[1], q[2]);
        }
      }
      const size_t c = static_cast<size_t>(y / 2) * cw + x / 2;
      image.cb[c] = chroma_from_sum4(cb);
      image.cr[c] = chroma_from_sum4(cr);
    }
  }
  return image;
}

}  // namespace svc::codec
