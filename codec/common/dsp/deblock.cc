// SPDX-License-Identifier: BSD-2-Clause
// Plain deblocking kernels (docs/codec.md, section 5.8 defines the arithmetic): the
// segments of an edge one after another, each the model of H.265 section 8.7.2.
#include <algorithm>
#include <cstdlib>

#include "codec/common/dsp/deblock_formulas.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

inline int clip_pixel(int v) { return std::clamp(v, 0, 255); }

// Sample k (k = -4..3) across the edge on line `line`: p_i is k = -1 - i, q_i is k = i.
struct Segment {
  uint8_t* origin;
  ptrdiff_t across, along;
  uint8_t& at(int line, int k) const { return origin[line * along + k * across]; }
};

void strong_filter_line(const Segment& s, int line, int tc) {
  const int p3 = s.at(line, -4), p2 = s.at(line, -3), p1 = s.at(line, -2), p0 = s.at(line, -1);
  const int q0 = s.at(line, 0), q1 = s.at(line, 1), q2 = s.at(line, 2), q3 = s.at(line, 3);
  const int t = 2 * tc;
  s.at(line, -1) = static_cast<uint8_t>(std::clamp((p2 + 2 * p1 + 2 * p0 + 2 * q0 + q1 + 4) >> 3, p0 - t, p0 + t));
  s.at(line, -2) = static_cast<uint8_t>(std::clamp((p2 + p1 + p0 + q0 + 2) >> 2, p1 - t, p1 + t));
  s.at(line, -3) = static_cast<uint8_t>(std::clamp((2 * p3 + 3 * p2 + p1 + p0 + q0 + 4) >> 3, p2 - t, p2 + t));
  s.at(line, 0) = static_cast<uint8_t>(std::clamp((p1 + 2 * p0 + 2 * q0 + 2 * q1 + q2 + 4) >> 3, q0 - t, q0 + t));
  s.at(line, 1) = static_cast<uint8_t>(std::clamp((p0 + q0 + q1 + q2 + 2) >> 2, q1 - t, q1 + t));
  s.at(line, 2) = static_cast<uint8_t>(std::clamp((p0 + q0 + q1 + 3 * q2 + 2 * q3 + 4) >> 3, q2 - t, q2 + t));
}

void normal_filter_line(const Segment& s, int line, int tc, bool filter_p1, bool filter_q1) {
  const int p2 = s.at(line, -3), p1 = s.at(line, -2), p0 = s.at(line, -1);
  const int q0 = s.at(line, 0), q1 = s.at(line, 1), q2 = s.at(line, 2);
  int delta = (9 * (q0 - p0) - 3 * (q1 - p1) + 8) >> 4;
  if (std::abs(delta) >= 10 * tc) return;  // a real edge of the picture, not a block edge
  delta = std::clamp(delta, -tc, tc);
  s.at(line, -1) = static_cast<uint8_t>(clip_pixel(p0 + delta));
  s.at(line, 0) = static_cast<uint8_t>(clip_pixel(q0 - delta));
  const int half = tc >> 1;
  if (filter_p1) {
    const int dp = std::clamp((((p2 + p0 + 1) >> 1) - p1 + delta) >> 1, -half, half);
    s.at(line, -2) = static_cast<uint8_t>(clip_pixel(p1 + dp));
  }
  if (filter_q1) {
    const int dq = std::clamp((((q2 + q0 + 1) >> 1) - q1 - delta) >> 1, -half, half);
    s.at(line, 1) = static_cast<uint8_t>(clip_pixel(q1 + dq));
  }
}

void filter_luma_segment(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int beta, int tc) {
  const LumaDecision decision = decide_luma_segment(pixels, across, along, beta, tc);
  const Segment s{pixels, across, along};
  for (int line = 0; line < 4; ++line) {
    if (decision.filter == LumaFilter::kStrong) strong_filter_line(s, line, tc);
    if (decision.filter == LumaFilter::kNormal)
      normal_filter_line(s, line, tc, decision.filter_p1, decision.filter_q1);
  }
}

void filter_chroma_segment(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int tc) {
  for (int line = 0; line < 4; ++line) {
    uint8_t* q = pixels + line * along;
    const int p1 = q[-2 * across], p0 = q[-across], q0 = q[0], q1 = q[across];
    const int delta = std::clamp((((q0 - p0) * 4) + p1 - q1 + 4) >> 3, -tc, tc);
    q[-across] = static_cast<uint8_t>(clip_pixel(p0 + delta));
    q[0] = static_cast<uint8_t>(clip_pixel(q0 - delta));
  }
}

void deblock_luma_c(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, int beta, const uint8_t* tc) {
  for (int s = 0; s < segments; ++s) {
    if (tc[s] != 0) filter_luma_segment(pixels + 4 * s * along, across, along, beta, tc[s]);
  }
}

void deblock_chroma_c(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, const uint8_t* tc) {
  for (int s = 0; s < segments; ++s) {
    if (tc[s] != 0) filter_chroma_segment(pixels + 4 * s * along, across, along, tc[s]);
  }
}

}  // namespace

void init_deblock_c(DspTable* table) {
  table->deblock_luma = deblock_luma_c;
  table->deblock_chroma = deblock_chroma_c;
}

}  // namespace svc::codec::dsp
