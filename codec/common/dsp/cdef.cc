// SPDX-License-Identifier: BSD-2-Clause
// Plain CDEF kernels (docs/codec.md, section 5.8.2 defines the arithmetic): the direction
// search of an 8x8 luma block and the filter of one 8x8 (luma) or 4x4 (chroma) block,
// the model of AV1 sections 7.15.2 and 7.15.3.
#include <algorithm>

#include "codec/common/dsp/cdef_formulas.h"
#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

int cdef_direction_8x8_c(const uint8_t* pixels, ptrdiff_t stride, int32_t* variance) {
  int32_t partial[8][15] = {};
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const int x = pixels[i * stride + j] - 128;
      partial[0][i + j] += x;
      partial[1][i + j / 2] += x;
      partial[2][i] += x;
      partial[3][3 + i - j / 2] += x;
      partial[4][7 + i - j] += x;
      partial[5][3 - i / 2 + j] += x;
      partial[6][j] += x;
      partial[7][i / 2 + j] += x;
    }
  }
  return cdef_direction_from_partials(partial, variance);
}

// Adds the constrained difference of tap `p` (skipped when unavailable) to *sum.
inline void add_tap(int p, int x, int weight, int threshold, int damping, int* sum, int* low, int* high) {
  if (p == kCdefUnavailable) return;
  *sum += weight * cdef_constrain(p - x, threshold, damping);
  *low = std::min(*low, p);
  *high = std::max(*high, p);
}

void cdef_filter_block_c(const uint16_t* in, ptrdiff_t in_stride, uint8_t* out, ptrdiff_t out_stride, int size,
                         const CdefTaps& taps) {
  const int* primary_taps = kCdefPrimaryTaps[taps.primary & 1];
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const uint16_t* center = in + y * in_stride + x;
      const int value = *center;
      int sum = 0, low = value, high = value;
      for (int k = 0; k < 2; ++k) {
        for (int sign = -1; sign <= 1; sign += 2) {
          const int* primary = kCdefDirections[taps.direction][k];
          add_tap(center[sign * (primary[0] * in_stride + primary[1])], value, primary_taps[k], taps.primary,
                  taps.damping, &sum, &low, &high);
          for (int turn = -2; turn <= 2; turn += 4) {
            const int* secondary = kCdefDirections[(taps.direction + turn) & 7][k];
            add_tap(center[sign * (secondary[0] * in_stride + secondary[1])], value, kCdefSecondaryTaps[k],
                    taps.secondary, taps.damping, &sum, &low, &high);
          }
        }
      }
      out[y * out_stride + x] = static_cast<uint8_t>(std::clamp(value + ((8 + sum - (sum < 0)) >> 4), low, high));
    }
  }
}

}  // namespace

void init_cdef_c(DspTable* table) {
  table->cdef_direction_8x8 = cdef_direction_8x8_c;
  table->cdef_filter_block = cdef_filter_block_c;
}

}  // namespace svc::codec::dsp
