// B-frame coding. Encoder and decoder share the frame state (reconstructed padded planes,
// per-block DC levels and coded flags, per-macroblock vectors and modes), the predictors
// derived from it and the reconstruction routines, so the encoder's reconstruction is the
// decoder's output by construction. The encoder evaluates every macroblock option (skip,
// forward, backward, bidirectional, intra) by cost = SSD + lambda * estimated bits, with
// bits estimated from the current adaptive probabilities.
#include "codec/bframe_codec.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>

#include "codec/block_coder.h"
#include "codec/motion_compensation.h"
#include "codec/quant.h"
#include "codec/range_coder.h"
#include "codec/warp_prediction.h"

namespace svc::codec {
namespace {

constexpr int kMvdPrefixBins = 8;   // unary bins of |mvd| before the Exp-Golomb escape
constexpr int kNeighbourContexts = 3;
constexpr int kNodePrefixBins = 8;  // unary bins of |node difference| before the escape
constexpr int kNodeMagnitudeContexts = 6;

struct SyntaxContexts {
  std::array<AdaptiveBit, kNeighbourContexts> skip{};
  std::array<AdaptiveBit, kNeighbourContexts> intra{};
  std::array<AdaptiveBit, kNeighbourContexts> bidirectional{};
  std::array<AdaptiveBit, kNeighbourContexts> backward{};
  std::array<std::array<AdaptiveBit, kNeighbourContexts>, 2> mvd_zero{};  // [component][ctx]
  std::array<std::array<AdaptiveBit, 4>, 2> mvd_magnitude{};              // [component][bin]
  std::array<AdaptiveBit, kNeighbourContexts> warp{};
  // Node differences: [component][predictor kind: 0 planar, 1 other].
  std::array<std::array<AdaptiveBit, 2>, 2> node_zero{};
  std::array<std::array<std::array<AdaptiveBit, kNodeMagnitudeContexts>, 2>, 2> node_magnitude{};
  std::array<AdaptiveBit, kNeighbourContexts> cbp_luma{};
  std::array<std::array<AdaptiveBit, kNeighbourContexts>, 2> cbp_chroma{};  // [Cb/Cr][ctx]
  BlockContextSet intra_luma, intra_chroma, inter_luma, inter_chroma;
};

struct MacroblockInfo {
  MacroblockMode mode = MacroblockMode::kIntra;
  // The prediction mode of an inter or skipped macroblock; for an intra one, the mode a
  // skip would have inherited there. Skips inherit it from the left (else top) neighbour.
  MacroblockMode inter_mode = MacroblockMode::kForward;
  // Whether that prediction is warped (inherited along with inter_mode).
  bool inter_warp = false;
  // Per reference: the vector used, or the predictor where the reference is unused, so
  // predictors propagate through intra and single-reference macroblocks.
  std::array<MotionVector, 2> vectors{};
  // Sum over references of |mvd.x| and |mvd.y| (0 when no vector was coded).
  std::array<int, 2> mvd_magnitude{};
};

struct FrameState {
  int width = 0, height = 0;
  int mbs_x = 0, mbs_y = 0;
  int chroma_width = 0, chroma_height = 0;  // visible
  int reference_count = 1;
  std::array<const ImageYCbCr420*, 2> references{};
  Quantizer intra_quantizer, inter_quantizer;
  int dc_step = 8;
  int vector_limit = 0;
  int node_limit = 0;
  // References with a warp node field (bit r for reference r).
  int warp_mask = 0;
  // Node grids (mbs_x + 1) x (mbs_y + 1) per reference: values and whether the decoder
  // knows them yet. The encoder stores its whole field up front and marks nodes known as
  // it codes them; the decoder fills values as it decodes them.
  int nodes_x = 0, nodes_y = 0;
  std::array<std::vector<WarpNode>, 2> nodes;
  std::array<std::vector<uint8_t>, 2> node_known;
  // Reconstructed planes padded to whole macroblocks; strides 16 mbs_x and 8 mbs_x.
  std::array<std::vector<uint8_t>, 3> planes;
  std::array<int, 3> strides{};
  // Per 8x8 block of each plane (grids 2 mbs_x x 2 mbs_y and mbs_x x mbs_y): the DC level
  // intra prediction uses, and whether the block had coded levels (intra: AC levels).
  std::array<std::vector<int>, 3> dc;
  std::array<std::vector<uint8_t>, 3> coded;
  std::vector<MacroblockInfo> macroblocks;
  SyntaxContexts contexts;

  int grid_width(int plane) const { return plane == 0 ? 2 * mbs_x : mbs_x; }
  const MacroblockInfo& mb(int x, int y) const { return macroblocks[static_cast<size_t>(y) * mbs_x + x]; }
  size_t node_index(int i, int j) const { return static_cast<size_t>(j) * nodes_x + i; }
  bool known(int r, int i, int j) const {
    return i >= 0 && j >= 0 && i < nodes_x && j < nodes_y && node_known[r][node_index(i, j)] != 0;
  }
};

void init_state(FrameState& s, int width, int height, int quant_scale, const ImageYCbCr420* ref0,
                const ImageYCbCr420* ref1) {
  s.width = width;
  s.height = height;
  s.mbs_x = (width + 15) / 16;
  s.mbs_y = (height + 15) / 16;
  s.chroma_width = (width + 1) / 2;
  s.chroma_height = (height + 1) / 2;
  s.references = {ref0, ref1};
  s.reference_count = ref1 != nullptr ? 2 : 1;
  s.intra_quantizer = make_quantizer(BlockKind::kIntra, quant_scale);
  s.inter_quantizer = make_quantizer(BlockKind::kNonIntra, quant_scale);
  s.dc_step = intra_dc_step(quant_scale);
  s.vector_limit = max_vector_component(width, height);
  s.node_limit = max_warp_node_component(width, height);
  s.nodes_x = s.mbs_x + 1;
  s.nodes_y = s.mbs_y + 1;
  for (int r = 0; r < 2; ++r) {
    s.nodes[r].assign(static_cast<size_t>(s.nodes_x) * s.nodes_y, WarpNode{});
    s.node_known[r].assign(s.nodes[r].size(), 0);
  }
  s.strides = {16 * s.mbs_x, 8 * s.mbs_x, 8 * s.mbs_x};
  const size_t luma_size = static_cast<size_t>(16 * s.mbs_x) * (16 * s.mbs_y);
  s.planes[0].assign(luma_size, 0);
  s.planes[1].assign(luma_size / 4, 0);
  s.planes[2].assign(luma_size / 4, 0);
  const size_t mb_count = static_cast<size_t>(s.mbs_x) * s.mbs_y;
  s.dc[0].assign(4 * mb_count, 0);
  s.coded[0].assign(4 * mb_count, 0);
  for (int p = 1; p < 3; ++p) {
    s.dc[p].assign(mb_count, 0);
    s.coded[p].assign(mb_count, 0);
  }
  s.macroblocks.assign(mb_count, MacroblockInfo{});
}

// ---- Block geometry within a macroblock: blocks 0..3 luma (raster), 4 Cb, 5 Cr. ----

inline int block_plane(int b) { return b < 4 ? 0 : b - 3; }
inline int block_x(int b, int mx) { return b < 4 ? 2 * mx + (b & 1) : mx; }
inline int block_y(int b, int my) { return b < 4 ? 2 * my + (b >> 1) : my; }
// Offset of block b in a MacroblockPrediction-shaped buffer and its row stride.
inline uint8_t* block_samples(MacroblockPrediction& m, int b) {
  if (b < 4) return m.y.data() + (b >> 1) * 8 * 16 + (b & 1) * 8;
  return b == 4 ? m.cb.data() : m.cr.data();
}
inline const uint8_t* block_samples(const MacroblockPrediction& m, int b) {
  return block_samples(const_cast<MacroblockPrediction&>(m), b);
}
inline int block_stride(int b) { return b < 4 ? 16 : 8; }

// Value of a per-block array at block (bx, by) of `plane`; blocks of macroblock (mx, my)
// are read from `local` (indexed by block number), the rest from the frame state.
template <typename T>
T block_value(const FrameState& s, const std::vector<T>& values, const T* local, int plane, int mx,
              int my, int bx, int by) {
  if (plane == 0) {
    if ((bx >> 1) == mx && (by >> 1) == my) return local[(by & 1) * 2 + (bx & 1)];
  } else if (bx == mx && by == my) {
    return local[3 + plane];
  }
  return values[static_cast<size_t>(by) * s.grid_width(plane) + bx];
}

// Intra DC prediction as in intra frames (docs/codec.md section 3) over all blocks; inter
// blocks contribute the DC level their reconstruction would have had.
int predict_dc(const FrameState& s, const int* local, int plane, int mx, int my, int bx, int by) {
  if (bx == 0 && by == 0) return 0;
  auto value = [&](int x, int y) { return block_value(s, s.dc[plane], local, plane, mx, my, x, y); };
  if (by == 0) return value(bx - 1, by);
  if (bx == 0) return value(bx, by - 1);
  const int left = value(bx - 1, by), top = value(bx, by - 1), top_left = value(bx - 1, by - 1);
  if (top_left >= std::max(left, top)) return std::min(left, top);
  if (top_left <= std::min(left, top)) return std::max(left, top);
  return left + top - top_left;
}

int coded_context(const FrameState& s, const uint8_t* local, int plane, int mx, int my, int bx, int by) {
  return (bx > 0 ? block_value(s, s.coded[plane], local, plane, mx, my, bx - 1, by) : 0) +
         (by > 0 ? block_value(s, s.coded[plane], local, plane, mx, my, bx, by - 1) : 0);
}

// DC level an intra block with these reconstructed samples would have: the block mean
// minus 128, times 8 (the DCT's DC gain), divided by dc_step, rounded half away from 0.
int derived_dc_level(const uint8_t* samples, int stride, int dc_step) {
  int sum = 0;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) sum += samples[y * stride + x];
  }
  const int numerator = sum - 64 * 128, denominator = 8 * dc_step;
  return numerator >= 0 ? (numerator + denominator / 2) / denominator
                        : -((-numerator + denominator / 2) / denominator);
}

inline int median3(int a, int b, int c) { return std::max(std::min(a, b), std::min(std::max(a, b), c)); }

MotionVector predict_vector(const FrameState& s, int mx, int my, int reference) {
  if (my == 0) return mx == 0 ? MotionVector{} : s.mb(mx - 1, 0).vectors[reference];
  const MotionVector top = s.mb(mx, my - 1).vectors[reference];
  const MotionVector left = mx > 0 ? s.mb(mx - 1, my).vectors[reference] : top;
  const MotionVector diagonal = mx + 1 < s.mbs_x ? s.mb(mx + 1, my - 1).vectors[reference]
                                : mx > 0        ? s.mb(mx - 1, my - 1).vectors[reference]
                                                : top;
  return MotionVector{static_cast<int16_t>(median3(left.x, top.x, diagonal.x)),
                      static_cast<int16_t>(median3(left.y, top.y, diagonal.y))};
}

MacroblockMode predicted_mode(const FrameState& s, int mx, int my) {
  if (mx > 0) return s.mb(mx - 1, my).inter_mode;
  if (my > 0) return s.mb(mx, my - 1).inter_mode;
  return s.reference_count == 2 ? MacroblockMode::kBidirectional : MacroblockMode::kForward;
}

// The warp flag a skip inherits, from the same neighbour as predicted_mode.
bool predicted_warp(const FrameState& s, int mx, int my) {
  if (mx > 0) return s.mb(mx - 1, my).inter_warp;
  if (my > 0) return s.mb(mx, my - 1).inter_warp;
  return false;
}

// Corner nodes within this many node units (1/8 pel) of each other count as one
// translation when the encoder screens warped prediction.
constexpr int kUniformWarpSpread = 2;

inline bool uses_reference(MacroblockMode mode, int reference) {
  if (mode == MacroblockMode::kBidirectional) return true;
  return reference == 0 ? mode == MacroblockMode::kForward : mode == MacroblockMode::kBackward;
}

// Number of the left and top neighbours satisfying `predicate`: context 0..2.
template <typename Predicate>
int neighbour_context(const FrameState& s, int mx, int my, Predicate predicate) {
  return (mx > 0 && predicate(s.mb(mx - 1, my))) + (my > 0 && predicate(s.mb(mx, my - 1)));
}

int skip_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.mode == MacroblockMode::kSkipped; });
}
int intra_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.mode == MacroblockMode::kIntra; });
}
int bidirectional_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.inter_mode == MacroblockMode::kBidirectional; });
}
int backward_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) { return m.inter_mode == MacroblockMode::kBackward; });
}
int warp_context(const FrameState& s, int mx, int my) {
  return neighbour_context(s, mx, my, [](const MacroblockInfo& m) {
    return m.mode != MacroblockMode::kIntra && m.inter_warp;
  });
}
// Bit mask of the references a prediction mode reads.
inline int reference_mask(MacroblockMode mode) {
  return mode == MacroblockMode::kBidirectional ? 3 : (mode == MacroblockMode::kBackward ? 2 : 1);
}
inline bool warp_allowed(const FrameState& s, MacroblockMode mode) {
  return s.warp_mask != 0 && (reference_mask(mode) & ~s.warp_mask) == 0;
}

// Node (i, j) of macroblock corner k (0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right).
inline int corner_i(int mx, int k) { return mx + (k & 1); }
inline int corner_j(int my, int k) { return my + (k >> 1); }

WarpCorners macroblock_corners(const FrameState& s, int reference, int mx, int my) {
  WarpCorners corners;
  for (int k = 0; k < 4; ++k) corners[k] = s.nodes[reference][s.node_index(corner_i(mx, k), corner_j(my, k))];
  return corners;
}

// The prediction of a not yet known node from known ones (docs/codec.md, section 10.3):
// planar from the left (or right) and top neighbours, else one neighbour, else the
// macroblock's vector predictor. `kind` receives 0 for planar, 1 otherwise.
WarpNode predict_node(const FrameState& s, int r, int i, int j, MotionVector vector_predictor, int* kind) {
  auto node = [&](int x, int y) { return s.nodes[r][s.node_index(x, y)]; };
  auto planar = [](WarpNode a, WarpNode b, WarpNode c) { return WarpNode{a.x + b.x - c.x, a.y + b.y - c.y}; };
  *kind = 0;
  if (s.known(r, i - 1, j) && s.known(r, i, j - 1) && s.known(r, i - 1, j - 1)) {
    return planar(node(i - 1, j), node(i, j - 1), node(i - 1, j - 1));
  }
  if (s.known(r, i + 1, j) && s.known(r, i, j - 1) && s.known(r, i + 1, j - 1)) {
    return planar(node(i + 1, j), node(i, j - 1), node(i + 1, j - 1));
  }
  *kind = 1;
  if (s.known(r, i - 1, j)) return node(i - 1, j);
  if (s.known(r, i, j - 1)) return node(i, j - 1);
  if (s.known(r, i + 1, j)) return node(i + 1, j);
  return WarpNode{4 * vector_predictor.x, 4 * vector_predictor.y};
}

// The vector a warped macroblock leaves for its neighbours' predictors: the mean of its
// corner nodes in half-pels, (sum + 8) >> 4, clamped to the vector range.
MotionVector warp_centre_vector(const FrameState& s, const WarpCorners& c) {
  auto component = [&](int sum) {
    return static_cast<int16_t>(std::clamp((sum + 8) >> 4, -s.vector_limit, s.vector_limit));
  };
  return MotionVector{component(c[0].x + c[1].x + c[2].x + c[3].x), component(c[0].y + c[1].y + c[2].y + c[3].y)};
}

int mvd_context(const FrameState& s, int mx, int my, int component) {
  const int sum = (mx > 0 ? s.mb(mx - 1, my).mvd_magnitude[component] : 0) +
                  (my > 0 ? s.mb(mx, my - 1).mvd_magnitude[component] : 0);
  return sum == 0 ? 0 : (sum < 8 ? 1 : 2);
}

void build_prediction(const FrameState& s, int mx, int my, MacroblockMode mode,
                      const std::array<MotionVector, 2>& vectors, MacroblockPrediction* out) {
  if (mode == MacroblockMode::kBackward) {
    predict_macroblock(*s.references[1], mx, my, vectors[1], out);
  } else {
    predict_macroblock(*s.references[0], mx, my, vectors[0], out);
    if (mode == MacroblockMode::kBidirectional) {
      MacroblockPrediction second;
      predict_macroblock(*s.references[1], mx, my, vectors[1], &second);
      average_predictions(*out, second, out);
    }
  }
}

void build_warp_prediction(const FrameState& s, int mx, int my, MacroblockMode mode, MacroblockPrediction* out) {
  const int first = mode == MacroblockMode::kBackward ? 1 : 0;
  predict_warp_macroblock(*s.references[first], mx, my, macroblock_corners(s, first, mx, my), out);
  if (mode == MacroblockMode::kBidirectional) {
    MacroblockPrediction second;
    predict_warp_macroblock(*s.references[1], mx, my, macroblock_corners(s, 1, mx, my), &second);
    average_predictions(*out, second, out);
  }
}

void reconstruct_residual_block(const Quantizer& quantizer, const int16_t* levels,
                                const uint8_t* prediction, int prediction_stride, uint8_t* out,
                                int out_stride) {
  int16_t residual[64];
  dequantize_inverse_transform_block(quantizer, levels, residual);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      out[y * out_stride + x] =
          static_cast<uint8_t>(std::clamp(prediction[y * prediction_stride + x] + residual[8 * y + x], 0, 255));
    }
  }
}

void reconstruct_intra_block(const Quantizer& quantizer, const int16_t* levels, uint8_t* out, int out_stride) {
  int16_t samples[64];
  dequantize_inverse_transform_block(quantizer, levels, samples);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) out[y * out_stride + x] = static_cast<uint8_t>(std::clamp(samples[8 * y + x] + 128, 0, 255));
  }
}

// Stores a finished macroblock: pixels, per-block DC levels and coded flags, and info.
void commit_macroblock(FrameState& s, int mx, int my, const MacroblockInfo& info,
                       const MacroblockPrediction& reconstruction, const int* intra_dc, uint8_t coded_mask) {
  for (int y = 0; y < 16; ++y) {
    std::copy_n(reconstruction.y.data() + 16 * y, 16,
                s.planes[0].data() + static_cast<size_t>(16 * my + y) * s.strides[0] + 16 * mx);
  }
  for (int y = 0; y < 8; ++y) {
    const size_t offset = static_cast<size_t>(8 * my + y) * s.strides[1] + 8 * mx;
    std::copy_n(reconstruction.cb.data() + 8 * y, 8, s.planes[1].data() + offset);
    std::copy_n(reconstruction.cr.data() + 8 * y, 8, s.planes[2].data() + offset);
  }
  for (int b = 0; b < 6; ++b) {
    const int plane = block_plane(b);
    const size_t index = static_cast<size_t>(block_y(b, my)) * s.grid_width(plane) + block_x(b, mx);
    s.coded[plane][index] = static_cast<uint8_t>((coded_mask >> b) & 1);
    s.dc[plane][index] = intra_dc != nullptr
                             ? intra_dc[b]
                             : derived_dc_level(block_samples(reconstruction, b), block_stride(b), s.dc_step);
  }
  s.macroblocks[static_cast<size_t>(my) * s.mbs_x + mx] = info;
}

// ---------------------------------------------------------------------------------------
// Encoder: bit-cost estimates from the adaptive probabilities.

const std::array<float, 4097>& cost_table() {
  static const std::array<float, 4097> table = [] {
    std::array<float, 4097> t{};
    for (int i = 0; i <= 4096; ++i) {
      const double p = std::clamp((i * 8.0 + 4.0) / 32768.0, 1.0 / 32768.0, 1.0);
      t[static_cast<size_t>(i)] = static_cast<float>(-std::log2(p));
    }
    return t;
  }();
  return table;
}

inline float bit_cost(const AdaptiveBit& model, int bit) {
  uint32_t p = model.probability_of_zero();
  if (bit) p = kProbabilityOne - p;
  return cost_table()[std::min<uint32_t>(p >> 3, 4096)];
}

inline float exp_golomb_bits(uint32_t value) {
  return static_cast<float>(2 * (std::bit_width(value + 1) - 1) + 1);
}

float block_levels_bits(const BlockContextSet& c, const int16_t* levels, int first_scan, int coded_block_context) {
  int last_scan = -1;
  for (int i = 63; i >= first_scan; --i) {
    if (levels[kZigZag[i]] != 0) {
      last_scan = i;
      break;
    }
  }
  float bits = 0;
  if (coded_block_context >= 0) {
    bits += bit_cost(c.coded_block[coded_block_context], last_scan >= 0);
  }
  if (last_scan < 0) return bits;
  for (int i = first_scan; i < 63; ++i) {
    const int significant = levels[kZigZag[i]] != 0;
    bits += bit_cost(c.significant[i], significant);
    if (significant) {
      bits += bit_cost(c.last[i], i == last_scan);
      if (i == last_scan) break;
    }
  }
  int greater_one = 0, equal_one = 0;
  for (int i = last_scan; i >= first_scan; --i) {
    const int level = levels[kZigZag[i]];
    if (level == 0) continue;
    const int minus_one = std::abs(level) - 1;
    const int context = greater_one != 0 ? 0 : std::min(4, 1 + equal_one);
    bits += bit_cost(c.greater_than_one[context], minus_one > 0);
    if (minus_one > 0) {
      const AdaptiveBit& remainder = c.level_remainder[std::min(4, greater_one)];
      int k = 1;
      for (; k < 14; ++k) {
        bits += bit_cost(remainder, minus_one > k);
        if (minus_one <= k) break;
      }
      if (k == 14) bits += exp_golomb_bits(static_cast<uint32_t>(minus_one - 14));
      ++greater_one;
    } else {
      ++equal_one;
    }
    bits += 1;  // sign
  }
  return bits;
}

float dc_difference_bits(const BlockContextSet& c, int previous_category, int difference) {
  const unsigned magnitude = static_cast<unsigned>(std::abs(difference));
  const int category = magnitude == 0 ? 0 : std::bit_width(magnitude);
  const int row = previous_category == 0 ? 0 : (previous_category <= 2 ? 1 : 2);
  float bits = 0;
  for (int i = 0; i < category; ++i) bits += bit_cost(c.dc_category[row][i], 1);
  if (category < kMaxDcCategory) bits += bit_cost(c.dc_category[row][category], 0);
  return bits + static_cast<float>(category);  // sign and the bits below the leading one
}

float mvd_component_bits(const SyntaxContexts& c, int component, int context, int value) {
  float bits = bit_cost(c.mvd_zero[component][context], value != 0);
  if (value == 0) return bits;
  const int magnitude = std::abs(value);
  int k = 1;
  for (; k <= kMvdPrefixBins; ++k) {
    bits += bit_cost(c.mvd_magnitude[component][std::min(k - 1, 3)], magnitude > k);
    if (magnitude <= k) break;
  }
  if (magnitude > kMvdPrefixBins) bits += exp_golomb_bits(static_cast<uint32_t>(magnitude - kMvdPrefixBins - 1));
  return bits + 1;  // sign
}

float mode_bits(const FrameState& s, int mx, int my, MacroblockMode mode) {
  const SyntaxContexts& c = s.contexts;
  float bits = bit_cost(c.skip[skip_context(s, mx, my)], 0);
  bits += bit_cost(c.intra[intra_context(s, mx, my)], mode == MacroblockMode::kIntra);
  if (mode == MacroblockMode::kIntra || s.reference_count == 1) return bits;
  bits += bit_cost(c.bidirectional[bidirectional_context(s, mx, my)], mode == MacroblockMode::kBidirectional);
  if (mode == MacroblockMode::kBidirectional) return bits;
  return bits + bit_cost(c.backward[backward_context(s, mx, my)], mode == MacroblockMode::kBackward);
}

// ---- Syntax writers (mirrored by the readers below). ----

void encode_mvd_component(RangeEncoder& encoder, SyntaxContexts& c, int component, int context, int value) {
  encoder.encode(c.mvd_zero[component][context], value != 0);
  if (value == 0) return;
  const int magnitude = std::abs(value);
  for (int k = 1; k <= kMvdPrefixBins; ++k) {
    encoder.encode(c.mvd_magnitude[component][std::min(k - 1, 3)], magnitude > k);
    if (magnitude <= k) break;
  }
  if (magnitude > kMvdPrefixBins) {
    encode_exp_golomb_bypass(encoder, static_cast<uint32_t>(magnitude - kMvdPrefixBins - 1));
  }
  encoder.encode_bypass(value < 0);
}

bool decode_mvd_component(RangeDecoder& decoder, SyntaxContexts& c, int component, int context, int* value) {
  *value = 0;
  if (!decoder.decode(c.mvd_zero[component][context])) return true;
  int magnitude = 1;
  for (int k = 1; k <= kMvdPrefixBins; ++k) {
    if (!decoder.decode(c.mvd_magnitude[component][std::min(k - 1, 3)])) break;
    magnitude = k + 1;
  }
  if (magnitude > kMvdPrefixBins) {
    uint32_t escape = 0;
    if (!decode_exp_golomb_bypass(decoder, &escape)) return false;
    magnitude = kMvdPrefixBins + 1 + static_cast<int>(escape);
  }
  *value = decoder.decode_bypass() ? -magnitude : magnitude;
  return true;
}

// A node difference component: zero flag, sign, then |d| - 1 as a unary prefix of
// kNodePrefixBins adaptive bins with an Exp-Golomb escape.
float node_component_bits(const SyntaxContexts& c, int component, int kind, int value) {
  float bits = bit_cost(c.node_zero[component][kind], value != 0);
  if (value == 0) return bits;
  const int magnitude = std::abs(value);
  const auto& bins = c.node_magnitude[component][kind];
  int k = 1;
  for (; k <= kNodePrefixBins; ++k) {
    bits += bit_cost(bins[std::min(k - 1, kNodeMagnitudeContexts - 1)], magnitude > k);
    if (magnitude <= k) break;
  }
  if (magnitude > kNodePrefixBins) bits += exp_golomb_bits(static_cast<uint32_t>(magnitude - kNodePrefixBins - 1));
  return bits + 1;
}

void encode_node_component(RangeEncoder& encoder, SyntaxContexts& c, int component, int kind, int value) {
  encoder.encode(c.node_zero[component][kind], value != 0);
  if (value == 0) return;
  encoder.encode_bypass(value < 0);
  const int magnitude = std::abs(value);
  auto& bins = c.node_magnitude[component][kind];
  for (int k = 1; k <= kNodePrefixBins; ++k) {
    encoder.encode(bins[std::min(k - 1, kNodeMagnitudeContexts - 1)], magnitude > k);
    if (magnitude <= k) break;
  }
  if (magnitude > kNodePrefixBins) {
    encode_exp_golomb_bypass(encoder, static_cast<uint32_t>(magnitude - kNodePrefixBins - 1));
  }
}

bool decode_node_component(RangeDecoder& decoder, SyntaxContexts& c, int component, int kind, int* value) {
  *value = 0;
  if (!decoder.decode(c.node_zero[component][kind])) return true;
  const bool negative = decoder.decode_bypass() != 0;
  auto& bins = c.node_magnitude[component][kind];
  int magnitude = 1;
  for (int k = 1; k <= kNodePrefixBins; ++k) {
    if (!decoder.decode(bins[std::min(k - 1, kNodeMagnitudeContexts - 1)])) break;
    magnitude = k + 1;
  }
  if (magnitude > kNodePrefixBins) {
    uint32_t escape = 0;
    if (!decode_exp_golomb_bypass(decoder, &escape)) return false;
    magnitude = kNodePrefixBins + 1 + static_cast<int>(escape);
  }
  *value = negative ? -magnitude : magnitude;
  return true;
}

// Codes (encoder) the corner nodes of macroblock (mx, my) towards `reference` that the
// decoder does not know yet, in corner order, and marks them known.
void encode_missing_nodes(RangeEncoder& encoder, FrameState& s, int reference, int mx, int my,
                          MotionVector vector_predictor) {
  for (int k = 0; k < 4; ++k) {
    const int i = corner_i(mx, k), j = corner_j(my, k);
    if (s.known(reference, i, j)) continue;
    int kind = 0;
    const WarpNode prediction = predict_node(s, reference, i, j, vector_predictor, &kind);
    const WarpNode value = s.nodes[reference][s.node_index(i, j)];
    encode_node_component(encoder, s.contexts, 0, kind, value.x - prediction.x);
    encode_node_component(encoder, s.contexts, 1, kind, value.y - prediction.y);
    s.node_known[reference][s.node_index(i, j)] = 1;
  }
}

// Estimated bits of encode_missing_nodes, leaving the state unchanged.
float missing_nodes_bits(FrameState& s, int reference, int mx, int my, MotionVector vector_predictor) {
  float bits = 0;
  std::array<size_t, 4> marked{};
  int marked_count = 0;
  for (int k = 0; k < 4; ++k) {
    const int i = corner_i(mx, k), j = corner_j(my, k);
    if (s.known(reference, i, j)) continue;
    int kind = 0;
    const WarpNode prediction = predict_node(s, reference, i, j, vector_predictor, &kind);
    const WarpNode value = s.nodes[reference][s.node_index(i, j)];
    bits += node_component_bits(s.contexts, 0, kind, value.x - prediction.x) +
            node_component_bits(s.contexts, 1, kind, value.y - prediction.y);
    marked[static_cast<size_t>(marked_count++)] = s.node_index(i, j);
    s.node_known[reference][s.node_index(i, j)] = 1;
  }
  for (int m = 0; m < marked_count; ++m) s.node_known[reference][marked[static_cast<size_t>(m)]] = 0;
  return bits;
}

// Decodes the missing corner nodes of macroblock (mx, my); false on a syntax error or a
// node beyond the range.
bool decode_missing_nodes(RangeDecoder& decoder, FrameState& s, int reference, int mx, int my,
                          MotionVector vector_predictor) {
  for (int k = 0; k < 4; ++k) {
    const int i = corner_i(mx, k), j = corner_j(my, k);
    if (s.known(reference, i, j)) continue;
    int kind = 0;
    const WarpNode prediction = predict_node(s, reference, i, j, vector_predictor, &kind);
    int dx = 0, dy = 0;
    if (!decode_node_component(decoder, s.contexts, 0, kind, &dx) ||
        !decode_node_component(decoder, s.contexts, 1, kind, &dy)) {
      return false;
    }
    const int64_t x = int64_t{prediction.x} + dx, y = int64_t{prediction.y} + dy;
    if (std::abs(x) > s.node_limit || std::abs(y) > s.node_limit) return false;
    s.nodes[reference][s.node_index(i, j)] = WarpNode{static_cast<int32_t>(x), static_cast<int32_t>(y)};
    s.node_known[reference][s.node_index(i, j)] = 1;
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// Encoder

// One evaluated macroblock option.
struct MacroblockChoice {
  MacroblockMode mode = MacroblockMode::kIntra;
  bool warp = false;                      // inter or skip: predicted by warping
  std::array<MotionVector, 2> vectors{};  // used vectors; predictors for unused references
  std::array<std::array<int16_t, 64>, 6> levels{};
  std::array<int, 6> dc_levels{};  // intra only
  uint8_t coded_mask = 0;          // inter: coded block pattern; intra: blocks with AC levels
  MacroblockPrediction reconstruction;
  double cost = 0;
};

struct PaddedSource {
  std::array<std::vector<uint8_t>, 3> planes;
  std::array<int, 3> strides{};
};

PaddedSource pad_source(const ImageYCbCr420& source, const FrameState& s) {
  PaddedSource padded;
  const uint8_t* inputs[3] = {source.y.data(), source.cb.data(), source.cr.data()};
  for (int p = 0; p < 3; ++p) {
    const int visible_w = p == 0 ? s.width : s.chroma_width, visible_h = p == 0 ? s.height : s.chroma_height;
    const int stride = s.strides[p], rows = p == 0 ? 16 * s.mbs_y : 8 * s.mbs_y;
    padded.strides[p] = stride;
    padded.planes[p].resize(static_cast<size_t>(stride) * rows);
    for (int y = 0; y < rows; ++y) {
      const uint8_t* row = inputs[p] + static_cast<size_t>(std::min(y, visible_h - 1)) * visible_w;
      uint8_t* dst = padded.planes[p].data() + static_cast<size_t>(y) * stride;
      std::copy_n(row, visible_w, dst);
      std::fill(dst + visible_w, dst + stride, row[visible_w - 1]);
    }
  }
  return padded;
}

int64_t squared_error(const uint8_t* a, int a_stride, const uint8_t* b, int b_stride, int w, int h) {
  int64_t sum = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int d = static_cast<int>(a[y * a_stride + x]) - static_cast<int>(b[y * b_stride + x]);
      sum += d * d;
    }
  }
  return sum;
}

class BFrameEncoder {
 public:
  BFrameEncoder(FrameState& state, const PaddedSource& source, const BFrameParams& params)
      : s_(state),
        source_(source),
        refine_(params.half_pel_refinement),
        full_evaluations_(std::max(1, params.inter_evaluations)),
        max_candidates_(std::max(1, params.max_candidates)) {
    lambda_ = std::max(0.0, params.lambda_factor) * s_.inter_quantizer.quant_scale * s_.inter_quantizer.quant_scale;
    lambda_sad_ = std::sqrt(lambda_);
  }

  MacroblockChoice choose(int mx, int my, const CandidateList* candidates0, const CandidateList* candidates1,
                          BFrameStats* stats) {
    mx_ = mx;
    my_ = my;
    warp_cache_ = {};
    compute_visible();
    std::array<MotionVector, 2> predictors{};
    for (int r = 0; r < s_.reference_count; ++r) predictors[r] = predict_vector(s_, mx, my, r);
    predictors_ = predictors;
    const MacroblockMode skip_mode = predicted_mode(s_, mx, my);

    std::array<MotionVector, 2> best = predictors;
    const CandidateList* lists[2] = {candidates0, candidates1};
    for (int r = 0; r < s_.reference_count; ++r) best[r] = search_reference(r, lists[r], stats);

    MacroblockChoice winner, option;
    evaluate_skip(skip_mode, predicted_warp(s_, mx, my), &winner);
    auto consider = [&](MacroblockMode mode, bool warp) {
      if (mode == MacroblockMode::kIntra) {
        evaluate_intra(&option);
      } else {
        evaluate_inter(mode, warp, best, &option);
      }
      if (option.cost < winner.cost) std::swap(winner, option);
    };
    const MacroblockMode inter_modes[3] = {MacroblockMode::kForward, MacroblockMode::kBackward,
                                           MacroblockMode::kBidirectional};
    const int inter_count = s_.reference_count == 2 ? 3 : 1;
    // Screen the inter options by luma SAD + sqrt(lambda) * side bits; the full
    // rate-distortion evaluation (transform, quantization, both chroma planes) is spent on
    // the best few only.
    struct Screened {
      double cost;
      MacroblockMode mode;
      bool warp;
    };
    std::array<Screened, 6> screened{};
    int screened_count = 0;
    const uint8_t* source = source_.planes[0].data() + static_cast<size_t>(16 * my) * source_.strides[0] + 16 * mx;
    std::array<std::array<uint8_t, 256>, 2> luma{}, warped{};
    // Warping is screened only towards references whose corner nodes differ: with four
    // (nearly) equal corners it predicts what a translation does, at a higher price.
    unsigned screen_warp = 0;
    for (int r = 0; r < s_.reference_count; ++r) {
      predict_macroblock_luma(*s_.references[r], mx, my, best[r], luma[r].data());
      if ((s_.warp_mask >> r) & 1) {
        const std::array<WarpNode, 4> corners = macroblock_corners(s_, r, mx, my);
        int spread = 0;
        for (const WarpNode& node : corners) {
          spread = std::max({spread, std::abs(node.x - corners[0].x), std::abs(node.y - corners[0].y)});
        }
        if (spread <= kUniformWarpSpread) continue;
        screen_warp |= 1u << r;
        std::copy_n(warped_prediction(r, false).y.data(), 256, warped[r].data());
      }
    }
    for (int warp = 0; warp < 2; ++warp) {
      auto& planes = warp ? warped : luma;
      for (int m = 0; m < inter_count; ++m) {
        const MacroblockMode mode = inter_modes[m];
        if (warp && !warp_allowed(s_, mode)) continue;
        if (warp && ((uses_reference(mode, 0) && !(screen_warp & 1u)) ||
                     (uses_reference(mode, 1) && !(screen_warp & 2u)))) {
          continue;
        }
        float bits = mode_bits(s_, mx, my, mode);
        if (warp_allowed(s_, mode)) bits += bit_cost(s_.contexts.warp[warp_context(s_, mx, my)], warp);
        int sad;
        if (mode == MacroblockMode::kBidirectional) {
          uint8_t mean[256];
          average_samples(planes[0].data(), planes[1].data(), 256, mean);
          sad = sad_16x16(source, source_.strides[0], mean);
        } else {
          sad = sad_16x16(source, source_.strides[0], planes[mode == MacroblockMode::kBackward ? 1 : 0].data());
        }
        if (warp) {
          bits += warp_nodes_bits(mode);
        } else {
          for (int r = 0; r < s_.reference_count; ++r) {
            if (uses_reference(mode, r)) bits += vector_bits(r, best[r]);
          }
        }
        screened[static_cast<size_t>(screened_count++)] = {sad + lambda_sad_ * bits, mode, warp != 0};
      }
    }
    std::stable_sort(screened.begin(), screened.begin() + screened_count,
                     [](const Screened& a, const Screened& b) { return a.cost < b.cost; });
    for (int k = 0; k < std::min(screened_count, full_evaluations_); ++k) consider(screened[k].mode, screened[k].warp);
    consider(MacroblockMode::kIntra, false);
    return winner;
  }

  // Writes the chosen option and stores it in the frame state.
  void write(RangeEncoder& encoder, const MacroblockChoice& choice) {
    const int mx = mx_, my = my_;
    SyntaxContexts& c = s_.contexts;
    MacroblockInfo info;
    info.mode = choice.mode;
    info.inter_mode = predicted_mode(s_, mx, my);
    info.inter_warp = predicted_warp(s_, mx, my);
    info.vectors = predictors_;
    encoder.encode(c.skip[skip_context(s_, mx, my)], choice.mode == MacroblockMode::kSkipped);
    if (choice.mode == MacroblockMode::kSkipped) {
      if (info.inter_warp) write_warp_nodes(encoder, info.inter_mode, &info);
      commit_macroblock(s_, mx, my, info, choice.reconstruction, nullptr, 0);
      return;
    }
    encoder.encode(c.intra[intra_context(s_, mx, my)], choice.mode == MacroblockMode::kIntra);
    if (choice.mode == MacroblockMode::kIntra) {
      uint8_t local_coded[6] = {};
      for (int b = 0; b < 6; ++b) {
        const int plane = block_plane(b), bx = block_x(b, mx), by = block_y(b, my);
        BlockContextSet& set = plane == 0 ? c.intra_luma : c.intra_chroma;
        const int dc = choice.dc_levels[b];
        encode_dc_difference(encoder, set, dc - predict_dc(s_, choice.dc_levels.data(), plane, mx, my, bx, by));
        encode_block_levels(encoder, set, choice.levels[b].data(), 1,
                            coded_context(s_, local_coded, plane, mx, my, bx, by));
        local_coded[b] = static_cast<uint8_t>((choice.coded_mask >> b) & 1);
      }
      commit_macroblock(s_, mx, my, info, choice.reconstruction, choice.dc_levels.data(), choice.coded_mask);
      return;
    }
    if (s_.reference_count == 2) {
      encoder.encode(c.bidirectional[bidirectional_context(s_, mx, my)], choice.mode == MacroblockMode::kBidirectional);
      if (choice.mode != MacroblockMode::kBidirectional) {
        encoder.encode(c.backward[backward_context(s_, mx, my)], choice.mode == MacroblockMode::kBackward);
      }
    }
    if (warp_allowed(s_, choice.mode)) encoder.encode(c.warp[warp_context(s_, mx, my)], choice.warp);
    if (choice.warp) {
      write_warp_nodes(encoder, choice.mode, &info);
    } else {
      const int contexts[2] = {mvd_context(s_, mx, my, 0), mvd_context(s_, mx, my, 1)};
      for (int r = 0; r < s_.reference_count; ++r) {
        if (!uses_reference(choice.mode, r)) continue;
        const int dx = choice.vectors[r].x - predictors_[r].x, dy = choice.vectors[r].y - predictors_[r].y;
        encode_mvd_component(encoder, c, 0, contexts[0], dx);
        encode_mvd_component(encoder, c, 1, contexts[1], dy);
        info.mvd_magnitude[0] += std::abs(dx);
        info.mvd_magnitude[1] += std::abs(dy);
        info.vectors[r] = choice.vectors[r];
      }
    }
    info.inter_mode = choice.mode;
    info.inter_warp = choice.warp;
    uint8_t local_coded[6] = {};
    for (int b = 0; b < 6; ++b) {
      const int plane = block_plane(b);
      const int context = coded_context(s_, local_coded, plane, mx, my, block_x(b, mx), block_y(b, my));
      local_coded[b] = static_cast<uint8_t>((choice.coded_mask >> b) & 1);
      encoder.encode(plane == 0 ? c.cbp_luma[context] : c.cbp_chroma[plane - 1][context], local_coded[b]);
    }
    for (int b = 0; b < 6; ++b) {
      if (!local_coded[b]) continue;
      encode_block_levels(encoder, block_plane(b) == 0 ? c.inter_luma : c.inter_chroma, choice.levels[b].data(), 0,
                          kNoCodedBlockFlag);
    }
    commit_macroblock(s_, mx, my, info, choice.reconstruction, nullptr, choice.coded_mask);
  }

 private:
  // Warped predictions of the current macroblock, made once per reference and reused by
  // screening, skip and inter evaluation (the corner nodes do not change within it).
  struct WarpCache {
    bool luma = false, chroma = false;
    MacroblockPrediction prediction;
  };

  const MacroblockPrediction& warped_prediction(int reference, bool with_chroma) {
    WarpCache& cache = warp_cache_[static_cast<size_t>(reference)];
    const WarpCorners corners = macroblock_corners(s_, reference, mx_, my_);
    if (!cache.luma) {
      predict_warp_macroblock_luma(*s_.references[reference], mx_, my_, corners, cache.prediction.y.data());
      cache.luma = true;
    }
    if (with_chroma && !cache.chroma) {
      predict_warp_macroblock_chroma(*s_.references[reference], mx_, my_, corners, &cache.prediction);
      cache.chroma = true;
    }
    return cache.prediction;
  }

  // build_warp_prediction from the cache.
  void build_cached_warp_prediction(MacroblockMode mode, MacroblockPrediction* out) {
    if (mode == MacroblockMode::kBidirectional) {
      average_predictions(warped_prediction(0, true), warped_prediction(1, true), out);
    } else {
      *out = warped_prediction(mode == MacroblockMode::kBackward ? 1 : 0, true);
    }
  }

  // Codes the missing nodes of every reference `mode` reads and stores the centre vectors.
  void write_warp_nodes(RangeEncoder& encoder, MacroblockMode mode, MacroblockInfo* info) {
    for (int r = 0; r < s_.reference_count; ++r) {
      if (!uses_reference(mode, r)) continue;
      encode_missing_nodes(encoder, s_, r, mx_, my_, predictors_[r]);
      info->vectors[r] = warp_centre_vector(s_, macroblock_corners(s_, r, mx_, my_));
    }
  }

  float warp_nodes_bits(MacroblockMode mode) {
    float bits = 0;
    for (int r = 0; r < s_.reference_count; ++r) {
      if (uses_reference(mode, r)) bits += missing_nodes_bits(s_, r, mx_, my_, predictors_[r]);
    }
    return bits;
  }

  void compute_visible() {
    const int w = std::min(16, s_.width - 16 * mx_), h = std::min(16, s_.height - 16 * my_);
    const int cw = std::min(8, s_.chroma_width - 8 * mx_), ch = std::min(8, s_.chroma_height - 8 * my_);
    for (int b = 0; b < 4; ++b) {
      visible_w_[b] = std::clamp(w - 8 * (b & 1), 0, 8);
      visible_h_[b] = std::clamp(h - 8 * (b >> 1), 0, 8);
    }
    visible_w_[4] = visible_w_[5] = cw;
    visible_h_[4] = visible_h_[5] = ch;
  }

  const uint8_t* source_block(int b) const {
    const int plane = block_plane(b);
    const int x = 8 * block_x(b, mx_), y = 8 * block_y(b, my_);
    return source_.planes[plane].data() + static_cast<size_t>(y) * source_.strides[plane] + x;
  }

  int64_t block_error(int b, const uint8_t* samples) const {
    return squared_error(source_block(b), source_.strides[block_plane(b)], samples, block_stride(b), visible_w_[b],
                         visible_h_[b]);
  }

  float vector_bits(int reference, MotionVector vector) const {
    return mvd_component_bits(s_.contexts, 0, mvd_context(s_, mx_, my_, 0), vector.x - predictors_[reference].x) +
           mvd_component_bits(s_.contexts, 1, mvd_context(s_, mx_, my_, 1), vector.y - predictors_[reference].y);
  }

  MotionVector clamp_vector(MotionVector v) const {
    return MotionVector{static_cast<int16_t>(std::clamp<int>(v.x, -s_.vector_limit, s_.vector_limit)),
                        static_cast<int16_t>(std::clamp<int>(v.y, -s_.vector_limit, s_.vector_limit))};
  }

  // Best vector towards one reference by SAD + lambda * vector bits over the supplied
  // candidates and the predictor (the zero vector too when no candidate is given).
  MotionVector search_reference(int reference, const CandidateList* list, BFrameStats* stats) {
    const uint8_t* source = source_.planes[0].data() + static_cast<size_t>(16 * my_) * source_.strides[0] + 16 * mx_;
    const ImageYCbCr420& ref = *s_.references[reference];
    tried_.clear();
    MotionVector best = predictors_[reference];
    double best_cost = 1e300;
    auto try_vector = [&](MotionVector v) {
      v = clamp_vector(v);
      if (std::find(tried_.begin(), tried_.end(), v) != tried_.end()) return false;
      tried_.push_back(v);
      const double rate = lambda_sad_ * vector_bits(reference, v);
      if (rate >= best_cost) return true;  // cannot win whatever its SAD
      const int limit = static_cast<int>(std::min(best_cost - rate, 1e9));
      const int sad = sad_macroblock_luma(ref, mx_, my_, v, source, source_.strides[0], limit);
      if (stats != nullptr) ++stats->sad_evaluations;
      const double cost = sad + rate;
      if (cost < best_cost) {
        best_cost = cost;
        best = v;
      }
      return true;
    };
    int supplied = 0;
    if (list != nullptr) {
      // Lists are ranked (most pixels first): the tail rarely wins and costs a SAD each.
      const size_t count = std::min(list->size(), static_cast<size_t>(max_candidates_));
      for (size_t k = 0; k < count; ++k) supplied += try_vector((*list)[k]);
    }
    if (stats != nullptr) stats->candidates_evaluated += supplied;
    if (supplied == 0) try_vector(MotionVector{});
    try_vector(predictors_[reference]);
    if (refine_) {
      const MotionVector centre = best;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx != 0 || dy != 0) {
            try_vector(MotionVector{static_cast<int16_t>(centre.x + dx), static_cast<int16_t>(centre.y + dy)});
          }
        }
      }
    }
    return best;
  }

  void evaluate_skip(MacroblockMode mode, bool warp, MacroblockChoice* out) {
    out->mode = MacroblockMode::kSkipped;
    out->warp = warp;
    out->vectors = predictors_;
    out->coded_mask = 0;
    float bits = bit_cost(s_.contexts.skip[skip_context(s_, mx_, my_)], 1);
    if (warp) {
      build_cached_warp_prediction(mode, &out->reconstruction);
      bits += warp_nodes_bits(mode);
    } else {
      build_prediction(s_, mx_, my_, mode, predictors_, &out->reconstruction);
    }
    int64_t distortion = 0;
    for (int b = 0; b < 6; ++b) distortion += block_error(b, block_samples(out->reconstruction, b));
    out->cost = static_cast<double>(distortion) + lambda_ * bits;
  }

  void evaluate_inter(MacroblockMode mode, bool warp, const std::array<MotionVector, 2>& best,
                      MacroblockChoice* out) {
    const SyntaxContexts& c = s_.contexts;
    out->mode = mode;
    out->warp = warp;
    out->vectors = predictors_;
    float bits = mode_bits(s_, mx_, my_, mode);
    if (warp_allowed(s_, mode)) bits += bit_cost(c.warp[warp_context(s_, mx_, my_)], warp);
    MacroblockPrediction prediction;
    if (warp) {
      bits += warp_nodes_bits(mode);
      build_cached_warp_prediction(mode, &prediction);
    } else {
      for (int r = 0; r < s_.reference_count; ++r) {
        if (!uses_reference(mode, r)) continue;
        out->vectors[r] = best[r];
        bits += vector_bits(r, best[r]);
      }
      build_prediction(s_, mx_, my_, mode, out->vectors, &prediction);
    }
    int64_t distortion = 0;
    uint8_t local_coded[6] = {};
    out->coded_mask = 0;
    for (int b = 0; b < 6; ++b) {
      const int plane = block_plane(b), stride = block_stride(b);
      const uint8_t* pred = block_samples(prediction, b);
      uint8_t* recon = block_samples(out->reconstruction, b);
      const uint8_t* src = source_block(b);
      const int source_stride = source_.strides[plane];
      const int context = coded_context(s_, local_coded, plane, mx_, my_, block_x(b, mx_), block_y(b, my_));
      const AdaptiveBit& cbp_model = plane == 0 ? c.cbp_luma[context] : c.cbp_chroma[plane - 1][context];
      int16_t residual[64];
      for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) residual[8 * y + x] = static_cast<int16_t>(src[y * source_stride + x] - pred[y * stride + x]);
      }
      int16_t* levels = out->levels[b].data();
      const int nonzero = transform_quantize_block(s_.inter_quantizer, residual, levels);
      const int64_t uncoded_error = block_error(b, pred);
      bool coded = false;
      if (nonzero > 0) {
        uint8_t trial[64];
        reconstruct_residual_block(s_.inter_quantizer, levels, pred, stride, trial, 8);
        const int64_t coded_error =
            squared_error(src, source_stride, trial, 8, visible_w_[b], visible_h_[b]);
        const float coded_bits = bit_cost(cbp_model, 1) +
                                 block_levels_bits(plane == 0 ? c.inter_luma : c.inter_chroma, levels, 0, kNoCodedBlockFlag);
        const float uncoded_bits = bit_cost(cbp_model, 0);
        if (coded_error + lambda_ * coded_bits < uncoded_error + lambda_ * uncoded_bits) {
          coded = true;
          distortion += coded_error;
          bits += coded_bits;
          for (int y = 0; y < 8; ++y) std::copy_n(trial + 8 * y, 8, recon + y * stride);
        }
      }
      if (!coded) {
        distortion += uncoded_error;
        bits += bit_cost(cbp_model, 0);
        for (int y = 0; y < 8; ++y) std::copy_n(pred + y * stride, 8, recon + y * stride);
      }
      local_coded[b] = coded;
      out->coded_mask |= static_cast<uint8_t>(coded << b);
    }
    out->cost = static_cast<double>(distortion) + lambda_ * bits;
  }

  void evaluate_intra(MacroblockChoice* out) {
    const SyntaxContexts& c = s_.contexts;
    out->mode = MacroblockMode::kIntra;
    out->vectors = predictors_;
    out->coded_mask = 0;
    float bits = mode_bits(s_, mx_, my_, MacroblockMode::kIntra);
    int64_t distortion = 0;
    uint8_t local_coded[6] = {};
    int previous_category[2] = {c.intra_luma.previous_dc_category, c.intra_chroma.previous_dc_category};
    for (int b = 0; b < 6; ++b) {
      const int plane = block_plane(b), bx = block_x(b, mx_), by = block_y(b, my_);
      const BlockContextSet& set = plane == 0 ? c.intra_luma : c.intra_chroma;
      const uint8_t* src = source_block(b);
      const int source_stride = source_.strides[plane];
      int16_t samples[64];
      for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) samples[8 * y + x] = static_cast<int16_t>(src[y * source_stride + x] - 128);
      }
      int16_t* levels = out->levels[b].data();
      transform_quantize_block(s_.intra_quantizer, samples, levels);
      out->dc_levels[b] = levels[0];
      const int difference = levels[0] - predict_dc(s_, out->dc_levels.data(), plane, mx_, my_, bx, by);
      int& previous = previous_category[plane == 0 ? 0 : 1];
      bits += dc_difference_bits(set, previous, difference);
      previous = difference == 0 ? 0 : std::bit_width(static_cast<unsigned>(std::abs(difference)));
      bits += block_levels_bits(set, levels, 1, coded_context(s_, local_coded, plane, mx_, my_, bx, by));
      bool any_ac = false;
      for (int i = 1; i < 64 && !any_ac; ++i) any_ac = levels[i] != 0;
      local_coded[b] = any_ac;
      out->coded_mask |= static_cast<uint8_t>(any_ac << b);
      uint8_t* recon = block_samples(out->reconstruction, b);
      reconstruct_intra_block(s_.intra_quantizer, levels, recon, block_stride(b));
      distortion += block_error(b, recon);
    }
    out->cost = static_cast<double>(distortion) + lambda_ * bits;
  }

  FrameState& s_;
  const PaddedSource& source_;
  double lambda_ = 0, lambda_sad_ = 0;
  // From BFrameParams, whose fields hold the defaults.
  const bool refine_;
  const int full_evaluations_;
  const int max_candidates_;
  int mx_ = 0, my_ = 0;
  std::array<MotionVector, 2> predictors_{};
  std::array<int, 6> visible_w_{}, visible_h_{};
  std::vector<MotionVector> tried_;
  std::array<WarpCache, 2> warp_cache_;
};

bool consistent_image(const ImageYCbCr420& image, int width, int height) {
  const size_t chroma = static_cast<size_t>((width + 1) / 2) * static_cast<size_t>((height + 1) / 2);
  return image.width == width && image.height == height &&
         image.y.size() == static_cast<size_t>(width) * static_cast<size_t>(height) && image.cb.size() == chroma &&
         image.cr.size() == chroma;
}

void crop_output(const FrameState& s, ImageYCbCr420* out) {
  out->width = s.width;
  out->height = s.height;
  out->y.resize(static_cast<size_t>(s.width) * s.height);
  out->cb.resize(static_cast<size_t>(s.chroma_width) * s.chroma_height);
  out->cr.resize(out->cb.size());
  for (int y = 0; y < s.height; ++y) {
    std::copy_n(s.planes[0].data() + static_cast<size_t>(y) * s.strides[0], s.width,
                out->y.data() + static_cast<size_t>(y) * s.width);
  }
  for (int y = 0; y < s.chroma_height; ++y) {
    const size_t from = static_cast<size_t>(y) * s.strides[1], to = static_cast<size_t>(y) * s.chroma_width;
    std::copy_n(s.planes[1].data() + from, s.chroma_width, out->cb.data() + to);
    std::copy_n(s.planes[2].data() + from, s.chroma_width, out->cr.data() + to);
  }
}

Status corrupt(const std::string& what) { return Status(ErrorCode::kCorruptData, "B-frame: " + what); }

std::string macroblock_name(int mx, int my) {
  return "macroblock (" + std::to_string(mx) + ", " + std::to_string(my) + ")";
}

}  // namespace

int suggested_b_quant_scale(int intra_quant_scale) {
  const int clamped = std::clamp(intra_quant_scale, kMinQuantScale, kMaxQuantScale);
  return std::clamp((clamped * 5 + 1) / 2, kMinQuantScale, kMaxQuantScale);
}

std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const FaceCandidates& candidates0,
                                    const FaceCandidates& candidates1, const BFrameParams& params,
                                    ImageYCbCr420* reconstruction, BFrameStats* stats) {
  return encode_b_frame(source, ref0, ref1, candidates0, candidates1, nullptr, nullptr, params, reconstruction,
                        stats);
}

std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const FaceCandidates& candidates0,
                                    const FaceCandidates& candidates1, const WarpField* warp0,
                                    const WarpField* warp1, const BFrameParams& params,
                                    ImageYCbCr420* reconstruction, BFrameStats* stats) {
  const int width = source.width, height = source.height;
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension ||
      !consistent_image(source, width, height) || !consistent_image(ref0, width, height) ||
      (ref1 != nullptr && !consistent_image(*ref1, width, height))) {
    return {};
  }
  const int quant_scale = std::clamp(params.quant_scale, kMinQuantScale, kMaxQuantScale);
  FrameState state;
  init_state(state, width, height, quant_scale, &ref0, ref1);
  const WarpField* fields[2] = {warp0, ref1 != nullptr ? warp1 : nullptr};
  for (int r = 0; r < state.reference_count; ++r) {
    const WarpField* field = fields[r];
    if (!params.warp || field == nullptr || field->nodes_x != state.nodes_x || field->nodes_y != state.nodes_y ||
        field->nodes.size() != state.nodes[r].size()) {
      continue;
    }
    state.warp_mask |= 1 << r;
    for (size_t n = 0; n < field->nodes.size(); ++n) {
      state.nodes[r][n] = WarpNode{std::clamp(field->nodes[n].x, -state.node_limit, state.node_limit),
                                   std::clamp(field->nodes[n].y, -state.node_limit, state.node_limit)};
    }
  }
  const PaddedSource padded = pad_source(source, state);
  if (stats != nullptr) {
    *stats = BFrameStats{};
    stats->macroblocks = state.mbs_x * state.mbs_y;
    stats->modes.reserve(static_cast<size_t>(stats->macroblocks));
  }

  std::vector<uint8_t> bytes = {static_cast<uint8_t>(FaceType::kPredicted), kBFrameSyntaxVersion,
                                static_cast<uint8_t>(quant_scale), 0,
                                static_cast<uint8_t>(state.reference_count),
                                static_cast<uint8_t>(state.warp_mask)};
  RangeEncoder encoder(&bytes);
  BFrameEncoder coder(state, padded, params);
  for (int my = 0; my < state.mbs_y; ++my) {
    for (int mx = 0; mx < state.mbs_x; ++mx) {
      const size_t index = static_cast<size_t>(my) * state.mbs_x + mx;
      const CandidateList* list0 = index < candidates0.size() ? &candidates0[index] : nullptr;
      const CandidateList* list1 =
          ref1 != nullptr && index < candidates1.size() ? &candidates1[index] : nullptr;
      const MacroblockChoice choice = coder.choose(mx, my, list0, list1, stats);
      coder.write(encoder, choice);
      if (stats != nullptr) {
        stats->modes.push_back(choice.mode);
        if (choice.mode != MacroblockMode::kIntra && choice.warp) ++stats->mb_warp;
        switch (choice.mode) {
          case MacroblockMode::kIntra: ++stats->mb_intra; break;
          case MacroblockMode::kForward: ++stats->mb_forward; break;
          case MacroblockMode::kBackward: ++stats->mb_backward; break;
          case MacroblockMode::kBidirectional: ++stats->mb_bidirectional; break;
          case MacroblockMode::kSkipped: ++stats->mb_skipped; break;
        }
      }
    }
  }
  encoder.finish();
  if (stats != nullptr) {
    for (int r = 0; r < state.reference_count; ++r) {
      for (uint8_t known : state.node_known[r]) stats->warp_nodes_coded += known;
    }
  }
  if (reconstruction != nullptr) crop_output(state, reconstruction);
  return bytes;
}

Status parse_b_frame_header(std::span<const uint8_t> bytes, BFrameHeader* out) {
  if (bytes.size() < static_cast<size_t>(kBFrameHeaderBytes)) {
    return corrupt("payload of " + std::to_string(bytes.size()) + " bytes is shorter than the " +
                   std::to_string(kBFrameHeaderBytes) + "-byte header");
  }
  if (bytes[0] != static_cast<uint8_t>(FaceType::kPredicted)) {
    return corrupt("byte 0: frame type " + std::to_string(bytes[0]) + " is not bidirectional (1)");
  }
  if (bytes[1] != kBFrameSyntaxVersion) {
    return Status(ErrorCode::kUnsupported, "B-frame: byte 1: syntax version " + std::to_string(bytes[1]) +
                                               " (this build reads " + std::to_string(kBFrameSyntaxVersion) + ")");
  }
  if (bytes[2] < kMinQuantScale || bytes[2] > kMaxQuantScale) {
    return corrupt("byte 2: quant_scale " + std::to_string(bytes[2]) + " outside 1..112");
  }
  if (bytes[3] != 0) return corrupt("byte 3: reserved byte is " + std::to_string(bytes[3]));
  if (bytes[4] != 1 && bytes[4] != 2) {
    return corrupt("byte 4: reference count " + std::to_string(bytes[4]) + " is not 1 or 2");
  }
  if ((bytes[5] & ~((1 << bytes[4]) - 1)) != 0) {
    return corrupt("byte 5: warp mask " + std::to_string(bytes[5]) + " names a reference beyond the " +
                   std::to_string(bytes[4]) + " present");
  }
  out->quant_scale = bytes[2];
  out->reference_count = bytes[4];
  out->warp_mask = bytes[5];
  return Status::Ok();
}

Status decode_b_frame(std::span<const uint8_t> bytes, int width, int height, const ImageYCbCr420& ref0,
                      const ImageYCbCr420* ref1, ImageYCbCr420* out, std::vector<MacroblockMode>* modes) {
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension) {
    return Status(ErrorCode::kInvalidArgument, "B-frame: size " + std::to_string(width) + "x" +
                                                   std::to_string(height) + " outside 1.." +
                                                   std::to_string(kMaxFrameDimension));
  }
  if (!consistent_image(ref0, width, height) || (ref1 != nullptr && !consistent_image(*ref1, width, height))) {
    return Status(ErrorCode::kInvalidArgument,
                  "B-frame: reference images are not " + std::to_string(width) + "x" + std::to_string(height) +
                      " with 4:2:0 planes of matching size");
  }
  BFrameHeader header;
  SVC_RETURN_IF_ERROR(parse_b_frame_header(bytes, &header));
  const int given = ref1 != nullptr ? 2 : 1;
  if (header.reference_count != given) {
    return Status(ErrorCode::kInvalidArgument, "B-frame: coded with " + std::to_string(header.reference_count) +
                                                   " reference(s) but " + std::to_string(given) + " given");
  }
  FrameState s;
  init_state(s, width, height, header.quant_scale, &ref0, ref1);
  s.warp_mask = header.warp_mask;
  if (modes != nullptr) {
    modes->clear();
    modes->reserve(s.macroblocks.size());
  }
  SyntaxContexts& c = s.contexts;
  RangeDecoder decoder(bytes.subspan(kBFrameHeaderBytes));
  MacroblockPrediction prediction, reconstruction;
  int16_t levels[64];
  BlockLevel decoded[64];

  for (int my = 0; my < s.mbs_y; ++my) {
    for (int mx = 0; mx < s.mbs_x; ++mx) {
      MacroblockInfo info;
      const MacroblockMode skip_mode = predicted_mode(s, mx, my);
      std::array<MotionVector, 2> predictors{};
      for (int r = 0; r < s.reference_count; ++r) predictors[r] = predict_vector(s, mx, my, r);
      info.inter_mode = skip_mode;
      info.inter_warp = predicted_warp(s, mx, my);
      info.vectors = predictors;
      uint8_t coded_mask = 0;
      const int* intra_dc = nullptr;
      std::array<int, 6> dc_levels{};
      // Reads the missing nodes of the references `mode` uses; stores the centre vectors.
      auto read_warp_nodes = [&](MacroblockMode mode) {
        if (!warp_allowed(s, mode)) return false;
        for (int r = 0; r < s.reference_count; ++r) {
          if (!uses_reference(mode, r)) continue;
          if (!decode_missing_nodes(decoder, s, r, mx, my, predictors[r])) return false;
          info.vectors[r] = warp_centre_vector(s, macroblock_corners(s, r, mx, my));
        }
        return true;
      };

      if (decoder.decode(c.skip[skip_context(s, mx, my)])) {
        info.mode = MacroblockMode::kSkipped;
        if (info.inter_warp) {
          if (!read_warp_nodes(skip_mode)) return corrupt(macroblock_name(mx, my) + ": invalid warp node");
          build_warp_prediction(s, mx, my, skip_mode, &reconstruction);
        } else {
          build_prediction(s, mx, my, skip_mode, predictors, &reconstruction);
        }
      } else if (decoder.decode(c.intra[intra_context(s, mx, my)])) {
        info.mode = MacroblockMode::kIntra;
        uint8_t local_coded[6] = {};
        for (int b = 0; b < 6; ++b) {
          const int plane = block_plane(b), bx = block_x(b, mx), by = block_y(b, my);
          BlockContextSet& set = plane == 0 ? c.intra_luma : c.intra_chroma;
          int difference = 0;
          if (!decode_dc_difference(decoder, set, &difference)) {
            return corrupt(macroblock_name(mx, my) + ": invalid DC difference");
          }
          const int dc = predict_dc(s, dc_levels.data(), plane, mx, my, bx, by) + difference;
          if (dc < -kMaxLevel || dc > kMaxLevel) {
            return corrupt(macroblock_name(mx, my) + ": DC level " + std::to_string(dc) + " out of range");
          }
          dc_levels[b] = dc;
          int count = 0;
          if (!decode_block_levels(decoder, set, 1, coded_context(s, local_coded, plane, mx, my, bx, by), decoded,
                                   &count)) {
            return corrupt(macroblock_name(mx, my) + ": invalid intra levels");
          }
          std::fill(std::begin(levels), std::end(levels), int16_t{0});
          levels[0] = static_cast<int16_t>(dc);
          for (int i = 0; i < count; ++i) levels[decoded[i].position] = decoded[i].level;
          local_coded[b] = count > 0;
          coded_mask |= static_cast<uint8_t>((count > 0) << b);
          reconstruct_intra_block(s.intra_quantizer, levels, block_samples(reconstruction, b), block_stride(b));
        }
        intra_dc = dc_levels.data();
      } else {
        MacroblockMode mode = MacroblockMode::kForward;
        if (s.reference_count == 2) {
          if (decoder.decode(c.bidirectional[bidirectional_context(s, mx, my)])) {
            mode = MacroblockMode::kBidirectional;
          } else if (decoder.decode(c.backward[backward_context(s, mx, my)])) {
            mode = MacroblockMode::kBackward;
          }
        }
        info.mode = mode;
        info.inter_mode = mode;
        info.inter_warp = warp_allowed(s, mode) && decoder.decode(c.warp[warp_context(s, mx, my)]) != 0;
        if (info.inter_warp && !read_warp_nodes(mode)) {
          return corrupt(macroblock_name(mx, my) + ": invalid warp node");
        }
        const int contexts[2] = {mvd_context(s, mx, my, 0), mvd_context(s, mx, my, 1)};
        for (int r = 0; r < s.reference_count && !info.inter_warp; ++r) {
          if (!uses_reference(mode, r)) continue;
          int dx = 0, dy = 0;
          if (!decode_mvd_component(decoder, c, 0, contexts[0], &dx) ||
              !decode_mvd_component(decoder, c, 1, contexts[1], &dy)) {
            return corrupt(macroblock_name(mx, my) + ": invalid motion vector difference");
          }
          const int vx = predictors[r].x + dx, vy = predictors[r].y + dy;
          if (std::abs(vx) > s.vector_limit || std::abs(vy) > s.vector_limit) {
            return corrupt(macroblock_name(mx, my) + ": motion vector (" + std::to_string(vx) + ", " +
                           std::to_string(vy) + ") half-pels beyond the limit " + std::to_string(s.vector_limit));
          }
          info.vectors[r] = MotionVector{static_cast<int16_t>(vx), static_cast<int16_t>(vy)};
          info.mvd_magnitude[0] += std::abs(dx);
          info.mvd_magnitude[1] += std::abs(dy);
        }
        uint8_t local_coded[6] = {};
        for (int b = 0; b < 6; ++b) {
          const int plane = block_plane(b);
          const int context = coded_context(s, local_coded, plane, mx, my, block_x(b, mx), block_y(b, my));
          local_coded[b] = static_cast<uint8_t>(
              decoder.decode(plane == 0 ? c.cbp_luma[context] : c.cbp_chroma[plane - 1][context]));
          coded_mask |= static_cast<uint8_t>(local_coded[b] << b);
        }
        if (info.inter_warp) {
          build_warp_prediction(s, mx, my, mode, &prediction);
        } else {
          build_prediction(s, mx, my, mode, info.vectors, &prediction);
        }
        for (int b = 0; b < 6; ++b) {
          const uint8_t* pred = block_samples(prediction, b);
          uint8_t* recon = block_samples(reconstruction, b);
          const int stride = block_stride(b);
          if (!local_coded[b]) {
            for (int y = 0; y < 8; ++y) std::copy_n(pred + y * stride, 8, recon + y * stride);
            continue;
          }
          int count = 0;
          if (!decode_block_levels(decoder, block_plane(b) == 0 ? c.inter_luma : c.inter_chroma, 0,
                                   kNoCodedBlockFlag, decoded, &count)) {
            return corrupt(macroblock_name(mx, my) + ": invalid residual levels");
          }
          std::fill(std::begin(levels), std::end(levels), int16_t{0});
          for (int i = 0; i < count; ++i) levels[decoded[i].position] = decoded[i].level;
          reconstruct_residual_block(s.inter_quantizer, levels, pred, stride, recon, stride);
        }
      }
      commit_macroblock(s, mx, my, info, reconstruction, intra_dc, coded_mask);
      if (modes != nullptr) modes->push_back(info.mode);
    }
    // A complete payload is never read past its end; stopping at the first row that does
    // bounds the work garbage can cause.
    if (decoder.overrun() > 0) {
      return corrupt("payload truncated (macroblock row " + std::to_string(my) + " needs bytes beyond the " +
                     std::to_string(bytes.size()) + " given)");
    }
  }
  const size_t used = decoder.consumed() + kBFrameHeaderBytes;
  if (used != bytes.size()) {
    return corrupt(std::to_string(bytes.size() - used) + " trailing bytes after offset " + std::to_string(used));
  }
  crop_output(s, out);
  return Status::Ok();
}

}  // namespace svc::codec
