// B-frame encoder: evaluates every macroblock option (skip, forward, backward,
// bidirectional, intra) by cost = SSD + lambda * estimated bits, with bits estimated from
// the current adaptive probabilities, and writes the chosen one.
#include "codec/common/bframe_codec.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "codec/common/bframe_loop_filter.h"
#include "codec/common/bframe_state.h"
#include "codec/common/bframe_syntax.h"
#include "codec/common/context_priors.h"
#include "codec/encoder/rdoq.h"
#include "codec/encoder/sad.h"
#include "codec/encoder/search_planes.h"

namespace svc::codec {
namespace {

using namespace bframe;

// An intra macroblock's blocks: its luma macroblock, its Cb and its Cr block.
struct IntraChoice {
  intra::MacroblockChoice luma;
  intra::BlockChoice cb, cr;
};

// The coded flags (bit b for block b of docs/codec.md 10.2) of an intra macroblock: an
// 8x8 luma block is coded when a transform block covering it has levels.
uint8_t intra_coded_mask(const IntraChoice& choice) {
  uint8_t mask = static_cast<uint8_t>((choice.cb.coded ? 16 : 0) | (choice.cr.coded ? 32 : 0));
  int n = 0;
  intra::for_each_luma_block(choice.luma.partition, [&](int x, int y, int size) {
    if (!choice.luma.blocks[static_cast<size_t>(n++)].coded) return;
    for (int b = 0; b < 4; ++b) {
      const int bx = 8 * (b & 1), by = 8 * (b >> 1);
      if (x < bx + 8 && bx < x + shape_width(size) && y < by + 8 && by < y + shape_height(size))
        mask |= static_cast<uint8_t>(1 << b);
    }
  });
  return mask;
}

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

// residual = source - prediction over a width x width block, packed rows.
void subtract_prediction(const uint8_t* source, int source_stride, const uint8_t* prediction, int prediction_stride,
                         int width, int16_t* residual) {
  for (int y = 0; y < width; ++y) {
    for (int x = 0; x < width; ++x) {
      residual[width * y + x] =
          static_cast<int16_t>(source[y * source_stride + x] - prediction[y * prediction_stride + x]);
    }
  }
}

// Samples of edge extension of the motion search's planes; vectors reaching further are
// priced exactly.
constexpr int kSearchMargin = 32;
// A filter bank other than the regular one is coded in full only when the regular
// bank's motion, predicted through it, comes this much closer to the source.
constexpr double kFilterScreenMargin = 0.01;
// The share of a new warp node's bits charged to the macroblock that sends it.
constexpr float kNewNodeShare = 0.5f;
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
  const double scale = quantizer_scale_q8(s.inter_quantizer.qindex) / 256.0;
  CdefSource visible;
  for (int p = 0; p < 3; ++p) {
    visible.planes[p] = source.planes[p].data();
    visible.strides[p] = source.strides[p];
  }
  visible.width = s.width;
  visible.height = s.height;
  const CdefParams cdef = choose_cdef(plane_views(s), visible, s.inter_quantizer.qindex, cdef_skip_map(s),
                                      std::max(0.0, params.lambda_factor) * scale * scale, params.full_cdef_search);
  if (cdef.presets.empty()) return 0;
  write_cdef_syntax(encoder, cdef, cdef_units(16 * s.mbs_x), cdef_units(16 * s.mbs_y));
  cdef_planes(s, cdef);
  return kLoopFilterCdef;
}

constexpr PartitionRect kWholeMacroblock{};

// Candidates of one macroblock and its 8x8 blocks towards one reference.
struct MacroblockHints {
  const CandidateList* macroblock = nullptr;
  std::array<const CandidateList*, 4> blocks{};
};

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

int sad_rect(const uint8_t* source, int source_stride, const uint8_t* prediction, const PartitionRect& rect) {
  int sum = 0;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
      sum += std::abs(static_cast<int>(source[y * source_stride + x]) - static_cast<int>(prediction[16 * y + x]));
    }
  }
  return sum;
}

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
                                   VectorSet& listed) {
  listed.clear();
  std::array<const CandidateList*, 4> lists{};
  int count = 0;
  for (int b = 0; b < 4; ++b) {
    const int x = 8 * (b & 1), y = 8 * (b >> 1);
    if (x < rect.x || y < rect.y || x >= rect.x + rect.width || y >= rect.y + rect.height) continue;
    if (hints.blocks[b] != nullptr) lists[count++] = hints.blocks[b];
  }
  if (count == 0) {
    if (hints.macroblock == nullptr) return {};
    const CandidateList& list = *hints.macroblock;
    CandidateList first(list.begin(), list.begin() + static_cast<ptrdiff_t>(std::min(limit, list.size())));
    for (const MotionVector& v : first) listed.insert(v);
    return first;
  }
  CandidateList merged;
  for (size_t rank = 0;; ++rank) {
    bool any = false;
    for (int l = 0; l < count; ++l) {
      if (rank >= lists[l]->size()) continue;
      any = true;
      const MotionVector v = (*lists[l])[rank];
      if (listed.insert(v)) merged.push_back(v);
      if (merged.size() >= limit) return merged;
    }
    if (!any) return merged;
  }
}

// Whether the depth-derived motion differs across the macroblock's 8x8 blocks (their most
// frequent vectors differ), or, without block lists, the macroblock has several vectors.
bool motion_varies(const MacroblockHints& hints) {
  const CandidateList* first = nullptr;
  for (const CandidateList* list : hints.blocks) {
    if (list == nullptr || list->empty()) continue;
    if (first != nullptr && list->front() != first->front()) return true;
    first = list;
  }
  return first == nullptr && hints.macroblock != nullptr && hints.macroblock->size() > 1;
}

// A macroblock's vector predictors towards one reference in the line coordinates of its
// epipolar line there (docs/codec.md 10.3), for pricing vectors against them.
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
// (docs/codec.md 10.5, "Partitions").
constexpr double kPartitionScreenMargin = 1.2;

// The intra frame's tools an intra macroblock uses (docs/codec.md 10.5).
CodingParams intra_tools(const BFrameParams& params) {
  CodingParams tools;
  tools.directional_intra = params.intra_prediction;
  tools.rd_intra_search = params.intra_rd_search;
  tools.transform_sizes = params.intra_transform_sizes;
  tools.cfl = params.intra_cfl;
  tools.rdoq = params.rdoq;
  tools.coarse_mode_search = true;
  tools.small_blocks = params.intra_small_blocks;
  return tools;
}

class BFrameEncoder {
 public:
  BFrameEncoder(FrameState& state, const PaddedSource& source, const BFrameParams& params,
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
        full_split_search_(params.full_inter_split_search),
        vector_predictors_(params.vector_predictors) {
    const double scale = quantizer_scale_q8(s_.inter_quantizer.qindex) / 256.0;
    lambda_ = std::max(0.0, params.lambda_factor) * scale * scale;
    lambda_sad_ = std::sqrt(lambda_);
    CodingParams tools = intra_tools(params);
    tools.rdoq = false;  // as every option is priced; the winner is searched again with RDOQ
    intra_search_ =
        std::make_unique<intra::MacroblockEncoder>(tools, s_.inter_quantizer.qindex, static_cast<float>(lambda_));
    intra_rd_search_ = std::make_unique<intra::MacroblockEncoder>(intra_tools(params), s_.inter_quantizer.qindex,
                                                                  static_cast<float>(lambda_));
  }

  MacroblockChoice choose(int mx, int my, const std::array<MacroblockHints, 2>& hints, BFrameStats* stats) {
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

    std::array<MotionVector, 2> best = predictors;
    for (int r = 0; r < s_.reference_count; ++r) {
      std::span<const MotionVector> list;
      if (hints[r].macroblock != nullptr) list = *hints[r].macroblock;
      best[r] = search_reference(r, kWholeMacroblock, predictor_lists_[r], list, stats);
    }

    MacroblockChoice winner, option;
    evaluate_skip(skip_mode, predicted_warp(s_, mx, my), &winner);
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
    int screened_count = 0;
    const uint8_t* source = source_.planes[0].data() + static_cast<size_t>(16 * my) * source_.strides[0] + 16 * mx;
    std::array<std::array<int16_t, 256>, 2> luma{}, warped{};
    // Warping is screened only towards references whose corner nodes differ: with four
    // (nearly) equal corners it predicts what a translation does, at a higher price.
    unsigned screen_warp = 0;
    for (int r = 0; r < s_.reference_count; ++r) {
      predict_macroblock_luma(*s_.references[r], reference_mb(s_, mx), reference_mb(s_, my), best[r],
                              luma[r].data(), s_.filter);
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
        float bits = mode_bits(s_, mx, my, mode) + partition_bits(s_, mx, my, Partition::k16x16);
        if (warp_allowed(s_, mode)) bits += bit_cost(s_.contexts.warp[warp_context(s_, mx, my)], warp);
        uint8_t prediction[256];
        if (mode == MacroblockMode::kBidirectional) {
          average_prediction(planes[0].data(), planes[1].data(), 256, prediction);
        } else {
          round_prediction(planes[mode == MacroblockMode::kBackward ? 1 : 0].data(), 256, prediction);
        }
        const int sad = sad_16x16(source, source_.strides[0], prediction);
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
    // Where skipping wins over the inter options, intra rarely wins (28 of 7,012 such
    // macroblocks at `svc encode -q 60` of the hall's 18-cell subset): not tried.
    if (winner.mode != MacroblockMode::kSkipped) consider(MacroblockMode::kIntra, false);
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
    encoder.encode(c.intra[intra_context(s_, mx, my)], choice.mode == MacroblockMode::kIntra);
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
      if (warp_allowed(s_, choice.mode)) encoder.encode(c.warp[warp_context(s_, mx, my)], choice.warp);
      if (choice.warp) {
        write_warp_nodes(encoder, choice.mode, &info);
      } else {
        write_vectors(encoder, choice, &info);
      }
    }
    info.inter_mode = choice.mode;
    info.inter_warp = choice.warp;
    info.luma_16x16 = choice.luma_16x16;
    if (s_.inter_transform_sizes) encoder.encode(c.luma_16x16[luma_16x16_context(s_, mx, my)], choice.luma_16x16);
    uint8_t local_coded[6] = {};
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
        encode_block_levels(encoder, c.inter_luma, choice.luma_levels.data(), 0, kNoCodedBlockFlag,
                            TransformSize::k16x16);
      }
    }
    for (int b = first_block; b < 6; ++b) {
      if (!local_coded[b]) continue;
      if (block_plane(b) == 0 && s_.inter_transform_sizes) {
        encoder.encode(c.luma_4x4, choice.split[b]);
        if (choice.split[b]) {
          for (int k = 0; k < 4; ++k) {
            encode_block_levels(encoder, c.inter_luma, choice.levels[b].data() + 16 * k, 0, 0, TransformSize::k4x4);
          }
          continue;
        }
      }
      encode_block_levels(encoder, block_plane(b) == 0 ? c.inter_luma : c.inter_chroma, choice.levels[b].data(), 0,
                          kNoCodedBlockFlag);
    }
    commit_macroblock(s_, mx, my, info, choice.reconstruction, choice.coded_mask);
  }

 private:
  void write_vectors(RangeEncoder& encoder, const MacroblockChoice& choice, MacroblockInfo* info) {
    const int contexts[2] = {mvd_context(s_, mx_, my_, 0), mvd_context(s_, mx_, my_, 1)};
    for (int r = 0; r < s_.reference_count; ++r) {
      if (!uses_reference(choice.mode, r)) continue;
      const MotionVector predictor = write_predictor_index(encoder, r, choice.vectors[r], predictor_lists_[r]);
      write_difference(encoder, contexts, r, choice.vectors[r], predictor, info);
      info->vectors[r] = choice.vectors[r];
    }
  }

  // The difference of `vector` from `predictor` (10.3), counted into the neighbour context.
  void write_difference(RangeEncoder& encoder, const int (&contexts)[2], int reference, MotionVector vector,
                        MotionVector predictor, MacroblockInfo* info) {
    const std::array<int64_t, 2> d = vector_difference(s_, reference, mx_, my_, vector, predictor);
    for (int c = 0; c < 2; ++c) {
      encode_mvd_component(encoder, s_.contexts, c, contexts[c], static_cast<int>(d[static_cast<size_t>(c)]));
      info->mvd_magnitude[static_cast<size_t>(c)] += static_cast<int>(std::llabs(d[static_cast<size_t>(c)]));
    }
  }

  // Each partition's direction and vector differences; the last vector per reference is
  // the one the macroblock leaves for its neighbours' predictors.
  void write_partition_vectors(RangeEncoder& encoder, const PartitionMotion& motion, MacroblockInfo* info) {
    const int contexts[2] = {mvd_context(s_, mx_, my_, 0), mvd_context(s_, mx_, my_, 1)};
    for (int k = 0; k < partition_count(motion.partition); ++k) {
      encode_direction(encoder, s_, mx_, my_, motion.modes[k]);
      for (int r = 0; r < s_.reference_count; ++r) {
        if (!uses_reference(motion.modes[k], r)) continue;
        const MotionVector predictor =
            write_predictor_index(encoder, r, motion.vectors[k][r],
                                  partition_predictors(motion, k, r, predictor_lists_[r]));
        write_difference(encoder, contexts, r, motion.vectors[k][r], predictor, info);
        info->vectors[r] = motion.vectors[k][r];
      }
    }
  }

  // Warped predictions of the current macroblock, made once per reference and reused by
  // screening, skip and inter evaluation (the corner nodes do not change within it).
  struct WarpCache {
    bool luma = false, chroma = false;
    MacroblockIntermediate prediction;
  };

  const MacroblockIntermediate& warped_prediction(int reference, bool with_chroma) {
    WarpCache& cache = warp_cache_[static_cast<size_t>(reference)];
    const WarpCorners corners = macroblock_corners(s_, reference, mx_, my_);
    if (!cache.luma) {
      predict_warp_macroblock_luma(*s_.references[reference], reference_mb(s_, mx_), reference_mb(s_, my_), corners,
                                   cache.prediction.y.data(), s_.filter);
      cache.luma = true;
    }
    if (with_chroma && !cache.chroma) {
      predict_warp_macroblock_chroma(*s_.references[reference], reference_mb(s_, mx_), reference_mb(s_, my_),
                                     corners, &cache.prediction, s_.filter);
      cache.chroma = true;
    }
    return cache.prediction;
  }

  // build_warp_prediction from the cache.
  void build_cached_warp_prediction(MacroblockMode mode, MacroblockPrediction* out) {
    if (mode == MacroblockMode::kBidirectional) {
      finish_prediction(warped_prediction(0, true), &warped_prediction(1, true), out);
    } else {
      finish_prediction(warped_prediction(mode == MacroblockMode::kBackward ? 1 : 0, true), nullptr, out);
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

  // The bits of the nodes a warp must send, weighted by kNewNodeShare: a node sent now
  // also serves the later macroblocks that share the corner, and charging it whole to
  // the first one keeps a face from ever starting to warp.
  float warp_nodes_bits(MacroblockMode mode) {
    float bits = 0;
    for (int r = 0; r < s_.reference_count; ++r) {
      if (uses_reference(mode, r)) bits += missing_nodes_bits(s_, r, mx_, my_, predictors_[r]);
    }
    return kNewNodeShare * bits;
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
    return vector_bits(reference, vector, predictor_lists_[reference]);
  }

  float vector_bits(int reference, MotionVector vector, const VectorPredictors& predictors) const {
    return vector_bits(vector, line_predictors(reference, predictors));
  }

  float vector_bits(MotionVector vector, const LinePredictors& predictors) const {
    float bits = 0;
    cheapest_predictor(vector, predictors, &bits);
    return bits;
  }

  // The usable predictors in the line coordinates of this macroblock's line towards
  // `reference`: worked out once for the many vectors a search prices against them.
  LinePredictors line_predictors(int reference, const VectorPredictors& predictors) const {
    LinePredictors out;
    out.count = predictors.count;
    out.usable = usable_predictors(predictors.count);
    out.line = macroblock_direction(s_, reference, mx_, my_);
    for (int i = 0; i < out.usable; ++i) {
      const MotionVector p = predictors.vectors[static_cast<size_t>(i)];
      out.coordinates[static_cast<size_t>(i)] = to_line_coordinates(p.x, p.y, out.line);
    }
    return out;
  }

  // The index of the predictor that codes `vector` in the fewest bits (the first of
  // equal ones), and those bits, index included.
  int cheapest_predictor(MotionVector vector, const LinePredictors& predictors, float* bits) const {
    int best = 0;
    const LineDirection line = predictors.line;
    const LineCoordinates coordinates = to_line_coordinates(vector.x, vector.y, line);
    for (int i = 0; i < predictors.usable; ++i) {
      const std::array<int64_t, 2> d =
          line_difference(line, coordinates, predictors.coordinates[static_cast<size_t>(i)]);
      const float candidate = predictor_index_bits(s_.contexts.predictor_index, predictors.count, i) +
                              mvd_costs_[0].bits(static_cast<int>(d[0])) +
                              mvd_costs_[1].bits(static_cast<int>(d[1]));
      if (i == 0 || candidate < *bits) {
        best = i;
        *bits = candidate;
      }
    }
    return best;
  }

  // Of `count` predictors, those the encoder may choose (the first only without the tool).
  int usable_predictors(int count) const { return vector_predictors_ ? count : 1; }

  // Codes the index of the predictor `vector` is cheapest from and returns that predictor.
  MotionVector write_predictor_index(RangeEncoder& encoder, int reference, MotionVector vector,
                                     const VectorPredictors& predictors) {
    float bits = 0;
    const int index = cheapest_predictor(vector, line_predictors(reference, predictors), &bits);
    encode_predictor_index(encoder, s_.contexts.predictor_index, predictors.count, index);
    return predictors.vectors[static_cast<size_t>(index)];
  }

  // Luma SAD of the prediction of `rect` from `reference` with vector v: on the search
  // planes (quarter positions approximated) where they reach, else exact.
  int rect_sad(int reference, const PartitionRect& rect, MotionVector v) const {
    const uint8_t* source =
        source_.planes[0].data() + static_cast<size_t>(16 * my_) * source_.strides[0] + 16 * mx_;
    if (search_[reference] != nullptr) {
      const int sad = search_[reference]->sad(source + rect.y * source_.strides[0] + rect.x, source_.strides[0],
                                              16 * reference_mb(s_, mx_) + rect.x,
                                              16 * reference_mb(s_, my_) + rect.y, rect.width, rect.height, v);
      if (sad >= 0) return sad;
    }
    const ImageYCbCr420& ref = *s_.references[reference];
    if (rect.width == 16 && rect.height == 16) {
      return sad_macroblock_luma(ref, reference_mb(s_, mx_), reference_mb(s_, my_), v, source, source_.strides[0],
                                 s_.filter);
    }
    int16_t intermediate[256];
    uint8_t prediction[256];
    predict_block(ref.y.data(), ref.width, ref.height, PlaneKind::kLuma, 16 * reference_mb(s_, mx_) + rect.x,
                  16 * reference_mb(s_, my_) + rect.y, rect.width, rect.height, v.x, v.y,
                  intermediate + 16 * rect.y + rect.x, 16, s_.filter);
    for (int y = rect.y; y < rect.y + rect.height; ++y) {
      round_prediction(intermediate + 16 * y + rect.x, rect.width, prediction + 16 * y + rect.x);
    }
    return sad_rect(source, source_.strides[0], prediction, rect);
  }

  // Within the range and, without quarter-pel vectors, on a half-pel position (odd
  // components away from zero).
  MotionVector clamp_vector(MotionVector v) const {
    auto component = [&](int c) {
      if (!quarter_pel_ && (c & 1) != 0) c += c > 0 ? 1 : -1;
      const int limit = quarter_pel_ ? s_.vector_limit : s_.vector_limit & ~1;
      return static_cast<int16_t>(std::clamp(c, -limit, limit));
    };
    return MotionVector{component(v.x), component(v.y)};
  }

  // Best vector for `rect` towards one reference by SAD + lambda * vector bits over the
  // supplied candidates and the predictor (the zero vector too when no candidate is given).
  MotionVector search_reference(int reference, const PartitionRect& rect, const VectorPredictors& predictors,
                                std::span<const MotionVector> list, BFrameStats* stats) {
    tried_.clear();
    MotionVector best = predictors.vectors[0];
    double best_cost = 1e300;
    const LinePredictors priced = line_predictors(reference, predictors);
    auto try_vector = [&](MotionVector v) {
      v = clamp_vector(v);
      if (!tried_.insert(v)) return false;
      const double rate = lambda_sad_ * vector_bits(v, priced);
      if (rate >= best_cost) return true;  // cannot win whatever its SAD
      const int sad = rect_sad(reference, rect, v);
      if (stats != nullptr) ++stats->sad_evaluations;
      const double cost = sad + rate;
      if (cost < best_cost) {
        best_cost = cost;
        best = v;
      }
      return true;
    };
    int supplied = 0;
    // Lists are ranked (most pixels first): the tail rarely wins and costs a SAD each.
    const size_t count = std::min(list.size(), static_cast<size_t>(max_candidates_));
    // A candidate is the motion of one pixel; on the line through the centre it predicts
    // a surface facing the camera as well or better, and costs no across difference.
    const LineDirection line = macroblock_direction(s_, reference, mx_, my_);
    for (size_t k = 0; k < count; ++k) {
      supplied += try_vector(list[k]);
      if (s_.lines[reference].present()) try_vector(onto_line(line, list[k], s_.vector_limit));
    }
    if (stats != nullptr && rect.width == 16 && rect.height == 16) stats->candidates_evaluated += supplied;
    if (supplied == 0) try_vector(MotionVector{});
    for (int i = 0; i < usable_predictors(predictors.count); ++i)
      try_vector(predictors.vectors[static_cast<size_t>(i)]);
    if (refine_) {
      // The half-pel ring around the best, then the quarter-pel ring around the new best.
      for (int step = 2; step >= (quarter_pel_ ? 1 : 2); --step) {
        const MotionVector centre = best;
        for (int dy = -step; dy <= step; dy += step) {
          for (int dx = -step; dx <= step; dx += step) {
            if (dx != 0 || dy != 0) {
              try_vector(MotionVector{static_cast<int16_t>(centre.x + dx), static_cast<int16_t>(centre.y + dy)});
            }
          }
        }
      }
    }
    return best;
  }

  // The chosen option's residual quantized again with RDOQ: its levels, coded mask,
  // reconstruction and cost change; its prediction and side information do not.
  void requantize(MacroblockChoice* choice) {
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

  // A translational skip tries each predictor index.
  void evaluate_skip(MacroblockMode mode, bool warp, MacroblockChoice* out) {
    out->mode = MacroblockMode::kSkipped;
    out->warp = warp;
    out->vectors = predictors_;
    out->coded_mask = 0;
    const float skip_bits = bit_cost(s_.contexts.skip[skip_context(s_, mx_, my_)], 1);
    if (warp) {
      build_cached_warp_prediction(mode, &out->reconstruction);
      out->cost = static_cast<double>(prediction_error(out->reconstruction)) +
                  lambda_ * (skip_bits + warp_nodes_bits(mode));
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

  int64_t prediction_error(const MacroblockPrediction& prediction) const {
    int64_t distortion = 0;
    for (int b = 0; b < 6; ++b) distortion += block_error(b, block_samples(prediction, b));
    return distortion;
  }

  void evaluate_inter(MacroblockMode mode, bool warp, const std::array<MotionVector, 2>& best,
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

  // Each 8x8 block's residual, kept where it lowers the cost; sets the levels, coded
  // mask, reconstruction and cost (with `bits` of side information).
  void code_residual(const MacroblockPrediction& prediction, float bits, MacroblockChoice* out) {
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

  // The whole luma residual as one 16x16 block, coded where that lowers the cost; its
  // levels go to out->luma_levels. Adds the error and bits (coded flag and levels).
  // Returns whether it is coded.
  bool code_luma_16x16(const MacroblockPrediction& prediction, MacroblockChoice* out, uint8_t* reconstruction,
                       int64_t* distortion, float* bits) {
    const SyntaxContexts& c = s_.contexts;
    const uint8_t* src = source_block(0);
    const int source_stride = source_.strides[0];
    const uint8_t no_local[6] = {};
    const AdaptiveBit& cbp_model = c.cbp_luma[coded_context(s_, no_local, 0, mx_, my_, 2 * mx_, 2 * my_)];
    int16_t residual[256];
    subtract_prediction(src, source_stride, prediction.y.data(), 16, 16, residual);
    const int visible_w = visible_w_[0] + visible_w_[1], visible_h = visible_h_[0] + visible_h_[2];
    const int64_t uncoded_error = squared_error(src, source_stride, prediction.y.data(), 16, visible_w, visible_h);
    int16_t* levels = out->luma_levels.data();
    float levels_bits = 0;
    const int nonzero = transform_quantize_block_rd(s_.inter_quantizer_16x16, residual, quantize_rd_, c.inter_luma,
                                                    0, kNoCodedBlockFlag, static_cast<float>(lambda_), levels,
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

  // Luma 8x8 block b's `residual` as four 4x4 blocks in raster order: their levels (16
  // each) and the reconstruction from `pred`, 8 samples a row. Adds the blocks' bits
  // (coded-block flags and levels) to *bits; returns the squared error.
  int64_t code_quarters(const int16_t* residual, const uint8_t* pred, int stride, int b, int16_t* levels,
                        uint8_t* reconstruction, float* bits) {
    const BlockContextSet& contexts = s_.contexts.inter_luma;
    for (int k = 0; k < 4; ++k) {
      const int row = 4 * (k >> 1), column = 4 * (k & 1);
      int16_t quarter[16];
      for (int y = 0; y < 4; ++y) std::copy_n(residual + 8 * (row + y) + column, 4, quarter + 4 * y);
      int16_t* quarter_levels = levels + 16 * k;
      const uint8_t* quarter_pred = pred + row * stride + column;
      uint8_t* out = reconstruction + 8 * row + column;
      float levels_bits = 0;
      if (transform_quantize_block_rd(s_.inter_quantizer_4x4, quarter, quantize_rd_, contexts, 0, 0,
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

  // 8x8 block b's residual, coded where that lowers the cost (a luma block, when the
  // frame codes transform sizes, as one 8x8 block or four 4x4 ones): its levels, split
  // flag, coded flag and reconstruction; adds its error and bits.
  void code_block(const MacroblockPrediction& prediction, int b, uint8_t* local_coded, MacroblockChoice* out,
                  int64_t* distortion, float* bits) {
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
                                                              0, kNoCodedBlockFlag, static_cast<float>(lambda_),
                                                              levels, TransformType::kDctDct, &levels_bits) > 0;
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

  // A split macroblock: per partition in coding order, the best vector per reference
  // from the partition's own candidates (and the 16x16 choice), then the direction by
  // SAD + side bits; the whole then by rate-distortion cost.
  // `best_screened`: the best 16x16 inter option's screening cost (kPartitionScreenMargin).
  void evaluate_partitioned(Partition partition, const std::array<MacroblockHints, 2>& hints,
                            const std::array<MotionVector, 2>& macroblock_best, double best_screened,
                            BFrameStats* stats, MacroblockChoice* out) {
    PartitionMotion& motion = out->motion;
    motion = PartitionMotion{};
    motion.partition = partition;
    out->warp = false;
    out->vectors = predictors_;
    float bits = bit_cost(s_.contexts.skip[skip_context(s_, mx_, my_)], 0) +
                 bit_cost(s_.contexts.intra[intra_context(s_, mx_, my_)], 0) +
                 partition_bits(s_, mx_, my_, partition);
    const uint8_t* source =
        source_.planes[0].data() + static_cast<size_t>(16 * my_) * source_.strides[0] + 16 * mx_;
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
            average_prediction(luma[0].y.data() + offset, luma[1].y.data() + offset, rect.width,
                               prediction + offset);
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

  // The intra frame's search (docs/codec.md 3.2) over the macroblock's luma, then its Cb
  // and Cr block, predicting from the reconstructed neighbours; the choice is
  // reconstructed in place in the frame's planes (the only option that writes there
  // before the commit) and marked in the intra neighbour state.
  // `budget`: the cost to beat (the best option so far). Past it the luma search skips
  // part of its partitions (MacroblockEncoder::choose_luma), and a luma costing that
  // much alone leaves chroma unsearched and out->cost infinite.
  void evaluate_intra(MacroblockChoice* out, double budget = std::numeric_limits<double>::infinity()) {
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
    cost += search.choose_luma(c.intra_luma, s_.intra_planes[0], source[0], recon[0], s_.strides[0], mx_, my_,
                               &choice.luma, static_cast<float>(budget - cost));
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
  const bool full_split_search_;  // 4x4 trials also where the 8x8 transform keeps no level
  const bool vector_predictors_;
  int mx_ = 0, my_ = 0;
  std::array<MotionVector, 2> predictors_{};  // the first of each list
  std::array<VectorPredictors, 2> predictor_lists_{};
  std::array<int, 6> visible_w_{}, visible_h_{};
  VectorSet tried_;
  VectorSet partition_listed_;             // partition_candidates' duplicates check
  std::array<MvdCostTable, 2> mvd_costs_;  // per component, for the current macroblock
  std::array<WarpCache, 2> warp_cache_;
  // The intra frame's macroblock search at the frame's qindex and lambda: plain
  // quantization, and RDOQ for the winner.
  std::unique_ptr<intra::MacroblockEncoder> intra_search_, intra_rd_search_;
};

}  // namespace

int suggested_b_qindex(int intra_qindex) {
  return std::clamp(intra_qindex + kBQIndexOffset, kMinQIndex, kMaxQIndex);
}

std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const FaceCandidates& candidates0,
                                    const FaceCandidates& candidates1, const BFrameParams& params,
                                    ImageYCbCr420* reconstruction, BFrameStats* stats) {
  return encode_b_frame(source, ref0, ref1, candidates0, candidates1, nullptr, nullptr, params, reconstruction,
                        stats);
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

// What an inter or skipped macroblock's prediction was built from, so it can be built
// again with another filter bank.
struct PredictionRecord {
  MacroblockMode mode = MacroblockMode::kIntra;  // the prediction's mode; kIntra: none
  bool warp = false;
  std::array<MotionVector, 2> vectors{};
  PartitionMotion motion;
};

// A frame whose macroblocks are coded with one filter bank, before its loop filters.
struct CodedMacroblocks {
  FrameState state;
  PaddedSource padded;
  BFrameHeader header;                          // its flags are known when the frame is finished
  std::unique_ptr<std::vector<uint8_t>> bytes;  // the header, then what the range encoder appends
  std::unique_ptr<RangeEncoder> encoder;
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
  if (header.epipolar_lines) {
    for (int r = 0; r < state.reference_count; ++r) encode_epipolar_lines(*coded.encoder, state.lines[r]);
  }
  BFrameEncoder coder(state, coded.padded, params, search);
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
    for (int r = 0; r < state.reference_count; ++r) {
      for (uint8_t known : state.node_known[r]) stats->warp_nodes_coded += known;
    }
  }
  if (reconstruction != nullptr) crop_output(state, reconstruction);
  return bytes;
}

}  // namespace

std::vector<uint8_t> encode_b_frame(const ImageYCbCr420& source, const ImageYCbCr420& ref0,
                                    const ImageYCbCr420* ref1, const FaceCandidates& candidates0,
                                    const FaceCandidates& candidates1, const WarpField* warp0,
                                    const WarpField* warp1, const BFrameParams& params,
                                    ImageYCbCr420* reconstruction, BFrameStats* stats) {
  const std::array<ReferenceHints, 2> hints = {ReferenceHints{&candidates0, nullptr, warp0, {}},
                                               ReferenceHints{&candidates1, nullptr, warp1, {}}};
  return encode_b_frame(source, ref0, ref1, hints, params, reconstruction, stats);
}

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
  auto code = [&](InterpolationFilter filter) {
    return code_macroblocks(source, ref0, ref1, hints, params, search, filter, stats != nullptr);
  };
  CodedMacroblocks best = code(InterpolationFilter::kRegular);
  if (params.switchable_filter) {
    // Screen: the regular bank's motion predicted again through each other bank. Only the
    // bank whose predictions come clearly closer to the source is coded in full, and it
    // is kept when the whole frame (squared error plus bits, before the loop filters)
    // costs less; so the loop filters' search runs once, on the winner.
    const int64_t regular_error = prediction_error(best, InterpolationFilter::kRegular);
    int64_t screened_error = regular_error;
    InterpolationFilter candidate = InterpolationFilter::kRegular;
    for (int f = 1; f < kInterpolationFilterCount; ++f) {
      const int64_t error = prediction_error(best, static_cast<InterpolationFilter>(f));
      if (error < screened_error) {  // ties keep the earlier bank
        screened_error = error;
        candidate = static_cast<InterpolationFilter>(f);
      }
    }
    if (candidate != InterpolationFilter::kRegular &&
        static_cast<double>(screened_error) < (1.0 - kFilterScreenMargin) * static_cast<double>(regular_error)) {
      const double scale = quantizer_scale_q8(std::clamp(params.qindex, kMinQIndex, kMaxQIndex)) / 256.0;
      const double lambda = params.lambda_factor * scale * scale;
      auto cost = [&](const CodedMacroblocks& coded) {
        return static_cast<double>(frame_error(coded.state, coded.padded)) +
               lambda * 8.0 * static_cast<double>(coded.bytes->size());
      };
      CodedMacroblocks trial = code(candidate);
      if (cost(trial) < cost(best)) best = std::move(trial);
    }
  }
  return finish_frame(best, params, reconstruction, stats);
}

}  // namespace svc::codec
