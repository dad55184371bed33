// SPDX-License-Identifier: BSD-2-Clause
// The contexts of an intra block's transform type (docs/codec.md 3.5): two adaptive
// bits after the block's levels, the vertical direction's DST flag then the horizontal
// one's, with contexts by transform size, by the class of the block's prediction mode
// (the direction the residual grows along depends on it) and, for the second bit, by
// the first. Coded only for blocks with levels, and only in frames whose header enables
// transform types.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <type_traits>

#include "codec/common/adaptive_bit.h"
#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"

namespace svc::codec {

// Prediction mode classes: planar and DC; near-horizontal (modes 6..14); near-vertical
// (22..30); the other angles (diagonals); chroma from luma.
inline constexpr int kTransformTypeModeClasses = 5;
int transform_type_mode_class(int mode);  // mode 0..34, or kCflMode

struct TransformTypeContexts {
  // Whether the frame codes transform types (header flag); when false every block is
  // DCT_DCT and nothing is coded.
  bool enabled = false;
  // [size][mode class][0: vertical, 1 + vertical: horizontal]; every size codes types.
  std::array<std::array<std::array<AdaptiveBit, 3>, kTransformTypeModeClasses>, kTransformSizes> bits{};
};

// Calls f on every context, in index order (docs/codec.md 6.1).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, TransformTypeContexts>
void for_each_context(Set& s, F&& f) { for_each_bit(s.bits, f); }

// The contexts of a block's two bits, by size and the class of its mode.
template <class Contexts>
requires std::same_as<std::remove_const_t<Contexts>, TransformTypeContexts>
auto& transform_type_bits_of(Contexts& contexts, TransformSize size, int mode) {
  return contexts.bits[static_cast<size_t>(size)][static_cast<size_t>(transform_type_mode_class(mode))];
}

}  // namespace svc::codec
