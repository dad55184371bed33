// SPDX-License-Identifier: BSD-2-Clause
// PSNR over RGB and BT.601 luma, the measure shared by the baseline and its benchmarks.
#include <cmath>
#include <limits>

#include "baseline/baseline.h"

namespace svc::baseline {

namespace {

struct SquaredErrors {
  double rgb = 0;  // sum over all R, G, B samples
  double y = 0;    // sum over all pixels
  uint64_t pixels = 0;
};

double luma(const uint8_t* rgb) { return 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2]; }

Status accumulate(const ImageRGB8& reference, const ImageRGB8& decoded, SquaredErrors* sums) {
  const size_t expected = static_cast<size_t>(reference.width) * reference.height * 3;
  if (reference.width <= 0 || reference.height <= 0 || reference.pixels.size() != expected) {
    return Status(ErrorCode::kInvalidArgument, "reference image is empty or malformed");
  }
  if (decoded.width != reference.width || decoded.height != reference.height || decoded.pixels.size() != expected) {
    return Status(ErrorCode::kInvalidArgument,
                  "decoded image is " + std::to_string(decoded.width) + "x" + std::to_string(decoded.height) +
                      ", reference is " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
  }
  const uint8_t* a = reference.pixels.data();
  const uint8_t* b = decoded.pixels.data();
  double rgb = 0, y = 0;
  for (size_t i = 0; i < expected; i += 3) {
    for (int c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a[i + c]) - b[i + c];
      rgb += d * d;
    }
    const double dy = luma(a + i) - luma(b + i);
    y += dy * dy;
  }
  sums->rgb += rgb;
  sums->y += y;
  sums->pixels += expected / 3;
  return Status::Ok();
}

Quality to_quality(const SquaredErrors& sums) {
  Quality quality;
  quality.mse_rgb = sums.rgb / (3.0 * static_cast<double>(sums.pixels));
  quality.mse_y = sums.y / static_cast<double>(sums.pixels);
  quality.psnr_rgb = psnr_from_mse(quality.mse_rgb);
  quality.psnr_y = psnr_from_mse(quality.mse_y);
  return quality;
}

}  // namespace

double psnr_from_mse(double mse) {
  if (mse <= 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

Result<Quality> compare_images(const ImageRGB8& reference, const ImageRGB8& decoded) {
  SquaredErrors sums;
  SVC_RETURN_IF_ERROR(accumulate(reference, decoded, &sums));
  return to_quality(sums);
}

Result<Quality> compare_sequences(std::span<const ImageRGB8> reference, std::span<const ImageRGB8> decoded) {
  if (reference.empty() || reference.size() != decoded.size()) {
    return Status(ErrorCode::kInvalidArgument, "sequences have " + std::to_string(reference.size()) + " and " +
                                                   std::to_string(decoded.size()) + " frames");
  }
  SquaredErrors sums;
  for (size_t k = 0; k < reference.size(); ++k) {
    Status status = accumulate(reference[k], decoded[k], &sums);
    if (!status.ok()) return status.with_context("frame " + std::to_string(k));
  }
  return to_quality(sums);
}

}  // namespace svc::baseline
