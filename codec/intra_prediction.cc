#include "codec/intra_prediction.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "codec/transform_size.h"

namespace svc::codec {
namespace {

constexpr int kRemainderBits = 5;

}  // namespace

void build_intra_edge(const uint8_t* plane, ptrdiff_t stride, int x0, int y0, int shape,
                      const EdgeAvailability& available, uint8_t* edge) {
  const int w = shape_width(shape), h = shape_height(shape);
  const int corner = w + h, samples = 2 * (w + h) + 1;
  if (!available.left && !available.above) {
    std::memset(edge, 128, static_cast<size_t>(samples));
    return;
  }
  const uint8_t* origin = plane + static_cast<ptrdiff_t>(y0) * stride + x0;
  if (available.left) {
    const int rows = available.below_left ? w + h : h;
    for (int i = 0; i < rows; ++i) edge[corner - 1 - i] = origin[i * stride - 1];
    if (!available.below_left) std::memset(edge, edge[corner - h], static_cast<size_t>(w));
  }
  if (available.above) {
    const int columns = available.above_right ? w + h : w;
    std::memcpy(edge + corner + 1, origin - stride, static_cast<size_t>(columns));
    if (!available.above_right) std::memset(edge + corner + 1 + w, edge[corner + w], static_cast<size_t>(h));
  }
  if (available.left && available.above) {
    edge[corner] = origin[-stride - 1];
  } else if (available.left) {
    std::memset(edge + corner, edge[corner - 1], static_cast<size_t>(w + h + 1));
  } else {
    std::memset(edge, edge[corner + 1], static_cast<size_t>(w + h + 1));
  }
}

namespace {

// Rectangular W x H blocks (16x8, 8x16): the modes of docs/codec.md 3.1 on an edge of
// W + H samples each side, the corner at W + H. Planar weighs both directions by the
// other side's length (as VVC), DC averages the longer side, angular modes project as
// for squares; the edge is smoothed as for 8x8 blocks.
constexpr int kAngles[33] = {32,  26,  21,  17,  13, 9,  5,  2, 0, -2, -5, -9, -13, -17, -21, -26, -32,
                             -26, -21, -17, -13, -9, -5, -2, 0, 2, 5,  9,  13, 17,  21,  26,  32};
// round(256 * 32 / -angle) for the negative angles (HEVC's table).
int inverse_angle_of(int angle) {
  switch (angle) {
    case -2: return -4096;
    case -5: return -1638;
    case -9: return -910;
    case -13: return -630;
    case -17: return -482;
    case -21: return -390;
    case -26: return -315;
    default: return -256;  // -32
  }
}

template <int W, int H>
void predict_rectangular(const uint8_t* raw_edge, int mode, uint8_t* out) {
  constexpr int kCorner = W + H, kSamples = 2 * (W + H) + 1;
  const int distance = std::min(std::abs(mode - 26), std::abs(mode - 10));
  uint8_t smoothed[kSamples];
  const uint8_t* edge = raw_edge;
  if (mode == kPlanarMode || (mode >= 2 && distance > 7)) {
    smoothed[0] = raw_edge[0];
    smoothed[kSamples - 1] = raw_edge[kSamples - 1];
    for (int i = 1; i < kSamples - 1; ++i)
      smoothed[i] = static_cast<uint8_t>((raw_edge[i - 1] + 2 * raw_edge[i] + raw_edge[i + 1] + 2) >> 2);
    edge = smoothed;
  }
  const uint8_t* above = edge + kCorner + 1;
  auto left = [&](int y) { return edge[kCorner - 1 - y]; };
  constexpr int kLogW = W == 16 ? 4 : 3, kLogH = H == 16 ? 4 : 3;
  if (mode == kPlanarMode) {
    for (int y = 0; y < H; ++y) {
      for (int x = 0; x < W; ++x) {
        const int vertical = ((H - 1 - y) * above[x] + (y + 1) * left(H)) << kLogW;
        const int horizontal = ((W - 1 - x) * left(y) + (x + 1) * above[W]) << kLogH;
        out[W * y + x] = static_cast<uint8_t>((vertical + horizontal + W * H) >> (kLogW + kLogH + 1));
      }
    }
    return;
  }
  if (mode == kDcMode) {
    int sum = 0;
    if (W >= H)
      for (int x = 0; x < W; ++x) sum += above[x];
    if (H >= W)
      for (int y = 0; y < H; ++y) sum += left(y);
    const int count = W == H ? 2 * W : std::max(W, H);
    const auto dc = static_cast<uint8_t>((sum + count / 2) / count);
    std::fill_n(out, W * H, dc);
    out[0] = static_cast<uint8_t>((left(0) + 2 * dc + above[0] + 2) >> 2);
    for (int x = 1; x < W; ++x) out[x] = static_cast<uint8_t>((above[x] + 3 * dc + 2) >> 2);
    for (int y = 1; y < H; ++y) out[W * y] = static_cast<uint8_t>((left(y) + 3 * dc + 2) >> 2);
    return;
  }
  const bool vertical = mode >= 18;
  const int angle = kAngles[mode - 2];
  // Predict a bw x bh block along its columns from `main` (above for vertical modes, else
  // the left column, transposed on the way out).
  const int bw = vertical ? W : H, bh = vertical ? H : W;
  uint8_t buffer[3 * (W + H) + 2] = {};
  uint8_t* ref = buffer + (W + H);  // ref[-(W+H) .. W+H+1]
  uint8_t side[W + H + 1];
  for (int k = 0; k <= W + H; ++k) {
    const int a = edge[kCorner + k], l = edge[kCorner - k];
    ref[k] = static_cast<uint8_t>(vertical ? a : l);
    side[k] = static_cast<uint8_t>(vertical ? l : a);
  }
  if (angle < 0) {
    const int inverse = inverse_angle_of(angle);
    for (int k = (bh * angle) >> 5; k < 0; ++k) ref[k] = side[std::min((k * inverse + 128) >> 8, W + H)];
  }
  for (int y = 0; y < bh; ++y) {
    const int position = (y + 1) * angle, whole = position >> 5, fraction = position & 31;
    for (int x = 0; x < bw; ++x) {
      const int value = ((32 - fraction) * ref[x + whole + 1] + fraction * ref[x + whole + 2] + 16) >> 5;
      out[vertical ? W * y + x : W * x + y] = static_cast<uint8_t>(value);
    }
  }
  const int corner = raw_edge[kCorner];
  if (mode == kVerticalMode) {
    for (int y = 0; y < H; ++y)
      out[W * y] = static_cast<uint8_t>(
          std::clamp(raw_edge[kCorner + 1] + ((raw_edge[kCorner - 1 - y] - corner) >> 1), 0, 255));
  } else if (mode == kHorizontalMode) {
    for (int x = 0; x < W; ++x)
      out[x] = static_cast<uint8_t>(
          std::clamp(raw_edge[kCorner - 1] + ((raw_edge[kCorner + 1 + x] - corner) >> 1), 0, 255));
  }
}

void predict_16x8(const uint8_t* edge, int mode, uint8_t* out) { predict_rectangular<16, 8>(edge, mode, out); }
void predict_8x16(const uint8_t* edge, int mode, uint8_t* out) { predict_rectangular<8, 16>(edge, mode, out); }

}  // namespace

IntraPredictor intra_predictor(int size) {
  if (size == block_shape(16, 8)) return predict_16x8;
  if (size == block_shape(8, 16)) return predict_8x16;
  const dsp::DspTable& dsp = dsp::get_dsp();
  return size == 4 ? dsp.intra_predict_4x4 : size == 16 ? dsp.intra_predict_16x16 : dsp.intra_predict_8x8;
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
