// SPDX-License-Identifier: BSD-2-Clause
// The epipolar lines of a reference camera seen from the current one, as the B-face
// coder carries them (codec/common/epipolar.h): from the cameras alone, no depth.
//
// Threading: a pure function; safe to call concurrently.
#pragma once

#include "codec/common/epipolar.h"
#include "svc/types.h"

namespace svc {

// The direction along which the point seen at each pixel of the current face moves in
// the reference face as its depth varies, as small integers (exact for cameras whose
// offset is a multiple of a common step in the camera's axes; otherwise each
// coefficient within 1/128 of the largest).
// None (all zero) when the two cameras differ in orientation or frustum (a point at
// infinity would move, so vectors are not multiples of one direction) or when they sit
// at the same place.
codec::EpipolarLines epipolar_lines(const Camera& current, const Camera& reference, int width, int height);

}  // namespace svc
