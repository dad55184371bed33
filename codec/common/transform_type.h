// SPDX-License-Identifier: BSD-2-Clause
// The transform types of intra residual blocks (docs/codec.md 5.5.2): per direction the
// DCT-II or an integer DST-VII, as in AV1 (ADST) and HEVC (4x4 DST). The DST's basis
// functions start near zero at the edge the prediction comes from, where the residual of
// a directional prediction is smallest, and grow away from it.
#pragma once

#include <cstdint>

namespace svc::codec {

// Bit 0: the rows (horizontal direction) use the DST; bit 1: the columns (vertical).
// Named vertical first, as AV1 names them.
enum class TransformType : uint8_t { kDctDct = 0, kDctDst = 1, kDstDct = 2, kDstDst = 3 };
inline constexpr int kTransformTypes = 4;

constexpr bool horizontal_dst(TransformType type) { return (static_cast<int>(type) & 1) != 0; }
constexpr bool vertical_dst(TransformType type) { return (static_cast<int>(type) & 2) != 0; }
constexpr TransformType transform_type_of(bool vertical, bool horizontal) {
  return static_cast<TransformType>((vertical ? 2 : 0) | (horizontal ? 1 : 0));
}

}  // namespace svc::codec
