// SPDX-License-Identifier: BSD-2-Clause
// The B-face mode decision: which option each macroblock takes (docs/encoder.md).
#include "codec/encoder/bframe_macroblock_coder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "codec/encoder/distortion.h"
#include "codec/encoder/rate_distortion.h"
#include "codec/encoder/sad.h"

namespace svc::codec::bframe {

uint8_t intra_coded_mask(const IntraChoice& choice) {
  uint8_t mask = static_cast<uint8_t>((choice.cb.coded ? 16 : 0) | (choice.cr.coded ? 32 : 0));
  int n = 0;
  intra::for_each_luma_block(choice.luma.partition, [&](int x, int y, TransformSize size) {
    if (!choice.luma.blocks[static_cast<size_t>(n++)].coded) return;
    for (int b = 0; b < 4; ++b) {
      if (intra::blocks_overlap(x, y, size, 8 * (b & 1), 8 * (b >> 1), TransformSize::k8x8))
        mask |= static_cast<uint8_t>(1 << b);
    }
  });
  return mask;
}

CodingParams intra_tools(const BFrameParams& params) {
  CodingParams tools;
  tools.directional_intra = params.intra_prediction;
  tools.rd_intra_search = params.intra_rd_search;
  tools.transform_sizes = params.intra_transform_sizes;
  tools.cfl = params.intra_cfl;
  tools.rdoq = params.rdoq;
  tools.coarse_mode_search = true;
  tools.small_blocks = params.intra_small_blocks;
  tools.rectangular_trials = params.intra_rectangular_trials;
  tools.small_trials = params.intra_small_trials;
  return tools;
}

BFrameMacroblockCoder::BFrameMacroblockCoder(FrameState& state, const PaddedSource& source,
                                             const BFrameParams& params,
                                             const std::array<const SearchPlanes*, 2>& search)
    : s_(state),
      source_(source),
      search_(search),
      refine_(params.sub_pel_refinement),
      quarter_pel_(params.quarter_pel),
      full_evaluations_(std::max(1, params.inter_evaluations)),
      max_candidates_(std::clamp(params.max_candidates, 1, kMaxCandidates)),
      rdoq_(params.rdoq),
      partitions_(params.partitions),
      intra_(params.intra_macroblocks),
      full_split_search_(params.full_inter_split_search),
      vector_predictors_(params.vector_predictors),
      keep_intra_partition_(params.keep_intra_partition),
      skip_exit_bits_(params.skip_exit_bits) {
  lambda_ = rd_lambda(s_.inter_quantizer.qindex, std::max(0.0, params.lambda_factor));
  lambda_sad_ = std::sqrt(lambda_);
  CodingParams tools = intra_tools(params);
  tools.rdoq = false;  // as every option is priced; the winner is searched again with RDOQ
  intra_search_ =
      std::make_unique<intra::MacroblockEncoder>(tools, s_.inter_quantizer.qindex, static_cast<float>(lambda_));
  intra_rd_search_ = std::make_unique<intra::MacroblockEncoder>(intra_tools(params), s_.inter_quantizer.qindex,
                                                                static_cast<float>(lambda_));
}

MacroblockChoice BFrameMacroblockCoder::choose(int mx, int my, const std::array<MacroblockHints, 2>& hints,
                                               BFrameStats* stats) {
  mx_ = mx;
  my_ = my;
  for (int component = 0; component < 2; ++component)
    mvd_costs_[component] = MvdCostTable(s_.contexts, component, mvd_context(s_, mx, my, component));
  warp_cache_ = {};
  compute_visible();
  std::array<MotionVector, 2> predictors{};
  for (int r = 0; r < s_.reference_count; ++r) {
    predictor_lists_[r] = macroblock_predictors(s_, mx, my, r);
    predictors[r] = predictor_lists_[r].vectors[0];
  }
  predictors_ = predictors;
  const MacroblockMode skip_mode = predicted_mode(s_, mx, my);
  MacroblockChoice winner, option;
  evaluate_skip(skip_mode, predicted_warp(s_, mx, my), &winner);
  if (skip_ends_search(winner.cost)) {
    if (stats != nullptr) count_screened_prediction(winner.reconstruction.y.data(), true, stats);
    return winner;
  }

  std::array<MotionVector, 2> best = predictors;
  for (int r = 0; r < s_.reference_count; ++r) {
    std::span<const MotionVector> list;
    if (hints[r].macroblock != nullptr) list = *hints[r].macroblock;
    best[r] = search_reference(r, kWholeMacroblock, predictor_lists_[r], list, stats);
  }
  auto consider = [&](MacroblockMode mode, bool warp) {
    if (mode == MacroblockMode::kIntra) {
      evaluate_intra(&option, winner.cost);
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
  // For the statistics: the screened prediction of the lowest SAD, its error taken once.
  std::array<uint8_t, 256> closest{};
  int closest_sad = std::numeric_limits<int>::max();
  int screened_count = 0;
  const uint8_t* source = source_block(0);
  std::array<std::array<int16_t, 256>, 2> luma{}, warped{};
  // Warping is screened only towards references whose corner nodes differ: with four
  // (nearly) equal corners it predicts what a translation does, at a higher price.
  unsigned screen_warp = 0;
  for (int r = 0; r < s_.reference_count; ++r) {
    predict_macroblock_luma(*s_.references[r], reference_mb(s_, mx), reference_mb(s_, my), best[r], luma[r].data(),
                            s_.filter);
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
      if (warp &&
          ((uses_reference(mode, 0) && !(screen_warp & 1u)) || (uses_reference(mode, 1) && !(screen_warp & 2u)))) {
        continue;
      }
      float bits = mode_bits(s_, mx, my, mode) + partition_bits(s_, mx, my, Partition::k16x16);
      if (warp_allowed(s_, mode)) bits += bit_cost(s_.contexts.warp[warp_context(s_, mx, my)], warp);
      uint8_t prediction[256];
      if (mode == MacroblockMode::kBidirectional) {
        average_prediction(planes[0].data(), planes[1].data(), 256, prediction);
      } else {
        round_prediction(planes[mode == MacroblockMode::kBackward ? 1 : 0].data(), 256, prediction);
      }
      const int sad = sad_16x16(source, source_.strides[0], prediction);
      if (stats != nullptr && sad < closest_sad) {
        closest_sad = sad;
        std::copy_n(prediction, 256, closest.data());
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
  for (int k = 0; k < std::min(screened_count, full_evaluations_); ++k)
    consider(screened[k].mode, screened[k].warp);
  // Where skipping wins over the inter options, intra rarely wins (docs/bench.md,
  // "Figures behind code constants"): not tried.
  if (intra_ && winner.mode != MacroblockMode::kSkipped) consider(MacroblockMode::kIntra, false);
  // Split partitions are tried only where one translation may not serve the whole
  // macroblock: the depth-derived motion varies across it, or intra won.
  if (partitions_ && (winner.mode == MacroblockMode::kIntra || motion_varies(hints[0]) ||
                      (s_.reference_count == 2 && motion_varies(hints[1])))) {
    for (const Partition partition : {Partition::k16x8, Partition::k8x16, Partition::k8x8}) {
      evaluate_partitioned(partition, hints, best, screened[0].cost, stats, &option);
      if (option.cost < winner.cost) std::swap(winner, option);
    }
  }
  if (rdoq_) requantize(&winner);
  if (stats != nullptr && screened_count > 0)
    count_screened_prediction(closest.data(), winner.mode != MacroblockMode::kIntra, stats);
  return winner;
}

void BFrameMacroblockCoder::count_screened_prediction(const uint8_t* prediction, bool coded_inter,
                                                      BFrameStats* stats) const {
  const uint8_t* source = source_block(0);
  const int width = visible_luma_width(), height = visible_luma_height();
  stats->screened_prediction_sse[coded_inter] +=
      squared_error(source, source_.strides[0], prediction, 16, width, height);
  stats->screened_prediction_pixels[coded_inter] += width * height;
}

bool BFrameMacroblockCoder::skip_ends_search(double skip_cost) const {
  return skip_cost * 256 < skip_exit_bits_ * lambda_ * visible_luma_width() * visible_luma_height();
}

const MacroblockIntermediate& BFrameMacroblockCoder::warped_prediction(int reference, bool with_chroma) {
  WarpCache& cache = warp_cache_[static_cast<size_t>(reference)];
  const WarpCorners corners = macroblock_corners(s_, reference, mx_, my_);
  if (!cache.luma) {
    predict_warp_macroblock_luma(*s_.references[reference], reference_mb(s_, mx_), reference_mb(s_, my_), corners,
                                 cache.prediction.y.data(), s_.filter);
    cache.luma = true;
  }
  if (with_chroma && !cache.chroma) {
    predict_warp_macroblock_chroma(*s_.references[reference], reference_mb(s_, mx_), reference_mb(s_, my_), corners,
                                   &cache.prediction, s_.filter);
    cache.chroma = true;
  }
  return cache.prediction;
}

void BFrameMacroblockCoder::build_cached_warp_prediction(MacroblockMode mode, MacroblockPrediction* out) {
  if (mode == MacroblockMode::kBidirectional) {
    finish_prediction(warped_prediction(0, true), &warped_prediction(1, true), out);
  } else {
    finish_prediction(warped_prediction(mode == MacroblockMode::kBackward ? 1 : 0, true), nullptr, out);
  }
}

float BFrameMacroblockCoder::warp_nodes_bits(MacroblockMode mode) {
  float bits = 0;
  for (int r = 0; r < s_.reference_count; ++r) {
    if (uses_reference(mode, r)) bits += missing_nodes_bits(s_, r, mx_, my_, predictors_[r]);
  }
  return kNewNodeShare * bits;
}

void BFrameMacroblockCoder::compute_visible() {
  const int w = std::min(16, s_.width - 16 * mx_), h = std::min(16, s_.height - 16 * my_);
  const int cw = std::min(8, s_.chroma_width - 8 * mx_), ch = std::min(8, s_.chroma_height - 8 * my_);
  for (int b = 0; b < 4; ++b) {
    visible_w_[b] = std::clamp(w - 8 * (b & 1), 0, 8);
    visible_h_[b] = std::clamp(h - 8 * (b >> 1), 0, 8);
  }
  visible_w_[4] = visible_w_[5] = cw;
  visible_h_[4] = visible_h_[5] = ch;
}

const uint8_t* BFrameMacroblockCoder::source_block(int b) const {
  const int plane = block_plane(b);
  const int x = 8 * block_x(b, mx_), y = 8 * block_y(b, my_);
  return source_.planes[plane].data() + static_cast<size_t>(y) * source_.strides[plane] + x;
}

int64_t BFrameMacroblockCoder::block_error(int b, const uint8_t* samples) const {
  return squared_error(source_block(b), source_.strides[block_plane(b)], samples, block_stride(b), visible_w_[b],
                       visible_h_[b]);
}

void BFrameMacroblockCoder::evaluate_skip(MacroblockMode mode, bool warp, MacroblockChoice* out) {
  out->mode = MacroblockMode::kSkipped;
  out->warp = warp;
  out->vectors = predictors_;
  out->coded_mask = 0;
  const float skip_bits = bit_cost(s_.contexts.skip[skip_context(s_, mx_, my_)], 1);
  if (warp) {
    build_cached_warp_prediction(mode, &out->reconstruction);
    out->cost =
        static_cast<double>(prediction_error(out->reconstruction)) + lambda_ * (skip_bits + warp_nodes_bits(mode));
    return;
  }
  const int count = skip_predictor_count(predictor_lists_, mode);
  MacroblockPrediction prediction;
  for (int index = 0; index < usable_predictors(count); ++index) {
    const std::array<MotionVector, 2> vectors = skip_vectors(predictor_lists_, mode, index);
    build_prediction(s_, mx_, my_, mode, vectors, &prediction);
    const double cost =
        static_cast<double>(prediction_error(prediction)) +
        lambda_ * (skip_bits + predictor_index_bits(s_.contexts.skip_predictor_index, count, index));
    if (index == 0 || cost < out->cost) {
      out->cost = cost;
      out->vectors = vectors;
      out->skip_index = index;
      out->reconstruction = prediction;
    }
  }
}

int64_t BFrameMacroblockCoder::prediction_error(const MacroblockPrediction& prediction) const {
  int64_t distortion = 0;
  for (int b = 0; b < 6; ++b) distortion += block_error(b, block_samples(prediction, b));
  return distortion;
}

void BFrameMacroblockCoder::evaluate_inter(MacroblockMode mode, bool warp, const std::array<MotionVector, 2>& best,
                                           MacroblockChoice* out) {
  const SyntaxContexts& c = s_.contexts;
  out->mode = mode;
  out->warp = warp;
  out->vectors = predictors_;
  out->motion = PartitionMotion{};
  float bits = mode_bits(s_, mx_, my_, mode) + partition_bits(s_, mx_, my_, Partition::k16x16);
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
  code_residual(prediction, bits, out);
}

void BFrameMacroblockCoder::evaluate_partitioned(Partition partition, const std::array<MacroblockHints, 2>& hints,
                                                 const std::array<MotionVector, 2>& macroblock_best,
                                                 double best_screened, BFrameStats* stats, MacroblockChoice* out) {
  PartitionMotion& motion = out->motion;
  motion = PartitionMotion{};
  motion.partition = partition;
  out->warp = false;
  out->vectors = predictors_;
  float bits = bit_cost(s_.contexts.skip[skip_context(s_, mx_, my_)], 0) +
               bit_cost(s_.contexts.intra[intra_context(s_, mx_, my_)], 0) +
               partition_bits(s_, mx_, my_, partition);
  const uint8_t* source = source_block(0);
  double sad = 0;
  for (int k = 0; k < partition_count(partition); ++k) {
    const PartitionRect rect = partition_rect(partition, k);
    std::array<MotionVector, 2> vectors{};
    std::array<VectorPredictors, 2> part_predictors{};
    std::array<MacroblockIntermediate, 2> luma;
    for (int r = 0; r < s_.reference_count; ++r) {
      part_predictors[r] = partition_predictors(motion, k, r, predictor_lists_[r]);
      // The 16x16 choice is tried too, within the max_candidates a search prices.
      CandidateList list =
          partition_candidates(hints[r], rect, static_cast<size_t>(max_candidates_ - 1), partition_listed_);
      if (partition_listed_.insert(macroblock_best[r])) list.push_back(macroblock_best[r]);
      vectors[r] = search_reference(r, rect, part_predictors[r], list, stats);
      const ImageYCbCr420& ref = *s_.references[r];
      predict_block(ref.y.data(), ref.width, ref.height, PlaneKind::kLuma, 16 * reference_mb(s_, mx_) + rect.x,
                    16 * reference_mb(s_, my_) + rect.y, rect.width, rect.height, vectors[r].x, vectors[r].y,
                    luma[r].y.data() + 16 * rect.y + rect.x, 16, s_.filter);
    }
    double best_cost = 1e300;
    float best_bits = 0;
    for (const MacroblockMode mode :
         {MacroblockMode::kForward, MacroblockMode::kBackward, MacroblockMode::kBidirectional}) {
      if (s_.reference_count == 1 && mode != MacroblockMode::kForward) continue;
      float mode_side_bits = direction_bits(s_, mx_, my_, mode);
      for (int r = 0; r < s_.reference_count; ++r) {
        if (uses_reference(mode, r)) mode_side_bits += vector_bits(r, vectors[r], part_predictors[r]);
      }
      uint8_t prediction[256];
      for (int y = rect.y; y < rect.y + rect.height; ++y) {
        const int offset = 16 * y + rect.x;
        if (mode == MacroblockMode::kBidirectional) {
          average_prediction(luma[0].y.data() + offset, luma[1].y.data() + offset, rect.width, prediction + offset);
        } else {
          round_prediction(luma[mode == MacroblockMode::kBackward ? 1 : 0].y.data() + offset, rect.width,
                           prediction + offset);
        }
      }
      const double cost = sad_rect(source, source_.strides[0], prediction, rect) + lambda_sad_ * mode_side_bits;
      if (cost < best_cost) {
        best_cost = cost;
        best_bits = mode_side_bits;
        motion.modes[k] = mode;
      }
    }
    bits += best_bits;
    sad += best_cost - lambda_sad_ * best_bits;
    motion.vectors[k] = vectors;
    for (int r = 0; r < s_.reference_count; ++r) {
      if (uses_reference(motion.modes[k], r)) out->vectors[r] = vectors[r];
    }
  }
  out->mode = motion.modes[partition_count(partition) - 1];
  if (sad + lambda_sad_ * bits > kPartitionScreenMargin * best_screened) {
    out->cost = std::numeric_limits<double>::infinity();
    return;
  }
  MacroblockPrediction prediction;
  build_partition_prediction(s_, mx_, my_, motion, &prediction);
  code_residual(prediction, bits, out);
}

void BFrameMacroblockCoder::evaluate_intra(MacroblockChoice* out, double budget) {
  const SyntaxContexts& c = s_.contexts;
  out->mode = MacroblockMode::kIntra;
  out->warp = false;
  out->vectors = predictors_;
  out->motion = PartitionMotion{};
  if (!out->intra) out->intra = std::make_unique<IntraChoice>();
  IntraChoice& choice = *out->intra;
  const uint8_t* source[3] = {source_.planes[0].data(), source_.planes[1].data(), source_.planes[2].data()};
  uint8_t* recon[3] = {s_.planes[0].data(), s_.planes[1].data(), s_.planes[2].data()};
  // The winner is searched again with RDOQ in every trial, as intra frames search.
  intra::MacroblockEncoder& search = quantize_rd_ ? *intra_rd_search_ : *intra_search_;
  double cost = lambda_ * mode_bits(s_, mx_, my_, MacroblockMode::kIntra);
  // The RDOQ pass keeps the winner's partition where the speed says so.
  const intra::LumaPartition partition = choice.luma.partition;
  cost += search.choose_luma(c.intra_luma, s_.intra_planes[0], source[0], recon[0], s_.strides[0], mx_, my_,
                             &choice.luma, static_cast<float>(budget - cost),
                             quantize_rd_ && keep_intra_partition_ ? &partition : nullptr);
  if (cost >= budget) {
    out->cost = std::numeric_limits<double>::infinity();
    return;
  }
  // Chroma may use CfL from the luma just reconstructed in place.
  cost += search.choose_chroma(c.intra_chroma, s_.intra_planes[1], s_.intra_planes[2], source[1], source[2],
                               recon[1], recon[2], s_.strides[1], recon[0], s_.strides[0], 8 * mx_, 8 * my_,
                               &choice.cb, &choice.cr);
  out->coded_mask = intra_coded_mask(choice);
  copy_macroblock_out(s_, mx_, my_, &out->reconstruction);
  out->cost = cost;
}

}  // namespace svc::codec::bframe
