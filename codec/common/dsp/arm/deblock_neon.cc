// SPDX-License-Identifier: BSD-2-Clause
// NEON deblocking kernels: the four lines of a segment side by side in 16-bit lanes, one
// vector per sample position across the edge, the decisions shared with the plain kernel
// (deblock_formulas.h). Table lookups transpose a vertical edge's lines into those
// vectors and back; saturating narrows are the plain kernel's clips to 0..255.
#include <arm_neon.h>

#include <cstring>

#include "codec/common/dsp/deblock_formulas.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

// Samples k = -4..3 across the edge (index k + 4), lanes 0..3 the four lines.
struct Columns {
  int16x4_t c[8];
};

// Byte 4 k + l of the result: sample k of line l, from lines (8 bytes each) in order,
// and the inverse.
constexpr uint8_t kLinesToColumns[2][16] = {{0, 8, 16, 24, 1, 9, 17, 25, 2, 10, 18, 26, 3, 11, 19, 27},
                                            {4, 12, 20, 28, 5, 13, 21, 29, 6, 14, 22, 30, 7, 15, 23, 31}};
constexpr uint8_t kColumnsToLines[2][16] = {{0, 4, 8, 12, 16, 20, 24, 28, 1, 5, 9, 13, 17, 21, 25, 29},
                                            {2, 6, 10, 14, 18, 22, 26, 30, 3, 7, 11, 15, 19, 23, 27, 31}};

// Eight columns of four bytes, as two vectors of four columns each.
Columns widen(uint8x16_t low, uint8x16_t high) {
  Columns s;
  const uint16x8_t halves[4] = {vmovl_u8(vget_low_u8(low)), vmovl_high_u8(low), vmovl_u8(vget_low_u8(high)),
                                vmovl_high_u8(high)};
  for (int i = 0; i < 4; ++i) {
    s.c[2 * i] = vreinterpret_s16_u16(vget_low_u16(halves[i]));
    s.c[2 * i + 1] = vreinterpret_s16_u16(vget_high_u16(halves[i]));
  }
  return s;
}

inline uint8x16_t narrow(int16x4_t a, int16x4_t b, int16x4_t c, int16x4_t d) {
  return vcombine_u8(vqmovun_s16(vcombine_s16(a, b)), vqmovun_s16(vcombine_s16(c, d)));
}

Columns load_columns(const uint8_t* pixels, ptrdiff_t across, ptrdiff_t along) {
  if (across == 1) {  // vertical edge: each line is 8 contiguous bytes
    const uint8_t* line = pixels - 4;
    const uint8x16x2_t lines = {{vcombine_u8(vld1_u8(line), vld1_u8(line + along)),
                                 vcombine_u8(vld1_u8(line + 2 * along), vld1_u8(line + 3 * along))}};
    return widen(vqtbl2q_u8(lines, vld1q_u8(kLinesToColumns[0])), vqtbl2q_u8(lines, vld1q_u8(kLinesToColumns[1])));
  }
  // A horizontal edge: each sample position holds the four lines contiguously (along is
  // 1, as every caller passes it and the x86 variants assume too).
  uint32_t words[8];
  for (int k = -4; k < 4; ++k) std::memcpy(&words[k + 4], pixels + k * across, 4);
  return widen(vreinterpretq_u8_u32(vld1q_u32(words)), vreinterpretq_u8_u32(vld1q_u32(words + 4)));
}

// Writes samples k = -3..2 back (p3 and q3 never change: a vertical edge's lines are
// rewritten whole with them).
void store_columns(const Columns& s, uint8_t* pixels, ptrdiff_t across, ptrdiff_t along) {
  const uint8x16x2_t columns = {{narrow(s.c[0], s.c[1], s.c[2], s.c[3]), narrow(s.c[4], s.c[5], s.c[6], s.c[7])}};
  if (across == 1) {
    const uint8x16_t lines01 = vqtbl2q_u8(columns, vld1q_u8(kColumnsToLines[0]));
    const uint8x16_t lines23 = vqtbl2q_u8(columns, vld1q_u8(kColumnsToLines[1]));
    uint8_t* line = pixels - 4;
    vst1_u8(line, vget_low_u8(lines01));
    vst1_u8(line + along, vget_high_u8(lines01));
    vst1_u8(line + 2 * along, vget_low_u8(lines23));
    vst1_u8(line + 3 * along, vget_high_u8(lines23));
    return;
  }
  uint32_t words[8];
  vst1q_u32(words, vreinterpretq_u32_u8(columns.val[0]));
  vst1q_u32(words + 4, vreinterpretq_u32_u8(columns.val[1]));
  for (int k = -3; k < 3; ++k) std::memcpy(pixels + k * across, &words[k + 4], 4);
}

inline int16x4_t clamp16(int16x4_t v, int16x4_t lo, int16x4_t hi) { return vmin_s16(vmax_s16(v, lo), hi); }

void strong_filter(Columns& s, int tc) {
  const int16x4_t p3 = s.c[0], p2 = s.c[1], p1 = s.c[2], p0 = s.c[3];
  const int16x4_t q0 = s.c[4], q1 = s.c[5], q2 = s.c[6], q3 = s.c[7];
  const int16x4_t t = vdup_n_s16(static_cast<int16_t>(2 * tc));
  auto limit = [&](int16x4_t value, int16x4_t centre) {
    return clamp16(value, vsub_s16(centre, t), vadd_s16(centre, t));
  };
  const int16x4_t p0q0 = vadd_s16(p0, q0);
  // (p2 + 2 p1 + 2 p0 + 2 q0 + q1 + 4) >> 3 and its mirror; vrshr adds the 4.
  s.c[3] = limit(vrshr_n_s16(vadd_s16(vadd_s16(p2, q1), vshl_n_s16(vadd_s16(p1, p0q0), 1)), 3), p0);
  s.c[4] = limit(vrshr_n_s16(vadd_s16(vadd_s16(p1, q2), vshl_n_s16(vadd_s16(q1, p0q0), 1)), 3), q0);
  // (p2 + p1 + p0 + q0 + 2) >> 2.
  s.c[2] = limit(vrshr_n_s16(vadd_s16(vadd_s16(p2, p1), p0q0), 2), p1);
  s.c[5] = limit(vrshr_n_s16(vadd_s16(vadd_s16(q2, q1), p0q0), 2), q1);
  // (2 p3 + 3 p2 + p1 + p0 + q0 + 4) >> 3.
  const int16x4_t three = vdup_n_s16(3);
  s.c[1] = limit(vrshr_n_s16(vmla_s16(vadd_s16(vshl_n_s16(p3, 1), vadd_s16(p1, p0q0)), p2, three), 3), p2);
  s.c[6] = limit(vrshr_n_s16(vmla_s16(vadd_s16(vshl_n_s16(q3, 1), vadd_s16(q1, p0q0)), q2, three), 3), q2);
}

void normal_filter(Columns& s, int tc, bool filter_p1, bool filter_q1) {
  const int16x4_t p2 = s.c[1], p1 = s.c[2], p0 = s.c[3], q0 = s.c[4], q1 = s.c[5], q2 = s.c[6];
  // (9 (q0 - p0) - 3 (q1 - p1) + 8) >> 4
  const int16x4_t raw =
      vrshr_n_s16(vmls_s16(vmul_s16(vsub_s16(q0, p0), vdup_n_s16(9)), vsub_s16(q1, p1), vdup_n_s16(3)), 4);
  const uint16x4_t active = vclt_s16(vabs_s16(raw), vdup_n_s16(static_cast<int16_t>(10 * tc)));
  const int16x4_t tcv = vdup_n_s16(static_cast<int16_t>(tc));
  const int16x4_t delta = clamp16(raw, vneg_s16(tcv), tcv);
  // Inactive lanes keep their sample, which the narrow leaves as it is.
  s.c[3] = vbsl_s16(active, vadd_s16(p0, delta), p0);
  s.c[4] = vbsl_s16(active, vsub_s16(q0, delta), q0);
  const int16x4_t half = vdup_n_s16(static_cast<int16_t>(tc >> 1)), minus_half = vneg_s16(half);
  if (filter_p1) {
    const int16x4_t mean = vrshr_n_s16(vadd_s16(p2, p0), 1);  // (p2 + p0 + 1) >> 1
    const int16x4_t dp = clamp16(vshr_n_s16(vadd_s16(vsub_s16(mean, p1), delta), 1), minus_half, half);
    s.c[2] = vbsl_s16(active, vadd_s16(p1, dp), p1);
  }
  if (filter_q1) {
    const int16x4_t mean = vrshr_n_s16(vadd_s16(q2, q0), 1);
    const int16x4_t dq = clamp16(vshr_n_s16(vsub_s16(vsub_s16(mean, q1), delta), 1), minus_half, half);
    s.c[5] = vbsl_s16(active, vadd_s16(q1, dq), q1);
  }
}

void filter_luma_segment(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int beta, int tc) {
  const LumaDecision decision = decide_luma_segment(pixels, across, along, beta, tc);
  if (decision.filter == LumaFilter::kNone) return;
  Columns s = load_columns(pixels, across, along);
  if (decision.filter == LumaFilter::kStrong) {
    strong_filter(s, tc);
  } else {
    normal_filter(s, tc, decision.filter_p1, decision.filter_q1);
  }
  store_columns(s, pixels, across, along);
}

// 4x4 byte transpose: groups of 4 bytes become columns (its own inverse).
constexpr uint8_t kTranspose4x4[16] = {0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15};

void filter_chroma_segment(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int tc) {
  // Four columns p1, p0, q0, q1 of four bytes (one per line).
  uint32_t words[4];
  for (int i = 0; i < 4; ++i) {
    std::memcpy(&words[i], across == 1 ? pixels + i * along - 2 : pixels + (i - 2) * across, 4);
  }
  uint8x16_t columns = vreinterpretq_u8_u32(vld1q_u32(words));
  if (across == 1) columns = vqtbl1q_u8(columns, vld1q_u8(kTranspose4x4));    // each line is p1 p0 q0 q1
  const int16x8_t p = vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(columns)));  // p1 | p0
  const int16x8_t q = vreinterpretq_s16_u16(vmovl_high_u8(columns));          // q0 | q1
  const int16x4_t p1 = vget_low_s16(p), p0 = vget_high_s16(p), q0 = vget_low_s16(q), q1 = vget_high_s16(q);
  const int16x4_t tcv = vdup_n_s16(static_cast<int16_t>(tc));
  // ((q0 - p0) * 4 + p1 - q1 + 4) >> 3, clipped to +-tc
  const int16x4_t raw = vrshr_n_s16(vadd_s16(vshl_n_s16(vsub_s16(q0, p0), 2), vsub_s16(p1, q1)), 3);
  const int16x4_t delta = clamp16(raw, vneg_s16(tcv), tcv);
  columns = vcombine_u8(vqmovun_s16(vcombine_s16(p1, vadd_s16(p0, delta))),
                        vqmovun_s16(vcombine_s16(vsub_s16(q0, delta), q1)));
  if (across == 1) columns = vqtbl1q_u8(columns, vld1q_u8(kTranspose4x4));
  vst1q_u32(words, vreinterpretq_u32_u8(columns));
  for (int i = 0; i < 4; ++i) {
    std::memcpy(across == 1 ? pixels + i * along - 2 : pixels + (i - 2) * across, &words[i], 4);
  }
}

// The segments of an edge one after another, each with the single-segment code above.
void deblock_luma_neon(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, int beta,
                       const uint8_t* tc) {
  for (int s = 0; s < segments; ++s) {
    if (tc[s] != 0) filter_luma_segment(pixels + 4 * s * along, across, along, beta, tc[s]);
  }
}

void deblock_chroma_neon(uint8_t* pixels, ptrdiff_t across, ptrdiff_t along, int segments, const uint8_t* tc) {
  for (int s = 0; s < segments; ++s) {
    if (tc[s] != 0) filter_chroma_segment(pixels + 4 * s * along, across, along, tc[s]);
  }
}

}  // namespace

void init_deblock_neon(DspTable* table) {
  table->deblock_luma = deblock_luma_neon;
  table->deblock_chroma = deblock_chroma_neon;
}

}  // namespace svc::codec::dsp
