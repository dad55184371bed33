// SPDX-License-Identifier: BSD-2-Clause
// Epipolar vector coordinates (docs/codec.md 3.8): with a reference camera of the same
// orientation, the point seen at a pixel moves along the line through that pixel and the
// epipole as its depth varies, so a depth-derived vector is a multiple of a direction the
// decoder can compute. Vector differences are coded along that direction and across it,
// where they are almost always zero.
//
// Threading: pure functions; safe to call concurrently.
#pragma once

#include <cstdint>

#include "codec/common/motion.h"

namespace svc::codec {

// The direction field of one reference: at the point (x2 / 2, y2 / 2) of a width x height
// face, in pixel-edge coordinates (pixel (i, j) covers [i, i + 1) x [j, j + 1)), with
// X = x2 - width and Y = y2 - height (twice the offset from the face centre), the
// direction is (a X + bx width, a Y + by height). All zero: no field (plain x, y
// coordinates).
struct EpipolarLines {
  int32_t a = 0, bx = 0, by = 0;
  bool present() const { return a != 0 || bx != 0 || by != 0; }
  friend bool operator==(const EpipolarLines&, const EpipolarLines&) = default;
};

// Largest |a|, |bx|, |by| a bitstream may carry: with faces of at most 2^14 pixels a
// side, directions stay below 2^28 and every product below 2^47.
inline constexpr int32_t kMaxEpipolarCoefficient = 1 << 12;

struct LineDirection {
  int64_t x = 0, y = 0;
};

LineDirection line_direction(const EpipolarLines& lines, int width, int height, int64_t x2, int64_t y2);

// A vector in line coordinates: `along` is its component on the direction's major axis
// (signed so that the direction is positive), `across` its offset on the minor axis from
// the quarter-pel point of the line at that `along`. A bijection on integer vectors;
// with a zero direction, along = x and across = y.
struct LineCoordinates {
  int64_t along = 0, across = 0;
};

LineCoordinates to_line_coordinates(int64_t x, int64_t y, LineDirection d);

// The inverse, as (x, y) in 64 bits so that the caller can check the range.
void from_line_coordinates(LineCoordinates c, LineDirection d, int64_t* x, int64_t* y);

// Carries the vector (x, y) (|x|, |y| < 2^18) of a point on the line of direction `from`
// to the line of direction `to` at the same depth: its parameter t = (x, y) . F / |F|^2
// along `from` times `to`, on the line there (across 0). With F and T the two
// directions, each component moved toward zero by the same shift s, the least that
// brings every component of both below 2^15 (k >> s of |k|, the sign kept), the result
// is from_line(round((x Fx + y Fy) M / (Fx^2 + Fy^2)), 0) with M = max(|Tx|, |Ty|) >> s,
// rounded as from_line rounds. False (nothing written) when F or M is zero.
bool carry_along_lines(int64_t x, int64_t y, LineDirection from, LineDirection to, int64_t* out_x, int64_t* out_y);

}  // namespace svc::codec
