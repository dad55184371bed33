// SPDX-License-Identifier: BSD-2-Clause
// Image quality metrics used by the tools and benchmarks.
#pragma once

#include "svc/export.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

// Accumulates squared error so PSNR can be computed over many images at once.
struct SquaredError {
  double sum = 0;      // sum of squared sample differences
  uint64_t count = 0;  // samples compared
  void add(const SquaredError& other) {
    sum += other.sum;
    count += other.count;
  }
  // 10*log10(255^2 / MSE); 99 dB when identical.
  double psnr() const;
};

// Over all three RGB channels. Errors when sizes differ.
SVC_API Result<SquaredError> rgb_squared_error(const ImageRGB8& a, const ImageRGB8& b);
// Over luma, computed with svc's color conversion (docs/codec.md).
SVC_API Result<SquaredError> luma_squared_error(const ImageRGB8& a, const ImageRGB8& b);
// Mean SSIM of luma over 8x8 windows with stride 4 (as in common codec tools).
SVC_API Result<double> luma_ssim(const ImageRGB8& a, const ImageRGB8& b);

}  // namespace svc
