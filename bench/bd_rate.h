// SPDX-License-Identifier: BSD-2-Clause
// Bjontegaard delta rate by the method of the common test conditions (JCTVC-L1100 and
// its successors): log-rate as a piecewise cubic Hermite (PCHIP, Fritsch-Carlson
// monotone slopes as in the CTC spreadsheet) function of PSNR for each curve, integrated
// exactly over the PSNR range both curves cover.
#pragma once

#include <optional>
#include <vector>

namespace svc::bench {

struct RatePoint {
  double bytes = 0;  // any rate unit; only ratios matter
  double psnr = 0;   // dB
};

struct BdRate {
  double ratio = 1;     // test bytes / anchor bytes at equal PSNR; BD-rate = ratio - 1
  double psnr_low = 0;  // the overlapping PSNR range it was averaged over
  double psnr_high = 0;
};

// nullopt when either curve has fewer than two distinct PSNR values, a rate <= 0, or the
// curves share no PSNR range (within [window_low, window_high] dB when given). Points may
// come in any order; of points with equal PSNR the smallest rate is kept.
std::optional<BdRate> bd_rate(std::vector<RatePoint> anchor, std::vector<RatePoint> test, double window_low = -1e9,
                              double window_high = 1e9);

// Integral of the PCHIP through (x[i], y[i]) (x strictly increasing, at least two
// points) from a to b, x.front() <= a <= b <= x.back().
double pchip_integral(const std::vector<double>& x, const std::vector<double>& y, double a, double b);

}  // namespace svc::bench
