#include "codec/intra_prediction.h"

#include <algorithm>
#include <cstring>

namespace svc::codec {
namespace {

constexpr int kCorner = 16;
constexpr int kRemainderBits = 5;

}  // namespace

void build_intra_edge(const uint8_t* plane, ptrdiff_t stride, int bx, int by, int blocks_x, uint8_t* edge) {
  const bool has_left = bx > 0, has_above = by > 0;
  if (!has_left && !has_above) {
    std::memset(edge, 128, dsp::kIntraEdgeSamples);
    return;
  }
  const uint8_t* origin = plane + static_cast<ptrdiff_t>(by) * 8 * stride + bx * 8;
  if (has_left) {
    for (int i = 0; i < 8; ++i) edge[kCorner - 1 - i] = origin[i * stride - 1];
    std::memset(edge, edge[kCorner - 8], 8);  // below-left is never decoded yet
  }
  if (has_above) {
    std::memcpy(edge + kCorner + 1, origin - stride, 8);
    if (bx + 1 < blocks_x) {
      std::memcpy(edge + kCorner + 9, origin - stride + 8, 8);
    } else {
      std::memset(edge + kCorner + 9, edge[kCorner + 8], 8);
    }
  }
  if (has_left && has_above) {
    edge[kCorner] = origin[-stride - 1];
  } else if (has_left) {
    std::memset(edge + kCorner, edge[kCorner - 1], 17);
  } else {
    std::memset(edge, edge[kCorner + 1], 17);
  }
}

std::array<int, kMostProbableModes> most_probable_modes(int left_mode, int above_mode) {
  if (left_mode == above_mode) {
    if (left_mode < 2) return {kPlanarMode, kDcMode, kVerticalMode};
    // The mode and its two angular neighbours (wrapping within 2..33).
    return {left_mode, 2 + (left_mode + 29) % 32, 2 + (left_mode - 2 + 1) % 32};
  }
  int third = kVerticalMode;
  if (left_mode != kPlanarMode && above_mode != kPlanarMode) {
    third = kPlanarMode;
  } else if (left_mode != kDcMode && above_mode != kDcMode) {
    third = kDcMode;
  }
  return {left_mode, above_mode, third};
}

void encode_intra_mode(RangeEncoder& encoder, IntraModeContexts& contexts,
                       const std::array<int, kMostProbableModes>& candidates, int mode) {
  const auto found = std::find(candidates.begin(), candidates.end(), mode);
  encoder.encode(contexts.is_most_probable, found != candidates.end());
  if (found != candidates.end()) {
    const int index = static_cast<int>(found - candidates.begin());
    encoder.encode(contexts.most_probable_index[0], index > 0);
    if (index > 0) encoder.encode(contexts.most_probable_index[1], index > 1);
    return;
  }
  int rank = mode;
  for (int candidate : candidates) rank -= candidate < mode;
  for (int bit = kRemainderBits - 1; bit >= 0; --bit) encoder.encode_bypass((rank >> bit) & 1);
}

int decode_intra_mode(RangeDecoder& decoder, IntraModeContexts& contexts,
                      const std::array<int, kMostProbableModes>& candidates) {
  if (decoder.decode(contexts.is_most_probable)) {
    if (!decoder.decode(contexts.most_probable_index[0])) return candidates[0];
    return candidates[decoder.decode(contexts.most_probable_index[1]) ? 2 : 1];
  }
  int mode = 0;
  for (int bit = 0; bit < kRemainderBits; ++bit) mode = (mode << 1) | decoder.decode_bypass();
  std::array<int, kMostProbableModes> sorted = candidates;
  std::sort(sorted.begin(), sorted.end());
  for (int candidate : sorted) mode += candidate <= mode;
  return mode;
}

int intra_mode_bits(const std::array<int, kMostProbableModes>& candidates, int mode) {
  if (mode == candidates[0]) return 2;
  if (mode == candidates[1] || mode == candidates[2]) return 3;
  return 1 + kRemainderBits;
}

}  // namespace svc::codec
