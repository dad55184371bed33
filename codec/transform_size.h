// The transform block sizes of the codec (docs/codec.md sections 3 and 7).
#pragma once

#include <cstdint>

namespace svc::codec {

enum class TransformSize : uint8_t { k8x8 = 0, k4x4 = 1, k16x16 = 2 };
inline constexpr int kTransformSizes = 3;
inline constexpr int kMaxTransformWidth = 16;  // the largest size the tables are laid out for
inline constexpr int kMaxTransformArea = kMaxTransformWidth * kMaxTransformWidth;

constexpr int transform_width(TransformSize size) {
  return size == TransformSize::k4x4 ? 4 : size == TransformSize::k16x16 ? 16 : 8;
}
constexpr int transform_area(TransformSize size) { return transform_width(size) * transform_width(size); }

}  // namespace svc::codec
