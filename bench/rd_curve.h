// SPDX-License-Identifier: BSD-2-Clause
// Rate-distortion curves and comparisons at equal quality, shared by the benchmarks.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace svc::bench {

struct RdPoint {
  int setting = 0;  // the quantizer / quality that produced it
  double bytes = 0;
  double psnr_y = 0;   // dB
  double seconds = 0;  // encode time
};

// Points sorted by PSNR; log(bytes) is interpolated linearly in PSNR between them.
class RdCurve {
 public:
  explicit RdCurve(std::vector<RdPoint> points);
  const std::vector<RdPoint>& points() const { return points_; }
  double min_psnr() const;
  double max_psnr() const;
  // Bytes needed for `psnr`, when it lies inside the curve's range.
  std::optional<double> bytes_at(double psnr) const;
  // The setting whose point lies nearest to `psnr` and at or above it, if any.
  std::optional<RdPoint> first_at_or_above(double psnr) const;

 private:
  std::vector<RdPoint> points_;
};

// Mean of log-byte differences over the PSNR range both curves cover (PCHIP, see
// bd_rate.h), as a size ratio (test / anchor): the Bjontegaard rate difference is
// ratio - 1. nullopt without overlap.
std::optional<double> bd_rate_ratio(const RdCurve& anchor, const RdCurve& test);

}  // namespace svc::bench
