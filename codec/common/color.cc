// SPDX-License-Identifier: BSD-2-Clause
// Full-range BT.601 (JFIF) conversion of whole decoded images to RGB through the dsp row
// kernel, and the per-pixel reference it is tested against.
#include "codec/common/color.h"

#include <algorithm>

#include "codec/common/dsp/color_formulas.h"
#include "codec/common/dsp/dsp.h"

namespace svc::codec {

using namespace dsp::color;

void ycbcr_to_rgb_pixel(uint8_t y, uint8_t cb, uint8_t cr, uint8_t rgb_out[3]) { to_rgb(y, cb, cr, rgb_out); }

void ycbcr420_to_rgb(const ImageYCbCr420& image, uint8_t* rgb_out) {
  ycbcr420_to_pixels(image, PixelFormat::kRGB8, RowOrder::kTopDown, {rgb_out, nullptr, nullptr},
                     {static_cast<size_t>(image.width) * 3, 0, 0});
}

void ycbcr420_to_pixels(const ImageYCbCr420& image, PixelFormat format, RowOrder order,
                        const std::array<uint8_t*, 3>& planes, const std::array<size_t, 3>& strides) {
  auto row_start = [&](int plane, int row, int rows) {
    const int stored = order == RowOrder::kTopDown ? row : rows - 1 - row;
    return planes[static_cast<size_t>(plane)] + static_cast<size_t>(stored) * strides[static_cast<size_t>(plane)];
  };
  const int width = image.width, height = image.height, cw = (width + 1) / 2, ch = (height + 1) / 2;
  if (format == PixelFormat::kYCbCr420) {
    for (int y = 0; y < height; ++y)
      std::copy_n(image.y.data() + static_cast<size_t>(y) * width, width, row_start(0, y, height));
    for (int y = 0; y < ch; ++y) {
      std::copy_n(image.cb.data() + static_cast<size_t>(y) * cw, cw, row_start(1, y, ch));
      std::copy_n(image.cr.data() + static_cast<size_t>(y) * cw, cw, row_start(2, y, ch));
    }
    return;
  }
  const dsp::DspTable& dsp = dsp::get_dsp();
  const auto row_kernel = format == PixelFormat::kRGBA8   ? dsp.ycbcr_to_rgba_row
                          : format == PixelFormat::kBGRA8 ? dsp.ycbcr_to_bgra_row
                                                          : dsp.ycbcr_to_rgb_row;
  for (int y = 0; y < height; ++y) {
    const size_t chroma_row = static_cast<size_t>(y / 2) * cw;
    row_kernel(image.y.data() + static_cast<size_t>(y) * width, image.cb.data() + chroma_row,
               image.cr.data() + chroma_row, width, row_start(0, y, height));
  }
}

void ycbcr420_to_rgb_reference(const ImageYCbCr420& image, uint8_t* rgb_out) {
  const int cw = (image.width + 1) / 2;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t c = static_cast<size_t>(y / 2) * cw + x / 2;
      ycbcr_to_rgb_pixel(image.y[static_cast<size_t>(y) * image.width + x], image.cb[c], image.cr[c],
                         rgb_out + (static_cast<size_t>(y) * image.width + x) * 3);
    }
  }
}

}  // namespace svc::codec
