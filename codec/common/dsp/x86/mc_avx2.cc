// SPDX-License-Identifier: BSD-2-Clause
// AVX2 separable 8-tap interpolation: the arithmetic of the SSE4.1 variant (mc_sse41.cc:
// pmaddubsw on pshufb-gathered sample pairs, then pmaddwd on pairs of first-pass rows)
// on 16 lanes. A 256-bit operation covers two groups of 8 intermediates: the halves of
// 16 columns of a row or, in 8- and 4-wide blocks, the same columns of two rows, so the
// codec's 16-, 8- and 4-wide blocks fill whole registers; a group left over takes 128-bit
// operations. Identity phases skip their pass ((64 t) >> 6 = t). Equal to
// interpolate_8tap_c bit for bit (tests/checkkernels).
#include <immintrin.h>

#include <cstring>

#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("avx2")

namespace svc::codec::dsp {
namespace {

inline __m128i load_bytes8(const uint8_t* p) { return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)); }
inline __m128i load_bytes16(const uint8_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
inline __m128i load_int16x8(const int16_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
inline __m256i load_int16x16(const int16_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
inline void store_int16x8(int16_t* p, __m128i v) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), v); }
inline void store_int16x16(int16_t* p, __m256i v) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v); }
inline __m256i join(__m128i low, __m128i high) {
  return _mm256_inserti128_si256(_mm256_castsi128_si256(low), high, 1);
}

inline bool identity(const int8_t* taps) { return taps[3] == 64; }

// pshufb orders gathering, in each 128-bit half, the sample pairs (i + 2k, i + 2k + 1)
// for i = 0..7 that taps 2k and 2k + 1 multiply.
struct PairOrders {
  alignas(32) int8_t bytes[4][32];
};
constexpr PairOrders kPairOrders = [] {
  PairOrders orders{};
  for (int k = 0; k < 4; ++k) {
    for (int i = 0; i < 16; ++i) {
      orders.bytes[k][2 * i] = static_cast<int8_t>(2 * k + i % 8);
      orders.bytes[k][2 * i + 1] = static_cast<int8_t>(2 * k + i % 8 + 1);
    }
  }
  return orders;
}();

// Whether taps 0, 1, 6 and 7 are zero (the chroma filters): only the middle two tap
// pairs then add anything, and the vertical pass needs 4 fewer first-pass rows.
inline bool four_taps(const int8_t* taps) { return (taps[0] | taps[1] | taps[6] | taps[7]) == 0; }

// The first pass of a non-identity phase: 8 sums per group of 8 columns, from tap
// pairs kFirst .. kFirst + kCount - 1 (the others zero).
template <int kFirst, int kCount>
class HorizontalTaps {
 public:
  explicit HorizontalTaps(const int8_t* taps) {
    for (int j = 0; j < kCount; ++j) {
      const int k = kFirst + j;
      pairs_[j] = _mm256_set1_epi16(static_cast<int16_t>((taps[2 * k] & 0xff) | (taps[2 * k + 1] << 8)));
      shuffles_[j] = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPairOrders.bytes[k]));
    }
  }
  // The group whose taps start at `a` in lanes 0..7, at `b` in lanes 8..15 (16 bytes read at each).
  __m256i two_groups(const uint8_t* a, const uint8_t* b) const {
    const __m256i samples = join(load_bytes16(a), load_bytes16(b));
    __m256i sum = _mm256_maddubs_epi16(_mm256_shuffle_epi8(samples, shuffles_[0]), pairs_[0]);
    for (int j = 1; j < kCount; ++j) {
      sum = _mm256_add_epi16(sum, _mm256_maddubs_epi16(_mm256_shuffle_epi8(samples, shuffles_[j]), pairs_[j]));
    }
    return sum;
  }
  __m128i one_group(const uint8_t* a) const {
    const __m128i samples = load_bytes16(a);
    __m128i sum = _mm_maddubs_epi16(_mm_shuffle_epi8(samples, low(shuffles_[0])), low(pairs_[0]));
    for (int j = 1; j < kCount; ++j) {
      sum = _mm_add_epi16(sum, _mm_maddubs_epi16(_mm_shuffle_epi8(samples, low(shuffles_[j])), low(pairs_[j])));
    }
    return sum;
  }

 private:
  static __m128i low(__m256i v) { return _mm256_castsi256_si128(v); }
  __m256i pairs_[kCount], shuffles_[kCount];
};

// The first pass of the identity phase: 64 times the sample (pointers at the samples, not the taps).
struct IdentityTaps {
  __m256i two_groups(const uint8_t* a, const uint8_t* b) const {
    return _mm256_slli_epi16(_mm256_cvtepu8_epi16(_mm_unpacklo_epi64(load_bytes8(a), load_bytes8(b))), 6);
  }
  __m128i one_group(const uint8_t* a) const { return _mm_slli_epi16(_mm_cvtepu8_epi16(load_bytes8(a)), 6); }
};

// First-pass rows of padded_width (a multiple of 8) intermediates from row_count rows at `src`.
template <typename Taps>
void first_pass(const uint8_t* src, ptrdiff_t stride, int row_count, int padded_width, const Taps& taps,
                int16_t* rows) {
  if (padded_width == 8) {  // two rows per operation
    int y = 0;
    for (; y + 2 <= row_count; y += 2) {
      store_int16x16(rows + 8 * y, taps.two_groups(src + y * stride, src + (y + 1) * stride));
    }
    if (y < row_count) store_int16x8(rows + 8 * y, taps.one_group(src + y * stride));
    return;
  }
  for (int y = 0; y < row_count; ++y) {
    const uint8_t* row = src + y * stride;
    int16_t* dst = rows + y * padded_width;
    int x = 0;
    for (; x + 16 <= padded_width; x += 16) store_int16x16(dst + x, taps.two_groups(row + x, row + x + 8));
    if (x < padded_width) store_int16x8(dst + x, taps.one_group(row + x));
  }
}

// The second pass: out = ((sum_j v[j] rows[y + j]) >> 6) - offset, in 32 bits, on
// groups of first-pass intermediates `step` apart (the next row's group), from tap pairs
// kFirst .. kFirst + kCount - 1 (the others zero; `rows` starts at the first one's row).
template <int kFirst, int kCount>
class VerticalTaps {
 public:
  VerticalTaps(const int8_t* taps, int step) : step_(step) {
    for (int j = 0; j < kCount; ++j) {
      const int k = kFirst + j;
      pairs_[j] = _mm256_set1_epi32(static_cast<int32_t>((taps[2 * k] & 0xffff) | (taps[2 * k + 1] << 16)));
    }
  }
  // Outputs o = 0, 2, 4, ... below `count` from groups o..o+2kCount-1 of the column at
  // `rows`, passed to store(o, value). Output o + 2 shares all but one of output o's
  // interleaved group pairs, so each pair is interleaved once.
  template <typename Store>
  void every_other_output(const int16_t* rows, int count, const Store& store) const {
    __m256i low[kCount], high[kCount];
    for (int k = 0; k < kCount - 1; ++k) interleave(rows + 2 * k * step_, &low[k], &high[k]);
    for (int o = 0; o < count; o += 2) {
      interleave(rows + (o + 2 * kCount - 2) * step_, &low[kCount - 1], &high[kCount - 1]);
      store(o, filtered(low, high));
      for (int k = 0; k < kCount - 1; ++k) {
        low[k] = low[k + 1];
        high[k] = high[k + 1];
      }
    }
  }
  // One group of 8 from the groups at rows, rows + step, ... (128-bit).
  __m128i one_group(const int16_t* rows) const {
    __m128i low = _mm_setzero_si128(), high = _mm_setzero_si128();
    for (int k = 0; k < kCount; ++k) {
      const __m128i a = load_int16x8(rows + 2 * k * step_), b = load_int16x8(rows + (2 * k + 1) * step_);
      const __m128i pair = _mm256_castsi256_si128(pairs_[k]);
      low = _mm_add_epi32(low, _mm_madd_epi16(_mm_unpacklo_epi16(a, b), pair));
      high = _mm_add_epi32(high, _mm_madd_epi16(_mm_unpackhi_epi16(a, b), pair));
    }
    const __m128i offset = _mm_set1_epi32(kIntermediateOffset);
    return _mm_packs_epi32(_mm_sub_epi32(_mm_srai_epi32(low, 6), offset),
                           _mm_sub_epi32(_mm_srai_epi32(high, 6), offset));
  }

 private:
  void interleave(const int16_t* group, __m256i* low, __m256i* high) const {
    const __m256i a = load_int16x16(group), b = load_int16x16(group + step_);
    *low = _mm256_unpacklo_epi16(a, b);
    *high = _mm256_unpackhi_epi16(a, b);
  }
  __m256i filtered(const __m256i (&low)[kCount], const __m256i (&high)[kCount]) const {
    __m256i sum_low = _mm256_madd_epi16(low[0], pairs_[0]), sum_high = _mm256_madd_epi16(high[0], pairs_[0]);
    for (int k = 1; k < kCount; ++k) {
      sum_low = _mm256_add_epi32(sum_low, _mm256_madd_epi16(low[k], pairs_[k]));
      sum_high = _mm256_add_epi32(sum_high, _mm256_madd_epi16(high[k], pairs_[k]));
    }
    const __m256i offset = _mm256_set1_epi32(kIntermediateOffset);
    return _mm256_packs_epi32(_mm256_sub_epi32(_mm256_srai_epi32(sum_low, 6), offset),
                              _mm256_sub_epi32(_mm256_srai_epi32(sum_high, 6), offset));
  }

  __m256i pairs_[kCount];
  int step_;
};

// Stores the first `count` (4 or 8) lanes of a group.
inline void store_group(int16_t* out, __m128i value, int count) {
  if (count >= 8) {
    store_int16x8(out, value);
  } else {
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out), value);
  }
}

// Stores 16 outputs of a row, `count` (4 to 16, a multiple of 4) of them.
inline void store_outputs(int16_t* out, __m256i value, int count) {
  if (count >= 16) {
    store_int16x16(out, value);
  } else {
    store_group(out, _mm256_castsi256_si128(value), 8);
    store_group(out + 8, _mm256_extracti128_si256(value, 1), count - 8);
  }
}

// The identity vertical phase: the block from first-pass rows of padded_width, grouped
// as the first pass grouped them.
void copy_block(const int16_t* rows, int padded_width, int width, int height, int16_t* out, ptrdiff_t out_stride) {
  const __m256i offset = _mm256_set1_epi16(kIntermediateOffset);
  if (padded_width == 8) {
    int y = 0;
    for (; y + 2 <= height; y += 2) {
      const __m256i value = _mm256_sub_epi16(load_int16x16(rows + 8 * y), offset);
      store_group(out + y * out_stride, _mm256_castsi256_si128(value), width);
      store_group(out + (y + 1) * out_stride, _mm256_extracti128_si256(value, 1), width);
    }
    if (y < height) {
      store_group(out + y * out_stride, _mm_sub_epi16(load_int16x8(rows + 8 * y), _mm256_castsi256_si128(offset)),
                  width);
    }
    return;
  }
  for (int y = 0; y < height; ++y) {
    const int16_t* src = rows + y * padded_width;
    int16_t* dst = out + y * out_stride;
    int x = 0;
    for (; x + 16 <= padded_width; x += 16) {
      store_outputs(dst + x, _mm256_sub_epi16(load_int16x16(src + x), offset), width - x);
    }
    if (x < padded_width) {
      store_group(dst + x, _mm_sub_epi16(load_int16x8(src + x), _mm256_castsi256_si128(offset)), width - x);
    }
  }
}

// Two rows of an 8-wide (or 4-wide) block per operation: group o holds rows o and o + 1.
template <typename Taps>
void filter_narrow_block(const int16_t* rows, int width, int height, const int8_t* v_taps, int16_t* out,
                         ptrdiff_t out_stride) {
  const Taps taps(v_taps, 8);
  taps.every_other_output(rows, height - 1, [&](int y, __m256i value) {
    store_group(out + y * out_stride, _mm256_castsi256_si128(value), width);
    store_group(out + (y + 1) * out_stride, _mm256_extracti128_si256(value, 1), width);
  });
  if (height & 1) store_group(out + (height - 1) * out_stride, taps.one_group(rows + 8 * (height - 1)), width);
}

// 16 columns per operation, even and odd rows in turn; a last group of 8 columns alone.
template <typename Taps>
void filter_wide_block(const int16_t* rows, int padded_width, int width, int height, const int8_t* v_taps,
                       int16_t* out, ptrdiff_t out_stride) {
  const Taps taps(v_taps, padded_width);
  int x = 0;
  for (; x + 16 <= padded_width; x += 16) {
    for (int parity = 0; parity < 2; ++parity) {
      taps.every_other_output(rows + parity * padded_width + x, height - parity, [&](int y, __m256i value) {
        store_outputs(out + (y + parity) * out_stride + x, value, width - x);
      });
    }
  }
  if (x < padded_width) {
    for (int y = 0; y < height; ++y) {
      store_group(out + y * out_stride + x, taps.one_group(rows + y * padded_width + x), width - x);
    }
  }
}

template <typename Taps>
void filter_block(const int16_t* rows, int padded_width, int width, int height, const int8_t* v_taps, int16_t* out,
                  ptrdiff_t out_stride) {
  if (padded_width == 8) {
    filter_narrow_block<Taps>(rows, width, height, v_taps, out, out_stride);
  } else {
    filter_wide_block<Taps>(rows, padded_width, width, height, v_taps, out, out_stride);
  }
}

// 4x4 blocks (the warped mode predicts in them): one row per 128-bit half, its four
// outputs' products of two tap pairs side by side (pair k in bytes 0..7, pair k + 1 in
// bytes 8..15), added across the halves of the half; the second pass two output rows
// per operation. Half the work of the padded 8-wide path for these blocks.
template <int kFirst, int kCount>
class Horizontal4 {
 public:
  explicit Horizontal4(const int8_t* taps) {
    for (int m = 0; m < kCount / 2; ++m) {
      alignas(32) int8_t order[32];
      alignas(32) int8_t weights[32];
      for (int half = 0; half < 2; ++half) {
        const int k = kFirst + 2 * m + half;
        for (int i = 0; i < 4; ++i) {
          for (int lane = 0; lane < 32; lane += 16) {
            order[lane + 8 * half + 2 * i] = static_cast<int8_t>(2 * k + i);
            order[lane + 8 * half + 2 * i + 1] = static_cast<int8_t>(2 * k + i + 1);
            weights[lane + 8 * half + 2 * i] = taps[2 * k];
            weights[lane + 8 * half + 2 * i + 1] = taps[2 * k + 1];
          }
        }
      }
      shuffles_[m] = _mm256_load_si256(reinterpret_cast<const __m256i*>(order));
      weights_[m] = _mm256_load_si256(reinterpret_cast<const __m256i*>(weights));
    }
  }
  // Rows a and b (16 bytes read at each): the four sums of each in lanes 0..3 of its half.
  __m256i two_rows(const uint8_t* a, const uint8_t* b) const {
    const __m256i samples = join(load_bytes16(a), load_bytes16(b));
    __m256i sum = _mm256_maddubs_epi16(_mm256_shuffle_epi8(samples, shuffles_[0]), weights_[0]);
    for (int m = 1; m < kCount / 2; ++m) {
      sum = _mm256_add_epi16(sum, _mm256_maddubs_epi16(_mm256_shuffle_epi8(samples, shuffles_[m]), weights_[m]));
    }
    return _mm256_add_epi16(sum, _mm256_srli_si256(sum, 8));
  }

 private:
  __m256i shuffles_[kCount / 2], weights_[kCount / 2];
};

struct Identity4 {
  __m256i two_rows(const uint8_t* a, const uint8_t* b) const {
    const __m128i pair =
        _mm_unpacklo_epi32(_mm_cvtsi32_si128(load_int32(a + 3)), _mm_cvtsi32_si128(load_int32(b + 3)));
    const __m256i wide = _mm256_slli_epi16(_mm256_cvtepu8_epi16(pair), 6);
    // Row a's four in lanes 0..3 of the low half, row b's in those of the high half.
    return _mm256_permute4x64_epi64(wide, 0x10);
  }
  static int32_t load_int32(const uint8_t* p) {
    int32_t value;
    std::memcpy(&value, p, 4);
    return value;
  }
};

// First-pass rows of a 4x4 block: row r's four intermediates in lanes 0..3 of rows[r].
template <typename Taps>
void first_pass_4x4(const uint8_t* src, ptrdiff_t stride, int row_count, const Taps& taps, __m128i* rows) {
  for (int r = 0; r < row_count; r += 2) {
    const __m256i pair = taps.two_rows(src + r * stride, src + (r + 1 < row_count ? r + 1 : r) * stride);
    rows[r] = _mm256_castsi256_si128(pair);
    rows[r + 1] = _mm256_extracti128_si256(pair, 1);
  }
}

inline void store_4x4(__m256i rows_0_2_1_3, int16_t* out, ptrdiff_t stride) {
  const __m128i low = _mm256_castsi256_si128(rows_0_2_1_3), high = _mm256_extracti128_si256(rows_0_2_1_3, 1);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(out), low);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(out + stride), high);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 2 * stride), _mm_unpackhi_epi64(low, low));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 3 * stride), _mm_unpackhi_epi64(high, high));
}

// The second pass from tap pairs kFirst .. kFirst + kCount - 1 on first-pass rows that
// start at the first one's row.
template <int kFirst, int kCount>
void second_pass_4x4(const __m128i* rows, const int8_t* taps, int16_t* out, ptrdiff_t stride) {
  // joined[m]: rows 2m, 2m + 1 interleaved in the low half, rows 2m + 1, 2m + 2 in the high.
  __m256i joined[kCount + 1];
  for (int m = 0; m <= kCount; ++m) {
    joined[m] = join(_mm_unpacklo_epi16(rows[2 * m], rows[2 * m + 1]),
                     _mm_unpacklo_epi16(rows[2 * m + 1], rows[2 * m + 2]));
  }
  __m256i sum_01 = _mm256_setzero_si256(), sum_23 = _mm256_setzero_si256();
  for (int j = 0; j < kCount; ++j) {
    const int k = kFirst + j;
    const __m256i pair = _mm256_set1_epi32(static_cast<int32_t>((taps[2 * k] & 0xffff) | (taps[2 * k + 1] << 16)));
    sum_01 = _mm256_add_epi32(sum_01, _mm256_madd_epi16(joined[j], pair));
    sum_23 = _mm256_add_epi32(sum_23, _mm256_madd_epi16(joined[j + 1], pair));
  }
  const __m256i offset = _mm256_set1_epi32(kIntermediateOffset);
  const __m256i rows_01 = _mm256_sub_epi32(_mm256_srai_epi32(sum_01, 6), offset);
  const __m256i rows_23 = _mm256_sub_epi32(_mm256_srai_epi32(sum_23, 6), offset);
  store_4x4(_mm256_packs_epi32(rows_01, rows_23), out, stride);
}

void interpolate_4x4(const uint8_t* window, ptrdiff_t window_stride, const int8_t* h_taps, const int8_t* v_taps,
                     int16_t* out, ptrdiff_t out_stride) {
  const bool vertical = !identity(v_taps), vertical_four = vertical && four_taps(v_taps);
  const int first_row = !vertical ? 3 : vertical_four ? 2 : 0;
  const int row_count = !vertical ? 4 : vertical_four ? 7 : 11;
  __m128i rows[12];
  const uint8_t* src = window + first_row * window_stride;
  if (identity(h_taps)) {
    first_pass_4x4(src, window_stride, row_count, Identity4{}, rows);
  } else if (four_taps(h_taps)) {
    first_pass_4x4(src, window_stride, row_count, Horizontal4<1, 2>(h_taps), rows);
  } else {
    first_pass_4x4(src, window_stride, row_count, Horizontal4<0, 4>(h_taps), rows);
  }
  if (!vertical) {
    const __m128i offset = _mm_set1_epi16(kIntermediateOffset);
    for (int y = 0; y < 4; ++y) {
      _mm_storel_epi64(reinterpret_cast<__m128i*>(out + y * out_stride), _mm_sub_epi16(rows[y], offset));
    }
  } else if (vertical_four) {
    second_pass_4x4<1, 2>(rows, v_taps, out, out_stride);
  } else {
    second_pass_4x4<0, 4>(rows, v_taps, out, out_stride);
  }
}

void interpolate_8tap_avx2(const uint8_t* window, ptrdiff_t window_stride, int width, int height,
                           const int8_t* h_taps, const int8_t* v_taps, int16_t* out, ptrdiff_t out_stride) {
  if (width == 4 && height == 4) {
    interpolate_4x4(window, window_stride, h_taps, v_taps, out, out_stride);
    return;
  }
  const bool vertical = !identity(v_taps), vertical_four = vertical && four_taps(v_taps);
  // First-pass rows: those the vertical taps reach (height + 7, or height + 3 from row 2
  // for four taps), else only the block's.
  const int first_row = !vertical ? 3 : vertical_four ? 2 : 0;
  const int row_count = !vertical ? height : vertical_four ? height + 3 : height + 7;
  const int padded_width = (width + 7) & ~7;
  alignas(32) int16_t rows[(kMaxInterpolationBlock + 7) * kMaxInterpolationBlock];
  const uint8_t* src = window + first_row * window_stride;
  if (identity(h_taps)) {
    first_pass(src + 3, window_stride, row_count, padded_width, IdentityTaps{}, rows);
  } else if (four_taps(h_taps)) {
    first_pass(src, window_stride, row_count, padded_width, HorizontalTaps<1, 2>(h_taps), rows);
  } else {
    first_pass(src, window_stride, row_count, padded_width, HorizontalTaps<0, 4>(h_taps), rows);
  }
  if (!vertical) {
    copy_block(rows, padded_width, width, height, out, out_stride);
  } else if (vertical_four) {
    filter_block<VerticalTaps<1, 2>>(rows, padded_width, width, height, v_taps, out, out_stride);
  } else {
    filter_block<VerticalTaps<0, 4>>(rows, padded_width, width, height, v_taps, out, out_stride);
  }
}

}  // namespace

void init_mc_avx2(DspTable* table) { table->interpolate_8tap = interpolate_8tap_avx2; }

}  // namespace svc::codec::dsp

SVC_TARGET_END
