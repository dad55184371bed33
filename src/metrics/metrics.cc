// SPDX-License-Identifier: BSD-2-Clause
#include "svc/metrics.h"

#include "codec/encoder/rgb_to_ycbcr.h"

#include <cmath>
#include <string>
#include <vector>

namespace svc {

namespace {

Status check_sizes(const ImageRGB8& a, const ImageRGB8& b) {
  if (a.width != b.width || a.height != b.height ||
      a.pixels.size() != static_cast<size_t>(a.width) * a.height * 3 || b.pixels.size() != a.pixels.size()) {
    return Status(ErrorCode::kInvalidArgument, "images differ in size: " + std::to_string(a.width) + "x" +
                                                   std::to_string(a.height) + " and " + std::to_string(b.width) +
                                                   "x" + std::to_string(b.height));
  }
  return Status::Ok();
}

// Luma through the codec's own color conversion, so PSNR-Y measures what it codes.
std::vector<uint8_t> luma_of(const ImageRGB8& image) {
  std::vector<uint8_t> y(static_cast<size_t>(image.width) * image.height);
  for (size_t i = 0; i < y.size(); ++i) {
    y[i] = codec::rgb_to_ycbcr_pixel(image.pixels[3 * i], image.pixels[3 * i + 1], image.pixels[3 * i + 2]).y;
  }
  return y;
}

}  // namespace

double SquaredError::psnr() const {
  if (count == 0 || sum <= 0) return 99.0;
  const double mse = sum / static_cast<double>(count);
  return std::min(99.0, 10.0 * std::log10(255.0 * 255.0 / mse));
}

Result<SquaredError> rgb_squared_error(const ImageRGB8& a, const ImageRGB8& b) {
  SVC_RETURN_IF_ERROR(check_sizes(a, b));
  SquaredError e;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = static_cast<double>(a.pixels[i]) - b.pixels[i];
    e.sum += d * d;
  }
  e.count = a.pixels.size();
  return e;
}

Result<SquaredError> luma_squared_error(const ImageRGB8& a, const ImageRGB8& b) {
  SVC_RETURN_IF_ERROR(check_sizes(a, b));
  const std::vector<uint8_t> ya = luma_of(a), yb = luma_of(b);
  SquaredError e;
  for (size_t i = 0; i < ya.size(); ++i) {
    const double d = static_cast<double>(ya[i]) - yb[i];
    e.sum += d * d;
  }
  e.count = ya.size();
  return e;
}

Result<double> luma_ssim(const ImageRGB8& a, const ImageRGB8& b) {
  SVC_RETURN_IF_ERROR(check_sizes(a, b));
  const std::vector<uint8_t> ya = luma_of(a), yb = luma_of(b);
  const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  const int w = a.width, h = a.height;
  double total = 0;
  int windows = 0;
  for (int y0 = 0; y0 + 8 <= h; y0 += 4) {
    for (int x0 = 0; x0 + 8 <= w; x0 += 4) {
      double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
      for (int y = y0; y < y0 + 8; ++y) {
        for (int x = x0; x < x0 + 8; ++x) {
          const double va = ya[static_cast<size_t>(y) * w + x], vb = yb[static_cast<size_t>(y) * w + x];
          sa += va;
          sb += vb;
          saa += va * va;
          sbb += vb * vb;
          sab += va * vb;
        }
      }
      const double n = 64, ma = sa / n, mb = sb / n;
      const double va = saa / n - ma * ma, vb = sbb / n - mb * mb, cov = sab / n - ma * mb;
      total += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++windows;
    }
  }
  if (windows == 0) return 1.0;
  return total / windows;
}

}  // namespace svc
