// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/epipolar_lines.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "spatial/camera_terms.h"

namespace svc {
namespace {

constexpr double kSameOrientation = 1e-6;  // largest difference of a rotation entry
constexpr int kMaxScale = 64;              // integers up to this: direction within 1/128
constexpr double kExact = 1e-6;            // rounding error that counts as exact

bool same_frustum(const Frustum& a, const Frustum& b) {
  auto close = [](double x, double y) { return std::abs(x - y) <= kSameOrientation * std::max(1.0, std::abs(x)); };
  return close(a.left / a.near_plane, b.left / b.near_plane) &&
         close(a.right / a.near_plane, b.right / b.near_plane) &&
         close(a.bottom / a.near_plane, b.bottom / b.near_plane) &&
         close(a.top / a.near_plane, b.top / b.near_plane);
}

// The smallest integer multiple (up to kMaxScale) of `v` / max|v| that rounds exactly,
// else the one at kMaxScale; divided by the common factor of its entries.
codec::EpipolarLines small_integers(const std::array<double, 3>& v) {
  const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  std::array<int, 3> n{};
  for (int scale = 1; scale <= kMaxScale; ++scale) {
    double error = 0;
    for (size_t i = 0; i < 3; ++i) {
      const double x = scale * v[i] / largest;
      n[i] = static_cast<int>(std::lround(x));
      error = std::max(error, std::abs(x - n[i]));
    }
    if (error <= kExact) break;
  }
  const int common = std::gcd(std::gcd(n[0], n[1]), n[2]);
  return {n[0] / common, n[1] / common, n[2] / common};
}

}  // namespace

codec::EpipolarLines epipolar_lines(const Camera& current, const Camera& reference, int width, int height) {
  if (!same_frustum(current.frustum, reference.frustum) || width <= 0 || height <= 0) return {};
  // Current camera space -> reference camera space: a rotation other than the identity
  // moves points at infinity too.
  const glm::dmat4 combined = current_to_reference(current, reference);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      if (std::abs(combined[c][r] - (c == r ? 1.0 : 0.0)) > kSameOrientation) return {};
    }
  }
  const glm::dvec3 t(combined[3]);
  const ProjectionTerms p = projection_terms(current.frustum);
  // The flow of a point at eye depth z is (tz X + w (p00 tx + p02 tz), tz Y - h (p11 ty +
  // p12 tz)) / (2 (z - tz)) pixels, X and Y as in codec/common/epipolar.h.
  const std::array<double, 3> direction = {t.z, p.p00 * t.x + p.p02 * t.z, -(p.p11 * t.y + p.p12 * t.z)};
  if (std::max({std::abs(direction[0]), std::abs(direction[1]), std::abs(direction[2])}) < kSameOrientation)
    return {};
  return small_integers(direction);
}

}  // namespace svc
