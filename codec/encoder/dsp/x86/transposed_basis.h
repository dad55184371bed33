// SPDX-License-Identifier: BSD-2-Clause
// A float transform basis b[k][n] transposed to bt[n][k], so that an SSE or AVX kernel
// loads four or eight frequencies of one sample at once. Shared by the SSE4.1 and AVX2
// DCT and the transform-type kernels; any basis type with a member `float b[N][N]`
// works.
#pragma once

namespace svc::codec::dsp {

template <int N>
struct TransposedBasis {
  alignas(32) float bt[N][N];
  template <class Basis>
  explicit TransposedBasis(const Basis& basis) {
    for (int k = 0; k < N; ++k) {
      for (int n = 0; n < N; ++n) bt[n][k] = basis.b[k][n];
    }
  }
};

}  // namespace svc::codec::dsp
