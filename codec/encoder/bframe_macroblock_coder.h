// SPDX-License-Identifier: BSD-2-Clause
// The macroblock decisions of the B-face encoder (internal to codec/encoder): every
// option of a macroblock (skip, forward, backward, bidirectional, their partitions and
// warps, intra) priced as SSD + lambda * estimated bits, with bits estimated from the
// current adaptive probabilities, and the chosen one written. One class, its members
// defined by job:
//   bframe_mode_decision.cc    the mode decision: which option a macroblock takes
//   bframe_motion_search.cc    vectors by SAD plus vector bits, predictors, candidates
//   bframe_residual_search.cc  the residual of an option: transform sizes and levels
//   bframe_macroblock_writer.cc  the chosen option's syntax
// bframe_encoder.cc runs them over a frame.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "codec/common/bframe_state.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/bframe_syntax_writer.h"
#include "codec/encoder/distortion.h"
#include "codec/encoder/intra_search.h"
#include "codec/encoder/range_encoder.h"
#include "codec/encoder/search_planes.h"

namespace svc::codec::bframe {

// An intra macroblock's blocks: its luma macroblock, its Cb and its Cr block.
struct IntraChoice {
  intra::MacroblockChoice luma;
  intra::BlockChoice cb, cr;
};

// The coded flags (bit b for block b of docs/codec.md 4.2) of an intra macroblock: an
// 8x8 luma block is coded when a transform block covering it has levels.
uint8_t intra_coded_mask(const IntraChoice& choice);

// One evaluated macroblock option.
struct MacroblockChoice {
  MacroblockMode mode = MacroblockMode::kIntra;
  bool warp = false;                                // inter or skip: predicted by warping
  std::array<MotionVector, 2> vectors{};            // used vectors; predictors for unused references
  std::array<std::array<int16_t, 64>, 6> levels{};  // inter only
  // Inter only: whether the luma residual is one 16x16 block, and its levels.
  bool luma_16x16 = false;
  std::array<int16_t, 256> luma_levels{};
  // Inter only: per luma 8x8 block, whether its levels are four 4x4 blocks (16 each).
  std::array<bool, 4> split{};
  // Intra only: the blocks as the intra frame's search chose them.
  std::unique_ptr<IntraChoice> intra;
  uint8_t coded_mask = 0;  // inter: coded block pattern; intra: 8x8 blocks with levels
  // Inter only: the partitions, with their modes and vectors when split.
  PartitionMotion motion;
  MacroblockPrediction reconstruction;
  int skip_index = 0;   // skipped by translation: the predictor index
  float side_bits = 0;  // inter: every bit but the residual's
  double cost = 0;
};

struct PaddedSource {
  std::array<std::vector<uint8_t>, 3> planes;
  std::array<int, 3> strides{};
};

// residual = source - prediction over a width x width block, packed rows.
void subtract_prediction(const uint8_t* source, int source_stride, const uint8_t* prediction, int prediction_stride,
                         int width, int16_t* residual);

// Samples of edge extension of the motion search's planes; vectors reaching further are
// priced exactly.
constexpr int kSearchMargin = 32;
// The share of a new warp node's bits charged to the macroblock that sends it.
constexpr float kNewNodeShare = 0.5f;

constexpr PartitionRect kWholeMacroblock{};

// Candidates of one macroblock and its 8x8 blocks towards one reference.
struct MacroblockHints {
  const CandidateList* macroblock = nullptr;
  std::array<const CandidateList*, 4> blocks{};
};

int sad_rect(const uint8_t* source, int source_stride, const uint8_t* prediction, const PartitionRect& rect);

// The vectors a search has priced: a small open-addressed set emptied in O(1) by moving
// to the next generation.
class VectorSet {
 public:
  void clear() {
    if (++generation_ == 0) {  // wrapped: forget every stamp
      stamps_.fill(0);
      generation_ = 1;
    }
  }
  // Adds v; false when it was already there.
  bool insert(MotionVector v) {
    const uint32_t key = (static_cast<uint32_t>(static_cast<uint16_t>(v.x)) << 16) | static_cast<uint16_t>(v.y);
    for (uint32_t slot = (key * 2654435761u) >> 24;; slot = (slot + 1) % kSlots) {
      if (stamps_[slot] != generation_) {
        stamps_[slot] = generation_;
        keys_[slot] = key;
        return true;
      }
      if (keys_[slot] == key) return false;
    }
  }

 private:
  // More than a search ever prices (candidates, predictors, zero, two rings of 8).
  static constexpr uint32_t kSlots = 256;
  std::array<uint32_t, kSlots> keys_{};
  std::array<uint32_t, kSlots> stamps_{};
  uint32_t generation_ = 1;
};

// The first `limit` candidates of a partition: the lists of the 8x8 blocks it covers,
// interleaved by rank without duplicates, so each block's best vectors come first.
// `listed` is cleared and left holding the candidates returned.
CandidateList partition_candidates(const MacroblockHints& hints, const PartitionRect& rect, size_t limit,
                                   VectorSet& listed);

// Whether the depth-derived motion differs across the macroblock's 8x8 blocks (their most
// frequent vectors differ), or, without block lists, the macroblock has several vectors.
bool motion_varies(const MacroblockHints& hints);

// A macroblock's vector predictors towards one reference in the line coordinates of its
// epipolar line there (docs/codec.md 3.8), for pricing vectors against them.
struct LinePredictors {
  int count = 0;   // listed, as the predictor index is coded
  int usable = 0;  // those the encoder may choose
  LineDirection line;
  std::array<LineCoordinates, kMaxVectorPredictors> coordinates{};
};

// Candidates priced per list at most, whatever BFrameParams::max_candidates says (the
// VectorSet's room).
constexpr int kMaxCandidates = 128;

// A split partition whose screening cost (luma SAD + sqrt(lambda) x side bits) exceeds
// the best 16x16 option's by this factor is not coded: it practically never wins
// (docs/encoder.md 5, "Partitions").
constexpr double kPartitionScreenMargin = 1.2;

// The intra frame's tools an intra macroblock uses (docs/encoder.md 5).
CodingParams intra_tools(const BFrameParams& params);

// The macroblock coder of one frame: chooses each macroblock's option and writes it.
class BFrameMacroblockCoder {
 public:
  BFrameMacroblockCoder(FrameState& state, const PaddedSource& source, const BFrameParams& params,
                        const std::array<const SearchPlanes*, 2>& search);

  MacroblockChoice choose(int mx, int my, const std::array<MacroblockHints, 2>& hints, BFrameStats* stats);

  // Writes the chosen option and stores it in the frame state.
  void write(RangeEncoder& encoder, const MacroblockChoice& choice);

 private:
  void write_vectors(RangeEncoder& encoder, const MacroblockChoice& choice, MacroblockInfo* info);

  // The difference of `vector` from `predictor` (3.8), counted into the neighbour context.
  void write_difference(RangeEncoder& encoder, const int (&contexts)[2], int reference, MotionVector vector,
                        MotionVector predictor, MacroblockInfo* info);

  // Each partition's direction and vector differences; the last vector per reference is
  // the one the macroblock leaves for its neighbours' predictors.
  void write_partition_vectors(RangeEncoder& encoder, const PartitionMotion& motion, MacroblockInfo* info);

  // Warped predictions of the current macroblock, made once per reference and reused by
  // screening, skip and inter evaluation (the corner nodes do not change within it).
  struct WarpCache {
    bool luma = false, chroma = false;
    MacroblockIntermediate prediction;
  };

  const MacroblockIntermediate& warped_prediction(int reference, bool with_chroma);

  // build_warp_prediction from the cache.
  void build_cached_warp_prediction(MacroblockMode mode, MacroblockPrediction* out);

  // Codes the missing nodes of every reference `mode` reads and stores the centre vectors.
  void write_warp_nodes(RangeEncoder& encoder, MacroblockMode mode, MacroblockInfo* info);

  // The bits of the nodes a warp must send, weighted by kNewNodeShare: a node sent now
  // also serves the later macroblocks that share the corner, and charging it whole to
  // the first one keeps a face from ever starting to warp.
  float warp_nodes_bits(MacroblockMode mode);

  void compute_visible();

  const uint8_t* source_block(int b) const;

  int64_t block_error(int b, const uint8_t* samples) const;

  float vector_bits(int reference, MotionVector vector) const;

  float vector_bits(int reference, MotionVector vector, const VectorPredictors& predictors) const;

  float vector_bits(MotionVector vector, const LinePredictors& predictors) const;

  // The usable predictors in the line coordinates of this macroblock's line towards
  // `reference`: worked out once for the many vectors a search prices against them.
  LinePredictors line_predictors(int reference, const VectorPredictors& predictors) const;

  // The index of the predictor that codes `vector` in the fewest bits (the first of
  // equal ones), and those bits, index included.
  int cheapest_predictor(MotionVector vector, const LinePredictors& predictors, float* bits) const;

  // Of `count` predictors, those the encoder may choose (the first only without the tool).
  int usable_predictors(int count) const;

  // Codes the index of the predictor `vector` is cheapest from and returns that predictor.
  MotionVector write_predictor_index(RangeEncoder& encoder, int reference, MotionVector vector,
                                     const VectorPredictors& predictors);

  // Luma SAD of the prediction of `rect` from `reference` with vector v: on the search
  // planes (quarter positions approximated) where they reach, else exact.
  int rect_sad(int reference, const PartitionRect& rect, MotionVector v) const;

  // Within the range and, without quarter-pel vectors, on a half-pel position (odd
  // components away from zero).
  MotionVector clamp_vector(MotionVector v) const;

  // Best vector for `rect` towards one reference by SAD + lambda * vector bits over the
  // supplied candidates and the predictor (the zero vector too when no candidate is given).
  MotionVector search_reference(int reference, const PartitionRect& rect, const VectorPredictors& predictors,
                                std::span<const MotionVector> list, BFrameStats* stats);

  // The chosen option's residual quantized again with RDOQ: its levels, coded mask,
  // reconstruction and cost change; its prediction and side information do not.
  void requantize(MacroblockChoice* choice);

  // A translational skip tries each predictor index.
  void evaluate_skip(MacroblockMode mode, bool warp, MacroblockChoice* out);
  // Whether a skip this cheap ends the macroblock's search (BFrameParams::skip_exit_bits).
  bool skip_ends_search(double skip_cost) const;
  // Adds a 16x16 luma prediction's error and pixels to the statistics' screened
  // prediction of intra (coded_inter false) or other macroblocks.
  void count_screened_prediction(const uint8_t* prediction, bool coded_inter, BFrameStats* stats) const;

  int64_t prediction_error(const MacroblockPrediction& prediction) const;

  void evaluate_inter(MacroblockMode mode, bool warp, const std::array<MotionVector, 2>& best,
                      MacroblockChoice* out);

  // Each 8x8 block's residual, kept where it lowers the cost; sets the levels, coded
  // mask, reconstruction and cost (with `bits` of side information).
  void code_residual(const MacroblockPrediction& prediction, float bits, MacroblockChoice* out);

  // The whole luma residual as one 16x16 block, coded where that lowers the cost; its
  // levels go to out->luma_levels. Adds the error and bits (coded flag and levels).
  // Returns whether it is coded.
  bool code_luma_16x16(const MacroblockPrediction& prediction, MacroblockChoice* out, uint8_t* reconstruction,
                       int64_t* distortion, float* bits);

  // Luma 8x8 block b's `residual` as four 4x4 blocks in raster order: their levels (16
  // each) and the reconstruction from `pred`, 8 samples a row. Adds the blocks' bits
  // (coded-block flags and levels) to *bits; returns the squared error.
  int64_t code_quarters(const int16_t* residual, const uint8_t* pred, int stride, int b, int16_t* levels,
                        uint8_t* reconstruction, float* bits);

  // 8x8 block b's residual, coded where that lowers the cost (a luma block, when the
  // frame codes transform sizes, as one 8x8 block or four 4x4 ones): its levels, split
  // flag, coded flag and reconstruction; adds its error and bits.
  void code_block(const MacroblockPrediction& prediction, int b, uint8_t* local_coded, MacroblockChoice* out,
                  int64_t* distortion, float* bits);

  // A split macroblock: per partition in coding order, the best vector per reference
  // from the partition's own candidates (and the 16x16 choice), then the direction by
  // SAD + side bits; the whole then by rate-distortion cost.
  // `best_screened`: the best 16x16 inter option's screening cost (kPartitionScreenMargin).
  void evaluate_partitioned(Partition partition, const std::array<MacroblockHints, 2>& hints,
                            const std::array<MotionVector, 2>& macroblock_best, double best_screened,
                            BFrameStats* stats, MacroblockChoice* out);

  // The intra frame's search (docs/codec.md 3.2) over the macroblock's luma, then its Cb
  // and Cr block, predicting from the reconstructed neighbours; the choice is
  // reconstructed in place in the frame's planes (the only option that writes there
  // before the commit) and marked in the intra neighbour state.
  // `budget`: the cost to beat (the best option so far). Past it the luma search skips
  // part of its partitions (MacroblockEncoder::choose_luma), and a luma costing that
  // much alone leaves chroma unsearched and out->cost infinite.
  void evaluate_intra(MacroblockChoice* out, double budget = std::numeric_limits<double>::infinity());

  FrameState& s_;
  const PaddedSource& source_;
  const std::array<const SearchPlanes*, 2> search_;  // per reference; null: exact SADs
  double lambda_ = 0, lambda_sad_ = 0;
  // From BFrameParams, whose fields hold the defaults.
  const bool refine_;
  const bool quarter_pel_;
  const int full_evaluations_;
  const int max_candidates_;
  const bool rdoq_;
  // Whether the residuals being priced use RDOQ: only the winner's, re-quantized once the
  // mode decision (made with plain quantization) is over.
  bool quantize_rd_ = false;
  const bool partitions_;
  const bool intra_;              // intra macroblocks tried
  const bool full_split_search_;  // 4x4 trials also where the 8x8 transform keeps no level
  const bool vector_predictors_;
  const bool keep_intra_partition_;  // the RDOQ pass of an intra winner keeps its partition
  const double skip_exit_bits_;      // BFrameParams::skip_exit_bits
  int mx_ = 0, my_ = 0;
  std::array<MotionVector, 2> predictors_{};  // the first of each list
  std::array<VectorPredictors, 2> predictor_lists_{};
  std::array<int, 6> visible_w_{}, visible_h_{};
  int visible_luma_width() const { return visible_w_[0] + visible_w_[1]; }
  int visible_luma_height() const { return visible_h_[0] + visible_h_[2]; }
  VectorSet tried_;
  VectorSet partition_listed_;             // partition_candidates' duplicates check
  std::array<MvdCostTable, 2> mvd_costs_;  // per component, for the current macroblock
  std::array<WarpCache, 2> warp_cache_;
  // The intra frame's macroblock search at the frame's qindex and lambda: plain
  // quantization, and RDOQ for the winner.
  std::unique_ptr<intra::MacroblockEncoder> intra_search_, intra_rd_search_;
};

}  // namespace svc::codec::bframe
