// SPDX-License-Identifier: BSD-2-Clause
// B-face decoder: reads each macroblock's mode, vectors or nodes and residual, and
// reconstructs it with the encoder's own routines (bframe_state.h).
#include "codec/decoder/bframe_decoder.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>

#include "codec/common/bframe_loop_filter.h"
#include "codec/common/bframe_state.h"
#include "codec/common/cube_padding.h"
#include "codec/common/thread_buffers.h"
#include "codec/decoder/bframe_syntax_reader.h"
#include "codec/decoder/cdef_syntax.h"
#include "codec/decoder/coefficient_reader.h"
#include "codec/decoder/intra_syntax_reader.h"
#include "codec/decoder/range_decoder.h"
#include "codec/decoder/syntax_version.h"

namespace svc::codec {
namespace {

using namespace bframe;

// Bytes held by a state's buffers (codec/common/thread_buffers.h); the intra neighbour state
// holds 3 bytes (mode, coded, width) per 4x4 unit of each plane.
uint64_t state_buffer_bytes(const FrameState& s) {
  uint64_t bytes = s.macroblocks.capacity() * sizeof(MacroblockInfo) + capacity_bytes(s.nodes[0]) +
                   capacity_bytes(s.nodes[1]) + capacity_bytes(s.node_known[0]) + capacity_bytes(s.node_known[1]);
  for (int p = 0; p < 3; ++p) {
    const uint64_t rows = (p == 0 ? 16 : 8) * static_cast<uint64_t>(s.mbs_y);
    bytes += capacity_bytes(s.planes[p]) + capacity_bytes(s.coded[p]) + 3 * (s.strides[p] / 4) * (rows / 4);
  }
  return bytes;
}

Status corrupt(const std::string& what) { return Status(ErrorCode::kCorruptData, "B-face: " + what); }

std::string macroblock_name(int mx, int my) {
  return "macroblock (" + std::to_string(mx) + ", " + std::to_string(my) + ")";
}

// Reads the blocks of one plane of an intra macroblock and reconstructs each in place in
// the frame's plane, so the next block predicts from it.
class IntraBlockDecoder final : public intra::BlockReader {
 public:
  IntraBlockDecoder(FrameState& s, RangeDecoder& decoder, int plane, int mx, int my)
      : s_(s), decoder_(decoder), plane_(plane), mx_(mx), my_(my) {}

  bool read(int x0, int y0, TransformSize size) override {
    intra::PlaneState& state = s_.intra_planes[static_cast<size_t>(plane_)];
    if (!intra::read_block_syntax(decoder_, s_.contexts.intra_luma, state, x0, y0, size, &block_)) return false;
    intra::reconstruct_block_in_plane(state, s_.planes[0].data(), s_.strides[0], x0, y0, size, block_.mode,
                                      dequantize(x0, y0, size), block_.transform_type);
    return true;
  }

  // The 8x8 chroma block at (x0, y0) of this plane; a Cb block's mode goes to `cb`, which
  // the Cr block reads. CfL predicts from the macroblock's reconstructed luma.
  bool read_chroma(int x0, int y0, ChromaMode* cb) {
    intra::PlaneState& state = s_.intra_planes[static_cast<size_t>(plane_)];
    const ChromaPlane plane = plane_ == 1 ? ChromaPlane::kCb : ChromaPlane::kCr;
    if (!intra::read_chroma_block_syntax(decoder_, s_.contexts.intra_chroma, state, x0, y0, plane, cb, &block_)) {
      return false;
    }
    intra::reconstruct_chroma_block_in_plane(state, s_.planes[static_cast<size_t>(plane_)].data(),
                                             s_.strides[plane_], x0, y0, {block_.mode, block_.cfl_alpha},
                                             s_.planes[0].data(), s_.strides[0],
                                             dequantize(x0, y0, intra::kChromaSize), block_.transform_type);
    return true;
  }

  // The macroblock's coded flags (bit b for block b of 4.2) from the blocks read.
  uint8_t coded_mask() const { return coded_mask_; }

 private:
  // The dequantized levels of the block read (null when it has none), marked coded.
  const int16_t* dequantize(int x0, int y0, TransformSize size) {
    const int count = block_.count;
    if (count > 0) {
      const Quantizer& quantizer = intra::quantizer_for(s_.intra_quantizers, size);
      std::fill_n(coefficients_, transform_area(size), int16_t{0});
      for (int i = 0; i < count; ++i) {
        const BlockLevel& level = block_.levels[i];
        coefficients_[level.position] =
            static_cast<int16_t>(dequantize_level(quantizer, level.position, level.level));
      }
      mark_coded(x0, y0, size);
    }
    return count > 0 ? coefficients_ : nullptr;
  }

  // Sets the coded flag of every 8x8 block (chroma: the block) the transform block covers.
  void mark_coded(int x0, int y0, TransformSize size) {
    if (plane_ != 0) {
      coded_mask_ |= static_cast<uint8_t>(1 << (3 + plane_));
      return;
    }
    for (int b = 0; b < 4; ++b) {
      const int bx = 16 * mx_ + 8 * (b & 1), by = 16 * my_ + 8 * (b >> 1);
      if (intra::blocks_overlap(x0, y0, size, bx, by, TransformSize::k8x8))
        coded_mask_ |= static_cast<uint8_t>(1 << b);
    }
  }

  FrameState& s_;
  RangeDecoder& decoder_;
  int plane_, mx_, my_;
  uint8_t coded_mask_ = 0;
  intra::BlockSyntax block_;
  int16_t coefficients_[kMaxTransformArea];
};

// Reads macroblocks in coding order and reconstructs each into the frame state.
class MacroblockReader {
 public:
  // `edges` null: every edge allowed, none recorded.
  MacroblockReader(FrameState& s, RangeDecoder& decoder, BorderEdges* edges)
      : s_(s), c_(s.contexts), decoder_(decoder), edges_(edges) {}

  // Reads and reconstructs macroblock (mx, my); `mode` receives how it was coded.
  Status read(int mx, int my, MacroblockMode* mode) {
    mx_ = mx;
    my_ = my;
    info_ = MacroblockInfo{};
    const MacroblockMode skip_mode = predicted_mode(s_, mx, my);
    predictors_ = {};
    for (int r = 0; r < s_.reference_count; ++r) {
      predictor_lists_[r] = macroblock_predictors(s_, mx, my, r);
      predictors_[r] = predictor_lists_[r].vectors[0];
    }
    info_.inter_mode = skip_mode;
    info_.inter_warp = predicted_warp(s_, mx, my);
    info_.vectors = predictors_;
    coded_mask_ = 0;
    if (decoder_.decode(c_.skip[skip_context(s_, mx, my)])) {
      SVC_RETURN_IF_ERROR(read_skipped(skip_mode));
    } else if (decoder_.decode(c_.intra[intra_context(s_, mx, my)])) {
      SVC_RETURN_IF_ERROR(read_intra());
    } else {
      SVC_RETURN_IF_ERROR(read_inter());
    }
    commit_macroblock(s_, mx, my, info_, reconstruction_, coded_mask_);
    *mode = info_.mode;
    return Status::Ok();
  }

 private:
  Status fail(const std::string& what) const { return corrupt(macroblock_name(mx_, my_) + ": " + what); }

  // Checks a prediction's reads of the cube border against the edges allowed, before it
  // is built, and records them.
  Status note_border_reads(const PredictionRecord& record) {
    if (edges_ == nullptr) return Status::Ok();
    const std::array<uint8_t, 2> edges = border_edges_read(s_, mx_, my_, record);
    for (int r = 0; r < s_.reference_count; ++r) {
      const int outside = edges[r] & ~edges_->allowed[r];
      if (outside != 0) {
        return fail("prediction from reference " + std::to_string(r) + " reads the cube border across edge " +
                    std::to_string(std::countr_zero(static_cast<unsigned>(outside))) +
                    ", whose face the frame does not depend on");
      }
      edges_->read[r] = static_cast<uint8_t>(edges_->read[r] | edges[r]);
    }
    return Status::Ok();
  }

  // Reads the missing nodes of the references `mode` uses; stores the centre vectors.
  bool read_warp_nodes(MacroblockMode mode) {
    if (!warp_allowed(s_, mode)) return false;
    for (int r = 0; r < s_.reference_count; ++r) {
      if (!uses_reference(mode, r)) continue;
      if (!decode_missing_nodes(decoder_, s_, r, mx_, my_, predictors_[r])) return false;
      info_.vectors[r] = warp_centre_vector(s_, macroblock_corners(s_, r, mx_, my_));
    }
    return true;
  }

  Status read_skipped(MacroblockMode skip_mode) {
    info_.mode = MacroblockMode::kSkipped;
    if (info_.inter_warp) {
      if (!read_warp_nodes(skip_mode)) return fail("invalid warp node");
      SVC_RETURN_IF_ERROR(note_border_reads({skip_mode, true, {}, {}}));
      build_warp_prediction(s_, mx_, my_, skip_mode, &reconstruction_);
    } else {
      const int count = skip_predictor_count(predictor_lists_, skip_mode);
      const int index = decode_predictor_index(decoder_, c_.skip_predictor_index, count);
      info_.vectors = skip_vectors(predictor_lists_, skip_mode, index);
      SVC_RETURN_IF_ERROR(note_border_reads({skip_mode, false, info_.vectors, {}}));
      build_prediction(s_, mx_, my_, skip_mode, info_.vectors, &reconstruction_);
    }
    return Status::Ok();
  }

  // The intra frame's syntax: the luma macroblock, then the Cb and the Cr block, each
  // reconstructed in the frame's planes as it is read (docs/codec.md 3.7).
  Status read_intra() {
    info_.mode = MacroblockMode::kIntra;
    IntraBlockDecoder luma(s_, decoder_, 0, mx_, my_);
    intra::LumaPartition partition = 0;
    if (!intra::read_luma_macroblock(decoder_, c_.intra_luma, s_.intra_planes[0], mx_, my_, luma, &partition)) {
      return fail("invalid intra levels");
    }
    IntraBlockDecoder cb(s_, decoder_, 1, mx_, my_), cr(s_, decoder_, 2, mx_, my_);
    ChromaMode cb_mode;
    if (!cb.read_chroma(8 * mx_, 8 * my_, &cb_mode)) return fail("invalid intra levels");
    if (!cr.read_chroma(8 * mx_, 8 * my_, &cb_mode)) return fail("invalid intra levels");
    coded_mask_ = static_cast<uint8_t>(luma.coded_mask() | cb.coded_mask() | cr.coded_mask());
    copy_macroblock_out(s_, mx_, my_, &reconstruction_);
    return Status::Ok();
  }

  Status read_inter() {
    const Partition partition = decode_partition(decoder_, s_, mx_, my_);
    if (partition != Partition::k16x16) return read_partitioned(partition);
    const MacroblockMode mode = decode_direction(decoder_, s_, mx_, my_);
    info_.mode = mode;
    info_.inter_mode = mode;
    info_.inter_warp = warp_allowed(s_, mode) && decoder_.decode(c_.warp[warp_context(s_, mx_, my_)]) != 0;
    if (info_.inter_warp && !read_warp_nodes(mode)) return fail("invalid warp node");
    if (!info_.inter_warp) {
      for (int r = 0; r < s_.reference_count; ++r) {
        if (uses_reference(mode, r)) SVC_RETURN_IF_ERROR(read_vector(r, predictor_lists_[r], &info_.vectors[r]));
      }
    }
    uint8_t local_coded[6] = {};
    read_coded_flags(local_coded);
    SVC_RETURN_IF_ERROR(note_border_reads({mode, info_.inter_warp, info_.vectors, {}}));
    if (info_.inter_warp) {
      build_warp_prediction(s_, mx_, my_, mode, &prediction_);
    } else {
      build_prediction(s_, mx_, my_, mode, info_.vectors, &prediction_);
    }
    return read_residual(local_coded);
  }

  // Each partition's direction and vector differences, then the macroblock's residual.
  Status read_partitioned(Partition partition) {
    PartitionMotion motion;
    motion.partition = partition;
    const int count = partition_count(partition);
    for (int k = 0; k < count; ++k) {
      motion.modes[k] = decode_direction(decoder_, s_, mx_, my_);
      for (int r = 0; r < s_.reference_count; ++r) {
        if (!uses_reference(motion.modes[k], r)) continue;
        SVC_RETURN_IF_ERROR(
            read_vector(r, partition_predictors(motion, k, r, predictor_lists_[r]), &motion.vectors[k][r]));
        info_.vectors[r] = motion.vectors[k][r];
      }
    }
    info_.partition = partition;
    info_.mode = motion.modes[count - 1];
    info_.inter_mode = info_.mode;
    info_.inter_warp = false;
    uint8_t local_coded[6] = {};
    read_coded_flags(local_coded);
    SVC_RETURN_IF_ERROR(note_border_reads({info_.mode, false, {}, motion}));
    build_partition_prediction(s_, mx_, my_, motion, &prediction_);
    return read_residual(local_coded);
  }

  // The luma transform size (when the frame codes it), then the coded flags: one for a
  // 16x16 luma block (standing for its four 8x8 blocks), else one per 8x8 block.
  void read_coded_flags(uint8_t* local_coded) {
    info_.luma_16x16 = s_.inter_transform_sizes && decoder_.decode(c_.luma_16x16[luma_16x16_context(s_, mx_, my_)]);
    for (int b = 0; b < 6; ++b) {
      const int plane = block_plane(b);
      if (info_.luma_16x16 && b >= 1 && b <= 3) {
        local_coded[b] = local_coded[0];
      } else {
        const int context = coded_context(s_, local_coded, plane, mx_, my_, block_x(b, mx_), block_y(b, my_));
        local_coded[b] = static_cast<uint8_t>(
            decoder_.decode(plane == 0 ? c_.cbp_luma[context] : c_.cbp_chroma[plane - 1][context]));
      }
      coded_mask_ |= static_cast<uint8_t>(local_coded[b] << b);
    }
  }

  // One vector towards reference r: the index of its predictor among `predictors`, then
  // the difference (x, then y) added to that predictor.
  Status read_vector(int r, const VectorPredictors& predictors, MotionVector* vector) {
    const int index = decode_predictor_index(decoder_, c_.predictor_index, predictors.count);
    const MotionVector predictor = predictors.vectors[static_cast<size_t>(index)];
    const int d0 = decode_mvd_component(decoder_, c_, 0, mvd_context(s_, mx_, my_, 0));
    const int d1 = decode_mvd_component(decoder_, c_, 1, mvd_context(s_, mx_, my_, 1));
    if (!add_vector_difference(s_, r, mx_, my_, predictor, {d0, d1}, vector)) {
      return fail("motion vector difference (" + std::to_string(d0) + ", " + std::to_string(d1) +
                  ") towards reference " + std::to_string(r) + " leads beyond the limit of " +
                  std::to_string(s_.vector_limit) + " quarter-pels");
    }
    info_.mvd_magnitude[0] += std::abs(d0);
    info_.mvd_magnitude[1] += std::abs(d1);
    return Status::Ok();
  }

  // Prediction plus the coded residual of each block whose flag is set.
  Status read_residual(const uint8_t* local_coded) {
    int first_block = 0;
    if (info_.luma_16x16) {
      first_block = 4;
      if (!local_coded[0]) {
        std::copy_n(prediction_.y.data(), 256, reconstruction_.y.data());
      } else {
        SVC_RETURN_IF_ERROR(read_block(c_.inter_luma, kNoCodedBlockFlag, s_.inter_quantizer_16x16,
                                       prediction_.y.data(), reconstruction_.y.data(), 16));
      }
    }
    for (int b = first_block; b < 6; ++b) {
      const uint8_t* pred = block_samples(prediction_, b);
      uint8_t* recon = block_samples(reconstruction_, b);
      const int stride = block_stride(b);
      if (!local_coded[b]) {
        for (int y = 0; y < 8; ++y) std::copy_n(pred + y * stride, 8, recon + y * stride);
        continue;
      }
      if (block_plane(b) == 0 && s_.inter_transform_sizes && decoder_.decode(c_.luma_4x4)) {
        // Four 4x4 blocks in raster order, each with its coded flag (context 0).
        for (int k = 0; k < 4; ++k) {
          const int offset = 4 * (k >> 1) * stride + 4 * (k & 1);
          SVC_RETURN_IF_ERROR(
              read_block(c_.inter_luma, 0, s_.inter_quantizer_4x4, pred + offset, recon + offset, stride));
        }
        continue;
      }
      SVC_RETURN_IF_ERROR(read_block(block_plane(b) == 0 ? c_.inter_luma : c_.inter_chroma, kNoCodedBlockFlag,
                                     s_.inter_quantizer, pred, recon, stride));
    }
    return Status::Ok();
  }

  FrameState& s_;
  SyntaxContexts& c_;
  RangeDecoder& decoder_;
  BorderEdges* edges_;
  int mx_ = 0, my_ = 0;
  MacroblockInfo info_;
  std::array<MotionVector, 2> predictors_{};  // the first of each list
  std::array<VectorPredictors, 2> predictor_lists_{};
  uint8_t coded_mask_ = 0;
  MacroblockPrediction prediction_, reconstruction_;
  // One residual block of quantizer.size read with `contexts` (coded_block_context as
  // decode_block_levels takes it) and added to `pred` into `recon`; a block without
  // levels copies the prediction.
  Status read_block(BlockContextSet& contexts, int coded_block_context, const Quantizer& quantizer,
                    const uint8_t* pred, uint8_t* recon, int stride) {
    int count = 0;
    if (!decode_block_levels(decoder_, contexts, coded_block_context, decoded_, &count, quantizer.size)) {
      return fail("invalid residual levels");
    }
    const int width = transform_width(quantizer.size);
    if (count == 0) {
      for (int y = 0; y < width; ++y) std::copy_n(pred + y * stride, width, recon + y * stride);
      return Status::Ok();
    }
    std::fill_n(levels_, transform_area(quantizer.size), int16_t{0});
    for (int i = 0; i < count; ++i) levels_[decoded_[i].position] = decoded_[i].level;
    reconstruct_residual_block(quantizer, levels_, pred, stride, recon, stride);
    return Status::Ok();
  }

  int16_t levels_[kMaxTransformArea];
  BlockLevel decoded_[kMaxTransformArea];
};

// Header byte 2: bits 0-2 reference border units, bits 3-4 interpolation filter, bit 5
// reference count - 1, bits 6-7 warp mask.
constexpr int kFilterShift = 3, kSecondReferenceShift = 5, kWarpMaskShift = 6;
constexpr uint8_t kBorderMask = 0x07, kFilterMask = 0x03, kWarpMaskMask = 0x03;

}  // namespace

Status parse_b_frame_header(std::span<const uint8_t> bytes, BFrameHeader* out) {
  if (bytes.size() < static_cast<size_t>(kBFrameHeaderBytes)) {
    return corrupt("payload of " + std::to_string(bytes.size()) + " bytes is shorter than the " +
                   std::to_string(kBFrameHeaderBytes) + "-byte header");
  }
  if (!(bytes[0] & kBidirectionalTypeBit)) return corrupt("byte 0: frame type bit says intra, not bidirectional");
  SVC_RETURN_IF_ERROR(
      check_syntax_version("B-face", bytes[0] & kSyntaxVersionMask, kBFrameSyntaxFirst, kBFrameSyntaxVersion));
  const uint8_t references = bytes[kBFrameReferencesByte], flags = bytes[kBFrameFlagsByte];
  const int border_units = references & kBorderMask, filter = (references >> kFilterShift) & kFilterMask;
  const int reference_count = 1 + ((references >> kSecondReferenceShift) & 1);
  const int warp_mask = (references >> kWarpMaskShift) & kWarpMaskMask;
  if (border_units > kMaxCubeBorderUnits) {
    return corrupt("byte 2: reference border of " + std::to_string(border_units) + " units outside 0.." +
                   std::to_string(kMaxCubeBorderUnits));
  }
  if (filter >= kInterpolationFilterCount) {
    return corrupt("byte 2: interpolation filter " + std::to_string(filter) + " is not 0, 1 or 2");
  }
  if ((warp_mask & ~((1 << reference_count) - 1)) != 0) {
    return corrupt("byte 2: warp mask " + std::to_string(warp_mask) + " names a reference beyond the " +
                   std::to_string(reference_count) + " present");
  }
  if ((flags & ~(kLoopFilterKnownBits | kTransformTypesFlag | kInterTransformSizesFlag | kEpipolarLinesFlag)) !=
      0) {
    return corrupt("byte 3: unknown flags " + std::to_string(flags));
  }
  out->qindex = bytes[kQIndexByte];  // every byte value is a valid index
  out->border_units = border_units;
  out->loop_filters = flags & kLoopFilterKnownBits;
  out->transform_types = (flags & kTransformTypesFlag) != 0;
  out->inter_transform_sizes = (flags & kInterTransformSizesFlag) != 0;
  out->epipolar_lines = (flags & kEpipolarLinesFlag) != 0;
  out->filter = static_cast<InterpolationFilter>(filter);
  out->reference_count = reference_count;
  out->warp_mask = warp_mask;
  return Status::Ok();
}

std::array<uint8_t, kBFrameHeaderBytes> serialize_b_frame_header(const BFrameHeader& header) {
  return {static_cast<uint8_t>(kBidirectionalTypeBit | kBFrameSyntaxVersion), static_cast<uint8_t>(header.qindex),
          static_cast<uint8_t>(header.border_units | static_cast<int>(header.filter) << kFilterShift |
                               (header.reference_count - 1) << kSecondReferenceShift |
                               header.warp_mask << kWarpMaskShift),
          static_cast<uint8_t>(header.loop_filters | (header.transform_types ? kTransformTypesFlag : 0) |
                               (header.inter_transform_sizes ? kInterTransformSizesFlag : 0) |
                               (header.epipolar_lines ? kEpipolarLinesFlag : 0))};
}

Status decode_b_frame(std::span<const uint8_t> bytes, int width, int height, const ImageYCbCr420& ref0,
                      const ImageYCbCr420* ref1, ImageYCbCr420* out, std::vector<MacroblockMode>* modes,
                      std::vector<Partition>* partitions, std::vector<uint8_t>* warped, BorderEdges* border_edges) {
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension) {
    return Status(ErrorCode::kInvalidArgument, "B-face: size " + std::to_string(width) + "x" +
                                                   std::to_string(height) + " outside 1.." +
                                                   std::to_string(kMaxFrameDimension));
  }
  BFrameHeader header;
  SVC_RETURN_IF_ERROR(parse_b_frame_header(bytes, &header));
  const int extra = 2 * kCubeBorderUnitPixels * header.border_units;
  if (!consistent_image(ref0, width + extra, height + extra) ||
      (ref1 != nullptr && !consistent_image(*ref1, width + extra, height + extra))) {
    return Status(ErrorCode::kInvalidArgument, "B-face: reference images are not " + std::to_string(width + extra) +
                                                   "x" + std::to_string(height + extra) +
                                                   " with 4:2:0 planes of matching size (a border of " +
                                                   std::to_string(header.border_units) + " units)");
  }
  const int given = ref1 != nullptr ? 2 : 1;
  if (header.reference_count != given) {
    return Status(ErrorCode::kInvalidArgument, "B-face: coded with " + std::to_string(header.reference_count) +
                                                   " reference(s) but " + std::to_string(given) + " given");
  }
  // The calling thread's state, reset for each frame: its buffers outlive the call, so
  // that decoding face after face allocates (and page-faults) nothing for them.
  ThreadBuffers<FrameState>& thread = thread_buffers<FrameState>();  // codec/common/thread_buffers.h
  FrameState& s = thread.buffers;
  init_state(s, width, height, header.qindex, &ref0, ref1, header.border_units);
  thread.share.set(state_buffer_bytes(s));
  s.warp_mask = header.warp_mask;
  s.filter = header.filter;
  s.inter_transform_sizes = header.inter_transform_sizes;
  s.contexts.intra_luma.types.enabled = s.contexts.intra_chroma.types.enabled = header.transform_types;
  if (modes != nullptr) {
    modes->clear();
    modes->reserve(s.macroblocks.size());
  }
  if (partitions != nullptr) partitions->clear();
  if (warped != nullptr) warped->clear();
  RangeDecoder decoder(bytes.subspan(kBFrameHeaderBytes));
  if (header.epipolar_lines) {
    for (int r = 0; r < s.reference_count; ++r) {
      if (!decode_epipolar_lines(decoder, &s.lines[r])) {
        return corrupt("epipolar lines of reference " + std::to_string(r) + ": a coefficient beyond " +
                       std::to_string(kMaxEpipolarCoefficient));
      }
    }
  }
  if (border_edges != nullptr) border_edges->read = {};
  MacroblockReader reader(s, decoder, border_edges);
  for (int my = 0; my < s.mbs_y; ++my) {
    for (int mx = 0; mx < s.mbs_x; ++mx) {
      MacroblockMode mode = MacroblockMode::kIntra;
      SVC_RETURN_IF_ERROR(reader.read(mx, my, &mode));
      if (modes != nullptr) modes->push_back(mode);
      if (partitions != nullptr) partitions->push_back(s.mb(mx, my).partition);
      if (warped != nullptr) {
        const bool coded_inter = mode != MacroblockMode::kIntra && mode != MacroblockMode::kSkipped;
        warped->push_back(coded_inter && s.mb(mx, my).inter_warp ? 1 : 0);
      }
    }
    // A complete payload is never read further past its end than its left-out final zeros;
    // stopping at the first row that does bounds the work garbage can cause.
    if (decoder.truncated()) {
      return corrupt("payload truncated (macroblock row " + std::to_string(my) + " needs bytes beyond the " +
                     std::to_string(bytes.size()) + " given)");
    }
  }
  CdefParams cdef;
  if (header.loop_filters & kLoopFilterCdef) {
    read_cdef_syntax(decoder, cdef_units(16 * s.mbs_x), cdef_units(16 * s.mbs_y), &cdef);
    if (decoder.truncated()) {
      return corrupt("payload truncated (CDEF syntax needs bytes beyond the " + std::to_string(bytes.size()) +
                     " given)");
    }
  }
  const size_t used = decoder.consumed() + kBFrameHeaderBytes;
  if (used != bytes.size()) {
    return corrupt(std::to_string(bytes.size() - used) + " trailing bytes after offset " + std::to_string(used));
  }
  if (header.loop_filters & kLoopFilterDeblocking) deblock_planes(s);
  if (header.loop_filters & kLoopFilterCdef) cdef_planes(s, cdef);
  crop_output(s, out);
  return Status::Ok();
}

}  // namespace svc::codec
