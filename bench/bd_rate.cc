// SPDX-License-Identifier: BSD-2-Clause
#include "bd_rate.h"

#include <algorithm>
#include <cmath>

namespace svc::bench {

namespace {

// Three-point end slope, kept monotone (the rule of MATLAB's and SciPy's pchip).
double end_slope(double h0, double h1, double m0, double m1) {
  double d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
  if (std::signbit(d) != std::signbit(m0) || m0 == 0) return 0;
  if (std::signbit(m0) != std::signbit(m1) && std::abs(d) > std::abs(3 * m0)) return 3 * m0;
  return d;
}

// Slopes at the knots: weighted harmonic mean of the neighbouring secants, zero at extrema.
std::vector<double> pchip_slopes(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  std::vector<double> h(n - 1), m(n - 1), d(n, 0.0);
  for (size_t k = 0; k + 1 < n; ++k) {
    h[k] = x[k + 1] - x[k];
    m[k] = (y[k + 1] - y[k]) / h[k];
  }
  if (n == 2) return {m[0], m[0]};
  for (size_t k = 1; k + 1 < n; ++k) {
    if (m[k - 1] * m[k] <= 0) continue;
    const double w1 = 2 * h[k] + h[k - 1], w2 = h[k] + 2 * h[k - 1];
    d[k] = (w1 + w2) / (w1 / m[k - 1] + w2 / m[k]);
  }
  d[0] = end_slope(h[0], h[1], m[0], m[1]);
  d[n - 1] = end_slope(h[n - 2], h[n - 3], m[n - 2], m[n - 3]);
  return d;
}

// Sorted by PSNR, one point per PSNR value, as (PSNR, log rate).
bool to_knots(std::vector<RatePoint> points, std::vector<double>* x, std::vector<double>* y) {
  std::sort(points.begin(), points.end(), [](const RatePoint& a, const RatePoint& b) {
    return a.psnr < b.psnr || (a.psnr == b.psnr && a.bytes < b.bytes);
  });
  for (const RatePoint& p : points) {
    if (!(p.bytes > 0) || !std::isfinite(p.psnr)) return false;
    if (!x->empty() && p.psnr == x->back()) continue;
    x->push_back(p.psnr);
    y->push_back(std::log(p.bytes));
  }
  return x->size() >= 2;
}

}  // namespace

double pchip_integral(const std::vector<double>& x, const std::vector<double>& y, double a, double b) {
  const std::vector<double> d = pchip_slopes(x, y);
  double total = 0;
  for (size_t k = 0; k + 1 < x.size(); ++k) {
    const double lo = std::max(a, x[k]), hi = std::min(b, x[k + 1]);
    if (!(hi > lo)) continue;
    // The segment's cubic in s = x - x[k], integrated term by term.
    const double h = x[k + 1] - x[k], m = (y[k + 1] - y[k]) / h;
    const double c0 = y[k], c1 = d[k], c2 = (3 * m - 2 * d[k] - d[k + 1]) / h,
                 c3 = (d[k] + d[k + 1] - 2 * m) / (h * h);
    auto antiderivative = [&](double s) { return s * (c0 + s * (c1 / 2 + s * (c2 / 3 + s * c3 / 4))); };
    total += antiderivative(hi - x[k]) - antiderivative(lo - x[k]);
  }
  return total;
}

std::optional<BdRate> bd_rate(std::vector<RatePoint> anchor, std::vector<RatePoint> test, double window_low,
                              double window_high) {
  std::vector<double> xa, ya, xt, yt;
  if (!to_knots(std::move(anchor), &xa, &ya) || !to_knots(std::move(test), &xt, &yt)) return std::nullopt;
  BdRate result;
  result.psnr_low = std::max({xa.front(), xt.front(), window_low});
  result.psnr_high = std::min({xa.back(), xt.back(), window_high});
  if (!(result.psnr_high > result.psnr_low)) return std::nullopt;
  const double mean_log_ratio = (pchip_integral(xt, yt, result.psnr_low, result.psnr_high) -
                                 pchip_integral(xa, ya, result.psnr_low, result.psnr_high)) /
                                (result.psnr_high - result.psnr_low);
  result.ratio = std::exp(mean_log_ratio);
  return result;
}

}  // namespace svc::bench
