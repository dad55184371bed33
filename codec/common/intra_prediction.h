// SPDX-License-Identifier: BSD-2-Clause
// Spatial intra prediction of 4x4, 8x8, 16x16, 16x8 and 8x16 blocks from reconstructed
// neighbours:
// the reference edge of a block, the most probable modes derived from its left and above
// neighbours, and the coding of a block's mode. The predictors themselves are kernels
// (dsp::DspTable::intra_predict_*). Exact definitions in docs/codec.md 5.2-3.2.
//
// Threading: pure functions; IntraModeContexts is plain mutable data owned by one coder.
#pragma once

#include <algorithm>
#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "codec/common/adaptive_bit.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/transform_size.h"

namespace svc::codec {

inline constexpr int kIntraModes = 35;
inline constexpr int kPlanarMode = 0;
inline constexpr int kDcMode = 1;
inline constexpr int kHorizontalMode = 10;
inline constexpr int kVerticalMode = 26;
inline constexpr int kMostProbableModes = 3;

// Which neighbours of a block are reconstructed: the N samples left and above, the N
// below-left and the N above-right (docs/codec.md 5.2 derives them from coding order).
struct EdgeAvailability {
  bool left = false, above = false, below_left = false, above_right = false;
};

// Fills edge[2 (W + H) + 1] (the corner at W + H) for the W x H block of `size` at
// sample (x0, y0) of `plane` (stride samples per row), reading only the neighbours
// `available` names. Missing neighbours are substituted as docs/codec.md 5.2 defines.
void build_intra_edge(const uint8_t* plane, ptrdiff_t stride, int x0, int y0, TransformSize size,
                      const EdgeAvailability& available, uint8_t* edge);

// The intra prediction kernel of a block size.
using IntraPredictor = void (*)(const uint8_t* edge, int mode, uint8_t* out);
IntraPredictor intra_predictor(TransformSize size);

// The mode flags' contexts by block size (fewer than 64 samples, 64, more) and by the
// neighbours' modes (docs/codec.md 3.2).
inline constexpr int kModeSizeClasses = 3;
inline constexpr int kModeNeighbourContexts = 6;
int mode_size_class(TransformSize size);

// The three most probable modes of a block, all different, and the neighbour context of
// its mode flags.
struct ModeCandidates {
  std::array<int, kMostProbableModes> modes;
  // min(left, 2) (planar, DC, angular) where both neighbours use the same mode, else
  // 3 + min(left, 2).
  int context;
  int operator[](size_t i) const { return modes[i]; }
  auto begin() const { return modes.begin(); }
  auto end() const { return modes.end(); }
};

// The candidates of a block whose left and above neighbours use left_mode and above_mode
// (kDcMode where a neighbour is missing).
ModeCandidates most_probable_modes(int left_mode, int above_mode);

struct IntraModeContexts {
  template <class T>
  using BySizeAndNeighbours = std::array<std::array<T, kModeNeighbourContexts>, kModeSizeClasses>;
  BySizeAndNeighbours<AdaptiveBit> is_most_probable{};
  BySizeAndNeighbours<std::array<AdaptiveBit, 2>> most_probable_index{};
  // A binary tree over the 32 ranks of the other modes, most significant bit first
  // (node n's children 2n and 2n + 1; node 1 is element 0).
  std::array<AdaptiveBit, 31> remainder{};
};

// Calls f on every context, in member order (docs/codec.md 6.1).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, IntraModeContexts>
void for_each_context(Set& s, F&& f) {
  for_each_bit(s.is_most_probable, f);
  for_each_bit(s.most_probable_index, f);
  for_each_bit(s.remainder, f);
}

// Mode coding of a block (contexts by its mode_size_class): a flag, then the index among the most
// probable modes (truncated unary) or the rank of the mode among the other 32 in
// increasing order, in kRemainderBits bits through the remainder tree (node n's
// children 2n and 2n + 1, node 1 at remainder[0]). Read by
// codec/decoder/intra_syntax_reader.h, written by codec/encoder/intra_syntax_writer.h.
inline constexpr int kRemainderBits = 5;

}  // namespace svc::codec
