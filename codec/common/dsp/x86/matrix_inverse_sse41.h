// SPDX-License-Identifier: BSD-2-Clause
// The integer inverse of a W x H separable transform (W samples a row) given its row
// (W-point) and column (H-point) matrices (m[frequency][sample], entries within 16 bits),
// shared by the SSE4.1 4x4 and 16x16 DCTs and the transform types of every size. It
// computes what the plain kernels define:
//   row pass    t[v][x] = (2^(rs-1) + sum_u rows[u][x] c[v][u]) >> rs      (32 bits)
//   column pass s[y][x] = clamp16((2^(cs-1) + sum_v columns[v][y] t[v][x]) >> cs)
// with pmaddwd on pairs of 16-bit operands: coefficient pairs against interleaved matrix
// rows, then pairs of row outputs against column entries. Row outputs of valid streams
// fit 16 bits; a block whose row outputs do not takes the 32-bit column pass (pmulld),
// so every input gives the plain result (4x4 blocks always do). All-zero coefficient rows give zero row outputs
// (the rounding term is below 2^rs) and are skipped, as are zero coefficient pairs.
// 32-bit sums cannot overflow: entries below 2^9, 16 terms of at most 2^24.
#pragma once

#include <smmintrin.h>

#include <cstdint>
#include <cstring>

#include "codec/common/dsp/x86/target.h"

SVC_TARGET_BEGIN("sse4.1")

namespace svc::codec::dsp {
namespace {

// A matrix in the layouts the passes read: pairs of rows interleaved for pmaddwd,
// interleaved[p][2x + i] = m[2p + i][x] (row pass); pairs of entries of one sample packed
// in 32 bits, packed[p][y] = m[2p][y] | m[2p + 1][y] << 16 (16-bit column pass); the
// entries themselves (32-bit column pass).
template <int N>
struct InverseMatrixPairs {
  alignas(16) int16_t interleaved[N / 2][2 * N];
  int32_t packed[N / 2][N];
  int32_t entries[N][N];
  template <class Matrix>
  explicit InverseMatrixPairs(const Matrix& m) {
    for (int u = 0; u < N; ++u) {
      for (int x = 0; x < N; ++x) entries[u][x] = m[u][x];
    }
    for (int p = 0; p < N / 2; ++p) {
      for (int x = 0; x < N; ++x) {
        interleaved[p][2 * x] = static_cast<int16_t>(m[2 * p][x]);
        interleaved[p][2 * x + 1] = static_cast<int16_t>(m[2 * p + 1][x]);
        packed[p][x] = static_cast<int32_t>((static_cast<uint32_t>(m[2 * p][x]) & 0xffffu) |
                                            (static_cast<uint32_t>(m[2 * p + 1][x]) << 16));
      }
    }
  }
};

// Row pass of row v into t (N int32); returns whether the row has a non-zero coefficient.
template <int N>
bool inverse_row_pass(const InverseMatrixPairs<N>& rows, int shift, const int16_t* coefficients, int32_t* t) {
  const __m128i round = _mm_set1_epi32(1 << (shift - 1));
  const __m128i bits = _mm_cvtsi32_si128(shift);
  __m128i sums[N / 4];
  for (__m128i& sum : sums) sum = round;
  bool any = false;
  for (int p = 0; p < N / 2; ++p) {
    int32_t pair;
    std::memcpy(&pair, coefficients + 2 * p, sizeof pair);  // c[2p] low, c[2p + 1] high
    if (pair == 0) continue;
    any = true;
    const __m128i weights = _mm_set1_epi32(pair);
    for (int g = 0; g < N / 4; ++g) {
      const __m128i matrix = _mm_load_si128(reinterpret_cast<const __m128i*>(&rows.interleaved[p][8 * g]));
      sums[g] = _mm_add_epi32(sums[g], _mm_madd_epi16(matrix, weights));
    }
  }
  for (int g = 0; g < N / 4; ++g)
    _mm_storeu_si128(reinterpret_cast<__m128i*>(t + 4 * g), _mm_sra_epi32(sums[g], bits));
  return any;
}

// Column pass with 16-bit row outputs: eight samples of an output row per two pmaddwd.
template <int W, int H>
void inverse_column_pass_16(const InverseMatrixPairs<H>& columns, int shift, const int32_t* t, uint32_t row_mask,
                            int16_t* samples) {
  __m128i interleaved[H / 2][W / 8][2];
  uint32_t pair_mask = 0;
  for (int p = 0; p < H / 2; ++p) {
    if (((row_mask >> (2 * p)) & 3u) == 0) continue;
    pair_mask |= 1u << p;
    for (int g = 0; g < W / 8; ++g) {
      auto row16 = [&](int v) {
        const __m128i* row = reinterpret_cast<const __m128i*>(t + W * v + 8 * g);
        return _mm_packs_epi32(_mm_loadu_si128(row), _mm_loadu_si128(row + 1));
      };
      const __m128i a = row16(2 * p), b = row16(2 * p + 1);
      interleaved[p][g][0] = _mm_unpacklo_epi16(a, b);
      interleaved[p][g][1] = _mm_unpackhi_epi16(a, b);
    }
  }
  const __m128i round = _mm_set1_epi32(1 << (shift - 1));
  const __m128i bits = _mm_cvtsi32_si128(shift);
  for (int y = 0; y < H; ++y) {
    for (int g = 0; g < W / 8; ++g) {
      __m128i low = round, high = round;
      for (uint32_t pairs = pair_mask; pairs != 0; pairs &= pairs - 1) {
        const int p = __builtin_ctz(pairs);
        const __m128i weights = _mm_set1_epi32(columns.packed[p][y]);
        low = _mm_add_epi32(low, _mm_madd_epi16(interleaved[p][g][0], weights));
        high = _mm_add_epi32(high, _mm_madd_epi16(interleaved[p][g][1], weights));
      }
      const __m128i out = _mm_packs_epi32(_mm_sra_epi32(low, bits), _mm_sra_epi32(high, bits));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(samples + W * y + 8 * g), out);
    }
  }
}

// Column pass in 32 bits, for row outputs beyond 16 bits.
template <int W, int H>
void inverse_column_pass_32(const InverseMatrixPairs<H>& columns, int shift, const int32_t* t, int16_t* samples) {
  const __m128i round = _mm_set1_epi32(1 << (shift - 1));
  const __m128i bits = _mm_cvtsi32_si128(shift);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; x += 4) {
      __m128i sum = round;
      for (int v = 0; v < H; ++v) {
        const __m128i row = _mm_loadu_si128(reinterpret_cast<const __m128i*>(t + W * v + x));
        sum = _mm_add_epi32(sum, _mm_mullo_epi32(_mm_set1_epi32(columns.entries[v][y]), row));
      }
      const __m128i out = _mm_sra_epi32(sum, bits);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(samples + W * y + x), _mm_packs_epi32(out, out));
    }
  }
}

// Whether each of the `count` values of t fits 16 bits.
template <int count>
bool fits_16_bits(const int32_t* t) {
  __m128i low = _mm_setzero_si128(), high = _mm_setzero_si128();
  for (int i = 0; i < count; i += 4) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(t + i));
    low = _mm_min_epi32(low, v);
    high = _mm_max_epi32(high, v);
  }
  const __m128i outside =
      _mm_or_si128(_mm_cmplt_epi32(low, _mm_set1_epi32(-32768)), _mm_cmpgt_epi32(high, _mm_set1_epi32(32767)));
  return _mm_testz_si128(outside, outside) != 0;
}

template <int W, int H>
void inverse_matrix_transform(const InverseMatrixPairs<W>& rows, int row_shift,
                              const InverseMatrixPairs<H>& columns, int column_shift, const int16_t* coefficients,
                              int16_t* samples) {
  alignas(16) int32_t t[W * H];
  uint32_t row_mask = 0;
  for (int v = 0; v < H; ++v) {
    if (inverse_row_pass<W>(rows, row_shift, coefficients + W * v, t + W * v)) row_mask |= 1u << v;
  }
  // A 4x4 block's rows are narrower than a 16-bit column pass's eight samples.
  if constexpr (W >= 8) {
    if (fits_16_bits<W * H>(t)) {
      inverse_column_pass_16<W, H>(columns, column_shift, t, row_mask, samples);
      return;
    }
  }
  inverse_column_pass_32<W, H>(columns, column_shift, t, samples);
}

}  // namespace
}  // namespace svc::codec::dsp

SVC_TARGET_END
