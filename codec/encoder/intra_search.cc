// SPDX-License-Identifier: BSD-2-Clause
// The intra mode decision: for each luma macroblock its partition, and for each block
// its prediction mode, transform type and levels, by rate-distortion cost; chroma blocks
// in pairs (a Cb block's mode with its Cr block's cost), CfL against the regular modes.
// Used by intra frames and by B-face intra macroblocks.
#include "codec/encoder/intra_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "codec/common/dsp/dsp.h"
#include "codec/common/intra_planes.h"
#include "codec/encoder/bit_cost.h"
#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/distortion.h"
#include "codec/encoder/dsp/encoder_dsp.h"
#include "codec/encoder/intra_syntax_writer.h"
#include "codec/encoder/rate_distortion.h"
#include "codec/encoder/rdoq.h"

namespace svc::codec {

int cfl_least_squares_alpha(const int16_t* ac, const uint8_t* source, ptrdiff_t stride, int dc) {
  int64_t cross = 0, energy = 0;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const int a = ac[8 * y + x];
      cross += a * (source[y * stride + x] - dc);
      energy += a * a;
    }
  }
  if (energy == 0) return 0;
  // prediction - dc = alpha * ac / 32
  const double alpha = 32.0 * static_cast<double>(cross) / static_cast<double>(energy);
  return std::clamp(static_cast<int>(std::lround(alpha)), -kCflMaxAlpha, kCflMaxAlpha);
}

namespace intra {
namespace {

// Encoder only: a set of modes to rank (all allowed ones when not given).
struct ModeSet {
  std::array<uint8_t, kIntraModes> modes{};
  int count = 0;
  void add(int mode) {
    if (std::find(modes.begin(), modes.begin() + count, mode) == modes.begin() + count)
      modes[static_cast<size_t>(count++)] = static_cast<uint8_t>(mode);
  }
};

// Hadamard SATD of a block of `size`: the 4x4 or 8x8 kernel, a larger block as the sum
// over its 8x8 tiles, or its 4x4 tiles when a side is 4.
int block_satd(const uint8_t* source, int stride, const uint8_t* prediction, TransformSize size) {
  const dsp::EncoderDspTable& dsp = dsp::get_encoder_dsp();
  if (size == TransformSize::k4x4) return dsp.satd_4x4(source, stride, prediction);
  if (size == TransformSize::k8x8) return dsp.satd_8x8(source, stride, prediction);
  if (size == TransformSize::k16x16) return dsp.satd_16x16(source, stride, prediction);
  const int w = transform_width(size), h = transform_height(size), t = std::min({w, h, 8});
  const auto satd = t == 8 ? dsp.satd_8x8 : dsp.satd_4x4;
  int sum = 0;
  uint8_t tile[64];
  for (int y = 0; y < h; y += t) {
    for (int x = 0; x < w; x += t) {
      for (int row = 0; row < t; ++row) std::copy_n(prediction + w * (y + row) + x, t, tile + t * row);
      sum += satd(source + y * stride + x, stride, tile);
    }
  }
  return sum;
}

// Encoder only: chooses a block's mode in two steps, as libaom and x265 do: the SATD of
// every mode's residual plus a rate term keeps a few candidates, then each is
// transformed, quantized and costed as SSE + lambda * bits with the current contexts
// (its levels dropped when the prediction alone costs less).
class BlockSearch {
 public:
  BlockSearch(const SizedQuantizers& quantizers, const CodingParams& params, float lambda)
      : quantizers_(quantizers),
        modes_(params.directional_intra ? kIntraModes : 2),
        rd_search_(params.rd_intra_search),
        coarse_(params.coarse_mode_search),
        rdoq_(params.rdoq),
        satd_lambda_(std::max(1, static_cast<int>(4 * quantizer_scale(quantizers[0].qindex) + 0.5))),
        lambda_(lambda) {}

  float lambda() const { return lambda_; }
  // SATD units per bit.
  int satd_lambda() const { return satd_lambda_; }

  // The first stage alone: the least SATD + rate of the block's modes (`ranked`, else
  // every allowed one) and that mode.
  std::pair<int, int> estimate(const uint8_t* source, int stride, const uint8_t* edge, TransformSize size,
                               const IntraModeContexts& contexts, const ModeCandidates& candidates,
                               const ModeSet* ranked) const {
    std::array<std::pair<int, int>, kIntraModes> costs;
    const int count = score_modes(source, stride, edge, size, contexts, candidates, ranked, costs);
    return *std::min_element(costs.begin(), costs.begin() + count);
  }

  // Chooses the mode and levels of a block of `size` and returns its cost.
  // `candidates` null: the mode is fixed (a Cr block takes its Cb block's). `ranked`: the
  // modes to rank, else every allowed one. `prefix_bits`: bits coded before the mode (a
  // Cb block's CfL flag).
  float choose(const uint8_t* source, int stride, const uint8_t* edge, TransformSize size,
               const PlaneContexts& contexts, const ModeCandidates* candidates, int cbf_context,
               const ModeSet* ranked, BlockChoice* best, float prefix_bits = 0) const {
    std::array<int, kSearchedModes> searched;
    searched.fill(-1);
    searched[0] = best->mode;  // a fixed mode is the only one searched
    if (candidates != nullptr)
      searched = preselect(source, stride, edge, size, contexts.modes, *candidates, ranked);
    float best_cost = std::numeric_limits<float>::max(), best_bits = 0;
    for (int mode : searched) {
      if (mode < 0) continue;
      trial_.mode = mode;
      trial_.cfl_alpha = 0;
      const float mode_bits =
          prefix_bits + (candidates != nullptr ? intra_mode_bits(contexts.modes, size, *candidates, mode) : 0);
      intra_predictor(size)(edge, mode, trial_.prediction);
      const float cost =
          evaluate(source, stride, size, contexts, cbf_context, mode_bits, TransformType::kDctDct, &trial_);
      if (cost < best_cost) {
        best_cost = cost;
        best_bits = mode_bits;
        copy_choice(trial_, size, best);
      }
    }
    return choose_transform_type(source, stride, size, contexts, cbf_context, best_bits, best, best_cost);
  }

  // CfL for an 8x8 chroma block with luma AC `ac`: the least-squares alpha and its two
  // neighbours (never 0 for Cb), by rate-distortion cost. Returns the cost.
  float choose_cfl(const uint8_t* source, int stride, const uint8_t* edge, const int16_t* ac,
                   const PlaneContexts& contexts, ChromaPlane plane, int cb_alpha, int cbf_context,
                   BlockChoice* best, float prefix_bits = 0) const {
    const int dc = dc_prediction_8x8(edge);
    const int fit = cfl_least_squares_alpha(ac, source, stride, dc);
    float best_cost = std::numeric_limits<float>::max(), best_bits = 0;
    for (int alpha = fit - 1; alpha <= fit + 1; ++alpha) {
      if (alpha < -kCflMaxAlpha || alpha > kCflMaxAlpha || (plane == ChromaPlane::kCb && alpha == 0)) continue;
      trial_.mode = kCflMode;
      trial_.cfl_alpha = alpha;
      predict_cfl(ac, dc, alpha, trial_.prediction);
      const float bits = prefix_bits + cfl_alpha_bits(contexts.cfl, plane, cb_alpha, alpha);
      const float cost =
          evaluate(source, stride, kChromaSize, contexts, cbf_context, bits, TransformType::kDctDct, &trial_);
      if (cost < best_cost) {
        best_cost = cost;
        best_bits = bits;
        copy_choice(trial_, kChromaSize, best);
      }
    }
    return choose_transform_type(source, stride, kChromaSize, contexts, cbf_context, best_bits, best, best_cost);
  }

  static void copy_choice(const BlockChoice& from, TransformSize size, BlockChoice* to) {
    to->mode = from.mode;
    to->cfl_alpha = from.cfl_alpha;
    to->coded = from.coded;
    to->transform_type = from.transform_type;
    std::copy_n(from.prediction, transform_area(size), to->prediction);
    std::copy_n(from.levels, transform_area(size), to->levels);
  }

 private:
  static constexpr int kSearchedModes = 3;

  std::array<int, kSearchedModes> preselect(const uint8_t* source, int stride, const uint8_t* edge,
                                            TransformSize size, const IntraModeContexts& contexts,
                                            const ModeCandidates& candidates, const ModeSet* ranked) const {
    std::array<std::pair<int, int>, kIntraModes> costs;
    const int count = score_modes(source, stride, edge, size, contexts, candidates, ranked, costs);
    // 4x4 blocks are many and each matters little: the best by SATD alone (a second
    // mode gains little for much time: docs/bench.md, "Figures behind code constants").
    const int kept = rd_search_ && size != TransformSize::k4x4 ? std::min(kSearchedModes, count) : 1;
    std::partial_sort(costs.begin(), costs.begin() + kept, costs.begin() + count);
    std::array<int, kSearchedModes> searched;
    searched.fill(-1);
    for (int i = 0; i < kept; ++i) searched[static_cast<size_t>(i)] = costs[static_cast<size_t>(i)].second;
    return searched;
  }

  // Scores the modes of `ranked` (else every allowed one, coarse to fine where set) by
  // SATD + satd_lambda_ * mode bits into costs[0..count); returns count.
  int score_modes(const uint8_t* source, int stride, const uint8_t* edge, TransformSize size,
                  const IntraModeContexts& contexts, const ModeCandidates& candidates, const ModeSet* ranked,
                  std::array<std::pair<int, int>, kIntraModes>& costs) const {
    const IntraPredictor predict = intra_predictor(size);
    uint8_t prediction[kMaxTransformArea];
    int count = 0;
    auto score = [&](int mode) {
      predict(edge, mode, prediction);
      costs[static_cast<size_t>(count++)] = {
          block_satd(source, stride, prediction, size) +
              static_cast<int>(satd_lambda_ * intra_mode_bits(contexts, size, candidates, mode) + 0.5f),
          mode};
    };
    if (ranked != nullptr) {
      for (int i = 0; i < ranked->count; ++i) score(ranked->modes[static_cast<size_t>(i)]);
    } else if (coarse_ && modes_ == kIntraModes) {
      score_coarse(candidates, score, costs, count);
    } else {
      for (int mode = 0; mode < modes_; ++mode) score(mode);
    }
    return count;
  }

  // Scores planar, DC, the most probable modes and every fourth angular mode, then the
  // two angular neighbours on each side of the best angular one.
  template <class Score>
  static void score_coarse(const ModeCandidates& candidates, Score& score,
                           const std::array<std::pair<int, int>, kIntraModes>& costs, const int& count) {
    ModeSet scored;
    auto once = [&](int mode) {
      const int before = scored.count;
      scored.add(mode);
      if (scored.count != before) score(mode);
    };
    once(kPlanarMode);
    once(kDcMode);
    for (int mode : candidates) once(mode);
    for (int mode = 2; mode < kIntraModes; mode += 4) once(mode);
    std::pair<int, int> best{std::numeric_limits<int>::max(), -1};
    for (int i = 0; i < count; ++i) {
      if (costs[static_cast<size_t>(i)].second >= 2) best = std::min(best, costs[static_cast<size_t>(i)]);
    }
    for (int offset : {-2, -1, 1, 2}) {
      const int mode = best.second + offset;
      if (best.second >= 2 && mode >= 2 && mode < kIntraModes) once(mode);
    }
  }

  // The best block's levels under each other transform type (where the contexts enable
  // types and the block has levels; the mode stays), by the same cost. Returns the cost.
  float choose_transform_type(const uint8_t* source, int stride, TransformSize size, const PlaneContexts& contexts,
                              int cbf_context, float mode_bits, BlockChoice* best, float best_cost) const {
    if (!contexts.types.enabled || !best->coded) return best_cost;
    trial_.mode = best->mode;
    trial_.cfl_alpha = best->cfl_alpha;
    std::copy_n(best->prediction, transform_area(size), trial_.prediction);
    for (int t = 1; t < kTransformTypes; ++t) {
      const float cost =
          evaluate(source, stride, size, contexts, cbf_context, mode_bits, static_cast<TransformType>(t), &trial_);
      if (cost < best_cost && trial_.coded) {
        best_cost = cost;
        copy_choice(trial_, size, best);
      }
    }
    return best_cost;
  }

  // The levels and cost of trial->prediction with transform type `type`.
  float evaluate(const uint8_t* source, int stride, TransformSize size, const PlaneContexts& plane_contexts,
                 int cbf_context, float mode_bits, TransformType type, BlockChoice* trial) const {
    const BlockContextSet& contexts = plane_contexts.residual;
    const Quantizer& quantizer = quantizer_for(quantizers_, size);
    const int area = transform_area(size), w = transform_width(size), h = transform_height(size);
    int16_t residual[kMaxTransformArea], coefficients[kMaxTransformArea];
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x)
        residual[w * y + x] = static_cast<int16_t>(source[y * stride + x] - trial->prediction[w * y + x]);
    }
    float levels_bits = 0;
    trial->coded = transform_quantize_block_rd(quantizer, residual, rdoq_, contexts, cbf_context, lambda_,
                                               trial->levels, type, &levels_bits) > 0;
    trial->transform_type = trial->coded ? type : TransformType::kDctDct;
    const float uncoded_cost = static_cast<float>(squared_error(source, stride, trial->prediction, w, w, h)) +
                               lambda_ * (mode_bits + uncoded_block_bits(contexts, cbf_context));
    if (!trial->coded) return uncoded_cost;
    uint8_t reconstructed[kMaxTransformArea];
    dequantize_block(quantizer, trial->levels, coefficients);
    reconstruct_block(trial->prediction, coefficients, type, size, reconstructed, w);
    const float coded_cost =
        static_cast<float>(squared_error(source, stride, reconstructed, w, w, h)) +
        lambda_ * (mode_bits + levels_bits +
                   transform_type_bits(plane_contexts.types, quantizer.size, trial->mode, type));
    if (coded_cost <= uncoded_cost || !rd_search_) return coded_cost;
    trial->coded = false;
    trial->transform_type = TransformType::kDctDct;
    std::fill_n(trial->levels, area, int16_t{0});
    return uncoded_cost;
  }

  const SizedQuantizers& quantizers_;
  int modes_;
  bool rd_search_;  // else the SATD's best mode, its levels as quantized
  bool coarse_;     // angular modes ranked coarse to fine
  bool rdoq_;
  int satd_lambda_;  // SATD units per bit, tuned on the photographic scenes
  float lambda_;     // SSE per bit, tuned on the photographic scenes
  mutable BlockChoice trial_;
};

// Encoder only: codes one block of the plane during the search: chooses it, writes its
// reconstruction into the plane and marks it in `state`. Returns its cost.
class PlaneSearch {
 public:
  PlaneSearch(const BlockSearch& search, const SizedQuantizers& quantizers, const PlaneContexts& contexts,
              const uint8_t* source, uint8_t* recon, int stride)
      : search_(search),
        quantizers_(quantizers),
        contexts_(contexts),
        source_(source),
        recon_(recon),
        stride_(stride) {}

  float code_block(PlaneState& state, int x0, int y0, TransformSize size, const ModeSet* ranked, bool fixed_mode,
                   BlockChoice* choice) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(recon_, stride_, x0, y0, size, state.availability(x0, y0, size), edge);
    const auto candidates = state.candidates(x0, y0);
    const size_t offset = static_cast<size_t>(y0) * stride_ + x0;
    const float cost = search_.choose(source_ + offset, stride_, edge, size, contexts_,
                                      fixed_mode ? nullptr : &candidates, state.coded_block_context(x0, y0), ranked,
                                      choice);
    finish_block(state, x0, y0, size, *choice);
    return cost;
  }

  // An 8x8 chroma block in a regular mode, not yet reconstructed: a Cb block's best
  // (`cb` null), or a Cr block in its Cb block's mode.
  float choose_chroma_regular(const PlaneState& state, int x0, int y0, const ChromaMode* cb,
                              BlockChoice* choice) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(recon_, stride_, x0, y0, kChromaSize, state.availability(x0, y0, kChromaSize), edge);
    const uint8_t* source = source_ + static_cast<size_t>(y0) * stride_ + x0;
    const int cbf_context = state.coded_block_context(x0, y0);
    if (cb != nullptr) {
      choice->mode = cb->mode;
      return search_.choose(source, stride_, edge, kChromaSize, contexts_, nullptr, cbf_context, nullptr, choice);
    }
    const auto candidates = state.candidates(x0, y0);
    return search_.choose(source, stride_, edge, kChromaSize, contexts_, &candidates, cbf_context, nullptr, choice,
                          cfl_flag_bits(contexts_.cfl, state.cfl_context(x0, y0), false));
  }

  // An 8x8 chroma block in CfL with luma AC `ac`, not yet reconstructed: a Cb block
  // (`cb` null) or a Cr block whose Cb block uses CfL.
  float choose_chroma_cfl(const PlaneState& state, int x0, int y0, const int16_t* ac, const ChromaMode* cb,
                          BlockChoice* choice) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(recon_, stride_, x0, y0, kChromaSize, state.availability(x0, y0, kChromaSize), edge);
    const uint8_t* source = source_ + static_cast<size_t>(y0) * stride_ + x0;
    const int cbf_context = state.coded_block_context(x0, y0);
    if (cb != nullptr) {
      return search_.choose_cfl(source, stride_, edge, ac, contexts_, ChromaPlane::kCr, cb->alpha, cbf_context,
                                choice);
    }
    return search_.choose_cfl(source, stride_, edge, ac, contexts_, ChromaPlane::kCb, 0, cbf_context, choice,
                              cfl_flag_bits(contexts_.cfl, state.cfl_context(x0, y0), true));
  }

  // Writes the chosen block's reconstruction into the plane and marks it.
  void finish_block(PlaneState& state, int x0, int y0, TransformSize size, const BlockChoice& choice) const {
    const size_t offset = static_cast<size_t>(y0) * stride_ + x0;
    int16_t coefficients[kMaxTransformArea];
    if (choice.coded) dequantize_block(quantizer_for(quantizers_, size), choice.levels, coefficients);
    reconstruct_block(choice.prediction, choice.coded ? coefficients : nullptr, choice.transform_type, size,
                      recon_ + offset, stride_);
    state.mark(x0, y0, size, choice.mode, choice.coded);
  }

  float split_bit_cost(const AdaptiveBit& bit, int value) const { return search_.lambda() * bit_cost(bit, value); }

  // The first stage's cost of the block of `size` at (x0, y0) and its best mode, open
  // loop: predicted from the source around it, since the blocks before it in the
  // macroblock are not reconstructed yet.
  std::pair<int, int> estimate_block(const PlaneState& state, int x0, int y0, TransformSize size,
                                     const ModeSet* ranked) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(source_, stride_, x0, y0, size, state.availability(x0, y0, size), edge);
    return search_.estimate(source_ + static_cast<size_t>(y0) * stride_ + x0, stride_, edge, size, contexts_.modes,
                            state.candidates(x0, y0), ranked);
  }
  // The first stage's cost of coding `value` with `bit`.
  int estimate_bit_cost(const AdaptiveBit& bit, int value) const {
    return static_cast<int>(search_.satd_lambda() * bit_cost(bit, value) + 0.5f);
  }

  void save(int x0, int y0, int size, uint8_t* out) const {
    for (int y = 0; y < size; ++y) std::copy_n(recon_ + (y0 + y) * stride_ + x0, size, out + size * y);
  }
  void restore(int x0, int y0, int size, const uint8_t* in) const {
    for (int y = 0; y < size; ++y) std::copy_n(in + size * y, size, recon_ + (y0 + y) * stride_ + x0);
  }
  const PlaneContexts& contexts() const { return contexts_; }

 private:
  const BlockSearch& search_;
  const SizedQuantizers& quantizers_;
  const PlaneContexts& contexts_;
  const uint8_t* source_;
  uint8_t* recon_;
  int stride_;
};

// Encoder only: the partition of a luma macroblock by rate-distortion cost. Four 8x8
// blocks come first, each also tried as four 4x4, two 8x4 and two 4x8 blocks when it has
// levels (a block the prediction alone serves gains nothing from splitting) and small
// blocks are allowed; then one 16x16 block whose modes are ranked among those blocks'
// and the most probable ones, two 16x8, two 8x16, four 16x4 and four 4x16 blocks
// (try_partition), the cheapest kept.
class MacroblockSearch {
 public:
  MacroblockSearch(bool transform_sizes, bool small_blocks, int rectangular_trials, int small_trials)
      : sizes_(transform_sizes),
        small_blocks_(small_blocks),
        rectangular_trials_(rectangular_trials),
        small_trials_(small_trials) {}

  // Chooses the blocks of macroblock (mbx, mby) of `plane`; returns their cost.
  // `partition`: search that partition alone (its blocks' modes, types and levels).
  float choose(const PlaneSearch& plane, PlaneState& state, int mbx, int mby, MacroblockChoice* out, float budget,
               const LumaPartition* partition) {
    plane_ = &plane;
    const int x0 = 16 * mbx, y0 = 16 * mby;
    const PlaneContexts& contexts = plane_->contexts();
    const int split_context = state.split_context(x0, y0, 16);
    state.clear(x0, y0, TransformSize::k16x16);
    const std::array<bool, kPartitionTrials> searched =
        partition != nullptr ? only(*partition, *out) : rank_partitions(state, x0, y0, split_context);
    split_.partition = kSplit16x16;
    float split_cost = plane_->split_bit_cost(contexts.split_16x16[static_cast<size_t>(split_context)], 1);
    bool over_budget = false;
    if (!searched[kSplitTrial]) {
      // The 16x16 partitions rank the modes the first stage found for the 8x8 blocks.
      for (int i = 0; i < 4; ++i)
        split_.blocks[static_cast<size_t>(i)].mode = estimated_mode_[static_cast<size_t>(i)];
      split_cost = std::numeric_limits<float>::infinity();
    }
    for (int i = 0; i < 4 && !over_budget && searched[kSplitTrial]; ++i) {
      split_cost += choose_8x8(state, x0, y0, i);
      if (i < 3 && split_cost >= budget) {
        // The split cannot beat the budget: its other 8x8 blocks are not searched (DC
        // stands in for them in the modes the whole macroblock ranks).
        for (int k = i + 1; k < 4; ++k) split_.blocks[static_cast<size_t>(block_index(k))].mode = kDcMode;
        split_cost = std::numeric_limits<float>::infinity();
        over_budget = true;
      }
    }
    if (!sizes_) {
      *out = split_;
      return split_cost;
    }
    uint8_t saved[kMaxTransformArea];
    plane_->save(x0, y0, 16, saved);
    ModeSet ranked;
    for_each_luma_block(split_.partition, [&, n = 0](int, int, TransformSize) mutable {
      ranked.add(split_.blocks[static_cast<size_t>(n++)].mode);
    });
    for (int mode : state.candidates(x0, y0)) ranked.add(mode);
    ranked.add(kPlanarMode);
    ranked.add(kDcMode);
    state.clear(x0, y0, TransformSize::k16x16);
    BlockChoice& whole = out->blocks[0];
    const float unsplit_bits = plane_->split_bit_cost(contexts.split_16x16[static_cast<size_t>(split_context)], 0);
    const auto& halves_bit = contexts.halves_16x16[static_cast<size_t>(split_context)];
    float whole_cost = std::numeric_limits<float>::infinity();
    out->partition = 0;
    // Past the budget only the 16x16 block may still come in under it.
    if (searched[kWholeTrial] || over_budget) {
      whole_cost = unsplit_bits + plane_->split_bit_cost(halves_bit, 0) +
                   plane_->code_block(state, x0, y0, TransformSize::k16x16, &ranked, false, &whole);
    }
    for (const bool vertical : {false, true}) {
      if (over_budget) break;
      const auto halves = static_cast<LumaPartition>(kHalves16x16 | (vertical ? kVerticalHalves : 0));
      const auto& strips_bit = contexts.strips[vertical ? 1 : 0];
      const float bits = unsplit_bits + plane_->split_bit_cost(halves_bit, 1) +
                         plane_->split_bit_cost(contexts.vertical_halves, vertical ? 1 : 0);
      if (searched[trial_of(halves)]) {
        try_partition(state, x0, y0, halves, bits + plane_->split_bit_cost(strips_bit, 0), &whole_cost, out);
      }
      const auto strips = static_cast<LumaPartition>(halves | kStrips);
      if (searched[trial_of(strips)]) {
        try_partition(state, x0, y0, strips, bits + plane_->split_bit_cost(strips_bit, 1), &whole_cost, out);
      }
    }
    if (whole_cost < split_cost) return whole_cost;
    plane_->restore(x0, y0, 16, saved);
    mark_blocks(state, x0, y0, split_);
    *out = split_;
    return split_cost;
  }

 private:
  // The partitions of a luma macroblock the first stage estimates.
  enum PartitionTrial {
    kSplitTrial,
    kWholeTrial,
    kHalvesTrial,
    kStripsTrial,
    kVerticalHalvesTrial,
    kVerticalStripsTrial,
    kPartitionTrials
  };
  static PartitionTrial trial_of(LumaPartition partition) {
    if (partition & kSplit16x16) return kSplitTrial;
    if (!(partition & kHalves16x16)) return kWholeTrial;
    const bool vertical = (partition & kVerticalHalves) != 0, strips = (partition & kStrips) != 0;
    return strips ? (vertical ? kVerticalStripsTrial : kStripsTrial)
                  : (vertical ? kVerticalHalvesTrial : kHalvesTrial);
  }

  // The smaller partitions of 8x8 block i, in the order of small_trials_mask_'s bits
  // (4x4, 8x4, 4x8), each with the cost of its flags at split context `context`, `price`
  // giving one flag's cost in the caller's units.
  template <class Price>
  static auto small_partitions(const PlaneContexts& c, size_t context, int i, Price price) {
    using Cost = decltype(price(c.split_8x8[context], 0));
    const Cost halves = price(c.split_8x8[context], 0) + price(c.halves_8x8[context], 1);
    return std::array<std::pair<LumaPartition, Cost>, kSmallPartitions>{
        {{split_8x8_bit(i), price(c.split_8x8[context], 1)},
         {halves_8x8_bit(i), halves + price(c.vertical_8x8, 0)},
         {static_cast<LumaPartition>(halves_8x8_bit(i) | vertical_8x8_bit(i)), halves + price(c.vertical_8x8, 1)}}};
  }

  // The first stage, where the search is narrowed (rectangular_trials_ < 4 or
  // small_trials_ < 3, with transform sizes): every partition's cost estimated open loop
  // (estimate_partitions). The 8x8 split and the 16x16 block are always searched in full,
  // of the halves and strips the rectangular_trials_ cheapest, and each coded 8x8 block
  // of the split tries its small_trials_ cheapest smaller partitions (small_trials_mask_).
  std::array<bool, kPartitionTrials> rank_partitions(const PlaneState& state, int x0, int y0, int split_context) {
    std::array<bool, kPartitionTrials> searched;
    searched.fill(true);
    small_trials_mask_.fill(7);
    if (!sizes_ || (rectangular_trials_ >= kRectangularPartitions && small_trials_ >= kSmallPartitions))
      return searched;
    const std::array<int, kPartitionTrials> cost = estimate_partitions(state, x0, y0, split_context);
    std::array<int, kRectangularPartitions> order = {kHalvesTrial, kStripsTrial, kVerticalHalvesTrial,
                                                     kVerticalStripsTrial};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cost[a] < cost[b]; });
    for (int k = std::max(0, rectangular_trials_); k < kRectangularPartitions; ++k)
      searched[static_cast<size_t>(order[k])] = false;
    for (int i = 0; i < 4; ++i) {
      const auto& small = small_cost_[static_cast<size_t>(i)];
      std::array<int, kSmallPartitions> ranked = {0, 1, 2};
      std::stable_sort(ranked.begin(), ranked.end(), [&](int a, int b) { return small[a] < small[b]; });
      int mask = 0;
      for (int k = 0; k < std::clamp(small_trials_, 0, kSmallPartitions); ++k) mask |= 1 << ranked[k];
      small_trials_mask_[static_cast<size_t>(i)] = mask;
    }
    return searched;
  }

  // Every partition's first-stage cost; sets estimated_mode_ and small_cost_.
  std::array<int, kPartitionTrials> estimate_partitions(const PlaneState& state, int x0, int y0,
                                                        int split_context) {
    const PlaneContexts& c = plane_->contexts();
    const auto context16 = static_cast<size_t>(split_context);
    const auto context8 = static_cast<size_t>(state.split_context(x0, y0, 8));
    std::array<int, kPartitionTrials> cost{};
    cost[kSplitTrial] = plane_->estimate_bit_cost(c.split_16x16[context16], 1);
    // Every 8x8 block takes the macroblock's split context: its neighbours inside the
    // macroblock are not coded yet.
    const int whole_flags =
        plane_->estimate_bit_cost(c.split_8x8[context8], 0) + plane_->estimate_bit_cost(c.halves_8x8[context8], 0);
    for (int i = 0; i < 4; ++i) {
      const int bx = x0 + 8 * (i & 1), by = y0 + 8 * (i >> 1);
      const auto [whole, mode] = plane_->estimate_block(state, bx, by, TransformSize::k8x8, nullptr);
      estimated_mode_[static_cast<size_t>(i)] = mode;
      int best = whole + whole_flags;
      small_cost_[static_cast<size_t>(i)].fill(std::numeric_limits<int>::max());
      if (small_blocks_) {
        ModeSet ranked;
        ranked.add(mode);
        ranked.add(kPlanarMode);
        ranked.add(kDcMode);
        const auto trials = small_partitions(c, context8, i, [&](const AdaptiveBit& bit, int value) {
          return plane_->estimate_bit_cost(bit, value);
        });
        for (int t = 0; t < kSmallPartitions; ++t) {
          int trial = trials[t].second;
          for_each_quarter_block(static_cast<LumaPartition>(kSplit16x16 | trials[t].first), i,
                                 [&](int x, int y, TransformSize size) {
                                   trial += plane_->estimate_block(state, x0 + x, y0 + y, size, &ranked).first;
                                 });
          small_cost_[static_cast<size_t>(i)][static_cast<size_t>(t)] = trial;
          best = std::min(best, trial);
        }
      }
      cost[kSplitTrial] += best;
    }
    const int unsplit = plane_->estimate_bit_cost(c.split_16x16[context16], 0);
    const auto& halves_bit = c.halves_16x16[context16];
    for (const LumaPartition partition :
         {LumaPartition{0}, kHalves16x16, static_cast<LumaPartition>(kHalves16x16 | kStrips),
          static_cast<LumaPartition>(kHalves16x16 | kVerticalHalves),
          static_cast<LumaPartition>(kHalves16x16 | kVerticalHalves | kStrips)}) {
      int trial = unsplit + plane_->estimate_bit_cost(halves_bit, partition != 0);
      if (partition != 0) {
        const bool vertical = (partition & kVerticalHalves) != 0;
        trial += plane_->estimate_bit_cost(c.vertical_halves, vertical) +
                 plane_->estimate_bit_cost(c.strips[vertical ? 1 : 0], (partition & kStrips) != 0);
      }
      for_each_luma_block(partition, [&](int x, int y, TransformSize size) {
        ModeSet ranked;
        for (int b = 0; b < 4; ++b) {
          if (blocks_overlap(x, y, size, 8 * (b & 1), 8 * (b >> 1), TransformSize::k8x8))
            ranked.add(estimated_mode_[static_cast<size_t>(b)]);
        }
        ranked.add(kPlanarMode);
        ranked.add(kDcMode);
        trial += plane_->estimate_block(state, x0 + x, y0 + y, size, &ranked).first;
      });
      cost[trial_of(partition)] = trial;
    }
    return cost;
  }

  // The second stage of `partition` alone, each 8x8 block of a split tried in its own
  // smaller partition only; the 16x16 blocks rank the modes of `previous`, the choice
  // being searched again.
  std::array<bool, kPartitionTrials> only(LumaPartition partition, const MacroblockChoice& previous) {
    std::array<bool, kPartitionTrials> searched{};
    for (int i = 0; i < 4; ++i) {
      const int bx = 8 * (i & 1), by = 8 * (i >> 1);
      for_each_luma_block(previous.partition, [&, n = 0](int x, int y, TransformSize size) mutable {
        const int mode = previous.blocks[static_cast<size_t>(n++)].mode;
        if (blocks_overlap(x, y, size, bx, by, TransformSize::k8x8)) estimated_mode_[static_cast<size_t>(i)] = mode;
      });
    }
    searched[trial_of(partition)] = true;
    for (int i = 0; i < 4; ++i) {
      const bool halves = (partition & halves_8x8_bit(i)) != 0;
      small_trials_mask_[static_cast<size_t>(i)] = (partition & split_8x8_bit(i)) ? 1
                                                   : halves ? ((partition & vertical_8x8_bit(i)) ? 4 : 2)
                                                            : 0;
    }
    return searched;
  }

  // 8x8 block i (Z order) of the split macroblock, or its four 4x4 blocks; fills
  // split_.blocks from index 0 on and returns the cost.
  float choose_8x8(PlaneState& state, int mb_x0, int mb_y0, int i) {
    const int x0 = mb_x0 + 8 * (i & 1), y0 = mb_y0 + 8 * (i >> 1);
    const PlaneContexts& contexts = plane_->contexts();
    const auto context = static_cast<size_t>(state.split_context(x0, y0, 8));
    const float unsplit_bits = plane_->split_bit_cost(contexts.split_8x8[context], 0);
    const int first = block_index(i);
    BlockChoice& whole = split_.blocks[static_cast<size_t>(first)];
    float best_cost = unsplit_bits + plane_->split_bit_cost(contexts.halves_8x8[context], 0) +
                      plane_->code_block(state, x0, y0, TransformSize::k8x8, nullptr, false, &whole);
    if (!sizes_ || !small_blocks_ || !whole.coded) return best_cost;
    kept_[0] = whole;
    int kept_count = 1;
    LumaPartition best = 0;
    uint8_t best_samples[64];
    plane_->save(x0, y0, 8, best_samples);
    const auto trials = small_partitions(contexts, context, i, [&](const AdaptiveBit& bit, int value) {
      return plane_->split_bit_cost(bit, value);
    });
    for (int t = 0; t < kSmallPartitions; ++t) {
      const auto& [bits, flags_cost] = trials[t];
      if (!((small_trials_mask_[static_cast<size_t>(i)] >> t) & 1)) continue;
      state.clear(x0, y0, TransformSize::k8x8);
      float cost = flags_cost;
      int n = 0;
      const auto partition = static_cast<LumaPartition>(kSplit16x16 | bits);
      for_each_quarter_block(partition, i, [&](int x, int y, TransformSize size) {
        if (cost >= best_cost) return;
        cost += plane_->code_block(state, mb_x0 + x, mb_y0 + y, size, nullptr, false,
                                   &trial_[static_cast<size_t>(n++)]);
      });
      if (cost < best_cost) {
        best_cost = cost;
        best = bits;
        std::copy_n(trial_.begin(), n, kept_.begin());
        kept_count = n;
        plane_->save(x0, y0, 8, best_samples);
        continue;
      }
      plane_->restore(x0, y0, 8, best_samples);
      mark_quarter(state, mb_x0, mb_y0, i, static_cast<LumaPartition>(kSplit16x16 | best));
    }
    split_.partition |= best;
    std::copy_n(kept_.begin(), kept_count, split_.blocks.begin() + first);
    return best_cost;
  }

  // Marks the blocks of 8x8 block i of the split partition in `state` again (their modes
  // from kept_), after a trial over them.
  void mark_quarter(PlaneState& state, int mb_x0, int mb_y0, int i, LumaPartition partition) const {
    for_each_quarter_block(partition, i, [&, n = 0](int x, int y, TransformSize size) mutable {
      const BlockChoice& b = kept_[static_cast<size_t>(n++)];
      state.mark(mb_x0 + x, mb_y0 + y, size, b.mode, b.coded);
    });
  }

  // Marks the blocks of `choice` in `state` again, after a trial over them.
  static void mark_blocks(PlaneState& state, int x0, int y0, const MacroblockChoice& choice) {
    for_each_luma_block(choice.partition, [&, n = 0](int x, int y, TransformSize size) mutable {
      const BlockChoice& b = choice.blocks[static_cast<size_t>(n++)];
      state.mark(x0 + x, y0 + y, size, b.mode, b.coded);
    });
  }

  // Tries the macroblock at (x0, y0) as `partition` (halves or strips), whose flags cost
  // `bits`, and keeps it in *out when it costs less than *best_cost. Each block's
  // trial stops once the partition costs more.
  void try_partition(PlaneState& state, int x0, int y0, LumaPartition partition, float bits, float* best_cost,
                     MacroblockChoice* out) {
    uint8_t best_samples[kMaxTransformArea];
    plane_->save(x0, y0, 16, best_samples);
    state.clear(x0, y0, TransformSize::k16x16);
    float cost = bits;
    int n = 0;
    for_each_luma_block(partition, [&](int x, int y, TransformSize size) {
      if (cost >= *best_cost) return;
      const ModeSet ranked = covered_modes(state, x0, y0, x, y, size, *out);
      cost += plane_->code_block(state, x0 + x, y0 + y, size, &ranked, false, &trial_[static_cast<size_t>(n++)]);
    });
    if (cost < *best_cost) {
      *best_cost = cost;
      out->partition = partition;
      std::copy_n(trial_.begin(), n, out->blocks.begin());
      return;
    }
    // The trial wrote only trial_: the best so far is still in `out`.
    plane_->restore(x0, y0, 16, best_samples);
    mark_blocks(state, x0, y0, *out);
  }

  // The modes a block (x, y, size within the macroblock at x0, y0) ranks: those of the
  // 8x8 blocks and of the best partition's blocks it overlaps, its most probable modes,
  // planar and DC.
  ModeSet covered_modes(const PlaneState& state, int x0, int y0, int x, int y, TransformSize size,
                        const MacroblockChoice& best) const {
    ModeSet ranked;
    auto add_overlapping = [&](const MacroblockChoice& choice) {
      for_each_luma_block(choice.partition, [&, n = 0](int bx, int by, TransformSize b) mutable {
        const int mode = choice.blocks[static_cast<size_t>(n++)].mode;
        if (blocks_overlap(x, y, size, bx, by, b)) ranked.add(mode);
      });
    };
    add_overlapping(split_);
    add_overlapping(best);
    for (int mode : state.candidates(x0 + x, y0 + y)) ranked.add(mode);
    ranked.add(kPlanarMode);
    ranked.add(kDcMode);
    return ranked;
  }

  // Index in split_.blocks of the first block of 8x8 block i, given the partitions before it.
  int block_index(int i) const {
    int index = 0;
    for (int k = 0; k < i; ++k)
      for_each_quarter_block(split_.partition, k, [&](int, int, TransformSize) { ++index; });
    return index;
  }

  const PlaneSearch* plane_ = nullptr;
  bool sizes_;
  bool small_blocks_;                    // 8x8 blocks also tried as 4x4, 8x4 and 4x8 ones
  int rectangular_trials_;               // halves and strips searched in full (of 4)
  int small_trials_;                     // smaller partitions of an 8x8 block searched in full (of 3)
  std::array<int, 4> estimated_mode_{};  // the first stage's mode of each 8x8 block
  std::array<std::array<int, kSmallPartitions>, 4> small_cost_{};  // and of its smaller partitions
  std::array<int, 4> small_trials_mask_{7, 7, 7, 7};               // the smaller partitions each 8x8 tries
  MacroblockChoice split_;
  std::array<BlockChoice, 4> trial_;  // the blocks of the partition being tried
  std::array<BlockChoice, 4> kept_;   // the best blocks of the 8x8 block being chosen
};

// The residual quantizers with the encoder's dead zone for intra residuals: narrower
// than inter residuals' (0.2), tuned on the photographic scenes.
SizedQuantizers encoder_quantizers(int qindex, ResidualMatrix matrix) {
  SizedQuantizers quantizers = residual_quantizers(qindex, matrix);
  for (Quantizer& q : quantizers) q.rounding_dc = q.rounding_ac = 0.25f;
  return quantizers;
}

}  // namespace

struct MacroblockEncoder::Impl {
  Impl(const CodingParams& params, int qindex, float lambda)
      : quantizers(encoder_quantizers(qindex, params.residual_matrix)),
        search(quantizers, params, lambda),
        macroblocks(params.transform_sizes, params.small_blocks, params.rectangular_trials, params.small_trials),
        cfl(params.cfl) {}

  SizedQuantizers quantizers;
  BlockSearch search;
  MacroblockSearch macroblocks;
  bool cfl;
  BlockChoice cb_trial, cr_trial;
};

MacroblockEncoder::MacroblockEncoder(const CodingParams& params, int qindex, float lambda)
    : impl_(std::make_unique<Impl>(params, std::clamp(qindex, kMinQIndex, kMaxQIndex), lambda)) {}

MacroblockEncoder::~MacroblockEncoder() = default;

float MacroblockEncoder::choose_luma(const PlaneContexts& contexts, PlaneState& state, const uint8_t* source,
                                     uint8_t* recon, int stride, int mbx, int mby, MacroblockChoice* out,
                                     float budget, const LumaPartition* partition) {
  const PlaneSearch plane(impl_->search, impl_->quantizers, contexts, source, recon, stride);
  return impl_->macroblocks.choose(plane, state, mbx, mby, out, budget, partition);
}

float MacroblockEncoder::choose_chroma(const PlaneContexts& contexts, PlaneState& cb_state, PlaneState& cr_state,
                                       const uint8_t* cb_source, const uint8_t* cr_source, uint8_t* cb_recon,
                                       uint8_t* cr_recon, int stride, const uint8_t* luma, int luma_stride, int x0,
                                       int y0, BlockChoice* cb, BlockChoice* cr) {
  const PlaneSearch cb_plane(impl_->search, impl_->quantizers, contexts, cb_source, cb_recon, stride);
  const PlaneSearch cr_plane(impl_->search, impl_->quantizers, contexts, cr_source, cr_recon, stride);
  float cost = cb_plane.choose_chroma_regular(cb_state, x0, y0, nullptr, cb);
  const ChromaMode cb_regular = cb->chroma_mode();
  cost += cr_plane.choose_chroma_regular(cr_state, x0, y0, &cb_regular, cr);
  if (impl_->cfl && luma != nullptr) {
    // CfL replaces the pair when cheaper; Cr's cost only adds to Cb's.
    int16_t ac[64];
    cfl_luma_ac(luma, luma_stride, x0, y0, ac);
    BlockChoice& cb_trial = impl_->cb_trial;
    BlockChoice& cr_trial = impl_->cr_trial;
    const float cb_cost = cb_plane.choose_chroma_cfl(cb_state, x0, y0, ac, nullptr, &cb_trial);
    if (cb_cost < cost) {
      const ChromaMode cb_mode = cb_trial.chroma_mode();
      const float cfl_cost = cb_cost + cr_plane.choose_chroma_cfl(cr_state, x0, y0, ac, &cb_mode, &cr_trial);
      if (cfl_cost < cost) {
        BlockSearch::copy_choice(cb_trial, kChromaSize, cb);
        BlockSearch::copy_choice(cr_trial, kChromaSize, cr);
        cost = cfl_cost;
      }
    }
  }
  cb_plane.finish_block(cb_state, x0, y0, kChromaSize, *cb);
  cr_plane.finish_block(cr_state, x0, y0, kChromaSize, *cr);
  return cost;
}

}  // namespace intra
}  // namespace svc::codec
