// SPDX-License-Identifier: BSD-2-Clause
#include "rd_curve.h"

#include "bd_rate.h"

#include <algorithm>
#include <cmath>

namespace svc::bench {

RdCurve::RdCurve(std::vector<RdPoint> points) : points_(std::move(points)) {
  std::sort(points_.begin(), points_.end(), [](const RdPoint& a, const RdPoint& b) { return a.psnr_y < b.psnr_y; });
}

double RdCurve::min_psnr() const { return points_.empty() ? 0 : points_.front().psnr_y; }
double RdCurve::max_psnr() const { return points_.empty() ? 0 : points_.back().psnr_y; }

std::optional<double> RdCurve::bytes_at(double psnr) const {
  if (points_.size() < 2 || psnr < min_psnr() || psnr > max_psnr()) return std::nullopt;
  for (size_t i = 1; i < points_.size(); ++i) {
    const RdPoint& a = points_[i - 1];
    const RdPoint& b = points_[i];
    if (psnr <= b.psnr_y) {
      const double span = b.psnr_y - a.psnr_y;
      const double t = span > 1e-9 ? (psnr - a.psnr_y) / span : 0.0;
      return std::exp(std::log(a.bytes) + t * (std::log(b.bytes) - std::log(a.bytes)));
    }
  }
  return points_.back().bytes;
}

std::optional<RdPoint> RdCurve::first_at_or_above(double psnr) const {
  for (const RdPoint& p : points_) {
    if (p.psnr_y >= psnr) return p;
  }
  return std::nullopt;
}

std::optional<double> bd_rate_ratio(const RdCurve& anchor, const RdCurve& test) {
  auto rate_points = [](const RdCurve& curve) {
    std::vector<RatePoint> points;
    for (const RdPoint& p : curve.points()) points.push_back({p.bytes, p.psnr_y});
    return points;
  };
  const auto bd = bd_rate(rate_points(anchor), rate_points(test));
  if (!bd) return std::nullopt;
  return bd->ratio;
}

}  // namespace svc::bench
