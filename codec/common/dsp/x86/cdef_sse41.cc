// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 CDEF kernels. The filter works on 8 samples at once in 16-bit lanes (a row of an
// 8x8 block, two rows of a 4x4 one); unavailable samples (kCdefUnavailable) constrain to 0
// by themselves and are masked out of the maximum. The direction search builds the partial
// sums with lane shifts, two of them mirrored (cdef_formulas.h), and shares the costs.
#include <smmintrin.h>

#include <cstring>

#include "codec/common/dsp/cdef_formulas.h"
#include "codec/common/dsp/dsp_init.h"
#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse2,ssse3,sse4.1")

namespace svc::codec::dsp {
namespace {

// 16 lanes of partial sums (lanes 15 unused) as two registers.
struct Lanes16 {
  __m128i low = _mm_setzero_si128(), high = _mm_setzero_si128();
};

template <int kShift>
inline void add_shifted(Lanes16* sums, __m128i v) {
  sums->low = _mm_add_epi16(sums->low, _mm_slli_si128(v, 2 * kShift));
  if constexpr (kShift > 0) sums->high = _mm_add_epi16(sums->high, _mm_srli_si128(v, 16 - 2 * kShift));
}

// Adds v, moved up by `shift` lanes (0..7).
inline void add_at(Lanes16* sums, __m128i v, int shift) {
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
  alignas(16) int16_t lanes[16];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), sums.low);
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes + 8), sums.high);
  for (int k = 0; k < 15; ++k) partial[k] = lanes[k];
}

int cdef_direction_8x8_sse41(const uint8_t* pixels, ptrdiff_t stride, int32_t* variance) {
  const __m128i bias = _mm_set1_epi16(128), zero = _mm_setzero_si128();
  __m128i rows[8];
  for (int i = 0; i < 8; ++i) {
    rows[i] =
        _mm_sub_epi16(_mm_cvtepu8_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(pixels + i * stride))),
                      bias);
  }
  Lanes16 sums[8];
  __m128i columns = zero;
  for (int i = 0; i < 8; ++i) {
    const __m128i pairs = _mm_hadd_epi16(rows[i], zero);  // lanes 0..3: samples 2m + 2m + 1
    columns = _mm_add_epi16(columns, rows[i]);
    add_at(&sums[0], rows[i], i);      // i + j
    add_at(&sums[1], pairs, i);        // i + j / 2
    add_at(&sums[3], pairs, 7 - i);    // mirrored 3 + i - j / 2
    add_at(&sums[4], rows[i], 7 - i);  // mirrored 7 + i - j
  }
  for (int m = 0; m < 4; ++m) {
    const __m128i both = _mm_add_epi16(rows[2 * m], rows[2 * m + 1]);
    add_at(&sums[5], both, 3 - m);  // 3 - i / 2 + j
    add_at(&sums[7], both, m);      // i / 2 + j
  }
  sums[6].low = columns;
  const __m128i h01 = _mm_hadd_epi16(rows[0], rows[1]), h23 = _mm_hadd_epi16(rows[2], rows[3]);
  const __m128i h45 = _mm_hadd_epi16(rows[4], rows[5]), h67 = _mm_hadd_epi16(rows[6], rows[7]);
  sums[2].low = _mm_hadd_epi16(_mm_hadd_epi16(h01, h23), _mm_hadd_epi16(h45, h67));  // row sums
  int32_t partial[8][15];
  for (int d = 0; d < 8; ++d) store_partial(sums[d], partial[d]);
  return cdef_direction_from_partials(partial, variance);
}

// Row y of an 8-wide block, or rows y and y + 1 of a 4-wide one.
inline __m128i load_lanes(const uint16_t* p, ptrdiff_t stride, int size) {
  if (size == 8) return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  return _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)),
                            _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p + stride)));
}

struct TapState {
  __m128i value, sum, low, high;
};

// kClamp: also track the taps' range, needed only with both kinds of tap (the AVX2
// kernel, cdef_avx2.cc, says why).
template <bool kClamp>
inline void add_tap(TapState* s, __m128i p, __m128i weight, __m128i threshold, __m128i shift) {
  const __m128i difference = _mm_sub_epi16(p, s->value);
  const __m128i magnitude = _mm_abs_epi16(difference);
  const __m128i limit = _mm_subs_epu16(threshold, _mm_srl_epi16(magnitude, shift));
  const __m128i constrained = _mm_sign_epi16(_mm_min_epi16(magnitude, limit), difference);
  s->sum = _mm_add_epi16(s->sum, _mm_mullo_epi16(constrained, weight));
  if constexpr (kClamp) {
    s->low = _mm_min_epi16(s->low, p);
    const __m128i unavailable = _mm_cmpeq_epi16(p, _mm_set1_epi16(static_cast<int16_t>(kCdefUnavailable)));
    s->high = _mm_max_epi16(s->high, _mm_andnot_si128(unavailable, p));
  }
}

inline __m128i shift_of(int threshold, int damping) {
  return _mm_cvtsi32_si128(threshold == 0 ? 0 : std::max(0, damping - cdef_floor_log2(threshold)));
}

template <bool kPrimary, bool kSecondary>
void filter_block(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride, int size,
                  const CdefTaps& taps) {
  constexpr bool kClamp = kPrimary && kSecondary;
  const __m128i primary = _mm_set1_epi16(static_cast<int16_t>(taps.primary));
  const __m128i secondary = _mm_set1_epi16(static_cast<int16_t>(taps.secondary));
  const __m128i primary_shift = shift_of(taps.primary, taps.damping);
  const __m128i secondary_shift = shift_of(taps.secondary, taps.damping);
  const int* primary_taps = kCdefPrimaryTaps[taps.primary & 1];
  const CdefTapOffsets offsets = cdef_tap_offsets(taps.direction, in_stride);
  const int rows_per_step = size == 8 ? 1 : 2;
  for (int y = 0; y < size; y += rows_per_step) {
    const uint16_t* center = in + y * in_stride;
    TapState s;
    s.value = load_lanes(center, in_stride, size);
    s.sum = _mm_setzero_si128();
    s.low = s.high = s.value;
    for (int k = 0; k < 2; ++k) {
      const __m128i primary_weight = _mm_set1_epi16(static_cast<int16_t>(primary_taps[k]));
      const __m128i secondary_weight = _mm_set1_epi16(static_cast<int16_t>(kCdefSecondaryTaps[k]));
      for (int sign = -1; sign <= 1; sign += 2) {
        if constexpr (kPrimary) {
          add_tap<kClamp>(&s, load_lanes(center + sign * offsets.primary[k], in_stride, size), primary_weight,
                          primary, primary_shift);
        }
        if constexpr (kSecondary) {
          for (int t = 0; t < 2; ++t) {
            add_tap<kClamp>(&s, load_lanes(center + sign * offsets.secondary[k][t], in_stride, size),
                            secondary_weight, secondary, secondary_shift);
          }
        }
      }
    }
    const __m128i negative = _mm_cmplt_epi16(s.sum, _mm_setzero_si128());
    const __m128i delta = _mm_srai_epi16(_mm_add_epi16(_mm_add_epi16(s.sum, _mm_set1_epi16(8)), negative), 4);
    __m128i result = _mm_add_epi16(s.value, delta);
    if constexpr (kClamp) result = _mm_min_epi16(_mm_max_epi16(result, s.low), s.high);
    const __m128i bytes = _mm_packus_epi16(result, result);
    uint8_t* row = out + y * out_stride;
    if (size == 8) {
      _mm_storel_epi64(reinterpret_cast<__m128i*>(row), bytes);
    } else {
      const int32_t first = _mm_cvtsi128_si32(bytes), second = _mm_extract_epi32(bytes, 1);
      std::memcpy(row, &first, 4);
      std::memcpy(row + out_stride, &second, 4);
    }
  }
}

void cdef_filter_block_sse41(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride, int size,
                             const CdefTaps& taps) {
  if (taps.secondary == 0) {
    filter_block<true, false>(in, in_stride, out, out_stride, size, taps);
  } else if (taps.primary == 0) {
    filter_block<false, true>(in, in_stride, out, out_stride, size, taps);
  } else {
    filter_block<true, true>(in, in_stride, out, out_stride, size, taps);
  }
}

}  // namespace

void init_cdef_sse41(DspTable* table) {
  table->cdef_direction_8x8 = cdef_direction_8x8_sse41;
  table->cdef_filter_block = cdef_filter_block_sse41;
}

}  // namespace svc::codec::dsp

SVC_TARGET_END
