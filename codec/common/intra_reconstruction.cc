// SPDX-License-Identifier: BSD-2-Clause
// Reconstruction of intra blocks and frames: prediction from the reconstructed
// neighbours in the block's mode, inverse transform of its dequantized levels, then the
// in-loop filters the header selects. The decoder's reconstruction is also the
// encoder's, so the two agree bit for bit by construction.
#include <algorithm>

#include "codec/common/cfl.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/image_planes.h"
#include "codec/common/intra_macroblock.h"
#include "codec/common/intra_planes.h"
#include "codec/common/intra_prediction.h"
#include "codec/common/quant.h"

namespace svc::codec {

namespace intra {

SizedQuantizers residual_quantizers(int qindex, ResidualMatrix matrix) {
  SizedQuantizers q;
  for (int s = 0; s < kTransformSizes; ++s)
    q[static_cast<size_t>(s)] = make_residual_quantizer(static_cast<TransformSize>(s), qindex, matrix);
  return q;
}

const Quantizer& quantizer_for(const SizedQuantizers& quantizers, TransformSize size) {
  return quantizers[static_cast<size_t>(size_index(size))];
}

std::array<PlaneGeometry, 3> planes_of(const BlockLayout& layout, int width, int height) {
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  return {PlaneGeometry{width, height, layout.luma_blocks_x, layout.luma_blocks_y, nullptr},
          PlaneGeometry{cw, ch, layout.chroma_blocks_x, layout.chroma_blocks_y, nullptr},
          PlaneGeometry{cw, ch, layout.chroma_blocks_x, layout.chroma_blocks_y, nullptr}};
}

PaddedFrame padded_frame(const BlockLayout& layout) {
  PaddedFrame frame;
  frame.widths = {8 * layout.luma_blocks_x, 8 * layout.chroma_blocks_x, 8 * layout.chroma_blocks_x};
  frame.heights = {8 * layout.luma_blocks_y, 8 * layout.chroma_blocks_y, 8 * layout.chroma_blocks_y};
  for (int p = 0; p < 3; ++p) frame.planes[p].assign(static_cast<size_t>(frame.widths[p]) * frame.heights[p], 0);
  return frame;
}

void deblock_intra(PaddedFrame* frame, int qindex) {
  deblock_frame(DeblockMap::uniform(frame->widths[0], frame->heights[0], 2), qindex, frame->views());
}

void cdef_intra(PaddedFrame* frame, const CdefParams& params, int qindex) {
  cdef_frame(params, qindex, {}, frame->views());
}

void crop(const PaddedFrame& frame, int width, int height, ImageYCbCr420* out) {
  copy_planes_to_image({frame.planes[0].data(), frame.planes[1].data(), frame.planes[2].data()}, frame.widths,
                       width, height, out);
}

void reconstruct_block(const uint8_t* prediction, const int16_t* coefficients, TransformType type,
                       TransformSize size, uint8_t* out, int stride) {
  const int w = transform_width(size);
  if (coefficients == nullptr) {
    for (int y = 0; y < transform_height(size); ++y)
      std::copy_n(prediction + w * y, w, out + static_cast<ptrdiff_t>(y) * stride);
    return;
  }
  const auto add = dsp::get_dsp().inverse_transform_add[size_index(size)][static_cast<int>(type)];
  add(coefficients, prediction, w, out, stride);
}

void reconstruct_block_in_plane(PlaneState& state, uint8_t* plane, int stride, int x0, int y0, TransformSize size,
                                int mode, const int16_t* coefficients, TransformType type) {
  uint8_t edge[dsp::kMaxIntraEdgeSamples], prediction[kMaxTransformArea];
  build_intra_edge(plane, stride, x0, y0, size, state.availability(x0, y0, size), edge);
  intra_predictor(size)(edge, mode, prediction);
  reconstruct_block(prediction, coefficients, type, size, plane + static_cast<ptrdiff_t>(y0) * stride + x0, stride);
  state.mark(x0, y0, size, mode, coefficients != nullptr);
}

void reconstruct_chroma_block_in_plane(PlaneState& state, uint8_t* plane, int stride, int x0, int y0,
                                       const ChromaMode& mode, const uint8_t* luma, int luma_stride,
                                       const int16_t* coefficients, TransformType type) {
  if (!mode.cfl()) {
    reconstruct_block_in_plane(state, plane, stride, x0, y0, kChromaSize, mode.mode, coefficients, type);
    return;
  }
  uint8_t edge[dsp::kMaxIntraEdgeSamples], prediction[kMaxTransformArea];
  build_intra_edge(plane, stride, x0, y0, kChromaSize, state.availability(x0, y0, kChromaSize), edge);
  int16_t ac[64];
  cfl_luma_ac(luma, luma_stride, x0, y0, ac);
  predict_cfl(ac, dc_prediction_8x8(edge), mode.alpha, prediction);
  reconstruct_block(prediction, coefficients, type, kChromaSize, plane + static_cast<ptrdiff_t>(y0) * stride + x0,
                    stride);
  state.mark(x0, y0, kChromaSize, kCflMode, coefficients != nullptr);
}

}  // namespace intra

namespace {

using namespace intra;

int luma_block_count(LumaPartition partition) {
  int count = 0;
  for_each_luma_block(partition, [&](int, int, TransformSize) { ++count; });
  return count;
}

// Predicts and reconstructs, in coding order, the blocks a CoefficientFrame lists, with
// their levels unpacked from it or, when given, from the parse's DecodedLevels.
class BlockReconstructor {
 public:
  BlockReconstructor(const CoefficientFrame& coefficients, const DecodedLevels* decoded)
      : coefficients_(coefficients),
        decoded_(decoded),
        quantizers_(residual_quantizers(coefficients.qindex, coefficients.residual_matrix)) {}

  // The next block: one of `size` at (x0, y0) of `recon` (stride samples per row); `luma`,
  // for a chroma block, is the reconstructed luma plane (stride 2 * stride).
  void next(PlaneState& state, uint8_t* recon, int stride, int x0, int y0, TransformSize size,
            const uint8_t* luma) {
    const int area = transform_area(size);
    const Quantizer& quantizer = quantizer_for(quantizers_, size);
    const int count = std::min<int>(coefficients_.block_counts[block_number_], area);
    TransformType type = TransformType::kDctDct;
    const int decoded = read_levels(count, size, &type);
    for (int i = 0; i < decoded; ++i) {
      block_[positions_[i]] = static_cast<int16_t>(dequantize_level(quantizer, positions_[i], values_[i]));
    }
    const int mode_byte = coefficients_.block_modes[block_number_];
    const int16_t* residual = decoded > 0 ? block_ : nullptr;
    if (luma != nullptr && size == kChromaSize && is_cfl_mode_byte(mode_byte)) {
      reconstruct_chroma_block_in_plane(state, recon, stride, x0, y0, {kCflMode, cfl_alpha_of_mode_byte(mode_byte)},
                                        luma, 2 * stride, residual, type);
    } else {
      reconstruct_block_in_plane(state, recon, stride, x0, y0, size, mode_byte % kIntraModes, residual, type);
    }
    for (int i = 0; i < decoded; ++i) block_[positions_[i]] = 0;
    ++block_number_;
  }

 private:
  // The next block's `count` levels into positions_ and values_; returns how many.
  int read_levels(int count, TransformSize size, TransformType* type) {
    if (decoded_ == nullptr) return coefficients_.read_levels(&offset_, count, size, positions_, values_, type);
    if (count == 0) return 0;
    *type = decoded_->types[typed_blocks_++];
    const BlockLevel* levels = decoded_->levels.data() + offset_;
    for (int i = 0; i < count; ++i) {
      positions_[i] = levels[i].position;
      values_[i] = levels[i].level;
    }
    offset_ += static_cast<size_t>(count);
    return count;
  }

  const CoefficientFrame& coefficients_;
  const DecodedLevels* decoded_;  // null: unpack coefficients_.levels
  SizedQuantizers quantizers_;
  // offset_: into coefficients_.levels' bytes, or decoded_'s levels.
  size_t block_number_ = 0, offset_ = 0, typed_blocks_ = 0;
  int16_t block_[kMaxTransformArea] = {};
  int positions_[kMaxTransformArea];
  int values_[kMaxTransformArea];
};

// Predicts and reconstructs every block of `coefficients` into `frame` (padding
// included: the filters read across it). The caller checked the block and partition
// counts, and `decoded`'s against them.
void predict_and_reconstruct(const CoefficientFrame& coefficients, const DecodedLevels* decoded,
                             const BlockLayout& layout, PaddedFrame* frame) {
  const auto planes = planes_of(layout, coefficients.width, coefficients.height);
  BlockReconstructor reconstructor(coefficients, decoded);
  const PlaneGeometry& luma = planes[0];
  PlaneState luma_state(luma.stride(), luma.padded_height());
  for (int mby = 0; mby < luma.blocks_y / 2; ++mby) {
    for (int mbx = 0; mbx < luma.blocks_x / 2; ++mbx) {
      const LumaPartition partition =
          coefficients.luma_partitions[static_cast<size_t>(mby) * (luma.blocks_x / 2) + mbx];
      for_each_luma_block(partition, [&](int x, int y, TransformSize size) {
        reconstructor.next(luma_state, frame->planes[0].data(), luma.stride(), 16 * mbx + x, 16 * mby + y, size,
                           nullptr);
      });
    }
  }
  for (int p = 1; p < 3; ++p) {
    const PlaneGeometry& plane = planes[p];
    PlaneState state(plane.stride(), plane.padded_height());
    for (int by = 0; by < plane.blocks_y; ++by) {
      for (int bx = 0; bx < plane.blocks_x; ++bx) {
        reconstructor.next(state, frame->planes[p].data(), plane.stride(), 8 * bx, 8 * by, kChromaSize,
                           frame->planes[0].data());
      }
    }
  }
}

// The number of blocks a frame of this layout and these partitions holds.
size_t expected_block_count(const BlockLayout& layout, const std::vector<LumaPartition>& partitions) {
  size_t count = 2 * static_cast<size_t>(layout.chroma_blocks_x) * layout.chroma_blocks_y;
  for (LumaPartition partition : partitions) count += static_cast<size_t>(luma_block_count(partition));
  return count;
}

// Whether `decoded` holds as many levels and transform types as `coefficients` counts.
bool decoded_levels_match(const CoefficientFrame& coefficients, const DecodedLevels& decoded) {
  size_t levels = 0, typed = 0;
  for (uint16_t count : coefficients.block_counts) {
    levels += count;
    typed += count > 0;
  }
  return decoded.levels.size() == levels && decoded.types.size() == typed;
}

}  // namespace

void reconstruct_intra_frame(const CoefficientFrame& coefficients, ImageYCbCr420* out,
                             const DecodedLevels* decoded) {
  const int width = coefficients.width, height = coefficients.height;
  const BlockLayout layout = block_layout(width, height);
  const bool partitions_match = coefficients.luma_partitions.size() ==
                                static_cast<size_t>(layout.chroma_blocks_x) * layout.chroma_blocks_y;
  const size_t block_count = partitions_match ? expected_block_count(layout, coefficients.luma_partitions) : 0;
  if (width <= 0 || height <= 0 || !partitions_match || coefficients.block_counts.size() != block_count ||
      coefficients.block_modes.size() != block_count) {
    // Not a frame that parse_intra_frame or encode_intra_frame built: a black frame.
    const bool valid_size = width > 0 && height > 0;
    out->width = width;
    out->height = height;
    out->y.assign(valid_size ? static_cast<size_t>(width) * height : 0, 0);
    out->cb.assign(valid_size ? static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2) : 0, 0);
    out->cr.assign(out->cb.size(), 0);
    return;
  }
  if (decoded != nullptr && !decoded_levels_match(coefficients, *decoded)) decoded = nullptr;
  PaddedFrame frame = padded_frame(layout);
  predict_and_reconstruct(coefficients, decoded, layout, &frame);
  if (coefficients.loop_filters & kLoopFilterDeblocking) deblock_intra(&frame, coefficients.qindex);
  if (coefficients.loop_filters & kLoopFilterCdef) cdef_intra(&frame, coefficients.cdef, coefficients.qindex);
  crop(frame, width, height, out);
}

}  // namespace svc::codec
