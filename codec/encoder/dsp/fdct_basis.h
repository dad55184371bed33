// SPDX-License-Identifier: BSD-2-Clause
// The forward DCT's float basis, shared by the plain kernel and its variants so that all
// multiply by the same constants.
#pragma once

namespace svc::codec::dsp {

struct ForwardDctBasis {
  float even[4][4];  // [k][x]: basis(2k, x)
  float odd[4][4];   // [k][x]: basis(2k+1, x)
  ForwardDctBasis();
};
extern const ForwardDctBasis kForwardDctBasis;

}  // namespace svc::codec::dsp
