// SPDX-License-Identifier: BSD-2-Clause
// AVX2 CDEF kernels. The filter is the SSE4.1 one (cdef_sse41.cc) on 16 lanes: two rows
// of an 8x8 block, or all four rows of a 4x4 one, per operation. The direction search
// builds two directions' partial sums in one register, one per 128-bit half: a half
// holding row 7 - i where the other holds row i turns a direction into its mirror image,
// whose costs are the same (cdef_formulas.h). The costs are the plain int32 sums in
// 32-bit lanes (pmaddwd squares, pmulld weights), added in another order.
#include <immintrin.h>

#include <cstring>

#include "codec/common/dsp/cdef_formulas.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("avx2")

namespace svc::codec::dsp {
namespace {

inline __m128i load_bytes8(const uint8_t* p) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)); }
inline __m256i join(__m128i low, __m128i high) {
  return _mm256_inserti128_si256(_mm256_castsi128_si256(low), high, 1);
}

// Partial sums of two directions, one per 128-bit half; 16 lanes each (lane 15 unused)
// as the halves of `low` and `high`.
struct DirectionPair {
  DirectionPair() : low(_mm256_setzero_si256()), high(_mm256_setzero_si256()) {}
  __m256i low, high;
};

template <int kShift>
inline void add_shifted(DirectionPair* sums, __m256i v) {
  sums->low = _mm256_add_epi16(sums->low, _mm256_slli_si256(v, 2 * kShift));
  if constexpr (kShift > 0) sums->high = _mm256_add_epi16(sums->high, _mm256_srli_si256(v, 16 - 2 * kShift));
}

// Adds v, moved up by `shift` lanes (0..7) in each half.
inline void add_at(DirectionPair* sums, __m256i v, int shift) {
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

inline __m256i weights(int a, int b, int c, int d) { return _mm256_setr_epi32(a, b, c, d, a, b, c, d); }

// Pairs each of lanes 0..7 of `low` with its mirror partner from `high` (lane k with
// partial 2 m - k, m = 7 or 5, read from lane 2 m - 8 - k of high by `mirror`), squares
// and sums each pair (pmaddwd) and weights it: four 32-bit terms per half.
inline __m256i mirrored_cost_terms(const DirectionPair& sums, __m256i mirror, __m256i low_weights,
                                   __m256i high_weights) {
  const __m256i partner = _mm256_shuffle_epi8(sums.high, mirror);
  const __m256i first = _mm256_unpacklo_epi16(sums.low, partner), second = _mm256_unpackhi_epi16(sums.low, partner);
  return _mm256_add_epi32(_mm256_mullo_epi32(_mm256_madd_epi16(first, first), low_weights),
                          _mm256_mullo_epi32(_mm256_madd_epi16(second, second), high_weights));
}

// pshufb order for `mirror`: lane k takes lane last - k of the high lanes, last = 6 for
// the diagonals (15 partials) and 2 for the others (11); -128 leaves zero.
inline __m256i mirror_order(int last) {
  alignas(16) int8_t order[16];
  for (int k = 0; k < 8; ++k) {
    const int from = last - k;
    order[2 * k] = static_cast<int8_t>(from >= 0 ? 2 * from : -128);
    order[2 * k + 1] = static_cast<int8_t>(from >= 0 ? 2 * from + 1 : -128);
  }
  return _mm256_broadcastsi128_si256(_mm_load_si128(reinterpret_cast<const __m128i*>(order)));
}

// Mirrored rows, less 128: row i in the low half, row 7 - i in the high half.
inline void load_mirrored_rows(const uint8_t* pixels, ptrdiff_t stride, __m256i (&rows)[8]) {
  const __m256i bias = _mm256_set1_epi16(128);
  for (int i = 0; i < 8; ++i) {
    const __m128i bytes =
        _mm_unpacklo_epi64(load_bytes8(pixels + i * stride), load_bytes8(pixels + (7 - i) * stride));
    rows[i] = _mm256_sub_epi16(_mm256_cvtepu8_epi16(bytes), bias);
  }
}

// Row sums in the low half, column sums in the high half (each in any order: their
// costs weight every partial alike).
inline __m256i row_and_column_sums(const __m256i (&rows)[8]) {
  const __m256i h01 = _mm256_hadd_epi16(rows[0], rows[1]), h23 = _mm256_hadd_epi16(rows[2], rows[3]);
  const __m256i quarter = _mm256_hadd_epi16(h01, h23);           // per half: rows 0..3 (7..4), two sums each
  const __m256i row_sums = _mm256_hadd_epi16(quarter, quarter);  // qword 0 of each half: four rows
  const __m128i rows_0_to_7 = _mm256_castsi256_si128(_mm256_permute4x64_epi64(row_sums, 0x08));
  const __m256i half_columns =
      _mm256_add_epi16(_mm256_add_epi16(rows[0], rows[1]), _mm256_add_epi16(rows[2], rows[3]));
  const __m128i columns =
      _mm_add_epi16(_mm256_castsi256_si128(half_columns), _mm256_extracti128_si256(half_columns, 1));
  return join(rows_0_to_7, columns);
}

int cdef_direction_8x8_avx2(const uint8_t* pixels, ptrdiff_t stride, int32_t* variance) {
  __m256i rows[8];
  load_mirrored_rows(pixels, stride, rows);
  // Halves: directions 0 and 4 (mirrored), 1 and 3 (mirrored), 7 and 5.
  DirectionPair diagonals, steep, shallow;
  const __m256i zero = _mm256_setzero_si256();
  for (int i = 0; i < 8; ++i) {
    add_at(&diagonals, rows[i], i);                       // i + j; 7 + i - j mirrored
    add_at(&steep, _mm256_hadd_epi16(rows[i], zero), i);  // i + j / 2; 3 + i - j / 2 mirrored
  }
  for (int m = 0; m < 4; ++m) {
    add_at(&shallow, _mm256_add_epi16(rows[2 * m], rows[2 * m + 1]), m);  // i / 2 + j; 3 - i / 2 + j
  }
  const __m256i straight = row_and_column_sums(rows);  // directions 2 and 6
  const __m256i diagonal_terms =
      mirrored_cost_terms(diagonals, mirror_order(6), weights(840, 420, 280, 210), weights(168, 140, 120, 105));
  const __m256i odd_weights_low = weights(420, 210, 140, 105), odd_weights_high = weights(105, 105, 105, 105);
  const __m256i steep_terms = mirrored_cost_terms(steep, mirror_order(2), odd_weights_low, odd_weights_high);
  const __m256i shallow_terms = mirrored_cost_terms(shallow, mirror_order(2), odd_weights_low, odd_weights_high);
  const __m256i straight_terms = _mm256_mullo_epi32(_mm256_madd_epi16(straight, straight), _mm256_set1_epi32(105));
  // Per half: the sums of each register's four terms, directions (0, 2, 1, 7) and (4, 6, 3, 5).
  const __m256i costs = _mm256_hadd_epi32(_mm256_hadd_epi32(diagonal_terms, straight_terms),
                                          _mm256_hadd_epi32(steep_terms, shallow_terms));
  alignas(32) int32_t lanes[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), costs);
  const int32_t cost[8] = {lanes[0], lanes[2], lanes[1], lanes[6], lanes[4], lanes[7], lanes[5], lanes[3]};
  return cdef_direction_from_costs(cost, variance);
}

// Rows y and y + 1 of an 8-wide block, or rows y..y + 3 of a 4-wide one.
template <int kSize>
inline __m256i load_lanes(const uint16_t* p, ptrdiff_t stride) {
  if constexpr (kSize == 8) {
    return join(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)),
                _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + stride)));
  } else {
    auto two_rows = [&](const uint16_t* q) {
      return _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(q)),
                                _mm_loadl_epi64(reinterpret_cast<const __m128i*>(q + stride)));
    };
    return join(two_rows(p), two_rows(p + 2 * stride));
  }
}

struct TapState {
  __m256i value, sum, low, high;
};

// kClamp: also track the taps' range. With one kind of tap only (primary or secondary)
// the weights add up to 12 of the 16 the sum is divided by, so the filtered value never
// leaves the range of its taps and the clamp is the identity: skipped then.
template <bool kClamp>
inline void add_tap(TapState* s, __m256i p, __m256i weight, __m256i threshold, __m128i shift) {
  const __m256i difference = _mm256_sub_epi16(p, s->value);
  const __m256i magnitude = _mm256_abs_epi16(difference);
  const __m256i limit = _mm256_subs_epu16(threshold, _mm256_srl_epi16(magnitude, shift));
  const __m256i constrained = _mm256_sign_epi16(_mm256_min_epi16(magnitude, limit), difference);
  s->sum = _mm256_add_epi16(s->sum, _mm256_mullo_epi16(constrained, weight));
  if constexpr (kClamp) {
    s->low = _mm256_min_epi16(s->low, p);
    const __m256i unavailable = _mm256_cmpeq_epi16(p, _mm256_set1_epi16(static_cast<int16_t>(kCdefUnavailable)));
    s->high = _mm256_max_epi16(s->high, _mm256_andnot_si256(unavailable, p));
  }
}

inline __m128i shift_of(int threshold, int damping) {
  return _mm_cvtsi32_si128(threshold == 0 ? 0 : std::max(0, damping - cdef_floor_log2(threshold)));
}

// Stores the filtered bytes: per half, 8 bytes of one row (size 8) or 4 of each of two rows (size 4).
template <int kSize>
inline void store_rows(__m256i bytes, uint8_t* row, ptrdiff_t stride) {
  const __m128i first = _mm256_castsi256_si128(bytes), second = _mm256_extracti128_si256(bytes, 1);
  if constexpr (kSize == 8) {
    _mm_storel_epi64(reinterpret_cast<__m128i*>(row), first);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(row + stride), second);
  } else {
    const int32_t rows[4] = {_mm_cvtsi128_si32(first), _mm_extract_epi32(first, 1), _mm_cvtsi128_si32(second),
                             _mm_extract_epi32(second, 1)};
    for (int i = 0; i < 4; ++i) std::memcpy(row + i * stride, &rows[i], 4);
  }
}

// kPrimary, kSecondary: which taps the block uses (a strength of 0 adds nothing).
template <int kSize, bool kPrimary, bool kSecondary>
void filter_block(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride,
                  const CdefTaps& taps) {
  constexpr bool kClamp = kPrimary && kSecondary;
  const __m256i primary = _mm256_set1_epi16(static_cast<int16_t>(taps.primary));
  const __m256i secondary = _mm256_set1_epi16(static_cast<int16_t>(taps.secondary));
  const __m128i primary_shift = shift_of(taps.primary, taps.damping);
  const __m128i secondary_shift = shift_of(taps.secondary, taps.damping);
  const int* primary_taps = kCdefPrimaryTaps[taps.primary & 1];
  const CdefTapOffsets offsets = cdef_tap_offsets(taps.direction, in_stride);
  constexpr int kRowsPerStep = kSize == 8 ? 2 : 4;
  for (int y = 0; y < kSize; y += kRowsPerStep) {
    const uint16_t* center = in + y * in_stride;
    TapState s;
    s.value = load_lanes<kSize>(center, in_stride);
    s.sum = _mm256_setzero_si256();
    s.low = s.high = s.value;
    for (int k = 0; k < 2; ++k) {
      const __m256i primary_weight = _mm256_set1_epi16(static_cast<int16_t>(primary_taps[k]));
      const __m256i secondary_weight = _mm256_set1_epi16(static_cast<int16_t>(kCdefSecondaryTaps[k]));
      for (int sign = -1; sign <= 1; sign += 2) {
        if constexpr (kPrimary) {
          add_tap<kClamp>(&s, load_lanes<kSize>(center + sign * offsets.primary[k], in_stride), primary_weight,
                          primary, primary_shift);
        }
        if constexpr (kSecondary) {
          for (int t = 0; t < 2; ++t) {
            add_tap<kClamp>(&s, load_lanes<kSize>(center + sign * offsets.secondary[k][t], in_stride),
                            secondary_weight, secondary, secondary_shift);
          }
        }
      }
    }
    const __m256i negative = _mm256_cmpgt_epi16(_mm256_setzero_si256(), s.sum);
    const __m256i delta =
        _mm256_srai_epi16(_mm256_add_epi16(_mm256_add_epi16(s.sum, _mm256_set1_epi16(8)), negative), 4);
    __m256i result = _mm256_add_epi16(s.value, delta);
    if constexpr (kClamp) result = _mm256_min_epi16(_mm256_max_epi16(result, s.low), s.high);
    store_rows<kSize>(_mm256_packus_epi16(result, result), out + y * out_stride, out_stride);
  }
}

template <int kSize>
void filter_block(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride,
                  const CdefTaps& taps) {
  if (taps.secondary == 0) {
    filter_block<kSize, true, false>(in, in_stride, out, out_stride, taps);
  } else if (taps.primary == 0) {
    filter_block<kSize, false, true>(in, in_stride, out, out_stride, taps);
  } else {
    filter_block<kSize, true, true>(in, in_stride, out, out_stride, taps);
  }
}

void cdef_filter_block_avx2(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride, int size,
                            const CdefTaps& taps) {
  if (size == 8) {
    filter_block<8>(in, in_stride, out, out_stride, taps);
  } else {
    filter_block<4>(in, in_stride, out, out_stride, taps);
  }
}

}  // namespace

void init_cdef_avx2(DspTable* table) {
  table->cdef_direction_8x8 = cdef_direction_8x8_avx2;
  table->cdef_filter_block = cdef_filter_block_avx2;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
