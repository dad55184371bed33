// SPDX-License-Identifier: BSD-2-Clause
// The encoder's RGB -> YCbCr 4:2:0 conversion of its input, the inverse of
// codec/common/color.h's. Full-range BT.601 (as JFIF), 16-bit fixed point; exact
// definition in docs/codec.md. All functions are pure and thread-safe; sizes are the
// caller's responsibility.
#pragma once

#include <cstdint>

#include "svc/types.h"

namespace svc::codec {

// rgb: width*height*3 bytes, row 0 at the top. Chroma is the rounded mean of each 2x2
// block (edge pixels replicated for odd sizes).
ImageYCbCr420 rgb_to_ycbcr420(const uint8_t* rgb, int width, int height);

// The per-pixel form of the same formulas (no subsampling), for tools and tests.
struct YCbCr {
  uint8_t y, cb, cr;
};
YCbCr rgb_to_ycbcr_pixel(uint8_t r, uint8_t g, uint8_t b);

// Plain per-pixel reference implementation of the image conversion (used by tests to
// check the optimized loop above; same results bit for bit).
ImageYCbCr420 rgb_to_ycbcr420_reference(const uint8_t* rgb, int width, int height);

}  // namespace svc::codec
