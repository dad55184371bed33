// Full-range BT.601 (JFIF) colour conversion in 16-bit fixed point. The constants sum
// exactly to 65536 (luma) and 0 (chroma), so greys map to Y = grey, Cb = Cr = 128 and
// back without error.
#include "codec/color.h"

#include <algorithm>

namespace svc::codec {
namespace {

constexpr int kYR = 19595, kYG = 38470, kYB = 7471;        // 0.299, 0.587, 0.114
constexpr int kCbR = -11059, kCbG = -21709, kCbB = 32768;  // -0.168736, -0.331264, 0.5
constexpr int kCrR = 32768, kCrG = -27439, kCrB = -5329;   // 0.5, -0.418688, -0.081312
constexpr int kRCr = 91881;                                // 1.402
constexpr int kGCb = -22554, kGCr = -46802;                // -0.344136, -0.714136
constexpr int kBCb = 116130;                               // 1.772

inline uint8_t clamp_byte(int v) { return static_cast<uint8_t>(std::clamp(v, 0, 255)); }

inline uint8_t luma(int r, int g, int b) {
  return clamp_byte((kYR * r + kYG * g + kYB * b + 32768) >> 16);
}
inline int cb_unscaled(int r, int g, int b) { return kCbR * r + kCbG * g + kCbB * b; }
inline int cr_unscaled(int r, int g, int b) { return kCrR * r + kCrG * g + kCrB * b; }

// Chroma of a 2x2 group from the sum of the four unscaled values: rounded mean + 128.
inline uint8_t chroma_from_sum4(int sum) { return clamp_byte((sum + (1 << 17) + (128 << 18)) >> 18); }

inline void to_rgb(int y, int cb, int cr, uint8_t* out) {
  const int dcb = cb - 128, dcr = cr - 128;
  out[0] = clamp_byte(y + ((kRCr * dcr + 32768) >> 16));
  out[1] = clamp_byte(y + ((kGCb * dcb + kGCr * dcr + 32768) >> 16));
  out[2] = clamp_byte(y + ((kBCb * dcb + 32768) >> 16));
}

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
  return {luma(r, g, b), chroma_from_sum4(4 * cb_unscaled(r, g, b)),
          chroma_from_sum4(4 * cr_unscaled(r, g, b))};
}

void ycbcr_to_rgb_pixel(uint8_t y, uint8_t cb, uint8_t cr, uint8_t rgb_out[3]) {
  to_rgb(y, cb, cr, rgb_out);
}

ImageYCbCr420 rgb_to_ycbcr420(const uint8_t* rgb, int width, int height) {
  if (width <= 0 || height <= 0) return ImageYCbCr420{};
  ImageYCbCr420 image = allocate(width, height);
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  const size_t stride = static_cast<size_t>(width) * 3;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = rgb + static_cast<size_t>(y) * stride;
    uint8_t* out = image.y.data() + static_cast<size_t>(y) * width;
    for (int x = 0; x < width; ++x) out[x] = luma(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
  }
  for (int cy = 0; cy < ch; ++cy) {
    const uint8_t* row0 = rgb + static_cast<size_t>(2 * cy) * stride;
    const uint8_t* row1 = rgb + static_cast<size_t>(std::min(2 * cy + 1, height - 1)) * stride;
    uint8_t* out_cb = image.cb.data() + static_cast<size_t>(cy) * cw;
    uint8_t* out_cr = image.cr.data() + static_cast<size_t>(cy) * cw;
    for (int cx = 0; cx < cw; ++cx) {
      const int x0 = 2 * cx * 3, x1 = std::min(2 * cx + 1, width - 1) * 3;
      const int r = row0[x0] + row0[x1] + row1[x0] + row1[x1];
      const int g = row0[x0 + 1] + row0[x1 + 1] + row1[x0 + 1] + row1[x1 + 1];
      const int b = row0[x0 + 2] + row0[x1 + 2] + row1[x0 + 2] + row1[x1 + 2];
      // Linear, so the sum of four pixels' unscaled chroma is the unscaled chroma of the sum.
      out_cb[cx] = chroma_from_sum4(cb_unscaled(r, g, b));
      out_cr[cx] = chroma_from_sum4(cr_unscaled(r, g, b));
    }
  }
  return image;
}

void ycbcr420_to_rgb(const ImageYCbCr420& image, uint8_t* rgb_out) {
  const int width = image.width, height = image.height, cw = (width + 1) / 2;
  for (int y = 0; y < height; ++y) {
    const uint8_t* yrow = image.y.data() + static_cast<size_t>(y) * width;
    const uint8_t* cbrow = image.cb.data() + static_cast<size_t>(y / 2) * cw;
    const uint8_t* crrow = image.cr.data() + static_cast<size_t>(y / 2) * cw;
    uint8_t* out = rgb_out + static_cast<size_t>(y) * width * 3;
    for (int x = 0; x < width; ++x) to_rgb(yrow[x], cbrow[x >> 1], crrow[x >> 1], out + 3 * x);
  }
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

void ycbcr420_to_rgb_reference(const ImageYCbCr420& image, uint8_t* rgb_out) {
  const int cw = (image.width + 1) / 2;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t c = static_cast<size_t>(y / 2) * cw + x / 2;
      ycbcr_to_rgb_pixel(image.y[static_cast<size_t>(y) * image.width + x], image.cb[c],
                         image.cr[c], rgb_out + (static_cast<size_t>(y) * image.width + x) * 3);
    }
  }
}

}  // namespace svc::codec
