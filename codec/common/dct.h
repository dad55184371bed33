// SPDX-License-Identifier: BSD-2-Clause
// The inverse of the 8x8 two-dimensional DCT-II (orthonormal scaling: DC = 8 x block
// mean) and of the other transform sizes and types: bit-exact 32-bit integer transforms
// that encoder and decoder share, so both reconstruct identical pixels on every
// platform. The forward transforms run only in the encoder and may be float
// (codec/encoder/forward_transform.h). Double-precision references are kept for tests.
// All functions are pure and thread-safe. Blocks are 64 values, row-major (index y*8+x
// for samples, v*8+u for coefficients, u = horizontal frequency).
#pragma once

#include <cstdint>

#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"

namespace svc::codec {

inline constexpr int kBlockSize = 8;
inline constexpr int kBlockArea = 64;

// The inverse accepts coefficients in this range (MPEG-2 saturation); callers clamp.
inline constexpr int kMinCoefficient = -2048;
inline constexpr int kMaxCoefficient = 2047;

// Integer inverse DCT; coefficients must lie in [kMinCoefficient, kMaxCoefficient].
// Output is not clipped (the caller adds a prediction or level shift and clips).
// Accuracy meets IEEE 1180-1990 (peak error <= 1 against the exact inverse).
// The orthonormal 8x8 DCT basis in double precision, [u][x] = c(u) cos((2x+1) u pi / 16)
// with c(0) = sqrt(1/8), c(u > 0) = 1/2: what the double references of both directions
// compute with.
using DctBasis8x8 = double[8][8];
const DctBasis8x8& dct_basis_8x8();

void inverse_dct_8x8(const int16_t* coefficients, int16_t* samples);
// The same integer transform as inverse_dct_8x8 written as a plain matrix product
// without shortcuts: bit-identical output (the definition docs/codec.md spells out).
void inverse_dct_8x8_integer_reference(const int16_t* coefficients, int16_t* samples);
// Exact inverse DCT in double precision.
void inverse_dct_8x8_reference(const double* coefficients, double* samples);

// Any transform size (blocks of transform_area(size) values, row-major). 4x4 and 16x16
// use HEVC's integer DCT matrices (codec/common/dsp/dct_4_16_basis.h, docs/codec.md
// section 5.5) scaled to near-orthonormal; the inverses undo exactly the scale of the
// encoder's forward transforms (codec/encoder/forward_transform.h).
void inverse_transform(TransformSize size, const int16_t* coefficients, int16_t* samples);
// The integer inverse as a plain matrix product: bit-identical to inverse_transform.
void inverse_transform_integer_reference(TransformSize size, const int16_t* coefficients, int16_t* samples);
// The inverse in double precision (for 4x4 and 16x16, the integer matrices without
// rounding), of the same scale as inverse_transform.
void inverse_transform_reference(TransformSize size, const double* coefficients, double* samples);

// The intra transform types (codec/common/transform_type.h, docs/codec.md 5.5.2): DCT_DCT
// is the transforms above; the others take per direction HEVC's integer DCT of the size
// or an integer DST-VII at the same scale, so quantization treats every type alike.
void inverse_transform(TransformSize size, TransformType type, const int16_t* coefficients, int16_t* samples);
// The integer inverse as a plain matrix product: bit-identical to inverse_transform.
void inverse_transform_integer_reference(TransformSize size, TransformType type, const int16_t* coefficients,
                                         int16_t* samples);

}  // namespace svc::codec
