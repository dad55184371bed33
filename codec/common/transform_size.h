// SPDX-License-Identifier: BSD-2-Clause
// The transform block sizes of the codec (docs/codec.md sections 3.1 and 5.5).
#pragma once

#include <cassert>
#include <cstdint>

namespace svc::codec {

// Rectangular sizes are width x height (16x8: rows of 16 samples, 8 rows).
enum class TransformSize : uint8_t {
  k8x8 = 0,
  k4x4 = 1,
  k16x16 = 2,
  k16x8 = 3,
  k8x16 = 4,
  k16x4 = 5,
  k4x16 = 6,
  k8x4 = 7,
  k4x8 = 8
};
inline constexpr int kTransformSizes = 9;
inline constexpr int kMaxTransformWidth = 16;  // the largest size the tables are laid out for
inline constexpr int kMaxTransformArea = kMaxTransformWidth * kMaxTransformWidth;

// The index of a size in tables laid out by size (kTransformSizes entries).
constexpr int size_index(TransformSize size) { return static_cast<int>(size); }

constexpr int transform_width(TransformSize size) {
  switch (size) {
    case TransformSize::k4x4:
    case TransformSize::k4x16:
    case TransformSize::k4x8: return 4;
    case TransformSize::k16x16:
    case TransformSize::k16x8:
    case TransformSize::k16x4: return 16;
    default: return 8;
  }
}
constexpr int transform_height(TransformSize size) {
  switch (size) {
    case TransformSize::k4x4:
    case TransformSize::k16x4:
    case TransformSize::k8x4: return 4;
    case TransformSize::k16x16:
    case TransformSize::k8x16:
    case TransformSize::k4x16: return 16;
    default: return 8;
  }
}
constexpr int transform_area(TransformSize size) { return transform_width(size) * transform_height(size); }
constexpr bool is_rectangular(TransformSize size) { return transform_width(size) != transform_height(size); }
// Rectangular coefficients are on the scale 8 / sqrt(W H) of the orthonormal ones
// (docs/codec.md 5.5.3): 1/sqrt(2) for 16x8 and 8x16, 1 for 16x4 and 4x16, sqrt(2) for 8x4
// and 4x8. The scale in units of sqrt(2): -1, 0 or 1.
constexpr int rectangular_scale_log_sqrt2(TransformSize size) {
  const int area = transform_area(size);
  return area == 128 ? -1 : area == 32 ? 1 : 0;
}

// The transform size of a width x height block, which must be one of the sizes.
constexpr TransformSize transform_size_of(int width, int height) {
  for (int s = 0; s < kTransformSizes; ++s) {
    const auto size = static_cast<TransformSize>(s);
    if (transform_width(size) == width && transform_height(size) == height) return size;
  }
  assert(false && "not a transform size");
  return TransformSize::k8x8;
}

}  // namespace svc::codec
