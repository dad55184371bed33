// SPDX-License-Identifier: BSD-2-Clause
// The plain 4x4, 8x8 and 16x16 Hadamard SATDs of the encoder's first-stage estimates.
#include <cstdlib>

#include "codec/encoder/dsp/encoder_dsp_init.h"

namespace svc::codec::dsp {
namespace {

// 1-D N-point Hadamard butterflies in place.
template <int N>
void hadamard(int* v, int stride) {
  for (int span = 1; span < N; span *= 2) {
    for (int i = 0; i < N; i += 2 * span) {
      for (int j = i; j < i + span; ++j) {
        const int a = v[j * stride], b = v[(j + span) * stride];
        v[j * stride] = a + b;
        v[(j + span) * stride] = a - b;
      }
    }
  }
}

template <int N>
int satd(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction, int prediction_stride = N) {
  int d[N * N];
  for (int y = 0; y < N; ++y) {
    for (int x = 0; x < N; ++x)
      d[N * y + x] = source[y * source_stride + x] - prediction[prediction_stride * y + x];
  }
  for (int y = 0; y < N; ++y) hadamard<N>(d + N * y, 1);
  for (int x = 0; x < N; ++x) hadamard<N>(d + x, N);
  int sum = 0;
  for (int i = 0; i < N * N; ++i) sum += std::abs(d[i]);
  return sum;
}

int satd_4x4_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  return satd<4>(source, source_stride, prediction);
}
int satd_8x8_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  return satd<8>(source, source_stride, prediction);
}

// The sum of the four 8x8 quadrants' SATDs.
int satd_16x16_c(const uint8_t* source, ptrdiff_t source_stride, const uint8_t* prediction) {
  int sum = 0;
  for (int q = 0; q < 4; ++q) {
    const int x = 8 * (q & 1), y = 8 * (q >> 1);
    sum += satd<8>(source + y * source_stride + x, source_stride, prediction + 16 * y + x, 16);
  }
  return sum;
}

}  // namespace

void init_satd_c(EncoderDspTable* table) {
  table->satd_4x4 = satd_4x4_c;
  table->satd_8x8 = satd_8x8_c;
  table->satd_16x16 = satd_16x16_c;
}

}  // namespace svc::codec::dsp
