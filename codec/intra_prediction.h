// Spatial intra prediction of 4x4, 8x8, 16x16, 16x8 and 8x16 blocks from reconstructed
// neighbours:
// the reference edge of a block, the most probable modes derived from its left and above
// neighbours, and the coding of a block's mode. The predictors themselves are kernels
// (dsp::DspTable::intra_predict_*). Exact definitions in docs/codec.md 3.1-3.2.
//
// Threading: pure functions; IntraModeContexts is plain mutable data owned by one coder.
// Errors: decode_intra_mode never fails (every bit pattern is a valid mode).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "codec/dsp/dsp.h"
#include "codec/range_coder.h"

namespace svc::codec {

inline constexpr int kIntraModes = 35;
inline constexpr int kPlanarMode = 0;
inline constexpr int kDcMode = 1;
inline constexpr int kHorizontalMode = 10;
inline constexpr int kVerticalMode = 26;
inline constexpr int kMostProbableModes = 3;

// Which neighbours of a block are reconstructed: the N samples left and above, the N
// below-left and the N above-right (docs/codec.md 3.1 derives them from coding order).
struct EdgeAvailability {
  bool left = false, above = false, below_left = false, above_right = false;
};

// Fills edge[2 (W + H) + 1] (the corner at W + H) for the W x H block of `shape`
// (block_shape of transform_size.h: 4, 8, 16, or 16x8 and 8x16) at sample (x0, y0) of
// `plane` (stride samples per row), reading only the neighbours `available` names.
// Missing neighbours are substituted as docs/codec.md 3.1 defines.
void build_intra_edge(const uint8_t* plane, ptrdiff_t stride, int x0, int y0, int shape,
                      const EdgeAvailability& available, uint8_t* edge);

// The intra prediction kernel of a block shape (as build_intra_edge's).
using IntraPredictor = void (*)(const uint8_t* edge, int mode, uint8_t* out);
IntraPredictor intra_predictor(int shape);

// The three most probable modes for a block whose left and above neighbours use
// left_mode and above_mode (kDcMode where a neighbour is missing); all different.
std::array<int, kMostProbableModes> most_probable_modes(int left_mode, int above_mode);

struct IntraModeContexts {
  AdaptiveBit is_most_probable;
  std::array<AdaptiveBit, 2> most_probable_index;
};

// Calls f on every context, in member order (docs/codec.md 4).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, IntraModeContexts>
void for_each_context(Set& s, F&& f) {
  for_each_bit(s.is_most_probable, f);
  for_each_bit(s.most_probable_index, f);
}

// Mode coding: a flag, then the index among the most probable modes (truncated unary)
// or the 5-bit rank of the mode among the other 32 (bypass bits).
void encode_intra_mode(RangeEncoder& encoder, IntraModeContexts& contexts,
                       const std::array<int, kMostProbableModes>& candidates, int mode);
int decode_intra_mode(RangeDecoder& decoder, IntraModeContexts& contexts,
                      const std::array<int, kMostProbableModes>& candidates);
// Bits encode_intra_mode spends on `mode`, counting the flag and index as one bit each
// (encoder only: mode pre-selection).
int intra_mode_bits(const std::array<int, kMostProbableModes>& candidates, int mode);

}  // namespace svc::codec
