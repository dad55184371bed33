// SPDX-License-Identifier: BSD-2-Clause
// The parts of the CDEF kernels (docs/codec.md, section 5.8.2) shared by the plain kernels
// and their variants: the direction offsets, the constraint function and the direction
// costs from the partial sums.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace svc::codec::dsp {

// Row and column offsets of the first (k = 0) and second (k = 1) tap along each direction
// (AV1's Cdef_Directions).
inline constexpr int kCdefDirections[8][2][2] = {
    {{-1, 1}, {-2, 2}}, {{0, 1}, {-1, 2}}, {{0, 1}, {0, 2}}, {{0, 1}, {1, 2}},
    {{1, 1}, {2, 2}},   {{1, 0}, {2, 1}},  {{1, 0}, {2, 0}}, {{1, 0}, {2, -1}},
};
// Sample offsets in a block of row stride `stride` of the primary taps (k = 0, 1) along
// `direction` and of the secondary taps along the directions two steps either side (t = 0:
// direction - 2, t = 1: direction + 2).
struct CdefTapOffsets {
  ptrdiff_t primary[2];
  ptrdiff_t secondary[2][2];  // [k][t]
};
inline CdefTapOffsets cdef_tap_offsets(int direction, ptrdiff_t stride) {
  CdefTapOffsets offsets{};
  for (int k = 0; k < 2; ++k) {
    const int* d = kCdefDirections[direction][k];
    offsets.primary[k] = d[0] * stride + d[1];
    for (int t = 0; t < 2; ++t) {
      const int* e = kCdefDirections[(direction + (t == 0 ? -2 : 2)) & 7][k];
      offsets.secondary[k][t] = e[0] * stride + e[1];
    }
  }
  return offsets;
}
// Primary tap weights by the parity of the primary strength; secondary weights.
inline constexpr int kCdefPrimaryTaps[2][2] = {{4, 2}, {3, 3}};
inline constexpr int kCdefSecondaryTaps[2] = {2, 1};

inline int cdef_floor_log2(int value) { return std::bit_width(static_cast<unsigned>(value)) - 1; }

// Limits a neighbour's difference: full up to about the threshold, fading to 0 for
// differences the damping marks as edges.
inline int cdef_constrain(int difference, int threshold, int damping) {
  if (threshold == 0) return 0;
  const int shift = std::max(0, damping - cdef_floor_log2(threshold));
  const int magnitude = std::min(std::abs(difference), std::max(0, threshold - (std::abs(difference) >> shift)));
  return difference < 0 ? -magnitude : magnitude;
}

// The first direction of the largest cost (0 when all are 0) and, in *variance, its
// contrast against the orthogonal direction.
inline int cdef_direction_from_costs(const int32_t cost[8], int32_t* variance) {
  int best = 0;
  int32_t best_cost = 0;
  for (int d = 0; d < 8; ++d) {
    if (cost[d] > best_cost) {
      best_cost = cost[d];
      best = d;
    }
  }
  *variance = (best_cost - cost[(best + 4) & 7]) >> 10;
  return best;
}

// Direction (0..7) and contrast from the partial sums of section 11.2. The costs are
// symmetric in partial[0], partial[4] (index k <-> 14 - k) and in partial[1],
// partial[3], partial[5], partial[7] (k <-> 10 - k), so a variant may fill those mirrored.
inline int cdef_direction_from_partials(const int32_t partial[8][15], int32_t* variance) {
  constexpr int32_t kDivTable[9] = {0, 840, 420, 280, 210, 168, 140, 120, 105};
  int32_t cost[8] = {};
  for (int i = 0; i < 8; ++i) {
    cost[2] += partial[2][i] * partial[2][i];
    cost[6] += partial[6][i] * partial[6][i];
  }
  cost[2] *= kDivTable[8];
  cost[6] *= kDivTable[8];
  for (int i = 0; i < 7; ++i) {
    cost[0] += (partial[0][i] * partial[0][i] + partial[0][14 - i] * partial[0][14 - i]) * kDivTable[i + 1];
    cost[4] += (partial[4][i] * partial[4][i] + partial[4][14 - i] * partial[4][14 - i]) * kDivTable[i + 1];
  }
  cost[0] += partial[0][7] * partial[0][7] * kDivTable[8];
  cost[4] += partial[4][7] * partial[4][7] * kDivTable[8];
  for (int d = 1; d < 8; d += 2) {
    for (int j = 0; j < 5; ++j) cost[d] += partial[d][3 + j] * partial[d][3 + j];
    cost[d] *= kDivTable[8];
    for (int j = 0; j < 3; ++j) {
      cost[d] += (partial[d][j] * partial[d][j] + partial[d][10 - j] * partial[d][10 - j]) * kDivTable[2 * j + 2];
    }
  }
  return cdef_direction_from_costs(cost, variance);
}

}  // namespace svc::codec::dsp
