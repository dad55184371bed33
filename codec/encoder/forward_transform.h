// SPDX-License-Identifier: BSD-2-Clause
// The encoder's forward transforms, through its kernel table
// (codec/encoder/dsp/encoder_dsp.h): the 8x8 two-dimensional DCT-II (orthonormal
// scaling: DC = 8 x block mean) and the other transform sizes and types, in float. They
// are the transposes of the shared integer inverses (codec/common/dct.h), whose scale
// the inverses undo exactly. All functions are pure and thread-safe. Blocks are
// row-major (index y*W+x for samples, v*W+u for coefficients, u = horizontal frequency).
#pragma once

#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"

namespace svc::codec {

// Fast separable forward DCT (even/odd butterfly per 1-D pass).
void forward_dct_8x8(const float* samples, float* coefficients);
// Textbook O(n^4) forward DCT in double precision.
void forward_dct_8x8_reference(const double* samples, double* coefficients);

// Any transform size (blocks of transform_area(size) values). 4x4 and 16x16 take the
// transposes of HEVC's integer DCT matrices (codec/common/dsp/dct_4_16_basis.h,
// docs/codec.md section 5.5) in float, scaled to near-orthonormal, at half scale for 16x16
// (so that coefficients of 8-bit residuals fit [kMinCoefficient, kMaxCoefficient]).
void forward_transform(TransformSize size, const float* samples, float* coefficients);

// The intra transform types (codec/common/transform_type.h, docs/codec.md 5.5.2): DCT_DCT
// is the transforms above; the others take per direction HEVC's DCT of the size or a
// DST-VII at the same scale, so quantization treats every type alike.
void forward_transform(TransformSize size, TransformType type, const float* samples, float* coefficients);

}  // namespace svc::codec
