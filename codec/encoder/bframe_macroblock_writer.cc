// SPDX-License-Identifier: BSD-2-Clause
// The syntax of a B-face macroblock as chosen (docs/codec.md 4.2-3.8).
#include "codec/encoder/bframe_macroblock_coder.h"

#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/intra_syntax_writer.h"

namespace svc::codec::bframe {

void BFrameMacroblockCoder::write(RangeEncoder& encoder, const MacroblockChoice& choice) {
  const int mx = mx_, my = my_;
  SyntaxContexts& c = s_.contexts;
  MacroblockInfo info;
  info.mode = choice.mode;
  info.inter_mode = predicted_mode(s_, mx, my);
  info.inter_warp = predicted_warp(s_, mx, my);
  info.vectors = predictors_;
  {
    const SyntaxScope scope(encoder, SyntaxElement::kModes);
    encoder.encode(c.skip[skip_context(s_, mx, my)], choice.mode == MacroblockMode::kSkipped);
  }
  if (choice.mode == MacroblockMode::kSkipped) {
    if (info.inter_warp) {
      write_warp_nodes(encoder, info.inter_mode, &info);
    } else {
      encode_predictor_index(encoder, c.skip_predictor_index,
                             skip_predictor_count(predictor_lists_, info.inter_mode), choice.skip_index);
      info.vectors = choice.vectors;
    }
    commit_macroblock(s_, mx, my, info, choice.reconstruction, 0);
    return;
  }
  {
    const SyntaxScope scope(encoder, SyntaxElement::kModes);
    encoder.encode(c.intra[intra_context(s_, mx, my)], choice.mode == MacroblockMode::kIntra);
  }
  if (choice.mode == MacroblockMode::kIntra) {
    // The planes and the intra neighbour state hold this choice since its evaluation.
    const IntraChoice& blocks = *choice.intra;
    intra::write_macroblock(encoder, c.intra_luma, s_.intra_planes[0], mx, my, blocks.luma);
    intra::write_chroma_block(encoder, c.intra_chroma, s_.intra_planes[1], 8 * mx, 8 * my, ChromaPlane::kCb, {},
                              blocks.cb);
    intra::write_chroma_block(encoder, c.intra_chroma, s_.intra_planes[2], 8 * mx, 8 * my, ChromaPlane::kCr,
                              blocks.cb.chroma_mode(), blocks.cr);
    commit_macroblock(s_, mx, my, info, choice.reconstruction, choice.coded_mask);
    return;
  }
  encode_partition(encoder, s_, mx, my, choice.motion.partition);
  if (choice.motion.partition != Partition::k16x16) {
    write_partition_vectors(encoder, choice.motion, &info);
    info.partition = choice.motion.partition;
  } else {
    encode_direction(encoder, s_, mx, my, choice.mode);
    if (warp_allowed(s_, choice.mode)) {
      const SyntaxScope scope(encoder, SyntaxElement::kModes);
      encoder.encode(c.warp[warp_context(s_, mx, my)], choice.warp);
    }
    if (choice.warp) {
      write_warp_nodes(encoder, choice.mode, &info);
    } else {
      write_vectors(encoder, choice, &info);
    }
  }
  info.inter_mode = choice.mode;
  info.inter_warp = choice.warp;
  info.luma_16x16 = choice.luma_16x16;
  if (s_.inter_transform_sizes) {
    const SyntaxScope scope(encoder, SyntaxElement::kPartitions);
    encoder.encode(c.luma_16x16[luma_16x16_context(s_, mx, my)], choice.luma_16x16);
  }
  uint8_t local_coded[6] = {};
  const SyntaxScope levels_scope(encoder, SyntaxElement::kLevels);  // the coded-block flags and levels
  for (int b = 0; b < 6; ++b) {
    const int plane = block_plane(b);
    const int context = coded_context(s_, local_coded, plane, mx, my, block_x(b, mx), block_y(b, my));
    local_coded[b] = static_cast<uint8_t>((choice.coded_mask >> b) & 1);
    // A 16x16 luma block's flag stands for its four 8x8 blocks.
    if (choice.luma_16x16 && b >= 1 && b <= 3) continue;
    encoder.encode(plane == 0 ? c.cbp_luma[context] : c.cbp_chroma[plane - 1][context], local_coded[b]);
  }
  int first_block = 0;
  if (choice.luma_16x16) {
    first_block = 4;
    if (local_coded[0]) {
      encode_block_levels(encoder, c.inter_luma, choice.luma_levels.data(), kNoCodedBlockFlag,
                          TransformSize::k16x16);
    }
  }
  for (int b = first_block; b < 6; ++b) {
    if (!local_coded[b]) continue;
    if (block_plane(b) == 0 && s_.inter_transform_sizes) {
      {
        const SyntaxScope scope(encoder, SyntaxElement::kPartitions);
        encoder.encode(c.luma_4x4, choice.split[b]);
      }
      if (choice.split[b]) {
        for (int k = 0; k < 4; ++k) {
          encode_block_levels(encoder, c.inter_luma, choice.levels[b].data() + 16 * k, 0, TransformSize::k4x4);
        }
        continue;
      }
    }
    encode_block_levels(encoder, block_plane(b) == 0 ? c.inter_luma : c.inter_chroma, choice.levels[b].data(),
                        kNoCodedBlockFlag);
  }
  commit_macroblock(s_, mx, my, info, choice.reconstruction, choice.coded_mask);
}

void BFrameMacroblockCoder::write_vectors(RangeEncoder& encoder, const MacroblockChoice& choice,
                                          MacroblockInfo* info) {
  const int contexts[2] = {mvd_context(s_, mx_, my_, 0), mvd_context(s_, mx_, my_, 1)};
  for (int r = 0; r < s_.reference_count; ++r) {
    if (!uses_reference(choice.mode, r)) continue;
    const MotionVector predictor = write_predictor_index(encoder, r, choice.vectors[r], predictor_lists_[r]);
    write_difference(encoder, contexts, r, choice.vectors[r], predictor, info);
    info->vectors[r] = choice.vectors[r];
  }
}

void BFrameMacroblockCoder::write_difference(RangeEncoder& encoder, const int (&contexts)[2], int reference,
                                             MotionVector vector, MotionVector predictor, MacroblockInfo* info) {
  const std::array<int64_t, 2> d = vector_difference(s_, reference, mx_, my_, vector, predictor);
  for (int c = 0; c < 2; ++c) {
    encode_mvd_component(encoder, s_.contexts, c, contexts[c], static_cast<int>(d[static_cast<size_t>(c)]));
    info->mvd_magnitude[static_cast<size_t>(c)] += static_cast<int>(std::llabs(d[static_cast<size_t>(c)]));
  }
}

void BFrameMacroblockCoder::write_partition_vectors(RangeEncoder& encoder, const PartitionMotion& motion,
                                                    MacroblockInfo* info) {
  const int contexts[2] = {mvd_context(s_, mx_, my_, 0), mvd_context(s_, mx_, my_, 1)};
  for (int k = 0; k < partition_count(motion.partition); ++k) {
    encode_direction(encoder, s_, mx_, my_, motion.modes[k]);
    for (int r = 0; r < s_.reference_count; ++r) {
      if (!uses_reference(motion.modes[k], r)) continue;
      const MotionVector predictor = write_predictor_index(encoder, r, motion.vectors[k][r],
                                                           partition_predictors(motion, k, r, predictor_lists_[r]));
      write_difference(encoder, contexts, r, motion.vectors[k][r], predictor, info);
      info->vectors[r] = motion.vectors[k][r];
    }
  }
}

void BFrameMacroblockCoder::write_warp_nodes(RangeEncoder& encoder, MacroblockMode mode, MacroblockInfo* info) {
  const SyntaxScope scope(encoder, SyntaxElement::kVectors);
  for (int r = 0; r < s_.reference_count; ++r) {
    if (!uses_reference(mode, r)) continue;
    encode_missing_nodes(encoder, s_, r, mx_, my_, predictors_[r]);
    info->vectors[r] = warp_centre_vector(s_, macroblock_corners(s_, r, mx_, my_));
  }
}

MotionVector BFrameMacroblockCoder::write_predictor_index(RangeEncoder& encoder, int reference, MotionVector vector,
                                                          const VectorPredictors& predictors) {
  float bits = 0;
  const int index = cheapest_predictor(vector, line_predictors(reference, predictors), &bits);
  encode_predictor_index(encoder, s_.contexts.predictor_index, predictors.count, index);
  return predictors.vectors[static_cast<size_t>(index)];
}

}  // namespace svc::codec::bframe
