// SPDX-License-Identifier: BSD-2-Clause
// B-face coding internals shared by the encoder (bframe_encoder.cc) and the decoder
// (bframe_decoder.cc): the frame state (reconstructed padded planes, per-block coded
// flags, the intra neighbour state, per-macroblock vectors and modes), the predictors
// derived from it and the reconstruction routines, so the encoder's reconstruction is
// the decoder's output by construction. Not part of the codec's interface
// (codec/bframe_codec.h).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "codec/common/adaptive_bit.h"
#include "codec/common/bframe.h"
#include "codec/common/coefficient_contexts.h"
#include "codec/common/intra_macroblock.h"
#include "codec/common/motion_compensation.h"
#include "codec/common/quant.h"
#include "codec/common/warp_prediction.h"

namespace svc::codec::bframe {

// A magnitude of class k lies in 2^k .. 2^(k+1) - 1 (docs/codec.md 3.8). Vector
// differences stay below 2^16 and node differences below 2^18 within the ranges of 10.3.
constexpr int kMagnitudeClasses = 18;
constexpr int kNeighbourContexts = 3;

// The adaptive bits of a magnitude coded by class: [k] whether the class is above k,
// and the bit below the leading one of a magnitude in class k + 1.
struct MagnitudeBits {
  std::array<AdaptiveBit, kMagnitudeClasses - 1> above{};
  std::array<AdaptiveBit, kMagnitudeClasses - 1> below{};
};

using svc::codec::for_each_bit;
template <class M, class F>
requires std::same_as<std::remove_const_t<M>, MagnitudeBits>
void for_each_bit(M& magnitude, F&& f) {
  for_each_bit(magnitude.above, f);
  for_each_bit(magnitude.below, f);
}

// The bits of a vector predictor's index: index > 0, then (three predictors) index 2.
using PredictorIndexBits = std::array<AdaptiveBit, 2>;

struct SyntaxContexts {
  std::array<AdaptiveBit, kNeighbourContexts> skip{};
  std::array<AdaptiveBit, kNeighbourContexts> intra{};
  std::array<AdaptiveBit, kNeighbourContexts> bidirectional{};
  std::array<AdaptiveBit, kNeighbourContexts> backward{};
  std::array<std::array<AdaptiveBit, kNeighbourContexts>, 2> mvd_zero{};  // [component][ctx]
  std::array<MagnitudeBits, 2> mvd_magnitude{};                           // [component]
  std::array<AdaptiveBit, kNeighbourContexts> warp{};
  // Partition of an inter macroblock (docs/codec.md, section 3.7).
  std::array<AdaptiveBit, kNeighbourContexts> partition_split{};
  AdaptiveBit partition_quad{};
  AdaptiveBit partition_vertical{};
  // Node differences: [component][predictor kind: 0 planar, 1 other].
  std::array<std::array<AdaptiveBit, 2>, 2> node_zero{};
  std::array<std::array<MagnitudeBits, 2>, 2> node_magnitude{};
  std::array<AdaptiveBit, kNeighbourContexts> cbp_luma{};
  std::array<std::array<AdaptiveBit, kNeighbourContexts>, 2> cbp_chroma{};  // [Cb/Cr][ctx]
  // Whether a coded inter macroblock's luma residual is one 16x16 block (header flag
  // kInterTransformSizesFlag).
  std::array<AdaptiveBit, kNeighbourContexts> luma_16x16{};
  // Whether a coded luma 8x8 block of such a macroblock is four 4x4 blocks.
  AdaptiveBit luma_4x4{};
  // Which vector predictor a coded vector's difference is taken from: [0] the first or a
  // later one, [1] the second or the third (docs/codec.md 3.8).
  PredictorIndexBits predictor_index{};
  // The same for the vectors of a skipped macroblock (one index for both references).
  PredictorIndexBits skip_predictor_index{};
  // Intra macroblocks: the intra frame's luma and chroma contexts (docs/codec.md 3.1).
  intra::PlaneContexts intra_luma, intra_chroma;
  BlockContextSet inter_luma, inter_chroma;
};

// Calls f on every context, in member order (docs/codec.md 6.1).
template <class Set, class F>
requires std::same_as<std::remove_const_t<Set>, SyntaxContexts>
void for_each_context(Set& s, F&& f) {
  for_each_bit(s.skip, f);
  for_each_bit(s.intra, f);
  for_each_bit(s.bidirectional, f);
  for_each_bit(s.backward, f);
  for_each_bit(s.mvd_zero, f);
  for_each_bit(s.mvd_magnitude, f);
  for_each_bit(s.warp, f);
  for_each_bit(s.partition_split, f);
  for_each_bit(s.partition_quad, f);
  for_each_bit(s.partition_vertical, f);
  for_each_bit(s.node_zero, f);
  for_each_bit(s.node_magnitude, f);
  for_each_bit(s.cbp_luma, f);
  for_each_bit(s.cbp_chroma, f);
  for_each_context(s.intra_luma, f);
  for_each_context(s.intra_chroma, f);
  for_each_context(s.inter_luma, f);
  for_each_context(s.inter_chroma, f);
  for_each_bit(s.luma_16x16, f);
  f(s.luma_4x4);
  for_each_bit(s.predictor_index, f);
  for_each_bit(s.skip_predictor_index, f);
}

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
  // Sum over references (and partitions) of |mvd.x| and |mvd.y| (0 when no vector was
  // coded).
  std::array<int, 2> mvd_magnitude{};
  // Inter macroblocks only; 16x16 for every other mode.
  Partition partition = Partition::k16x16;
  // Inter macroblocks only: the luma residual is one 16x16 transform block.
  bool luma_16x16 = false;
};

// ---- Partitions of an inter macroblock: rectangles in luma samples of the macroblock,
// in coding order (raster). Chroma uses the same rectangle halved. ----
struct PartitionRect {
  int x = 0, y = 0, width = 16, height = 16;
};

inline int partition_count(Partition p) { return p == Partition::k16x16 ? 1 : (p == Partition::k8x8 ? 4 : 2); }

inline PartitionRect partition_rect(Partition p, int k) {
  switch (p) {
    case Partition::k16x8: return {0, 8 * k, 16, 8};
    case Partition::k8x16: return {8 * k, 0, 8, 16};
    case Partition::k8x8: return {8 * (k & 1), 8 * (k >> 1), 8, 8};
    default: return {};
  }
}

// The partition of the same macroblock left of (above) partition k, or -1.
inline int partition_left(Partition p, int k) {
  return (p == Partition::k8x16 && k == 1) || (p == Partition::k8x8 && (k & 1)) ? k - 1 : -1;
}

inline int partition_above(Partition p, int k) {
  return (p == Partition::k16x8 && k == 1) || (p == Partition::k8x8 && k >= 2) ? k - (p == Partition::k8x8 ? 2 : 1)
                                                                               : -1;
}

// The prediction of every partition of an inter macroblock: its mode (forward, backward
// or bidirectional) and its vectors (those of references it does not use are unused).
struct PartitionMotion {
  Partition partition = Partition::k16x16;
  std::array<MacroblockMode, 4> modes{};
  std::array<std::array<MotionVector, 2>, 4> vectors{};
};

struct FrameState {
  int width = 0, height = 0;
  int mbs_x = 0, mbs_y = 0;
  int chroma_width = 0, chroma_height = 0;  // visible
  int reference_count = 1;
  std::array<const ImageYCbCr420*, 2> references{};
  // Macroblocks of cube-map border around each reference face (codec/cube_padding.h):
  // macroblock (mx, my) of the face is macroblock (mx + border_mbs, my + border_mbs) of
  // its reference planes. 0 without padding.
  int border_mbs = 0;
  Quantizer inter_quantizer;
  // The 16x16 luma residual's steps at the same qindex (docs/codec.md 5.4).
  Quantizer inter_quantizer_16x16;
  Quantizer inter_quantizer_4x4;
  // Whether coded inter macroblocks choose their luma transform size (header flag
  // kInterTransformSizesFlag); clear, every residual block is 8x8.
  bool inter_transform_sizes = false;
  // Intra macroblocks: the intra frame's residual steps at the frame's qindex.
  intra::SizedQuantizers intra_quantizers{};
  int vector_limit = 0;
  int node_limit = 0;
  // References with a warp node field (bit r for reference r).
  int warp_mask = 0;
  // Per reference: the epipolar lines vector differences follow (absent: x and y).
  std::array<EpipolarLines, 2> lines{};
  // The frame's interpolation filter bank (header byte 2, bits 3-4).
  InterpolationFilter filter = InterpolationFilter::kRegular;
  // Node grids (mbs_x + 1) x (mbs_y + 1) per reference: values and whether the decoder
  // knows them yet. The encoder stores its whole field up front and marks nodes known as
  // it codes them; the decoder fills values as it decodes them.
  int nodes_x = 0, nodes_y = 0;
  std::array<std::vector<WarpNode>, 2> nodes;
  std::array<std::vector<uint8_t>, 2> node_known;
  // Reconstructed planes padded to whole macroblocks; strides 16 mbs_x and 8 mbs_x.
  std::array<std::vector<uint8_t>, 3> planes;
  std::array<int, 3> strides{};
  // Per 8x8 block of each plane (grids 2 mbs_x x 2 mbs_y and mbs_x x mbs_y): whether the
  // block had coded levels (intra: some transform block covering it has a level).
  std::array<std::vector<uint8_t>, 3> coded;
  // Intra prediction's neighbour state of each plane (Y, Cb, Cr; docs/codec.md 3.7):
  // intra blocks as in intra frames, inter and skipped macroblocks as DC, uncoded blocks.
  std::vector<intra::PlaneState> intra_planes;
  std::vector<MacroblockInfo> macroblocks;
  SyntaxContexts contexts;

  int grid_width(int plane) const { return plane == 0 ? 2 * mbs_x : mbs_x; }
  const MacroblockInfo& mb(int x, int y) const { return macroblocks[static_cast<size_t>(y) * mbs_x + x]; }
  size_t node_index(int i, int j) const { return static_cast<size_t>(j) * nodes_x + i; }
  bool known(int r, int i, int j) const {
    return i >= 0 && j >= 0 && i < nodes_x && j < nodes_y && node_known[r][node_index(i, j)] != 0;
  }
};

// The references are width x height, or that plus a border of border_mbs macroblocks on
// each side.
void init_state(FrameState& s, int width, int height, int qindex, const ImageYCbCr420* ref0,
                const ImageYCbCr420* ref1, int border_mbs = 0);

// Macroblock coordinate of the current face within the (padded) reference planes.
inline int reference_mb(const FrameState& s, int m) { return m + s.border_mbs; }

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
T block_value(const FrameState& s, const std::vector<T>& values, const T* local, int plane, int mx, int my, int bx,
              int by) {
  if (plane == 0) {
    if ((bx >> 1) == mx && (by >> 1) == my) return local[(by & 1) * 2 + (bx & 1)];
  } else if (bx == mx && by == my) {
    return local[3 + plane];
  }
  return values[static_cast<size_t>(by) * s.grid_width(plane) + bx];
}

// ctx_cbf of block (bx, by) of `plane` (docs/codec.md 4.2): the coded flags of its left
// and top neighbours, those of macroblock (mx, my) read from `local` (by block number).
int coded_context(const FrameState& s, const uint8_t* local, int plane, int mx, int my, int bx, int by);

inline int median3(int a, int b, int c) { return std::max(std::min(a, b), std::min(std::max(a, b), c)); }

MotionVector predict_vector(const FrameState& s, int mx, int my, int reference);

// The vector of macroblock (nx, ny) towards r as a macroblock with direction `here`
// would see the same depth (carry_along_lines from the neighbour's direction), on_line;
// the vector itself, not on_line, without lines, where a direction is zero or beyond
// the range.
struct CarriedVector {
  MotionVector vector;
  bool on_line = false;
};
CarriedVector carried_vector(const FrameState& s, int r, int nx, int ny, LineDirection here);

inline constexpr int kMaxVectorPredictors = 3;

// The distinct predictors a coded vector may take its difference from, in order; the
// vector codes the index of the one it uses (docs/codec.md 3.8).
struct VectorPredictors {
  int count = 0;
  std::array<MotionVector, kMaxVectorPredictors> vectors{};
  // Appends v unless it is already listed or the list is full.
  void add(MotionVector v);
};

// predict_vector's median, then the vectors of the left, top and top-right macroblocks
// that exist, the first three distinct ones.
VectorPredictors macroblock_predictors(const FrameState& s, int mx, int my, int reference);

MacroblockMode predicted_mode(const FrameState& s, int mx, int my);

// The warp flag a skip inherits, from the same neighbour as predicted_mode.
bool predicted_warp(const FrameState& s, int mx, int my);

// Corner nodes within this many node units (1/8 pel) of each other count as one
// translation when the encoder screens warped prediction.
inline constexpr int kUniformWarpSpread = 2;

inline bool uses_reference(MacroblockMode mode, int reference) {
  if (mode == MacroblockMode::kBidirectional) return true;
  return reference == 0 ? mode == MacroblockMode::kForward : mode == MacroblockMode::kBackward;
}

// Number of the left and top neighbours satisfying `predicate`: context 0..2.
template <typename Predicate>
int neighbour_context(const FrameState& s, int mx, int my, Predicate predicate) {
  return (mx > 0 && predicate(s.mb(mx - 1, my))) + (my > 0 && predicate(s.mb(mx, my - 1)));
}

int skip_context(const FrameState& s, int mx, int my);

int intra_context(const FrameState& s, int mx, int my);

int bidirectional_context(const FrameState& s, int mx, int my);

int backward_context(const FrameState& s, int mx, int my);

int warp_context(const FrameState& s, int mx, int my);

// Left and top macroblocks that are inter (not skipped) with a partition other than 16x16.
int partition_context(const FrameState& s, int mx, int my);

// Left and top macroblocks whose luma residual is one 16x16 block.
int luma_16x16_context(const FrameState& s, int mx, int my);

// The vector predictor of partition k towards reference r, given the motion of the
// partitions before it: the left partition's vector when it exists and uses r, else the
// upper one's under the same condition, else the macroblock's predictor.
MotionVector partition_predictor(const PartitionMotion& motion, int k, int r, MotionVector macroblock_predictor);

// A translational skip in `mode` codes an index below the longest list of the references
// it uses; reference r takes entry min(index, count - 1) of its list.
int skip_predictor_count(const std::array<VectorPredictors, 2>& lists, MacroblockMode mode);
std::array<MotionVector, 2> skip_vectors(const std::array<VectorPredictors, 2>& lists, MacroblockMode mode,
                                         int index);

// Partition k's predictors towards reference r: partition_predictor's vector (with the
// macroblock's first predictor), then the macroblock's predictors, distinct.
VectorPredictors partition_predictors(const PartitionMotion& motion, int k, int r,
                                      const VectorPredictors& macroblock);

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

WarpCorners macroblock_corners(const FrameState& s, int reference, int mx, int my);

// The prediction of a not yet known node from known ones (docs/codec.md, section 3.8):
// planar from the left (or right) and top neighbours, else one neighbour, else the
// macroblock's vector predictor. `kind` receives 0 for planar, 1 otherwise.
WarpNode predict_node(const FrameState& s, int r, int i, int j, MotionVector vector_predictor, int* kind);

// The vector a warped macroblock leaves for its neighbours' predictors: the mean of its
// corner nodes in quarter-pels, (sum + 4) >> 3, clamped to the vector range.
MotionVector warp_centre_vector(const FrameState& s, const WarpCorners& c);

int mvd_context(const FrameState& s, int mx, int my, int component);

// The epipolar direction of reference r at the centre of macroblock (mx, my) and at
// warp node (i, j) (zero without lines).
LineDirection macroblock_direction(const FrameState& s, int r, int mx, int my);
LineDirection node_direction(const FrameState& s, int r, int i, int j);

// The difference of a vector from its prediction, given by their line coordinates v and p
// for direction d: along, the difference of the two; across, v's alone, the line being
// where motion lies (with a zero direction, the x and y difference).
std::array<int64_t, 2> line_difference(LineDirection d, LineCoordinates v, LineCoordinates p);
// Its inverse.
void add_line_difference(LineDirection d, int64_t px, int64_t py, std::array<int64_t, 2> difference, int64_t* x,
                         int64_t* y);

// The vector on line d with the line coordinate `along` of v (v itself without a line or
// when that vector lies beyond `limit`).
MotionVector onto_line(LineDirection d, MotionVector v, int limit);

// The coded difference of `vector` from `predictor` towards reference r at macroblock
// (mx, my): in x and y, or along and across the reference's epipolar line there
// (docs/codec.md 3.8). Components may exceed 16 bits.
std::array<int64_t, 2> vector_difference(const FrameState& s, int r, int mx, int my, MotionVector vector,
                                         MotionVector predictor);

// The vector whose difference from `predictor` is `difference`; false when it lies
// outside the range of 10.3.
bool add_vector_difference(const FrameState& s, int r, int mx, int my, MotionVector predictor,
                           std::array<int64_t, 2> difference, MotionVector* vector);

void build_prediction(const FrameState& s, int mx, int my, MacroblockMode mode,
                      const std::array<MotionVector, 2>& vectors, MacroblockPrediction* out);

void build_warp_prediction(const FrameState& s, int mx, int my, MacroblockMode mode, MacroblockPrediction* out);

// The translational prediction of every partition of `motion` (docs/codec.md, 5.6).
void build_partition_prediction(const FrameState& s, int mx, int my, const PartitionMotion& motion,
                                MacroblockPrediction* out);

// Partition k's prediction from one reference: luma and both chroma planes, as
// intermediates written into the partition's rectangle of `out`.
void predict_partition(const FrameState& s, int mx, int my, const PartitionRect& rect, int reference,
                       MotionVector vector, MacroblockIntermediate* out);

// What an inter or skipped macroblock's prediction is built from (mode kIntra: none).
struct PredictionRecord {
  MacroblockMode mode = MacroblockMode::kIntra;  // the prediction's mode, never kSkipped
  bool warp = false;
  std::array<MotionVector, 2> vectors{};
  PartitionMotion motion;
};

// Per reference, the cube-border edges (FaceEdge bits, codec/common/cube_padding.h) whose
// samples the prediction of macroblock (mx, my) reads, by the read windows of
// motion_compensation.h (docs/codec.md 5.7); {0, 0} without a border.
std::array<uint8_t, 2> border_edges_read(const FrameState& s, int mx, int my, const PredictionRecord& record);

// Whether the luma prediction of macroblock (mx, my) with this mode reads a reference
// sample outside the face (in the cube border or, without one, the edge extension).
bool prediction_leaves_face(const FrameState& s, int mx, int my, MacroblockMode mode, bool warp,
                            const std::array<MotionVector, 2>& vectors);

// Prediction plus the dequantized, inverse transformed levels of one residual block of
// quantizer.size, clipped to 8 bits.
void reconstruct_residual_block(const Quantizer& quantizer, const int16_t* levels, const uint8_t* prediction,
                                int prediction_stride, uint8_t* out, int out_stride);

// Copies macroblock (mx, my) of the reconstructed planes into `out`.
void copy_macroblock_out(const FrameState& s, int mx, int my, MacroblockPrediction* out);

// Stores a finished macroblock: pixels, per-block coded flags and info; an inter or
// skipped one also enters the intra neighbour state (an intra one is there already).
void commit_macroblock(FrameState& s, int mx, int my, const MacroblockInfo& info,
                       const MacroblockPrediction& reconstruction, uint8_t coded_mask);

// Whether `image` is width x height with 4:2:0 planes of matching size.
bool consistent_image(const ImageYCbCr420& image, int width, int height);

// Copies the visible part of the reconstructed planes into `out`.
void crop_output(const FrameState& s, ImageYCbCr420* out);

}  // namespace svc::codec::bframe
