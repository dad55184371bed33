// SPDX-License-Identifier: BSD-2-Clause
// The block coding of one intra macroblock that both sides share, for intra frames and
// the intra macroblocks of B-faces: the neighbour state and contexts, the partitions of
// a luma macroblock, and the prediction and reconstruction of a block from its
// reconstructed neighbours (docs/codec.md 3.1, 5.2 and 3.7). Its syntax is read by
// codec/decoder/intra_syntax_reader.h and written by codec/encoder/intra_syntax_writer.h;
// the encoder's search is codec/encoder/intra_search.h. Not part of the codec's
// interface.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "codec/common/cfl.h"
#include "codec/common/coefficient_contexts.h"
#include "codec/common/intra_frame.h"
#include "codec/common/intra_prediction.h"
#include "codec/common/quant.h"
#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"
#include "codec/common/transform_type_contexts.h"

namespace svc::codec::intra {

// Entropy-coding state of one plane class (luma, chroma).
struct PlaneContexts {
  IntraModeContexts modes;
  BlockContextSet residual;
  std::array<AdaptiveBit, 3> split_16x16{};  // luma only, by split_context
  std::array<AdaptiveBit, 3> split_8x8{};
  std::array<AdaptiveBit, 3> halves_16x16{};  // luma only, by split_context
  AdaptiveBit vertical_halves;
  std::array<AdaptiveBit, 2> strips{};      // luma only, by vertical_halves
  std::array<AdaptiveBit, 3> halves_8x8{};  // luma only, by split_context
  AdaptiveBit vertical_8x8;
  CflContexts cfl;              // chroma only
  TransformTypeContexts types;  // `enabled` from the frame header
};

// Calls f on every context, in member order (docs/codec.md 6.1).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, PlaneContexts>
void for_each_context(Set& s, F&& f) {
  for_each_context(s.modes, f);
  for_each_context(s.residual, f);
  for_each_bit(s.split_16x16, f);
  for_each_bit(s.split_8x8, f);
  for_each_bit(s.halves_16x16, f);
  for_each_bit(s.vertical_halves, f);
  for_each_bit(s.strips, f);
  for_each_bit(s.halves_8x8, f);
  for_each_bit(s.vertical_8x8, f);
  for_each_context(s.cfl, f);
  for_each_context(s.types, f);
}

// Macroblock partition (CoefficientFrame::luma_partitions): bit 0, the 16x16 luma region
// splits into four 8x8 blocks; bit 1 + i, 8x8 block i (Z order) splits into four 4x4
// blocks, or bit 8 + i into two 8x4 blocks (top, bottom), with bit 12 + i two 4x8 blocks
// (left, right); without bit 0, bit 5 makes it two 16x8 blocks (top, bottom), or with
// bit 6 two 8x16 blocks (left, right), and bit 7 with bit 5 four strips instead: 16x4
// blocks top to bottom, or with bit 6 4x16 blocks left to right.
using LumaPartition = uint16_t;
inline constexpr LumaPartition kSplit16x16 = 1;
constexpr LumaPartition split_8x8_bit(int i) { return static_cast<LumaPartition>(2 << i); }
inline constexpr LumaPartition kHalves16x16 = 32;
inline constexpr LumaPartition kVerticalHalves = 64;
inline constexpr LumaPartition kStrips = 128;
constexpr LumaPartition halves_8x8_bit(int i) { return static_cast<LumaPartition>(256 << i); }
constexpr LumaPartition vertical_8x8_bit(int i) { return static_cast<LumaPartition>(4096 << i); }

// Calls visit(x, y, size) for the transform blocks of 8x8 block i (Z order) of a split
// macroblock, in coding order (x, y relative to the macroblock; size a TransformSize).
template <class Visit>
void for_each_quarter_block(LumaPartition partition, int i, Visit&& visit) {
  const int x = 8 * (i & 1), y = 8 * (i >> 1);
  if (partition & split_8x8_bit(i)) {
    for (int j = 0; j < 4; ++j) visit(x + 4 * (j & 1), y + 4 * (j >> 1), TransformSize::k4x4);
  } else if ((partition & halves_8x8_bit(i)) == 0) {
    visit(x, y, TransformSize::k8x8);
  } else if (partition & vertical_8x8_bit(i)) {
    visit(x, y, TransformSize::k4x8);
    visit(x + 4, y, TransformSize::k4x8);
  } else {
    visit(x, y, TransformSize::k8x4);
    visit(x, y + 4, TransformSize::k8x4);
  }
}

// Calls visit(x, y, size) for the transform blocks of a macroblock partition in coding
// order (x, y relative to the macroblock; size a TransformSize).
template <class Visit>
void for_each_luma_block(LumaPartition partition, Visit&& visit) {
  if ((partition & kSplit16x16) == 0) {
    if ((partition & kHalves16x16) == 0) {
      visit(0, 0, TransformSize::k16x16);
    } else if (partition & kStrips) {
      const bool vertical = (partition & kVerticalHalves) != 0;
      const TransformSize strip = vertical ? TransformSize::k4x16 : TransformSize::k16x4;
      for (int k = 0; k < 4; ++k) visit(vertical ? 4 * k : 0, vertical ? 0 : 4 * k, strip);
    } else if (partition & kVerticalHalves) {
      visit(0, 0, TransformSize::k8x16);
      visit(8, 0, TransformSize::k8x16);
    } else {
      visit(0, 0, TransformSize::k16x8);
      visit(0, 8, TransformSize::k16x8);
    }
    return;
  }
  for (int i = 0; i < 4; ++i) for_each_quarter_block(partition, i, visit);
}

// The size of every chroma block.
inline constexpr TransformSize kChromaSize = TransformSize::k8x8;

// Whether the block of size `a` at (xa, ya) and the block of size `b` at (xb, yb) overlap.
constexpr bool blocks_overlap(int xa, int ya, TransformSize a, int xb, int yb, TransformSize b) {
  return xa < xb + transform_width(b) && xb < xa + transform_width(a) && ya < yb + transform_height(b) &&
         yb < ya + transform_height(a);
}

// Per 4x4 unit of the plane being coded: the mode, coded flag and transform width (the
// shorter side) of the block covering it (width 0: not reconstructed yet). Source of the neighbour
// derivations of docs/codec.md 3.1 and 5.2.
class PlaneState {
 public:
  PlaneState(int width, int height)
      : units_x_(width / 4), units_y_(height / 4), units_(static_cast<size_t>(units_x_) * units_y_) {}

  ModeCandidates candidates(int x0, int y0) const {
    return most_probable_modes(x0 > 0 ? regular_mode(at(x0 - 4, y0).mode) : kDcMode,
                               y0 > 0 ? regular_mode(at(x0, y0 - 4).mode) : kDcMode);
  }
  // Left and above neighbours coded with CfL (chroma).
  int cfl_context(int x0, int y0) const {
    return (x0 > 0 && at(x0 - 4, y0).mode == kCflMode) + (y0 > 0 && at(x0, y0 - 4).mode == kCflMode);
  }
  int coded_block_context(int x0, int y0) const {
    return (x0 > 0 ? at(x0 - 4, y0).coded : 0) + (y0 > 0 ? at(x0, y0 - 4).coded : 0);
  }
  // Left and above neighbours coded with transforms narrower than `width`.
  int split_context(int x0, int y0, int width) const {
    return (x0 > 0 && at(x0 - 4, y0).width < width) + (y0 > 0 && at(x0, y0 - 4).width < width);
  }
  // The neighbours of the block of `size` at (x0, y0). Below-left and above-right count
  // when the whole segment (the other side's length) lies in the plane, reconstructed.
  EdgeAvailability availability(int x0, int y0, TransformSize size) const {
    const int w = transform_width(size), h = transform_height(size);
    EdgeAvailability a;
    a.left = x0 > 0;
    a.above = y0 > 0;
    a.below_left = a.left && (y0 + h + w) / 4 <= units_y_ && at(x0 - 4, y0 + h).width != 0 &&
                   at(x0 - 4, y0 + h + w - 4).width != 0;
    a.above_right = a.above && (x0 + w + h) / 4 <= units_x_ && at(x0 + w, y0 - 4).width != 0 &&
                    at(x0 + w + h - 4, y0 - 4).width != 0;
    return a;
  }
  void mark(int x0, int y0, TransformSize size, int mode, bool coded) {
    const int narrow = std::min(transform_width(size), transform_height(size));
    fill(x0, y0, size, {static_cast<uint8_t>(mode), coded, static_cast<uint8_t>(narrow)});
  }
  // Forgets a region, as before it was reconstructed (encoder: trying another partition).
  void clear(int x0, int y0, TransformSize size) { fill(x0, y0, size, Unit{}); }

 private:
  struct Unit {
    uint8_t mode = kDcMode;
    bool coded = false;
    uint8_t width = 0;
  };
  // A CfL block counts as DC for the most probable modes (its prediction's base).
  static int regular_mode(int mode) { return mode == kCflMode ? kDcMode : mode; }
  const Unit& at(int x, int y) const { return units_[static_cast<size_t>(y / 4) * units_x_ + x / 4]; }
  void fill(int x0, int y0, TransformSize size, const Unit& unit) {
    for (int y = y0 / 4; y < (y0 + transform_height(size)) / 4; ++y) {
      std::fill_n(units_.begin() + static_cast<ptrdiff_t>(static_cast<size_t>(y) * units_x_ + x0 / 4),
                  transform_width(size) / 4, unit);
    }
  }
  int units_x_, units_y_;
  std::vector<Unit> units_;
};

// The residual quantizers of every transform size at one index, indexed by TransformSize.
using SizedQuantizers = std::array<Quantizer, kTransformSizes>;
// The residual quantizers of one index (B-face intra macroblocks: flat).
SizedQuantizers residual_quantizers(int qindex, ResidualMatrix matrix = ResidualMatrix::kFlat);
const Quantizer& quantizer_for(const SizedQuantizers& quantizers, TransformSize size);

// Predicts the block of `size` at (x0, y0) of `plane` (stride samples a row) in `mode`
// from its reconstructed neighbours, adds the inverse transform of type `type` of
// `coefficients` (dequantized, natural order; null when the block has no levels),
// writes the clipped result into the plane and marks the block in `state`.
void reconstruct_block_in_plane(PlaneState& state, uint8_t* plane, int stride, int x0, int y0, TransformSize size,
                                int mode, const int16_t* coefficients, TransformType type);
// The same for an 8x8 chroma block in `mode`; CfL predicts from `luma`, the plane's
// reconstructed luma (luma_stride samples a row, luma sample (2 x0, 2 y0) co-located).
void reconstruct_chroma_block_in_plane(PlaneState& state, uint8_t* plane, int stride, int x0, int y0,
                                       const ChromaMode& mode, const uint8_t* luma, int luma_stride,
                                       const int16_t* coefficients, TransformType type);

}  // namespace svc::codec::intra
