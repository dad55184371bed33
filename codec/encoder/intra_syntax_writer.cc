// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/intra_syntax_writer.h"

#include <algorithm>
#include <cstdlib>

#include "codec/encoder/bit_cost.h"
#include "codec/encoder/coefficient_writer.h"

namespace svc::codec {

namespace {

// Cr's alpha may be 0 (a flag says whether it is); Cb's never is (that block would be
// the DC mode).
void encode_alpha(RangeEncoder& encoder, CflContexts& cfl, ChromaPlane plane, int cb_alpha, int alpha) {
  if (plane == ChromaPlane::kCr) {
    encoder.encode(cfl.cr_nonzero, alpha != 0);
    if (alpha == 0) return;
  }
  encoder.encode(cfl.sign[cfl_sign_context(plane, cb_alpha)], alpha < 0);
  auto& magnitude = cfl.magnitude[cfl_plane_index(plane)];
  const int m = std::abs(alpha);
  for (int k = 1; k < kCflMaxAlpha; ++k) {
    encoder.encode(magnitude[static_cast<size_t>(k - 1)], m > k);
    if (m == k) break;
  }
}

}  // namespace

int rank_among_others(const ModeCandidates& candidates, int mode) {
  int rank = mode;
  for (int candidate : candidates) rank -= candidate < mode;
  return rank;
}

void encode_intra_mode(RangeEncoder& encoder, IntraModeContexts& contexts, TransformSize size,
                       const ModeCandidates& candidates, int mode) {
  const SyntaxScope scope(encoder, SyntaxElement::kModes);
  for_each_mode_bit(contexts, size, candidates, mode,
                    [&](AdaptiveBit& model, int bit) { encoder.encode(model, bit); });
}

float intra_mode_bits(const IntraModeContexts& contexts, TransformSize size, const ModeCandidates& candidates,
                      int mode) {
  float bits = 0;
  for_each_mode_bit(contexts, size, candidates, mode,
                    [&](const AdaptiveBit& model, int bit) { bits += bit_cost(model, bit); });
  return bits;
}

void encode_chroma_mode(RangeEncoder& encoder, CflContexts& cfl, IntraModeContexts& modes, int cfl_context,
                        const ModeCandidates& candidates, ChromaPlane plane, const ChromaMode& cb,
                        const ChromaMode& mode) {
  const SyntaxScope scope(encoder, SyntaxElement::kModes);
  if (plane == ChromaPlane::kCr) {
    if (cb.cfl()) encode_alpha(encoder, cfl, plane, cb.alpha, mode.alpha);
    return;
  }
  encoder.encode(cfl.flag[static_cast<size_t>(cfl_context)], mode.cfl());
  if (mode.cfl()) {
    encode_alpha(encoder, cfl, plane, 0, mode.alpha);
  } else {
    encode_intra_mode(encoder, modes, intra::kChromaSize, candidates, mode.mode);
  }
}

float cfl_flag_bits(const CflContexts& cfl, int cfl_context, bool set) {
  return bit_cost(cfl.flag[static_cast<size_t>(cfl_context)], set);
}

float cfl_alpha_bits(const CflContexts& cfl, ChromaPlane plane, int cb_alpha, int alpha) {
  float bits = 0;
  if (plane == ChromaPlane::kCr) {
    bits += bit_cost(cfl.cr_nonzero, alpha != 0);
    if (alpha == 0) return bits;
  }
  bits += bit_cost(cfl.sign[cfl_sign_context(plane, cb_alpha)], alpha < 0);
  const auto& magnitude = cfl.magnitude[cfl_plane_index(plane)];
  const int m = std::abs(alpha);
  for (int k = 1; k < kCflMaxAlpha; ++k) {
    bits += bit_cost(magnitude[static_cast<size_t>(k - 1)], m > k);
    if (m == k) break;
  }
  return bits;
}

void encode_transform_type(RangeEncoder& encoder, TransformTypeContexts& contexts, TransformSize size, int mode,
                           TransformType type) {
  if (!contexts.enabled) return;
  const SyntaxScope scope(encoder, SyntaxElement::kPartitions);
  auto& bits = transform_type_bits_of(contexts, size, mode);
  const bool vertical = vertical_dst(type);
  encoder.encode(bits[0], vertical);
  encoder.encode(bits[1 + (vertical ? 1 : 0)], horizontal_dst(type));
}

float transform_type_bits(const TransformTypeContexts& contexts, TransformSize size, int mode, TransformType type) {
  if (!contexts.enabled) return 0;
  const auto& bits = transform_type_bits_of(contexts, size, mode);
  const bool vertical = vertical_dst(type);
  return bit_cost(bits[0], vertical) + bit_cost(bits[1 + (vertical ? 1 : 0)], horizontal_dst(type));
}

namespace intra {

namespace {

// Writes a block's levels and, when it has levels, its transform type, and marks it.
void write_levels(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0,
                  TransformSize size, const BlockChoice& choice) {
  encode_block_levels(encoder, contexts.residual, choice.levels, state.coded_block_context(x0, y0), size);
  const bool has_levels =
      std::any_of(choice.levels, choice.levels + transform_area(size), [](int16_t l) { return l != 0; });
  if (has_levels) encode_transform_type(encoder, contexts.types, size, choice.mode, choice.transform_type);
  state.mark(x0, y0, size, choice.mode, choice.coded);
}

}  // namespace

void write_block(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0,
                 TransformSize size, const BlockChoice& choice) {
  encode_intra_mode(encoder, contexts.modes, size, state.candidates(x0, y0), choice.mode);
  write_levels(encoder, contexts, state, x0, y0, size, choice);
}

void write_chroma_block(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0,
                        ChromaPlane plane, const ChromaMode& cb, const BlockChoice& choice) {
  encode_chroma_mode(encoder, contexts.cfl, contexts.modes, state.cfl_context(x0, y0), state.candidates(x0, y0),
                     plane, cb, choice.chroma_mode());
  write_levels(encoder, contexts, state, x0, y0, kChromaSize, choice);
}

namespace {

// The split and halves flags of 8x8 block i of a split macroblock at (x0, y0).
void write_quarter_flags(RangeEncoder& encoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                         int i, LumaPartition partition) {
  const SyntaxScope scope(encoder, SyntaxElement::kPartitions);
  const auto context = static_cast<size_t>(state.split_context(x0 + 8 * (i & 1), y0 + 8 * (i >> 1), 8));
  encoder.encode(contexts.split_8x8[context], (partition & split_8x8_bit(i)) != 0);
  if (partition & split_8x8_bit(i)) return;
  encoder.encode(contexts.halves_8x8[context], (partition & halves_8x8_bit(i)) != 0);
  if (partition & halves_8x8_bit(i)) encoder.encode(contexts.vertical_8x8, (partition & vertical_8x8_bit(i)) != 0);
}

}  // namespace

void write_macroblock(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int mbx, int mby,
                      const MacroblockChoice& choice) {
  const int x0 = 16 * mbx, y0 = 16 * mby;
  const int split_context = state.split_context(x0, y0, 16);
  {
    const SyntaxScope scope(encoder, SyntaxElement::kPartitions);
    encoder.encode(contexts.split_16x16[static_cast<size_t>(split_context)], choice.partition & kSplit16x16);
    if ((choice.partition & kSplit16x16) == 0) {
      encoder.encode(contexts.halves_16x16[static_cast<size_t>(split_context)],
                     (choice.partition & kHalves16x16) != 0);
      if (choice.partition & kHalves16x16) {
        const bool vertical = (choice.partition & kVerticalHalves) != 0;
        encoder.encode(contexts.vertical_halves, vertical);
        encoder.encode(contexts.strips[vertical ? 1 : 0], (choice.partition & kStrips) != 0);
      }
    }
  }
  int n = 0;
  for_each_luma_block(choice.partition, [&](int x, int y, TransformSize size) {
    if ((choice.partition & kSplit16x16) && x % 8 == 0 && y % 8 == 0)
      write_quarter_flags(encoder, contexts, state, x0, y0, x / 8 + 2 * (y / 8), choice.partition);
    write_block(encoder, contexts, state, x0 + x, y0 + y, size, choice.blocks[static_cast<size_t>(n++)]);
  });
}

}  // namespace intra
}  // namespace svc::codec
