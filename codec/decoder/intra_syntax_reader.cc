// SPDX-License-Identifier: BSD-2-Clause
#include "codec/decoder/intra_syntax_reader.h"

#include <algorithm>
#include <array>
#include <cstdlib>

#include "codec/decoder/coefficient_reader.h"

namespace svc::codec {

namespace {

// Cr's alpha may be 0 (a flag says whether it is); Cb's never is.
int decode_alpha(RangeDecoder& decoder, CflContexts& cfl, ChromaPlane plane, int cb_alpha) {
  if (plane == ChromaPlane::kCr && !decoder.decode(cfl.cr_nonzero)) return 0;
  const bool negative = decoder.decode(cfl.sign[cfl_sign_context(plane, cb_alpha)]);
  auto& magnitude = cfl.magnitude[cfl_plane_index(plane)];
  int m = 1;
  while (m < kCflMaxAlpha && decoder.decode(magnitude[static_cast<size_t>(m - 1)])) ++m;
  return negative ? -m : m;
}

}  // namespace

int decode_intra_mode(RangeDecoder& decoder, IntraModeContexts& contexts, TransformSize size,
                      const ModeCandidates& candidates) {
  const auto size_class = static_cast<size_t>(mode_size_class(size));
  const auto context = static_cast<size_t>(candidates.context);
  if (decoder.decode(contexts.is_most_probable[size_class][context])) {
    auto& index_bits = contexts.most_probable_index[size_class][context];
    if (!decoder.decode(index_bits[0])) return candidates[0];
    return candidates[decoder.decode(index_bits[1]) ? 2 : 1];
  }
  size_t node = 1;
  for (int bit = 0; bit < kRemainderBits; ++bit)
    node = 2 * node + static_cast<size_t>(decoder.decode(contexts.remainder[node - 1]));
  int mode = static_cast<int>(node) - (1 << kRemainderBits);
  std::array<int, kMostProbableModes> sorted = candidates.modes;
  std::sort(sorted.begin(), sorted.end());
  for (int candidate : sorted) mode += candidate <= mode;
  return mode;
}

ChromaMode decode_chroma_mode(RangeDecoder& decoder, CflContexts& cfl, IntraModeContexts& modes, int cfl_context,
                              const ModeCandidates& candidates, ChromaPlane plane, const ChromaMode& cb) {
  ChromaMode mode;
  if (plane == ChromaPlane::kCr) {
    mode.mode = cb.mode;
    if (cb.cfl()) mode.alpha = decode_alpha(decoder, cfl, plane, cb.alpha);
    return mode;
  }
  if (decoder.decode(cfl.flag[static_cast<size_t>(cfl_context)])) {
    mode.mode = kCflMode;
    mode.alpha = decode_alpha(decoder, cfl, plane, 0);
  } else {
    mode.mode = decode_intra_mode(decoder, modes, intra::kChromaSize, candidates);
  }
  return mode;
}

TransformType decode_transform_type(RangeDecoder& decoder, TransformTypeContexts& contexts, TransformSize size,
                                    int mode) {
  if (!contexts.enabled) return TransformType::kDctDct;
  auto& bits = transform_type_bits_of(contexts, size, mode);
  const bool vertical = decoder.decode(bits[0]) != 0;
  const bool horizontal = decoder.decode(bits[1 + (vertical ? 1 : 0)]) != 0;
  return transform_type_of(vertical, horizontal);
}

namespace intra {

namespace {

// A block's levels, then its transform type when it has levels (out->mode set).
bool read_levels_and_type(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                          TransformSize size, BlockSyntax* out) {
  out->count = 0;
  out->transform_type = TransformType::kDctDct;
  if (!decode_block_levels(decoder, contexts.residual, state.coded_block_context(x0, y0), out->levels, &out->count,
                           size)) {
    return false;
  }
  if (out->count > 0) out->transform_type = decode_transform_type(decoder, contexts.types, size, out->mode);
  return true;
}

}  // namespace

bool read_block_syntax(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                       TransformSize size, BlockSyntax* out) {
  out->mode = decode_intra_mode(decoder, contexts.modes, size, state.candidates(x0, y0));
  out->cfl_alpha = 0;
  return read_levels_and_type(decoder, contexts, state, x0, y0, size, out);
}

bool read_chroma_block_syntax(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0,
                              int y0, ChromaPlane plane, ChromaMode* cb, BlockSyntax* out) {
  const ChromaMode mode = decode_chroma_mode(decoder, contexts.cfl, contexts.modes, state.cfl_context(x0, y0),
                                             state.candidates(x0, y0), plane, *cb);
  if (plane == ChromaPlane::kCb) *cb = mode;
  out->mode = mode.mode;
  out->cfl_alpha = mode.alpha;
  return read_levels_and_type(decoder, contexts, state, x0, y0, kChromaSize, out);
}

bool read_luma_macroblock(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int mbx, int mby,
                          BlockReader& reader, LumaPartition* partition) {
  const int x0 = 16 * mbx, y0 = 16 * mby;
  *partition = 0;
  const int split_context = state.split_context(x0, y0, 16);
  if (!decoder.decode(contexts.split_16x16[static_cast<size_t>(split_context)])) {
    if (!decoder.decode(contexts.halves_16x16[static_cast<size_t>(split_context)]))
      return reader.read(x0, y0, TransformSize::k16x16);
    const bool vertical = decoder.decode(contexts.vertical_halves) != 0;
    const bool strips = decoder.decode(contexts.strips[vertical ? 1 : 0]) != 0;
    *partition =
        static_cast<LumaPartition>(kHalves16x16 | (vertical ? kVerticalHalves : 0) | (strips ? kStrips : 0));
    bool read = true;
    for_each_luma_block(*partition, [&](int x, int y, TransformSize size) {
      read = read && reader.read(x0 + x, y0 + y, size);
    });
    return read;
  }
  *partition = kSplit16x16;
  for (int i = 0; i < 4; ++i) {
    const int x = x0 + 8 * (i & 1), y = y0 + 8 * (i >> 1);
    const auto context = static_cast<size_t>(state.split_context(x, y, 8));
    if (decoder.decode(contexts.split_8x8[context])) {
      *partition |= split_8x8_bit(i);
    } else if (decoder.decode(contexts.halves_8x8[context])) {
      *partition |= halves_8x8_bit(i);
      if (decoder.decode(contexts.vertical_8x8)) *partition |= vertical_8x8_bit(i);
    }
    bool read = true;
    for_each_quarter_block(*partition, i, [&](int bx, int by, TransformSize size) {
      read = read && reader.read(x0 + bx, y0 + by, size);
    });
    if (!read) return false;
  }
  return true;
}

}  // namespace intra
}  // namespace svc::codec
