// SPDX-License-Identifier: BSD-2-Clause
// NEON CDEF kernels. The filter works on 8 samples at once in 16-bit lanes (a row of an
// 8x8 block, two rows of a 4x4 one); unavailable samples (kCdefUnavailable) constrain to 0
// by themselves and are masked out of the maximum. The direction search builds the partial
// sums with lane shifts, two of them mirrored (cdef_formulas.h), and shares the costs.
#include <arm_neon.h>

#include <algorithm>
#include <cstring>

#include "codec/common/dsp/cdef_formulas.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

// 16 lanes of partial sums (lane 15 unused) as two registers; every sum fits 16 bits
// (at most 8 samples of +-128).
struct Lanes16 {
  int16x8_t low = vdupq_n_s16(0), high = vdupq_n_s16(0);
};

template <int kShift>
inline void add_shifted(Lanes16* sums, int16x8_t v) {
  if constexpr (kShift == 0) {
    sums->low = vaddq_s16(sums->low, v);
  } else {
    const int16x8_t zero = vdupq_n_s16(0);
    sums->low = vaddq_s16(sums->low, vextq_s16(zero, v, 8 - kShift));
    sums->high = vaddq_s16(sums->high, vextq_s16(v, zero, 8 - kShift));
  }
}

// Adds v, moved up by `shift` lanes (0..7); lane shifts take immediates only.
inline void add_at(Lanes16* sums, int16x8_t v, int shift) {
  switch (shift) {
    case 0: add_shifted<0>(sums, v); break;
    case 1: add_shifted<1>(sums, v); break;
    case 2: add_shifted<2>(sums, v); break;
    case 3: add_shifted<3>(sums, v); break;
    case 4: add_shifted<4>(sums, v); break;
    case 5: add_shifted<5>(sums, v); break;
    case 6: add_shifted<6>(sums, v); break;
    default: add_shifted<7>(sums, v); break;
  }
}

void store_partial(const Lanes16& sums, int32_t* partial) {
  int16_t lanes[16];
  vst1q_s16(lanes, sums.low);
  vst1q_s16(lanes + 8, sums.high);
  for (int k = 0; k < 15; ++k) partial[k] = lanes[k];
}

int cdef_direction_8x8_neon(const uint8_t* pixels, ptrdiff_t stride, int32_t* variance) {
  const int16x8_t bias = vdupq_n_s16(128), zero = vdupq_n_s16(0);
  int16x8_t rows[8];
  for (int i = 0; i < 8; ++i)
    rows[i] = vsubq_s16(vreinterpretq_s16_u16(vmovl_u8(vld1_u8(pixels + i * stride))), bias);
  Lanes16 sums[8];
  int16x8_t columns = zero;
  int32_t partial[8][15];
  for (int i = 0; i < 8; ++i) {
    const int16x8_t pairs = vpaddq_s16(rows[i], zero);  // lanes 0..3: samples 2m + 2m + 1
    columns = vaddq_s16(columns, rows[i]);
    add_at(&sums[0], rows[i], i);      // i + j
    add_at(&sums[1], pairs, i);        // i + j / 2
    add_at(&sums[3], pairs, 7 - i);    // mirrored 3 + i - j / 2
    add_at(&sums[4], rows[i], 7 - i);  // mirrored 7 + i - j
  }
  for (int m = 0; m < 4; ++m) {
    const int16x8_t both = vaddq_s16(rows[2 * m], rows[2 * m + 1]);
    add_at(&sums[5], both, 3 - m);  // 3 - i / 2 + j
    add_at(&sums[7], both, m);      // i / 2 + j
  }
  sums[6].low = columns;
  for (int d = 0; d < 8; ++d) store_partial(sums[d], partial[d]);
  for (int i = 0; i < 8; ++i) partial[2][i] = vaddvq_s16(rows[i]);  // row sums
  return cdef_direction_from_partials(partial, variance);
}

// Row y of an 8-wide block, or rows y and y + 1 of a 4-wide one.
inline int16x8_t load_lanes(const uint16_t* p, ptrdiff_t stride, int size) {
  if (size == 8) return vreinterpretq_s16_u16(vld1q_u16(p));
  return vreinterpretq_s16_u16(vcombine_u16(vld1_u16(p), vld1_u16(p + stride)));
}

struct TapState {
  int16x8_t value, sum, low, high;
};

// The strength and the right shift (as a negative count) of the constraint.
struct Constraint {
  uint16x8_t threshold;
  int16x8_t shift;
};

Constraint constraint_of(int threshold, int damping) {
  const int shift = threshold == 0 ? 0 : std::max(0, damping - cdef_floor_log2(threshold));
  return {vdupq_n_u16(static_cast<uint16_t>(threshold)), vdupq_n_s16(static_cast<int16_t>(-shift))};
}

inline void add_tap(TapState* s, int16x8_t p, int16_t weight, const Constraint& constraint) {
  const int16x8_t difference = vsubq_s16(p, s->value);
  const uint16x8_t magnitude = vreinterpretq_u16_s16(vabsq_s16(difference));
  const uint16x8_t limit = vqsubq_u16(constraint.threshold, vshlq_u16(magnitude, constraint.shift));
  const int16x8_t constrained = vreinterpretq_s16_u16(vminq_u16(magnitude, limit));
  s->sum = vmlaq_n_s16(s->sum, vbslq_s16(vcltzq_s16(difference), vnegq_s16(constrained), constrained), weight);
  s->low = vminq_s16(s->low, p);
  const uint16x8_t unavailable = vceqq_s16(p, vdupq_n_s16(static_cast<int16_t>(kCdefUnavailable)));
  s->high = vmaxq_s16(s->high, vbicq_s16(p, vreinterpretq_s16_u16(unavailable)));
}

inline void store_bytes(uint8_t* row, ptrdiff_t stride, uint8x8_t bytes, int size) {
  if (size == 8) {
    vst1_u8(row, bytes);
    return;
  }
  const uint32_t first = vget_lane_u32(vreinterpret_u32_u8(bytes), 0);
  const uint32_t second = vget_lane_u32(vreinterpret_u32_u8(bytes), 1);
  std::memcpy(row, &first, 4);
  std::memcpy(row + stride, &second, 4);
}

void cdef_filter_block_neon(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride, int size,
                            const CdefTaps& taps) {
  const Constraint primary = constraint_of(taps.primary, taps.damping);
  const Constraint secondary = constraint_of(taps.secondary, taps.damping);
  const int* primary_taps = kCdefPrimaryTaps[taps.primary & 1];
  const CdefTapOffsets offsets = cdef_tap_offsets(taps.direction, in_stride);
  const int rows_per_step = size == 8 ? 1 : 2;
  for (int y = 0; y < size; y += rows_per_step) {
    const uint16_t* center = in + y * in_stride;
    TapState s;
    s.value = load_lanes(center, in_stride, size);
    s.sum = vdupq_n_s16(0);
    s.low = s.high = s.value;
    for (int k = 0; k < 2; ++k) {
      for (int sign = -1; sign <= 1; sign += 2) {
        add_tap(&s, load_lanes(center + sign * offsets.primary[k], in_stride, size),
                static_cast<int16_t>(primary_taps[k]), primary);
        for (int t = 0; t < 2; ++t) {
          add_tap(&s, load_lanes(center + sign * offsets.secondary[k][t], in_stride, size),
                  static_cast<int16_t>(kCdefSecondaryTaps[k]), secondary);
        }
      }
    }
    // (8 + sum - (sum < 0)) >> 4: a true comparison's lanes are -1.
    const int16x8_t delta =
        vshrq_n_s16(vaddq_s16(vaddq_s16(s.sum, vdupq_n_s16(8)), vreinterpretq_s16_u16(vcltzq_s16(s.sum))), 4);
    const int16x8_t result = vminq_s16(vmaxq_s16(vaddq_s16(s.value, delta), s.low), s.high);
    store_bytes(out + y * out_stride, out_stride, vqmovun_s16(result), size);
  }
}

}  // namespace

void init_cdef_neon(DspTable* table) {
  table->cdef_direction_8x8 = cdef_direction_8x8_neon;
  table->cdef_filter_block = cdef_filter_block_neon;
}

}  // namespace svc::codec::dsp
