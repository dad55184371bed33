// Full-range BT.601 (JFIF) conversion of whole decoded images to RGB through the dsp row
// kernel, and the per-pixel reference it is tested against.
#include "codec/common/color.h"

#include "codec/common/dsp/color_formulas.h"
#include "codec/common/dsp/dsp.h"

namespace svc::codec {

using namespace dsp::color;

void ycbcr_to_rgb_pixel(uint8_t y, uint8_t cb, uint8_t cr, uint8_t rgb_out[3]) { to_rgb(y, cb, cr, rgb_out); }

void ycbcr420_to_rgb(const ImageYCbCr420& image, uint8_t* rgb_out) {
  const dsp::DspTable& dsp = dsp::get_dsp();
  const int width = image.width, height = image.height, cw = (width + 1) / 2;
  for (int y = 0; y < height; ++y) {
    const size_t chroma_row = static_cast<size_t>(y / 2) * cw;
    dsp.ycbcr_to_rgb_row(image.y.data() + static_cast<size_t>(y) * width, image.cb.data() + chroma_row,
                         image.cr.data() + chroma_row, width, rgb_out + static_cast<size_t>(y) * width * 3);
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
