// SPDX-License-Identifier: BSD-2-Clause
// Intra frame decoding: the parse stage reads every block's syntax into the packed
// CoefficientFrame (what the runtime caches semi-decoded); reconstruction
// (codec/common/intra_frame.h) turns it into pixels.
#include "codec/decoder/intra_decoder.h"

#include <memory>
#include <string>

#include "codec/common/context_priors.h"
#include "codec/common/intra_planes.h"
#include "codec/decoder/cdef_syntax.h"
#include "codec/decoder/intra_syntax_reader.h"
#include "codec/decoder/range_decoder.h"
#include "codec/decoder/syntax_version.h"

namespace svc::codec {
namespace {

using namespace intra;

Status corrupt(const std::string& what) { return Status(ErrorCode::kCorruptData, "intra frame: " + what); }

// Parse stage of an intra frame: reads each block's syntax into `frame` and marks it.
class FrameBlockReader final : public BlockReader {
 public:
  FrameBlockReader(RangeDecoder& decoder, PlaneContexts& contexts, PlaneState& state, CoefficientFrame* frame,
                   DecodedLevels* decoded)
      : decoder_(decoder), contexts_(contexts), state_(state), frame_(frame), decoded_(decoded) {}

  bool read(int x0, int y0, TransformSize size) override {
    if (!read_block_syntax(decoder_, contexts_, state_, x0, y0, size, &block_)) return false;
    append(x0, y0, size, static_cast<uint8_t>(block_.mode));
    return true;
  }

  // An 8x8 chroma block; a Cb block's mode goes to `cb`, which the Cr block reads.
  bool read_chroma(int x0, int y0, ChromaPlane plane, ChromaMode* cb) {
    if (!read_chroma_block_syntax(decoder_, contexts_, state_, x0, y0, plane, cb, &block_)) return false;
    append(x0, y0, kChromaSize, ChromaMode{block_.mode, block_.cfl_alpha}.mode_byte());
    return true;
  }

 private:
  // Marks the block read and appends it to the frame with its mode byte.
  void append(int x0, int y0, TransformSize size, uint8_t mode_byte) {
    state_.mark(x0, y0, size, block_.mode, block_.count > 0);
    frame_->append_levels(block_.levels, block_.count, size, block_.transform_type);
    frame_->block_counts.push_back(static_cast<uint16_t>(block_.count));
    frame_->block_modes.push_back(mode_byte);
    if (decoded_ != nullptr && block_.count > 0) {
      decoded_->levels.insert(decoded_->levels.end(), block_.levels, block_.levels + block_.count);
      decoded_->types.push_back(block_.transform_type);
    }
  }

  RangeDecoder& decoder_;
  PlaneContexts& contexts_;
  PlaneState& state_;
  CoefficientFrame* frame_;
  DecodedLevels* decoded_;  // optional
  BlockSyntax block_;
};

}  // namespace

Status parse_intra_frame(std::span<const uint8_t> bytes, int width, int height, CoefficientFrame* out,
                         DecodedLevels* decoded) {
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension) {
    return Status(ErrorCode::kInvalidArgument, "intra frame: size " + std::to_string(width) + "x" +
                                                   std::to_string(height) + " outside 1.." +
                                                   std::to_string(kMaxFrameDimension));
  }
  if (bytes.size() < static_cast<size_t>(kFrameHeaderBytes)) {
    return corrupt("payload of " + std::to_string(bytes.size()) + " bytes is shorter than the " +
                   std::to_string(kFrameHeaderBytes) + "-byte header");
  }
  if (bytes[0] & kBidirectionalTypeBit) return corrupt("byte 0: frame type bit says bidirectional, not intra");
  SVC_RETURN_IF_ERROR(check_syntax_version("intra frame", bytes[0], kIntraSyntaxFirst, kIntraSyntaxVersion));
  const int qindex = bytes[kQIndexByte];  // every byte value is a valid index
  const uint8_t flags = bytes[kIntraFlagsByte];
  if ((flags & ~(kLoopFilterKnownBits | kIntraWeightedMatrix | kTransformTypesFlag)) != 0) {
    return corrupt("byte 2: unknown flags " + std::to_string(flags));
  }

  const BlockLayout layout = block_layout(width, height);
  const auto planes = planes_of(layout, width, height);
  RangeDecoder decoder(bytes.subspan(kFrameHeaderBytes));
  PlaneContexts luma_contexts, chroma_contexts;
  prime_intra_frame_contexts(luma_contexts, chroma_contexts);
  luma_contexts.types.enabled = chroma_contexts.types.enabled = (flags & kTransformTypesFlag) != 0;

  CoefficientFrame result;
  result.width = width;
  result.height = height;
  result.qindex = qindex;
  result.loop_filters = flags & kLoopFilterKnownBits;
  result.residual_matrix = (flags & kIntraWeightedMatrix) ? ResidualMatrix::kWeighted : ResidualMatrix::kFlat;
  result.block_counts.reserve(static_cast<size_t>(layout.block_count()));
  result.block_modes.reserve(static_cast<size_t>(layout.block_count()));
  result.luma_partitions.reserve(static_cast<size_t>(layout.chroma_blocks_x) * layout.chroma_blocks_y);
  // The packed levels take about as many bytes as the payload that codes them.
  result.levels.reserve(bytes.size() * 5 / 4);
  if (decoded != nullptr) {
    decoded->levels.clear();
    decoded->types.clear();
    // About 5 bits a level, and never more levels than the frame has samples.
    const size_t samples = static_cast<size_t>(width) * height * 3 / 2;
    decoded->levels.reserve(std::min(bytes.size() * 2, samples));
  }

  // A complete payload is never read past its end; stopping at the first row that does
  // bounds the work garbage can cause.
  auto truncated = [&](int plane, int row) {
    return corrupt("payload truncated (plane " + std::to_string(plane) + ", block row " + std::to_string(row) +
                   " needs bytes beyond the " + std::to_string(bytes.size()) + " given)");
  };
  auto invalid = [&]() {
    return corrupt("block " + std::to_string(result.block_counts.size()) + ": invalid levels");
  };
  const PlaneGeometry& luma = planes[0];
  PlaneState luma_state(luma.stride(), luma.padded_height());
  auto luma_reader = std::make_unique<FrameBlockReader>(decoder, luma_contexts, luma_state, &result, decoded);
  for (int mby = 0; mby < luma.blocks_y / 2; ++mby) {
    for (int mbx = 0; mbx < luma.blocks_x / 2; ++mbx) {
      LumaPartition partition = 0;
      if (!read_luma_macroblock(decoder, luma_contexts, luma_state, mbx, mby, *luma_reader, &partition)) {
        return invalid();
      }
      result.luma_partitions.push_back(partition);
    }
    if (decoder.truncated()) return truncated(0, 2 * mby);
  }
  const PlaneGeometry& chroma = planes[1];
  std::vector<ChromaMode> cb_modes(static_cast<size_t>(chroma.blocks_x) * chroma.blocks_y);
  for (int p = 1; p < 3; ++p) {
    const ChromaPlane plane = p == 1 ? ChromaPlane::kCb : ChromaPlane::kCr;
    PlaneState state(chroma.stride(), chroma.padded_height());
    auto reader = std::make_unique<FrameBlockReader>(decoder, chroma_contexts, state, &result, decoded);
    for (int by = 0; by < chroma.blocks_y; ++by) {
      for (int bx = 0; bx < chroma.blocks_x; ++bx) {
        ChromaMode& cb = cb_modes[static_cast<size_t>(by) * chroma.blocks_x + bx];
        if (!reader->read_chroma(8 * bx, 8 * by, plane, &cb)) return invalid();
      }
      if (decoder.truncated()) return truncated(p, by);
    }
  }
  if (result.loop_filters & kLoopFilterCdef) {
    read_cdef_syntax(decoder, cdef_units(8 * layout.luma_blocks_x), cdef_units(8 * layout.luma_blocks_y),
                     &result.cdef);
    if (decoder.truncated()) {
      return corrupt("payload truncated (CDEF syntax needs bytes beyond the " + std::to_string(bytes.size()) +
                     " given)");
    }
  }
  const size_t used = decoder.consumed() + kFrameHeaderBytes;
  if (used != bytes.size()) {
    return corrupt(std::to_string(bytes.size() - used) + " trailing bytes after offset " + std::to_string(used));
  }
  result.levels.shrink_to_fit();
  *out = std::move(result);
  return Status::Ok();
}

Status decode_intra_frame(std::span<const uint8_t> bytes, int width, int height, ImageYCbCr420* out) {
  CoefficientFrame coefficients;
  DecodedLevels decoded;
  SVC_RETURN_IF_ERROR(parse_intra_frame(bytes, width, height, &coefficients, &decoded));
  reconstruct_intra_frame(coefficients, out, &decoded);
  return Status::Ok();
}

}  // namespace svc::codec
