// SPDX-License-Identifier: BSD-2-Clause
// The B-face encoder's frame loop: every macroblock chosen and written in raster order
// by the macroblock coder (bframe_macroblock_coder.h), the interpolation filter bank
// screened, then the loop filters chosen on the finished reconstruction.
#include "codec/encoder/bframe_encoder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include "codec/common/bframe_loop_filter.h"
#include "codec/common/bframe_state.h"
#include "codec/common/context_priors.h"
#include "codec/encoder/bframe_macroblock_coder.h"
#include "codec/encoder/bframe_syntax_writer.h"
#include "codec/encoder/cdef_search.h"
#include "codec/encoder/range_encoder.h"
#include "codec/encoder/rate_distortion.h"
#include "codec/encoder/search_planes.h"

namespace svc::codec {
namespace {

using namespace bframe;

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

// A filter bank other than the regular one is coded in full only when the regular
// bank's motion, predicted through it, comes this much closer to the source.
constexpr double kFilterScreenMargin = 0.01;
// Squared error of the visible part of the frame state's planes against the source.
int64_t frame_error(const FrameState& s, const PaddedSource& source) {
  int64_t sum = 0;
  for (int p = 0; p < 3; ++p) {
    const int w = p == 0 ? s.width : s.chroma_width, h = p == 0 ? s.height : s.chroma_height;
    sum += squared_error(s.planes[p].data(), s.strides[p], source.planes[p].data(), source.strides[p], w, h);
  }
  return sum;
}

// Deblocks the finished frame when that brings it closer to the source; returns the
// loop filter flags for the header. The filter changes no coded symbol.
uint8_t choose_loop_filters(FrameState& s, const PaddedSource& source, const BFrameParams& params) {
  if (!params.deblocking) return 0;
  const std::array<std::vector<uint8_t>, 3> unfiltered = s.planes;
  const int64_t before = frame_error(s, source);
  deblock_planes(s);
  if (frame_error(s, source) < before) return kLoopFilterDeblocking;
  s.planes = unfiltered;
  return 0;
}

// Chooses CDEF for the finished (deblocked) frame; when it pays, filters the frame, writes
// its syntax and returns kLoopFilterCdef.
uint8_t apply_cdef_choice(RangeEncoder& encoder, FrameState& s, const PaddedSource& source,
                          const BFrameParams& params) {
  if (!params.cdef) return 0;
  CdefSource visible;
  for (int p = 0; p < 3; ++p) {
    visible.planes[p] = source.planes[p].data();
    visible.strides[p] = source.strides[p];
  }
  visible.width = s.width;
  visible.height = s.height;
  const CdefParams cdef = choose_cdef(plane_views(s), visible, s.inter_quantizer.qindex, cdef_skip_map(s),
                                      rd_lambda(s.inter_quantizer.qindex, std::max(0.0, params.lambda_factor)),
                                      params.full_cdef_search);
  if (cdef.presets.empty()) return 0;
  write_cdef_syntax(encoder, cdef, cdef_units(16 * s.mbs_x), cdef_units(16 * s.mbs_y));
  cdef_planes(s, cdef);
  return kLoopFilterCdef;
}

MacroblockHints macroblock_hints_at(const ReferenceHints& hints, const FrameState& s, int mx, int my) {
  MacroblockHints out;
  const size_t index = static_cast<size_t>(my) * s.mbs_x + mx;
  if (hints.macroblocks != nullptr && index < hints.macroblocks->size())
    out.macroblock = &(*hints.macroblocks)[index];
  if (hints.blocks == nullptr || hints.blocks->size() != 4 * static_cast<size_t>(s.mbs_x) * s.mbs_y) return out;
  for (int b = 0; b < 4; ++b) {
    const size_t block = static_cast<size_t>(2 * my + (b >> 1)) * (2 * s.mbs_x) + 2 * mx + (b & 1);
    out.blocks[b] = &(*hints.blocks)[block];
  }
  return out;
}

}  // namespace

int b_qindex_for_offset(int intra_qindex, int offset) {
  return std::clamp(intra_qindex + offset, kMinQIndex, kMaxQIndex);
}

int suggested_b_qindex(int intra_qindex) { return b_qindex_for_offset(intra_qindex, kBQIndexOffset); }

int adapted_b_qindex(int intra_qindex, double intra_share) {
  // Full offset up to kSharePredicted of intra macroblocks, the least from kShareUnpredicted.
  constexpr double kSharePredicted = 0.12, kShareUnpredicted = 0.5;
  const double share = std::isfinite(intra_share) ? std::clamp(intra_share, 0.0, 1.0) : 0.0;
  const double t = std::clamp((share - kSharePredicted) / (kShareUnpredicted - kSharePredicted), 0.0, 1.0);
  return b_qindex_for_offset(intra_qindex, static_cast<int>(std::lround(kBQIndexOffset -
                                                                        t * (kBQIndexOffset - kMinBQIndexOffset))));
}

namespace {

void count_macroblock(const MacroblockChoice& choice, BFrameStats* stats) {
  stats->modes.push_back(choice.mode);
  if (choice.mode != MacroblockMode::kIntra && choice.warp) ++stats->mb_warp;
  if (choice.mode != MacroblockMode::kIntra && choice.mode != MacroblockMode::kSkipped &&
      choice.motion.partition != Partition::k16x16) {
    ++stats->mb_partitioned;
  }
  if (choice.mode != MacroblockMode::kIntra && choice.mode != MacroblockMode::kSkipped) {
    stats->mb_luma_16x16 += choice.luma_16x16;
    for (int b = 0; b < 4; ++b) stats->luma_blocks_4x4 += !choice.luma_16x16 && choice.split[b];
  }
  switch (choice.mode) {
    case MacroblockMode::kIntra: ++stats->mb_intra; break;
    case MacroblockMode::kForward: ++stats->mb_forward; break;
    case MacroblockMode::kBackward: ++stats->mb_backward; break;
    case MacroblockMode::kBidirectional: ++stats->mb_bidirectional; break;
    case MacroblockMode::kSkipped: ++stats->mb_skipped; break;
  }
}

// A frame whose macroblocks are coded with one filter bank, before its loop filters.
struct CodedMacroblocks {
  FrameState state;
  PaddedSource padded;
  BFrameHeader header;                          // its flags are known when the frame is finished
  std::unique_ptr<std::vector<uint8_t>> bytes;  // the header, then what the range encoder appends
  std::unique_ptr<RangeEncoder> encoder;
  std::unique_ptr<SyntaxBits> syntax;  // the encoder's account, with stats only
  BFrameStats stats;
  std::vector<PredictionRecord> predictions;  // per macroblock, raster order
};

PredictionRecord prediction_record(const FrameState& s, int mx, int my, const MacroblockChoice& choice) {
  if (choice.mode == MacroblockMode::kIntra) return {};
  const bool skipped = choice.mode == MacroblockMode::kSkipped;
  return {skipped ? predicted_mode(s, mx, my) : choice.mode, choice.warp, choice.vectors, choice.motion};
}

// Squared error against the source of every inter and skipped macroblock's prediction
// (before residuals) built again with filter bank `filter`.
int64_t prediction_error(CodedMacroblocks& coded, InterpolationFilter filter) {
  FrameState& s = coded.state;
  const InterpolationFilter coded_filter = s.filter;
  s.filter = filter;
  int64_t sum = 0;
  MacroblockPrediction prediction;
  for (int my = 0; my < s.mbs_y; ++my) {
    for (int mx = 0; mx < s.mbs_x; ++mx) {
      const PredictionRecord& record = coded.predictions[static_cast<size_t>(my) * s.mbs_x + mx];
      if (record.mode == MacroblockMode::kIntra) continue;
      if (record.warp) {
        build_warp_prediction(s, mx, my, record.mode, &prediction);
      } else if (record.motion.partition != Partition::k16x16) {
        build_partition_prediction(s, mx, my, record.motion, &prediction);
      } else {
        build_prediction(s, mx, my, record.mode, record.vectors, &prediction);
      }
      for (int p = 0; p < 3; ++p) {
        const int size = p == 0 ? 16 : 8, stride = p == 0 ? 16 : 8;
        const int visible_w = p == 0 ? s.width : s.chroma_width, visible_h = p == 0 ? s.height : s.chroma_height;
        const int w = std::min(size, visible_w - size * mx), h = std::min(size, visible_h - size * my);
        const uint8_t* predicted = p == 0 ? prediction.y.data()
                                          : (p == 1 ? prediction.cb.data() : prediction.cr.data());
        const uint8_t* source =
            coded.padded.planes[p].data() + static_cast<size_t>(size * my) * coded.padded.strides[p] + size * mx;
        sum += squared_error(predicted, stride, source, coded.padded.strides[p], w, h);
      }
    }
  }
  s.filter = coded_filter;
  return sum;
}

// The bank of least prediction error over `coded`'s motion, when below (1 -
// kFilterScreenMargin) times the regular bank's; else the regular bank.
InterpolationFilter screened_filter(CodedMacroblocks& coded) {
  const int64_t regular_error = prediction_error(coded, InterpolationFilter::kRegular);
  int64_t screened_error = regular_error;
  InterpolationFilter candidate = InterpolationFilter::kRegular;
  for (int f = 1; f < kInterpolationFilterCount; ++f) {
    const int64_t error = prediction_error(coded, static_cast<InterpolationFilter>(f));
    if (error < screened_error) {  // ties keep the earlier bank
      screened_error = error;
      candidate = static_cast<InterpolationFilter>(f);
    }
  }
  if (static_cast<double>(screened_error) >= (1.0 - kFilterScreenMargin) * static_cast<double>(regular_error))
    return InterpolationFilter::kRegular;
  return candidate;
}

// Codes every macroblock with filter bank `filter` (arguments already validated).
CodedMacroblocks code_macroblocks(const ImageYCbCr420& source, const ImageYCbCr420& ref0, const ImageYCbCr420* ref1,
                                  const std::array<ReferenceHints, 2>& hints, const BFrameParams& params,
                                  const std::array<const SearchPlanes*, 2>& search, InterpolationFilter filter,
                                  bool with_stats) {
  const int width = source.width, height = source.height;
  const int border_units = reference_border_units(ref0.width - width);
  const int qindex = std::clamp(params.qindex, kMinQIndex, kMaxQIndex);
  CodedMacroblocks coded;
  FrameState& state = coded.state;
  init_state(state, width, height, qindex, &ref0, ref1, border_units);
  state.filter = filter;
  state.inter_transform_sizes = params.inter_transform_sizes;
  state.contexts.intra_luma.types.enabled = state.contexts.intra_chroma.types.enabled =
      params.intra_transform_types;
  const WarpField* fields[2] = {hints[0].warp, ref1 != nullptr ? hints[1].warp : nullptr};
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
  for (int r = 0; r < state.reference_count; ++r) {
    if (params.epipolar_lines) state.lines[r] = hints[r].lines;
  }
  coded.padded = pad_source(source, state);
  BFrameStats* stats = with_stats ? &coded.stats : nullptr;
  if (stats != nullptr) {
    stats->macroblocks = state.mbs_x * state.mbs_y;
    stats->modes.reserve(static_cast<size_t>(stats->macroblocks));
  }

  BFrameHeader& header = coded.header;
  header.qindex = qindex;
  header.border_units = border_units;
  header.filter = filter;
  header.reference_count = state.reference_count;
  header.warp_mask = state.warp_mask;
  header.transform_types = params.intra_transform_types;
  header.inter_transform_sizes = state.inter_transform_sizes;
  header.epipolar_lines = state.lines[0].present() || state.lines[1].present();
  const std::array<uint8_t, kBFrameHeaderBytes> header_bytes = serialize_b_frame_header(header);
  coded.bytes = std::make_unique<std::vector<uint8_t>>(header_bytes.begin(), header_bytes.end());
  coded.encoder = std::make_unique<RangeEncoder>(coded.bytes.get());
  if (stats != nullptr) {
    coded.syntax = std::make_unique<SyntaxBits>();
    coded.syntax->add(SyntaxElement::kHeader, 8.0 * static_cast<double>(header_bytes.size()));
    coded.encoder->set_account(coded.syntax.get());
  }
  if (header.epipolar_lines) {
    for (int r = 0; r < state.reference_count; ++r) encode_epipolar_lines(*coded.encoder, state.lines[r]);
  }
  BFrameMacroblockCoder coder(state, coded.padded, params, search);
  for (int my = 0; my < state.mbs_y; ++my) {
    for (int mx = 0; mx < state.mbs_x; ++mx) {
      const std::array<MacroblockHints, 2> macroblock_hints = {macroblock_hints_at(hints[0], state, mx, my),
                                                               ref1 != nullptr
                                                                   ? macroblock_hints_at(hints[1], state, mx, my)
                                                                   : MacroblockHints{}};
      const MacroblockChoice choice = coder.choose(mx, my, macroblock_hints, stats);
      coded.predictions.push_back(prediction_record(state, mx, my, choice));
      if (stats != nullptr && choice.mode != MacroblockMode::kIntra) {
        const MacroblockMode prediction = choice.mode == MacroblockMode::kSkipped ? predicted_mode(state, mx, my)
                                                                                  : choice.mode;
        stats->mb_leaving_face += prediction_leaves_face(state, mx, my, prediction, choice.warp, choice.vectors);
      }
      coder.write(*coded.encoder, choice);
      if (stats != nullptr) count_macroblock(choice, stats);
    }
  }
  return coded;
}

// Runs the loop filters the encoder chooses, finishes the payload and returns it.
std::vector<uint8_t> finish_frame(CodedMacroblocks& coded, const BFrameParams& params,
                                  ImageYCbCr420* reconstruction, BFrameStats* stats) {
  FrameState& state = coded.state;
  uint8_t loop_filters = choose_loop_filters(state, coded.padded, params);
  loop_filters |= apply_cdef_choice(*coded.encoder, state, coded.padded, params);
  observe_bframe_contexts(state.contexts);
  coded.encoder->finish();
  std::vector<uint8_t> bytes = std::move(*coded.bytes);
  // The header again with the loop filters, known only now.
  coded.header.loop_filters = loop_filters;
  const std::array<uint8_t, kBFrameHeaderBytes> header_bytes = serialize_b_frame_header(coded.header);
  std::copy(header_bytes.begin(), header_bytes.end(), bytes.begin());
  if (stats != nullptr) {
    *stats = std::move(coded.stats);
    if (coded.syntax != nullptr) {
      stats->syntax = *coded.syntax;
      stats->syntax.current = SyntaxElement::kHeader;
    }
    for (int r = 0; r < state.reference_count; ++r) {
      for (uint8_t known : state.node_known[r]) stats->warp_nodes_coded += known;
    }
  }
  if (reconstruction != nullptr) crop_output(state, reconstruction);
  return bytes;
}

}  // namespace

std::shared_ptr<const SearchPlanes> b_frame_search_planes(const ImageYCbCr420& reference) {
  return std::make_shared<const SearchPlanes>(reference, kSearchMargin);
}

std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const std::array<ReferenceHints, 2>& hints,
                                    const BFrameParams& params, ImageYCbCr420* reconstruction, BFrameStats* stats) {
  const int width = source.width, height = source.height;
  const int border_units = reference_border_units(ref0.width - width);
  const int padded_width = ref0.width, padded_height = height + (ref0.width - width);
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension || border_units < 0 ||
      !consistent_image(source, width, height) || !consistent_image(ref0, padded_width, padded_height) ||
      (ref1 != nullptr && !consistent_image(*ref1, padded_width, padded_height))) {
    return {};
  }
  std::array<std::optional<SearchPlanes>, 2> built;
  std::array<const SearchPlanes*, 2> search = {nullptr, nullptr};
  const std::array<const ImageYCbCr420*, 2> refs = {&ref0, ref1};
  for (size_t r = 0; r < 2 && refs[r] != nullptr; ++r) {
    const SearchPlanes* given = hints[r].search;
    if (given != nullptr && given->width() == refs[r]->width && given->height() == refs[r]->height &&
        given->margin() == kSearchMargin) {
      search[r] = given;
    } else {
      search[r] = &built[r].emplace(*refs[r], kSearchMargin);
    }
  }
  auto code = [&](const BFrameParams& pass, InterpolationFilter filter) {
    return code_macroblocks(source, ref0, ref1, hints, pass, search, filter, stats != nullptr);
  };
  if (!params.switchable_filter) {
    CodedMacroblocks coded = code(params, InterpolationFilter::kRegular);
    return finish_frame(coded, params, reconstruction, stats);
  }
  // The regular bank's motion predicted again through each other bank: the bank whose
  // predictions come clearly closer to the source is coded in full. With the full
  // search the regular bank's pass is a full coding, kept when the whole frame (squared
  // error plus bits, before the loop filters) costs less; without it, a screening pass
  // (inter options and skips only) and the screened bank's coding alone. Either way the
  // loop filters' search runs once, on the winner.
  BFrameParams screening = params;
  if (!params.full_filter_search) {
    screening.intra_macroblocks = false;
    screening.partitions = false;
    screening.rdoq = false;
    screening.inter_evaluations = 1;
  }
  CodedMacroblocks regular = code(screening, InterpolationFilter::kRegular);
  const InterpolationFilter chosen = screened_filter(regular);
  if (chosen == InterpolationFilter::kRegular && params.full_filter_search)
    return finish_frame(regular, params, reconstruction, stats);
  CodedMacroblocks best = code(params, chosen);
  if (params.full_filter_search) {
    const double lambda = rd_lambda(std::clamp(params.qindex, kMinQIndex, kMaxQIndex), params.lambda_factor);
    auto cost = [&](const CodedMacroblocks& coded) {
      return static_cast<double>(frame_error(coded.state, coded.padded)) +
             lambda * 8.0 * static_cast<double>(coded.bytes->size());
    };
    if (cost(regular) <= cost(best)) best = std::move(regular);
  }
  return finish_frame(best, params, reconstruction, stats);
}

}  // namespace svc::codec
