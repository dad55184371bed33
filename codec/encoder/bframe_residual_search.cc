// SPDX-License-Identifier: BSD-2-Clause
// The residual of a B-face option: transform sizes and levels by rate-distortion cost.
#include "codec/encoder/bframe_macroblock_coder.h"

#include "codec/encoder/coefficient_writer.h"
#include "codec/encoder/rdoq.h"

namespace svc::codec::bframe {

void subtract_prediction(const uint8_t* source, int source_stride, const uint8_t* prediction, int prediction_stride,
                         int width, int16_t* residual) {
  for (int y = 0; y < width; ++y) {
    for (int x = 0; x < width; ++x) {
      residual[width * y + x] =
          static_cast<int16_t>(source[y * source_stride + x] - prediction[y * prediction_stride + x]);
    }
  }
}

void BFrameMacroblockCoder::requantize(MacroblockChoice* choice) {
  if (choice->mode == MacroblockMode::kSkipped) return;
  quantize_rd_ = true;
  if (choice->mode == MacroblockMode::kIntra) {
    evaluate_intra(choice);
  } else {
    MacroblockPrediction prediction;
    if (choice->warp) {
      build_cached_warp_prediction(choice->mode, &prediction);
    } else if (choice->motion.partition != Partition::k16x16) {
      build_partition_prediction(s_, mx_, my_, choice->motion, &prediction);
    } else {
      build_prediction(s_, mx_, my_, choice->mode, choice->vectors, &prediction);
    }
    code_residual(prediction, choice->side_bits, choice);
  }
  quantize_rd_ = false;
}

void BFrameMacroblockCoder::code_residual(const MacroblockPrediction& prediction, float bits,
                                          MacroblockChoice* out) {
  out->side_bits = bits;
  int64_t distortion = 0;
  uint8_t local_coded[6] = {};
  out->coded_mask = 0;
  out->luma_16x16 = false;
  for (int b = 0; b < 4; ++b) code_block(prediction, b, local_coded, out, &distortion, &bits);
  if (s_.inter_transform_sizes) {
    const AdaptiveBit& flag = s_.contexts.luma_16x16[luma_16x16_context(s_, mx_, my_)];
    const float flag_bits[2] = {bit_cost(flag, 0), bit_cost(flag, 1)};
    bits += flag_bits[0];
    int64_t large_distortion = 0;
    float large_bits = flag_bits[1];
    uint8_t large_reconstruction[256];
    const bool coded = code_luma_16x16(prediction, out, large_reconstruction, &large_distortion, &large_bits);
    const float small_bits = bits - out->side_bits;
    if (large_distortion + lambda_ * large_bits < distortion + lambda_ * small_bits) {
      out->luma_16x16 = true;
      distortion = large_distortion;
      bits = out->side_bits + large_bits;
      std::fill_n(local_coded, 4, static_cast<uint8_t>(coded));
      out->coded_mask = coded ? 15 : 0;
      std::copy_n(large_reconstruction, 256, out->reconstruction.y.data());
    }
  }
  for (int b = 4; b < 6; ++b) code_block(prediction, b, local_coded, out, &distortion, &bits);
  out->cost = static_cast<double>(distortion) + lambda_ * bits;
}

bool BFrameMacroblockCoder::code_luma_16x16(const MacroblockPrediction& prediction, MacroblockChoice* out,
                                            uint8_t* reconstruction, int64_t* distortion, float* bits) {
  const SyntaxContexts& c = s_.contexts;
  const uint8_t* src = source_block(0);
  const int source_stride = source_.strides[0];
  const uint8_t no_local[6] = {};
  const AdaptiveBit& cbp_model = c.cbp_luma[coded_context(s_, no_local, 0, mx_, my_, 2 * mx_, 2 * my_)];
  int16_t residual[256];
  subtract_prediction(src, source_stride, prediction.y.data(), 16, 16, residual);
  const int visible_w = visible_luma_width(), visible_h = visible_luma_height();
  const int64_t uncoded_error = squared_error(src, source_stride, prediction.y.data(), 16, visible_w, visible_h);
  int16_t* levels = out->luma_levels.data();
  float levels_bits = 0;
  const int nonzero = transform_quantize_block_rd(s_.inter_quantizer_16x16, residual, quantize_rd_, c.inter_luma,
                                                  kNoCodedBlockFlag, static_cast<float>(lambda_), levels,
                                                  TransformType::kDctDct, &levels_bits);
  if (nonzero > 0) {
    reconstruct_residual_block(s_.inter_quantizer_16x16, levels, prediction.y.data(), 16, reconstruction, 16);
    const int64_t coded_error = squared_error(src, source_stride, reconstruction, 16, visible_w, visible_h);
    const float coded_bits = bit_cost(cbp_model, 1) + levels_bits;
    if (coded_error + lambda_ * coded_bits < uncoded_error + lambda_ * bit_cost(cbp_model, 0)) {
      *distortion += coded_error;
      *bits += coded_bits;
      return true;
    }
  }
  *distortion += uncoded_error;
  *bits += bit_cost(cbp_model, 0);
  std::copy_n(prediction.y.data(), 256, reconstruction);
  return false;
}

int64_t BFrameMacroblockCoder::code_quarters(const int16_t* residual, const uint8_t* pred, int stride, int b,
                                             int16_t* levels, uint8_t* reconstruction, float* bits) {
  const BlockContextSet& contexts = s_.contexts.inter_luma;
  for (int k = 0; k < 4; ++k) {
    const int row = 4 * (k >> 1), column = 4 * (k & 1);
    int16_t quarter[16];
    for (int y = 0; y < 4; ++y) std::copy_n(residual + 8 * (row + y) + column, 4, quarter + 4 * y);
    int16_t* quarter_levels = levels + 16 * k;
    const uint8_t* quarter_pred = pred + row * stride + column;
    uint8_t* out = reconstruction + 8 * row + column;
    float levels_bits = 0;
    if (transform_quantize_block_rd(s_.inter_quantizer_4x4, quarter, quantize_rd_, contexts, 0,
                                    static_cast<float>(lambda_), quarter_levels, TransformType::kDctDct,
                                    &levels_bits) > 0) {
      reconstruct_residual_block(s_.inter_quantizer_4x4, quarter_levels, quarter_pred, stride, out, 8);
    } else {
      for (int y = 0; y < 4; ++y) std::copy_n(quarter_pred + y * stride, 4, out + 8 * y);
    }
    *bits += levels_bits;
  }
  return squared_error(source_block(b), source_.strides[0], reconstruction, 8, visible_w_[b], visible_h_[b]);
}

void BFrameMacroblockCoder::code_block(const MacroblockPrediction& prediction, int b, uint8_t* local_coded,
                                       MacroblockChoice* out, int64_t* distortion, float* bits) {
  const SyntaxContexts& c = s_.contexts;
  const int plane = block_plane(b), stride = block_stride(b);
  const uint8_t* pred = block_samples(prediction, b);
  uint8_t* recon = block_samples(out->reconstruction, b);
  const uint8_t* src = source_block(b);
  const int source_stride = source_.strides[plane];
  const int context = coded_context(s_, local_coded, plane, mx_, my_, block_x(b, mx_), block_y(b, my_));
  const AdaptiveBit& cbp_model = plane == 0 ? c.cbp_luma[context] : c.cbp_chroma[plane - 1][context];
  const BlockContextSet& contexts = plane == 0 ? c.inter_luma : c.inter_chroma;
  int16_t residual[64];
  subtract_prediction(src, source_stride, pred, stride, 8, residual);
  // The uncoded block, then each coded form that costs less.
  int64_t best_error = block_error(b, pred);
  float best_bits = bit_cost(cbp_model, 0);
  const uint8_t* best_samples = pred;
  int best_stride = stride;
  const bool sizes = plane == 0 && s_.inter_transform_sizes;
  if (plane == 0) out->split[b] = false;
  int16_t* levels = out->levels[b].data();
  uint8_t trial[64];
  float levels_bits = 0;
  const bool whole_has_levels = transform_quantize_block_rd(s_.inter_quantizer, residual, quantize_rd_, contexts,
                                                            kNoCodedBlockFlag, static_cast<float>(lambda_), levels,
                                                            TransformType::kDctDct, &levels_bits) > 0;
  if (whole_has_levels) {
    reconstruct_residual_block(s_.inter_quantizer, levels, pred, stride, trial, 8);
    const int64_t error = squared_error(src, source_stride, trial, 8, visible_w_[b], visible_h_[b]);
    const float coded_bits = bit_cost(cbp_model, 1) + (sizes ? bit_cost(c.luma_4x4, 0) : 0.0f) + levels_bits;
    if (error + lambda_ * coded_bits < best_error + lambda_ * best_bits) {
      best_error = error;
      best_bits = coded_bits;
      best_samples = trial;
      best_stride = 8;
    }
  }
  uint8_t split_trial[64];
  int16_t split_levels[64];
  if (sizes && (full_split_search_ || whole_has_levels)) {
    float split_bits = bit_cost(cbp_model, 1) + bit_cost(c.luma_4x4, 1);
    const int64_t error = code_quarters(residual, pred, stride, b, split_levels, split_trial, &split_bits);
    if (error + lambda_ * split_bits < best_error + lambda_ * best_bits) {
      best_error = error;
      best_bits = split_bits;
      best_samples = split_trial;
      best_stride = 8;
      out->split[b] = true;
      std::copy_n(split_levels, 64, levels);
    }
  }
  const bool coded = best_samples != pred;
  *distortion += best_error;
  *bits += best_bits;
  for (int y = 0; y < 8; ++y) std::copy_n(best_samples + y * best_stride, 8, recon + y * stride);
  local_coded[b] = coded;
  out->coded_mask |= static_cast<uint8_t>(coded << b);
}

}  // namespace svc::codec::bframe
