// SPDX-License-Identifier: BSD-2-Clause
// The per-segment decisions of the luma deblocking filter (docs/codec.md, section 5.8),
// shared by the plain kernel and the NEON variant, which differ only in how they filter
// the four lines (the SSE4.1 variant makes the same decisions as lane masks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace svc::codec::dsp {

enum class LumaFilter : uint8_t { kNone, kNormal, kStrong };

struct LumaDecision {
  LumaFilter filter = LumaFilter::kNone;
  bool filter_p1 = false, filter_q1 = false;  // normal filter: also p1 / q1
};

// `pixels` is q0 of line 0; p_i at -(i + 1) across, q_i at i across.
inline LumaDecision decide_luma_segment(const uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int beta,
                                        int tc) {
  auto at = [&](int line, int k) { return static_cast<int>(pixels[line * along + k * across]); };
  // Second differences on each side of lines 0 and 3: how textured the edge's surroundings are.
  auto dp = [&](int line) { return std::abs(at(line, -3) - 2 * at(line, -2) + at(line, -1)); };
  auto dq = [&](int line) { return std::abs(at(line, 2) - 2 * at(line, 1) + at(line, 0)); };
  const int dp0 = dp(0), dp3 = dp(3), dq0 = dq(0), dq3 = dq(3);
  const int dpq0 = dp0 + dq0, dpq3 = dp3 + dq3;
  LumaDecision decision;
  if (dpq0 + dpq3 >= beta) return decision;  // textured: the step is likely content
  auto strong_line = [&](int line, int dpq) {
    return 2 * dpq < (beta >> 2) &&
           std::abs(at(line, -4) - at(line, -1)) + std::abs(at(line, 0) - at(line, 3)) < (beta >> 3) &&
           std::abs(at(line, -1) - at(line, 0)) < ((5 * tc + 1) >> 1);
  };
  if (strong_line(0, dpq0) && strong_line(3, dpq3)) {
    decision.filter = LumaFilter::kStrong;
    return decision;
  }
  const int side_threshold = (beta + (beta >> 1)) >> 3;
  decision.filter = LumaFilter::kNormal;
  decision.filter_p1 = dp0 + dp3 < side_threshold;
  decision.filter_q1 = dq0 + dq3 < side_threshold;
  return decision;
}

}  // namespace svc::codec::dsp
