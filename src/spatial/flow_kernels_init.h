// SPDX-License-Identifier: BSD-2-Clause
// Internal to the flow kernels: the per-pixel formulas that the plain kernels loop over
// and the x86 variants use for their tails (internal linkage, so code built for one
// instruction set is never linked into another's callers), and the variants' init.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "spatial/flow_kernels.h"

namespace svc {
namespace {

// Pixel i of a flow row; the SSE2 kernel does the same operations in the same order.
inline void flow_pixel(const FlowRow& r, int i, float z, float* dx, float* dy, uint8_t* valid) {
  const double dir_x = r.column_x[i] + r.row_x, dir_y = r.column_y[i] + r.row_y, dir_z = r.column_z[i] + r.row_z;
  // Background is a point at infinity: only the direction moves (rotation only). Written
  // as "not inside (0, far)" so that a NaN far plane makes everything background.
  const bool background = !(z > 0.0f && std::isfinite(z) && static_cast<double>(z) < r.far_plane);
  const double scale = background ? 1.0 : static_cast<double>(z);
  const double shift = background ? 0.0 : 1.0;
  const double px = scale * dir_x + shift * r.shift_x;
  const double py = scale * dir_y + shift * r.shift_y;
  const double pz = scale * dir_z + shift * r.shift_z;
  const bool in_front = pz < -kMinDepthInFront;
  const double inv = -1.0 / (in_front ? pz : -1.0);
  const double u = (r.p00 * px * inv - r.p02 + 1.0) * 0.5 * r.width - 0.5;
  const double v = (1.0 - (r.p11 * py * inv - r.p12)) * 0.5 * r.height - 0.5;
  const double fx = u - i, fy = v - r.row;
  const double largest = std::numeric_limits<double>::max();
  const bool ok = in_front & (std::abs(fx) <= largest) & (std::abs(fy) <= largest);
  *dx = ok ? static_cast<float>(fx) : 0.0f;
  *dy = ok ? static_cast<float>(fy) : 0.0f;
  *valid = ok;
}

// One component in quarter pels, halves away from zero; false beyond +-limit, for NaN
// and for infinities. Every float step is exact (multiplying by 4, truncating a value
// below 2^15, subtracting that), so four lanes at a time give the same results.
inline bool round_half_away(float d, float bound, int limit, int* out) {
  const float scaled = d * 4.0f;
  const bool in_range = std::abs(scaled) < bound;  // false for NaN
  const float safe = in_range ? scaled : 0.0f;
  int rounded = static_cast<int>(safe);
  const float fraction = safe - static_cast<float>(rounded);
  rounded += static_cast<int>(fraction >= 0.5f) - static_cast<int>(fraction <= -0.5f);
  *out = rounded;
  return in_range & (rounded <= limit) & (rounded >= -limit);
}

inline int32_t quarter_pel_key(float dx, float dy, uint8_t valid, int limit, int32_t no_key) {
  const float bound = static_cast<float>(limit) + 0.5f;
  int x = 0, y = 0;
  const bool x_ok = round_half_away(dx, bound, limit, &x);
  const bool y_ok = round_half_away(dy, bound, limit, &y);
  return (valid != 0) & x_ok & y_ok ? y * 65536 + x : no_key;
}

}  // namespace

#if defined(__x86_64__) || defined(__i386__)
void init_flow_sse2(FlowKernels* kernels);
#endif

}  // namespace svc
