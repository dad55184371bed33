// Intra frame coding: macroblock-padded planes, 8x8 DCT blocks in raster order per plane
// (Y, Cb, Cr), DC predicted from neighbouring blocks, AC by block_coder. The decoder's
// inverse path (reconstruct_intra_frame) is also the encoder's reconstruction, so the
// two agree bit for bit by construction.
#include "codec/intra_codec.h"

#include <algorithm>
#include <array>
#include <string>

#include "codec/block_coder.h"
#include "codec/dct.h"
#include "codec/loop_filter.h"
#include "codec/quant.h"
#include "codec/range_coder.h"

namespace svc::codec {
namespace {

struct PlaneGeometry {
  int width, height;       // visible samples
  int blocks_x, blocks_y;  // padded size in blocks
  const uint8_t* pixels;   // source plane (encoder) or nullptr
};

// Median edge detector (LOCO-I) over the neighbouring blocks' DC levels.
inline int predict_dc(const int* dc, int blocks_x, int bx, int by) {
  const int index = by * blocks_x + bx;
  if (bx == 0 && by == 0) return 0;
  if (by == 0) return dc[index - 1];
  if (bx == 0) return dc[index - blocks_x];
  const int left = dc[index - 1], top = dc[index - blocks_x], top_left = dc[index - blocks_x - 1];
  if (top_left >= std::max(left, top)) return std::min(left, top);
  if (top_left <= std::min(left, top)) return std::max(left, top);
  return left + top - top_left;
}

inline int coded_block_context(const uint8_t* has_ac, int blocks_x, int bx, int by) {
  const int index = by * blocks_x + bx;
  return (bx > 0 ? has_ac[index - 1] : 0) + (by > 0 ? has_ac[index - blocks_x] : 0);
}

// Copies the 8x8 block at (bx, by) minus 128, replicating the plane's last row/column
// into the padding.
inline void load_block(const PlaneGeometry& plane, int bx, int by, int16_t* samples) {
  for (int y = 0; y < 8; ++y) {
    const int sy = std::min(by * 8 + y, plane.height - 1);
    const uint8_t* row = plane.pixels + static_cast<size_t>(sy) * plane.width;
    const int x0 = bx * 8;
    if (x0 + 8 <= plane.width) {
      for (int x = 0; x < 8; ++x) samples[8 * y + x] = static_cast<int16_t>(row[x0 + x] - 128);
    } else {
      for (int x = 0; x < 8; ++x) {
        samples[8 * y + x] = static_cast<int16_t>(row[std::min(x0 + x, plane.width - 1)] - 128);
      }
    }
  }
}

std::array<PlaneGeometry, 3> planes_of(const BlockLayout& layout, int width, int height) {
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  return {PlaneGeometry{width, height, layout.luma_blocks_x, layout.luma_blocks_y, nullptr},
          PlaneGeometry{cw, ch, layout.chroma_blocks_x, layout.chroma_blocks_y, nullptr},
          PlaneGeometry{cw, ch, layout.chroma_blocks_x, layout.chroma_blocks_y, nullptr}};
}

Status corrupt(const std::string& what) { return Status(ErrorCode::kCorruptData, "intra frame: " + what); }

// The reconstructed macroblock-padded planes of a frame, before cropping (stride = width).
struct PaddedFrame {
  std::array<std::vector<uint8_t>, 3> planes;
  std::array<int, 3> widths{}, heights{};

  std::array<PlaneView, 3> views() {
    std::array<PlaneView, 3> result;
    for (int p = 0; p < 3; ++p) result[p] = PlaneView{planes[p].data(), widths[p], widths[p], heights[p]};
    return result;
  }
};

PaddedFrame padded_frame(const BlockLayout& layout) {
  PaddedFrame frame;
  frame.widths = {8 * layout.luma_blocks_x, 8 * layout.chroma_blocks_x, 8 * layout.chroma_blocks_x};
  frame.heights = {8 * layout.luma_blocks_y, 8 * layout.chroma_blocks_y, 8 * layout.chroma_blocks_y};
  for (int p = 0; p < 3; ++p) frame.planes[p].assign(static_cast<size_t>(frame.widths[p]) * frame.heights[p], 0);
  return frame;
}

// Inverse transforms every block of `coefficients` into `frame` (padding included: the
// filters read across it). Returns false for a frame no parser or encoder built.
bool reconstruct_blocks(const CoefficientFrame& coefficients, const BlockLayout& layout, PaddedFrame* frame) {
  if (coefficients.block_counts.size() != static_cast<size_t>(layout.block_count())) return false;
  const Quantizer quantizer = make_quantizer(BlockKind::kIntra, coefficients.qindex);
  int16_t block[64] = {};
  int16_t samples[64];
  int positions[64];
  size_t block_number = 0, entry = 0;
  const std::array<PlaneView, 3> views = frame->views();
  for (int p = 0; p < 3; ++p) {
    const PlaneView& plane = views[p];
    for (int by = 0; by < plane.height / 8; ++by) {
      for (int bx = 0; bx < plane.width / 8; ++bx, ++block_number) {
        const int count = std::min<int>(coefficients.block_counts[block_number], 64);
        int decoded = 0;
        for (; decoded < count; ++decoded) {
          int position, level;
          if (!coefficients.read(&entry, &position, &level)) break;
          positions[decoded] = position;
          block[position] = static_cast<int16_t>(dequantize_level(quantizer, position, level));
        }
        inverse_dct_8x8(block, samples);
        for (int y = 0; y < 8; ++y) {
          uint8_t* row = plane.data + static_cast<size_t>(8 * by + y) * plane.stride + 8 * bx;
          for (int x = 0; x < 8; ++x) row[x] = static_cast<uint8_t>(std::clamp(samples[8 * y + x] + 128, 0, 255));
        }
        for (int i = 0; i < decoded; ++i) block[positions[i]] = 0;
      }
    }
  }
  return true;
}

void deblock_intra(PaddedFrame* frame, int qindex) {
  deblock_frame(DeblockMap::uniform(frame->widths[0], frame->heights[0], 2), qindex, frame->views());
}

// CDEF of an intra frame: no block is skipped (every block has a DC level).
void cdef_intra(PaddedFrame* frame, const CdefParams& params, int qindex) {
  cdef_frame(params, qindex, {}, frame->views());
}

// Encoder only: chooses CDEF for the deblocked frame, filters it and writes the syntax
// when the filter pays. lambda as the B-frame encoder's default (0.12 scale^2 per bit).
// Returns whether it did.
bool apply_cdef_choice(RangeEncoder& encoder, PaddedFrame* frame, const ImageYCbCr420& source, int qindex) {
  const double scale = quantizer_scale_q8(qindex) / 256.0;
  CdefSource visible;
  visible.planes = {source.y.data(), source.cb.data(), source.cr.data()};
  visible.strides = {source.width, (source.width + 1) / 2, (source.width + 1) / 2};
  visible.width = source.width;
  visible.height = source.height;
  const CdefParams params = choose_cdef(frame->views(), visible, qindex, {}, 0.12 * scale * scale);
  if (params.presets.empty()) return false;
  write_cdef_syntax(encoder, params, cdef_units(frame->widths[0]), cdef_units(frame->heights[0]));
  cdef_intra(frame, params, qindex);
  return true;
}

void crop(const PaddedFrame& frame, int width, int height, ImageYCbCr420* out) {
  out->width = width;
  out->height = height;
  std::vector<uint8_t>* outputs[3] = {&out->y, &out->cb, &out->cr};
  for (int p = 0; p < 3; ++p) {
    const int w = p == 0 ? width : (width + 1) / 2, h = p == 0 ? height : (height + 1) / 2;
    outputs[p]->resize(static_cast<size_t>(w) * h);
    for (int y = 0; y < h; ++y) {
      const uint8_t* row = frame.planes[p].data() + static_cast<size_t>(y) * frame.widths[p];
      std::copy_n(row, w, outputs[p]->data() + static_cast<size_t>(y) * w);
    }
  }
}

// Sum of squared differences of the visible part of a padded plane against a source plane.
int64_t plane_error(const std::vector<uint8_t>& plane, int stride, const std::vector<uint8_t>& source, int width,
                    int height) {
  int64_t sum = 0;
  for (int y = 0; y < height; ++y) {
    const uint8_t* a = plane.data() + static_cast<size_t>(y) * stride;
    const uint8_t* b = source.data() + static_cast<size_t>(y) * width;
    for (int x = 0; x < width; ++x) sum += (a[x] - b[x]) * (a[x] - b[x]);
  }
  return sum;
}

int64_t frame_error(const PaddedFrame& frame, const ImageYCbCr420& source) {
  const int cw = (source.width + 1) / 2, ch = (source.height + 1) / 2;
  return plane_error(frame.planes[0], frame.widths[0], source.y, source.width, source.height) +
         plane_error(frame.planes[1], frame.widths[1], source.cb, cw, ch) +
         plane_error(frame.planes[2], frame.widths[2], source.cr, cw, ch);
}

}  // namespace

size_t CoefficientFrame::memory_bytes() const {
  return sizeof(*this) + block_counts.capacity() * sizeof(uint8_t) + entries.capacity() * sizeof(uint16_t) +
         cdef.memory_bytes();
}

BlockLayout block_layout(int width, int height) {
  BlockLayout layout;
  if (width <= 0 || height <= 0) return layout;
  const int mb_x = (width + 15) / 16, mb_y = (height + 15) / 16;
  layout.luma_blocks_x = 2 * mb_x;
  layout.luma_blocks_y = 2 * mb_y;
  layout.chroma_blocks_x = mb_x;
  layout.chroma_blocks_y = mb_y;
  return layout;
}

std::vector<uint8_t> encode_intra_frame(const ImageYCbCr420& source, const CodingParams& params,
                                        ImageYCbCr420* reconstruction) {
  const int width = source.width, height = source.height;
  const size_t chroma_size = static_cast<size_t>((width + 1) / 2) * static_cast<size_t>((height + 1) / 2);
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension ||
      source.y.size() != static_cast<size_t>(width) * static_cast<size_t>(height) ||
      source.cb.size() != chroma_size || source.cr.size() != chroma_size) {
    return {};
  }
  const int qindex = std::clamp(params.qindex, kMinQIndex, kMaxQIndex);
  const Quantizer quantizer = make_quantizer(BlockKind::kIntra, qindex);
  const BlockLayout layout = block_layout(width, height);
  auto planes = planes_of(layout, width, height);
  planes[0].pixels = source.y.data();
  planes[1].pixels = source.cb.data();
  planes[2].pixels = source.cr.data();

  std::vector<uint8_t> bytes = {static_cast<uint8_t>(FaceType::kIntra), kIntraSyntaxVersion,
                                static_cast<uint8_t>(qindex), 0};
  bytes.reserve(static_cast<size_t>(width) * height / 4 + 64);
  RangeEncoder encoder(&bytes);
  BlockContextSet luma_contexts, chroma_contexts;

  CoefficientFrame coefficients;
  coefficients.width = width;
  coefficients.height = height;
  coefficients.qindex = qindex;
  coefficients.block_counts.reserve(static_cast<size_t>(layout.block_count()));
  const size_t max_plane_blocks = static_cast<size_t>(layout.luma_blocks_x) * layout.luma_blocks_y;
  std::vector<int> dc_levels(max_plane_blocks);
  std::vector<uint8_t> has_ac(max_plane_blocks);

  for (int p = 0; p < 3; ++p) {
    const PlaneGeometry& plane = planes[p];
    BlockContextSet& contexts = p == 0 ? luma_contexts : chroma_contexts;
    for (int by = 0; by < plane.blocks_y; ++by) {
      for (int bx = 0; bx < plane.blocks_x; ++bx) {
        int16_t samples[64], levels[64];
        load_block(plane, bx, by, samples);
        transform_quantize_block(quantizer, samples, levels);
        const int index = by * plane.blocks_x + bx;
        const int dc = levels[0];
        encode_dc_difference(encoder, contexts, dc - predict_dc(dc_levels.data(), plane.blocks_x, bx, by));
        dc_levels[index] = dc;
        bool any_ac = false;
        for (int i = 1; i < 64 && !any_ac; ++i) any_ac = levels[i] != 0;
        encode_block_levels(encoder, contexts, levels, 1,
                            coded_block_context(has_ac.data(), plane.blocks_x, bx, by));
        has_ac[index] = any_ac;
        int count = 0;
        for (int i = 0; i < 64; ++i) {
          const int position = kZigZag[i];
          if (levels[position] != 0) {
            coefficients.append(position, levels[position]);
            ++count;
          }
        }
        coefficients.block_counts.push_back(static_cast<uint8_t>(count));
      }
    }
  }
  // The filters change no block symbol: decide them on the finished reconstruction.
  PaddedFrame frame = padded_frame(layout);
  reconstruct_blocks(coefficients, layout, &frame);
  if (params.deblocking) {
    PaddedFrame filtered = frame;
    deblock_intra(&filtered, qindex);
    if (frame_error(filtered, source) < frame_error(frame, source)) {
      bytes[3] |= kLoopFilterDeblocking;
      frame = std::move(filtered);
    }
  }
  if (params.cdef && apply_cdef_choice(encoder, &frame, source, qindex)) bytes[3] |= kLoopFilterCdef;
  encoder.finish();
  if (reconstruction != nullptr) crop(frame, width, height, reconstruction);
  return bytes;
}

Status parse_intra_frame(std::span<const uint8_t> bytes, int width, int height, CoefficientFrame* out) {
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension) {
    return Status(ErrorCode::kInvalidArgument, "intra frame: size " + std::to_string(width) + "x" +
                                                   std::to_string(height) + " outside 1.." +
                                                   std::to_string(kMaxFrameDimension));
  }
  if (bytes.size() < static_cast<size_t>(kFrameHeaderBytes)) {
    return corrupt("payload of " + std::to_string(bytes.size()) + " bytes is shorter than the " +
                   std::to_string(kFrameHeaderBytes) + "-byte header");
  }
  if (bytes[0] != static_cast<uint8_t>(FaceType::kIntra)) {
    return corrupt("byte 0: frame type " + std::to_string(bytes[0]) + " is not intra (0)");
  }
  if (bytes[1] != kIntraSyntaxVersion) {
    return Status(ErrorCode::kUnsupported, "intra frame: byte 1: syntax version " + std::to_string(bytes[1]) +
                                               " (this build reads " + std::to_string(kIntraSyntaxVersion) + ")");
  }
  const int qindex = bytes[2];  // every byte value is a valid index
  if ((bytes[3] & ~kLoopFilterKnownBits) != 0) {
    return corrupt("byte 3: unknown loop filter flags " + std::to_string(bytes[3]));
  }

  const BlockLayout layout = block_layout(width, height);
  const auto planes = planes_of(layout, width, height);
  RangeDecoder decoder(bytes.subspan(kFrameHeaderBytes));
  BlockContextSet luma_contexts, chroma_contexts;

  CoefficientFrame result;
  result.width = width;
  result.height = height;
  result.qindex = qindex;
  result.loop_filters = bytes[3];
  result.block_counts.reserve(static_cast<size_t>(layout.block_count()));
  // A frame rarely holds more than a few coefficients per block; grow beyond that.
  result.entries.reserve(std::min<size_t>(bytes.size() * 2, static_cast<size_t>(layout.block_count()) * 64));
  const size_t max_plane_blocks = static_cast<size_t>(layout.luma_blocks_x) * layout.luma_blocks_y;
  std::vector<int> dc_levels(max_plane_blocks);
  std::vector<uint8_t> has_ac(max_plane_blocks);

  int block_number = 0;
  for (int p = 0; p < 3; ++p) {
    const PlaneGeometry& plane = planes[p];
    BlockContextSet& contexts = p == 0 ? luma_contexts : chroma_contexts;
    for (int by = 0; by < plane.blocks_y; ++by) {
      for (int bx = 0; bx < plane.blocks_x; ++bx, ++block_number) {
        const int index = by * plane.blocks_x + bx;
        int difference = 0;
        if (!decode_dc_difference(decoder, contexts, &difference)) {
          return corrupt("block " + std::to_string(block_number) + ": invalid DC difference");
        }
        const int dc = predict_dc(dc_levels.data(), plane.blocks_x, bx, by) + difference;
        if (dc < -kMaxLevel || dc > kMaxLevel) {
          return corrupt("block " + std::to_string(block_number) + ": DC level " + std::to_string(dc) +
                         " out of range");
        }
        dc_levels[index] = dc;
        if (dc != 0) result.append(0, dc);
        BlockLevel levels[64];
        int count = 0;
        if (!decode_block_levels(decoder, contexts, 1, coded_block_context(has_ac.data(), plane.blocks_x, bx, by),
                                 levels, &count)) {
          return corrupt("block " + std::to_string(block_number) + ": invalid AC levels");
        }
        has_ac[index] = count > 0;
        for (int i = 0; i < count; ++i) result.append(levels[i].position, levels[i].level);
        result.block_counts.push_back(static_cast<uint8_t>(count + (dc != 0)));
      }
      // A complete payload is never read past its end; stopping at the first row that
      // does bounds the work garbage can cause.
      if (decoder.overrun() > 0) {
        return corrupt("payload truncated (plane " + std::to_string(p) + ", block row " + std::to_string(by) +
                       " needs bytes beyond the " + std::to_string(bytes.size()) + " given)");
      }
    }
  }
  if (result.loop_filters & kLoopFilterCdef) {
    read_cdef_syntax(decoder, cdef_units(8 * layout.luma_blocks_x), cdef_units(8 * layout.luma_blocks_y),
                     &result.cdef);
    if (decoder.overrun() > 0) {
      return corrupt("payload truncated (CDEF syntax needs bytes beyond the " + std::to_string(bytes.size()) +
                     " given)");
    }
  }
  const size_t used = decoder.consumed() + kFrameHeaderBytes;
  if (used != bytes.size()) {
    return corrupt(std::to_string(bytes.size() - used) + " trailing bytes after offset " + std::to_string(used));
  }
  result.entries.shrink_to_fit();
  *out = std::move(result);
  return Status::Ok();
}

void reconstruct_intra_frame(const CoefficientFrame& coefficients, ImageYCbCr420* out) {
  const int width = coefficients.width, height = coefficients.height;
  const BlockLayout layout = block_layout(width, height);
  PaddedFrame frame = padded_frame(layout);
  if (width <= 0 || height <= 0 || !reconstruct_blocks(coefficients, layout, &frame)) {
    // Not a frame that parse_intra_frame or encode_intra_frame built: a black frame.
    const bool valid_size = width > 0 && height > 0;
    out->width = width;
    out->height = height;
    out->y.assign(valid_size ? static_cast<size_t>(width) * height : 0, 0);
    out->cb.assign(valid_size ? static_cast<size_t>((width + 1) / 2) * ((height + 1) / 2) : 0, 0);
    out->cr.assign(out->cb.size(), 0);
    return;
  }
  if (coefficients.loop_filters & kLoopFilterDeblocking) deblock_intra(&frame, coefficients.qindex);
  if (coefficients.loop_filters & kLoopFilterCdef) cdef_intra(&frame, coefficients.cdef, coefficients.qindex);
  crop(frame, width, height, out);
}

Status decode_intra_frame(std::span<const uint8_t> bytes, int width, int height, ImageYCbCr420* out) {
  CoefficientFrame coefficients;
  SVC_RETURN_IF_ERROR(parse_intra_frame(bytes, width, height, &coefficients));
  reconstruct_intra_frame(coefficients, out);
  return Status::Ok();
}

}  // namespace svc::codec
