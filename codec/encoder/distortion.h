// SPDX-License-Identifier: BSD-2-Clause
// The encoder's measure of distortion: the sum of squared differences of two blocks of
// samples, each with its own stride. Inline: the mode decisions call it for every option.
#pragma once

#include <cstddef>
#include <cstdint>

namespace svc::codec {

inline int64_t squared_error(const uint8_t* a, ptrdiff_t a_stride, const uint8_t* b, ptrdiff_t b_stride, int width,
                             int height) {
  int64_t sum = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int d = static_cast<int>(a[y * a_stride + x]) - static_cast<int>(b[y * b_stride + x]);
      sum += d * d;
    }
  }
  return sum;
}

}  // namespace svc::codec
