// SPDX-License-Identifier: BSD-2-Clause
// The float bases of the 4x4 and 16x16 forward DCTs, shared by the plain kernels and
// their variants so that all multiply by the same numbers: HEVC's integer matrices
// (codec/common/dsp/dct_4_16_basis.h) scaled to (near) orthonormal.
#pragma once

#include "codec/common/dsp/dct_4_16_basis.h"

namespace svc::codec::dsp {

// The forward transforms' basis in float, [k][n]: HEVC's integer matrix / (64 sqrt(N)),
// the transpose of the inverse (HEVC's matrices are orthogonal to within 0.1 %).
template <int N>
struct ForwardDctFloatBasis {
  float b[N][N];
  ForwardDctFloatBasis();
};
extern const ForwardDctFloatBasis<4> kForwardDct4Basis;
extern const ForwardDctFloatBasis<16> kForwardDct16Basis;

}  // namespace svc::codec::dsp
