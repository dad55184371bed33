// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/epipolar.h"

#include <algorithm>
#include <bit>
#include <cstdlib>

#include "codec/common/integer_division.h"

namespace svc::codec {
namespace {

// floor((2 n + m) / (2 m)) for m > 0: n / m rounded to nearest, halves up.
int64_t divide_rounded(int64_t n, int64_t m) { return floor_divide(2 * n + m, 2 * m); }

int64_t shifted_toward_zero(int64_t value, int shift) { return value < 0 ? -(-value >> shift) : value >> shift; }

}  // namespace

bool carry_along_lines(int64_t x, int64_t y, LineDirection from, LineDirection to, int64_t* out_x, int64_t* out_y) {
  const int64_t largest = std::max({std::llabs(from.x), std::llabs(from.y), std::llabs(to.x), std::llabs(to.y)});
  const int shift = std::max(0, static_cast<int>(std::bit_width(static_cast<uint64_t>(largest))) - 15);
  const int64_t fx = shifted_toward_zero(from.x, shift), fy = shifted_toward_zero(from.y, shift);
  const int64_t major = std::max(std::llabs(to.x), std::llabs(to.y)) >> shift;
  const int64_t norm = fx * fx + fy * fy;
  if (norm == 0 || major == 0) return false;
  const int64_t along = divide_rounded((x * fx + y * fy) * major, norm);
  from_line_coordinates({along, 0}, to, out_x, out_y);
  return true;
}

LineDirection line_direction(const EpipolarLines& lines, int width, int height, int64_t x2, int64_t y2) {
  const int64_t x = x2 - width, y = y2 - height;
  return {lines.a * x + int64_t{lines.bx} * width, lines.a * y + int64_t{lines.by} * height};
}

LineCoordinates to_line_coordinates(int64_t x, int64_t y, LineDirection d) {
  if (d.x == 0 && d.y == 0) return {x, y};
  if (std::llabs(d.x) >= std::llabs(d.y)) {
    const int64_t along = d.x > 0 ? x : -x;
    return {along, y - divide_rounded(along * d.y, std::llabs(d.x))};
  }
  const int64_t along = d.y > 0 ? y : -y;
  return {along, x - divide_rounded(along * d.x, std::llabs(d.y))};
}

void from_line_coordinates(LineCoordinates c, LineDirection d, int64_t* x, int64_t* y) {
  if (d.x == 0 && d.y == 0) {
    *x = c.along;
    *y = c.across;
  } else if (std::llabs(d.x) >= std::llabs(d.y)) {
    *x = d.x > 0 ? c.along : -c.along;
    *y = c.across + divide_rounded(c.along * d.y, std::llabs(d.x));
  } else {
    *y = d.y > 0 ? c.along : -c.along;
    *x = c.across + divide_rounded(c.along * d.x, std::llabs(d.y));
  }
}

}  // namespace svc::codec
