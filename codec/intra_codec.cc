// Intra frame coding: macroblock-padded planes, 8x8 blocks in raster order per plane
// (Y, Cb, Cr), each predicted from its reconstructed neighbours in a signalled mode
// (codec/intra_prediction.h) and its residual coded as quantized DCT levels by
// block_coder; then the in-loop filters the header selects (deblocking, CDEF) over the
// whole frame. The decoder's reconstruction (reconstruct_block, apply_loop_filters) is
// also the encoder's, so the two agree bit for bit by construction.
#include "codec/intra_codec.h"

#include <algorithm>
#include <limits>
#include <string>

#include "codec/bframe_syntax.h"
#include "codec/block_coder.h"
#include "codec/dct.h"
#include "codec/dsp/dsp.h"
#include "codec/intra_prediction.h"
#include "codec/loop_filter.h"
#include "codec/quant.h"
#include "codec/range_coder.h"
#include "codec/rdoq.h"

namespace svc::codec {
namespace {

struct PlaneGeometry {
  int width, height;       // visible samples
  int blocks_x, blocks_y;  // padded size in blocks
  const uint8_t* pixels;   // source plane (encoder) or nullptr
  int stride() const { return blocks_x * 8; }
  size_t padded_size() const { return static_cast<size_t>(stride()) * blocks_y * 8; }
};

// Entropy-coding state of one plane class (luma, chroma).
struct PlaneContexts {
  IntraModeContexts modes;
  BlockContextSet residual;
};

// Per-block neighbour state of the plane being coded.
struct PlaneState {
  std::vector<uint8_t> modes, has_levels;
  explicit PlaneState(size_t blocks) : modes(blocks, kDcMode), has_levels(blocks, 0) {}
  std::array<int, kMostProbableModes> candidates(int blocks_x, int bx, int by) const {
    const size_t index = static_cast<size_t>(by) * blocks_x + bx;
    return most_probable_modes(bx > 0 ? modes[index - 1] : kDcMode, by > 0 ? modes[index - blocks_x] : kDcMode);
  }
  int coded_block_context(int blocks_x, int bx, int by) const {
    const size_t index = static_cast<size_t>(by) * blocks_x + bx;
    return (bx > 0 ? has_levels[index - 1] : 0) + (by > 0 ? has_levels[index - blocks_x] : 0);
  }
};

// Residuals of every block use the flat matrix: spatial prediction leaves little
// low-frequency energy for a perceptual matrix to spare.
Quantizer residual_quantizer(int qindex) { return make_quantizer(BlockKind::kNonIntra, qindex); }

// The quantiser scale of an index as the MPEG-2 quantiser_scale it replaces.
double scale_of(int qindex) { return quantizer_scale_q8(qindex) / 256.0; }

// out = clip(prediction + inverse DCT of `coefficients`), or the prediction alone when
// there are none.
void reconstruct_block(const uint8_t* prediction, const int16_t* coefficients, uint8_t* out, int stride) {
  int16_t residual[64];
  if (coefficients != nullptr) inverse_dct_8x8(coefficients, residual);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const int value = prediction[8 * y + x] + (coefficients != nullptr ? residual[8 * y + x] : 0);
      out[y * stride + x] = static_cast<uint8_t>(std::clamp(value, 0, 255));
    }
  }
}

// The source plane with its last row and column replicated into the padding.
std::vector<uint8_t> pad_plane(const PlaneGeometry& plane) {
  std::vector<uint8_t> padded(plane.padded_size());
  for (int y = 0; y < plane.blocks_y * 8; ++y) {
    const uint8_t* row = plane.pixels + static_cast<size_t>(std::min(y, plane.height - 1)) * plane.width;
    uint8_t* out = padded.data() + static_cast<size_t>(y) * plane.stride();
    std::copy_n(row, plane.width, out);
    std::fill(out + plane.width, out + plane.stride(), row[plane.width - 1]);
  }
  return padded;
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

// Predicts and reconstructs every block of `coefficients` into `frame` (padding
// included: the filters read across it). The caller checked the block counts.
void predict_and_reconstruct(const CoefficientFrame& coefficients, const BlockLayout& layout, PaddedFrame* frame) {
  const auto planes = planes_of(layout, coefficients.width, coefficients.height);
  const Quantizer quantizer = residual_quantizer(coefficients.qindex);
  const dsp::DspTable& dsp = dsp::get_dsp();
  int16_t block[64] = {};
  int positions[64];
  size_t block_number = 0, entry = 0;
  for (int p = 0; p < 3; ++p) {
    const PlaneGeometry& plane = planes[p];
    std::vector<uint8_t>& recon = frame->planes[p];
    for (int by = 0; by < plane.blocks_y; ++by) {
      for (int bx = 0; bx < plane.blocks_x; ++bx, ++block_number) {
        const int count = std::min<int>(coefficients.block_counts[block_number], 64);
        int decoded = 0;
        for (; decoded < count; ++decoded) {
          int position, level;
          if (!coefficients.read(&entry, &position, &level)) break;
          positions[decoded] = position;
          block[position] = static_cast<int16_t>(dequantize_level(quantizer, position, level));
        }
        uint8_t edge[dsp::kIntraEdgeSamples], prediction[64];
        const size_t offset = static_cast<size_t>(by) * 8 * plane.stride() + bx * 8;
        build_intra_edge(recon.data(), plane.stride(), bx, by, plane.blocks_x, edge);
        dsp.intra_predict_8x8(edge, coefficients.block_modes[block_number] % kIntraModes, prediction);
        reconstruct_block(prediction, decoded > 0 ? block : nullptr, recon.data() + offset, plane.stride());
        for (int i = 0; i < decoded; ++i) block[positions[i]] = 0;
      }
    }
  }
}

// Encoder only: a block's mode, prediction and residual levels.
struct BlockChoice {
  int mode = kDcMode;
  bool coded = false;
  uint8_t prediction[64];
  int16_t levels[64];
};

float intra_mode_cost(const IntraModeContexts& c, const std::array<int, kMostProbableModes>& candidates, int mode) {
  const auto found = std::find(candidates.begin(), candidates.end(), mode);
  const int index = static_cast<int>(found - candidates.begin());
  if (found == candidates.end()) return bframe::bit_cost(c.is_most_probable, 0) + 5;
  float bits = bframe::bit_cost(c.is_most_probable, 1) + bframe::bit_cost(c.most_probable_index[0], index > 0);
  return index > 0 ? bits + bframe::bit_cost(c.most_probable_index[1], index > 1) : bits;
}

int block_sse(const uint8_t* source, int stride, const uint8_t* block) {
  int sum = 0;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const int d = source[y * stride + x] - block[8 * y + x];
      sum += d * d;
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
  BlockSearch(const Quantizer& quantizer, const CodingParams& params)
      : quantizer_(quantizer),
        modes_(params.directional_intra ? kIntraModes : 2),
        rd_search_(params.rd_intra_search),
        rdoq_(params.rdoq),
        satd_lambda_(std::max(1, static_cast<int>(4 * scale_of(quantizer.qindex) + 0.5))),
        lambda_(static_cast<float>(0.1 * scale_of(quantizer.qindex) * scale_of(quantizer.qindex))) {}

  // `candidates` null: the mode is fixed (a Cr block takes its Cb block's).
  void choose(const uint8_t* source, int stride, const uint8_t* edge, const PlaneContexts& contexts,
              const std::array<int, kMostProbableModes>* candidates, int cbf_context, BlockChoice* best) const {
    std::array<int, kSearchedModes> searched{best->mode, -1, -1};
    if (candidates != nullptr) searched = preselect(source, stride, edge, *candidates);
    float best_cost = std::numeric_limits<float>::max();
    for (int mode : searched) {
      if (mode < 0) continue;
      BlockChoice trial;
      trial.mode = mode;
      const float mode_bits = candidates != nullptr ? intra_mode_cost(contexts.modes, *candidates, mode) : 0;
      const float cost = evaluate(source, stride, edge, contexts.residual, cbf_context, mode_bits, &trial);
      if (cost < best_cost) {
        best_cost = cost;
        *best = trial;
      }
    }
  }

 private:
  static constexpr int kSearchedModes = 3;

  std::array<int, kSearchedModes> preselect(const uint8_t* source, int stride, const uint8_t* edge,
                                            const std::array<int, kMostProbableModes>& candidates) const {
    const dsp::DspTable& dsp = dsp::get_dsp();
    std::array<std::pair<int, int>, kIntraModes> costs;
    uint8_t prediction[64];
    for (int mode = 0; mode < modes_; ++mode) {
      dsp.intra_predict_8x8(edge, mode, prediction);
      costs[mode] = {dsp.satd_8x8(source, stride, prediction) + satd_lambda_ * intra_mode_bits(candidates, mode),
                     mode};
    }
    const int kept = rd_search_ ? std::min(kSearchedModes, modes_) : 1;
    std::partial_sort(costs.begin(), costs.begin() + kept, costs.begin() + modes_);
    std::array<int, kSearchedModes> searched{-1, -1, -1};
    for (int i = 0; i < kept; ++i) searched[i] = costs[i].second;
    return searched;
  }

  float evaluate(const uint8_t* source, int stride, const uint8_t* edge, const BlockContextSet& contexts,
                 int cbf_context, float mode_bits, BlockChoice* trial) const {
    dsp::get_dsp().intra_predict_8x8(edge, trial->mode, trial->prediction);
    int16_t residual[64], coefficients[64];
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 8; ++x)
        residual[8 * y + x] = static_cast<int16_t>(source[y * stride + x] - trial->prediction[8 * y + x]);
    }
    trial->coded = transform_quantize_block_rd(quantizer_, residual, rdoq_, contexts, 0, cbf_context, lambda_,
                                               trial->levels) > 0;
    const int16_t zero[64] = {};
    const float uncoded_cost = static_cast<float>(block_sse(source, stride, trial->prediction)) +
                               lambda_ * (mode_bits + block_levels_bits(contexts, zero, 0, cbf_context));
    if (!trial->coded) return uncoded_cost;
    uint8_t reconstructed[64];
    dequantize_block(quantizer_, trial->levels, coefficients);
    reconstruct_block(trial->prediction, coefficients, reconstructed, 8);
    const float coded_cost = static_cast<float>(block_sse(source, stride, reconstructed)) +
                             lambda_ * (mode_bits + block_levels_bits(contexts, trial->levels, 0, cbf_context));
    if (coded_cost <= uncoded_cost || !rd_search_) return coded_cost;
    trial->coded = false;
    std::fill_n(trial->levels, 64, int16_t{0});
    return uncoded_cost;
  }

  const Quantizer& quantizer_;
  int modes_;
  bool rd_search_;  // else the SATD's best mode, its levels as quantized
  bool rdoq_;
  int satd_lambda_;  // SATD units per bit, tuned on the photographic scenes
  float lambda_;     // SSE per bit, tuned on the photographic scenes
};

}  // namespace

size_t CoefficientFrame::memory_bytes() const {
  return sizeof(*this) + block_counts.capacity() + block_modes.capacity() + entries.capacity() * sizeof(uint16_t) +
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
  Quantizer quantizer = residual_quantizer(qindex);
  // A narrower dead zone than inter residuals use (0.2), tuned on the photographic scenes.
  quantizer.rounding_dc = quantizer.rounding_ac = 0.25f;
  const BlockSearch search(quantizer, params);
  const BlockLayout layout = block_layout(width, height);
  auto planes = planes_of(layout, width, height);
  planes[0].pixels = source.y.data();
  planes[1].pixels = source.cb.data();
  planes[2].pixels = source.cr.data();

  std::vector<uint8_t> bytes = {static_cast<uint8_t>(FaceType::kIntra), kIntraSyntaxVersion,
                                static_cast<uint8_t>(qindex), 0};
  bytes.reserve(static_cast<size_t>(width) * height / 4 + 64);
  RangeEncoder encoder(&bytes);
  PlaneContexts luma_contexts, chroma_contexts;
  std::vector<uint8_t> chroma_modes;
  PaddedFrame frame = padded_frame(layout);

  for (int p = 0; p < 3; ++p) {
    const PlaneGeometry& plane = planes[p];
    PlaneContexts& contexts = p == 0 ? luma_contexts : chroma_contexts;
    const std::vector<uint8_t> padded_source = pad_plane(plane);
    std::vector<uint8_t>& recon = frame.planes[p];
    PlaneState state(static_cast<size_t>(plane.blocks_x) * plane.blocks_y);
    for (int by = 0; by < plane.blocks_y; ++by) {
      for (int bx = 0; bx < plane.blocks_x; ++bx) {
        const size_t index = static_cast<size_t>(by) * plane.blocks_x + bx;
        const size_t offset = static_cast<size_t>(by) * 8 * plane.stride() + bx * 8;
        uint8_t edge[dsp::kIntraEdgeSamples];
        build_intra_edge(recon.data(), plane.stride(), bx, by, plane.blocks_x, edge);
        const int cbf_context = state.coded_block_context(plane.blocks_x, bx, by);
        BlockChoice choice;
        if (p == 2) {
          choice.mode = chroma_modes[index];
          search.choose(padded_source.data() + offset, plane.stride(), edge, contexts, nullptr, cbf_context,
                        &choice);
        } else {
          const auto candidates = state.candidates(plane.blocks_x, bx, by);
          search.choose(padded_source.data() + offset, plane.stride(), edge, contexts, &candidates, cbf_context,
                        &choice);
          encode_intra_mode(encoder, contexts.modes, candidates, choice.mode);
        }
        state.modes[index] = static_cast<uint8_t>(choice.mode);
        encode_block_levels(encoder, contexts.residual, choice.levels, 0, cbf_context);
        state.has_levels[index] = choice.coded;
        int16_t coefficients[64];
        if (choice.coded) dequantize_block(quantizer, choice.levels, coefficients);
        reconstruct_block(choice.prediction, choice.coded ? coefficients : nullptr, recon.data() + offset,
                          plane.stride());
      }
    }
    if (p == 1) chroma_modes = state.modes;
  }
  // The filters change no block symbol: decide them on the finished reconstruction.
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
  PlaneContexts luma_contexts, chroma_contexts;

  CoefficientFrame result;
  result.width = width;
  result.height = height;
  result.qindex = qindex;
  result.loop_filters = bytes[3];
  result.block_counts.reserve(static_cast<size_t>(layout.block_count()));
  result.block_modes.reserve(static_cast<size_t>(layout.block_count()));
  // A frame rarely holds more than a few coefficients per block; grow beyond that.
  result.entries.reserve(std::min<size_t>(bytes.size() * 2, static_cast<size_t>(layout.block_count()) * 64));
  std::vector<uint8_t> chroma_modes;

  int block_number = 0;
  for (int p = 0; p < 3; ++p) {
    const PlaneGeometry& plane = planes[p];
    PlaneContexts& contexts = p == 0 ? luma_contexts : chroma_contexts;
    PlaneState state(static_cast<size_t>(plane.blocks_x) * plane.blocks_y);
    for (int by = 0; by < plane.blocks_y; ++by) {
      for (int bx = 0; bx < plane.blocks_x; ++bx, ++block_number) {
        const size_t index = static_cast<size_t>(by) * plane.blocks_x + bx;
        const int mode = p == 2
                             ? chroma_modes[index]
                             : decode_intra_mode(decoder, contexts.modes, state.candidates(plane.blocks_x, bx, by));
        state.modes[index] = static_cast<uint8_t>(mode);
        BlockLevel levels[64];
        int count = 0;
        if (!decode_block_levels(decoder, contexts.residual, 0, state.coded_block_context(plane.blocks_x, bx, by),
                                 levels, &count)) {
          return corrupt("block " + std::to_string(block_number) + ": invalid levels");
        }
        state.has_levels[index] = count > 0;
        for (int i = 0; i < count; ++i) result.append(levels[i].position, levels[i].level);
        result.block_counts.push_back(static_cast<uint8_t>(count));
        result.block_modes.push_back(static_cast<uint8_t>(mode));
      }
      // A complete payload is never read past its end; stopping at the first row that
      // does bounds the work garbage can cause.
      if (decoder.overrun() > 0) {
        return corrupt("payload truncated (plane " + std::to_string(p) + ", block row " + std::to_string(by) +
                       " needs bytes beyond the " + std::to_string(bytes.size()) + " given)");
      }
    }
    if (p == 1) chroma_modes = state.modes;
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
  const size_t block_count = static_cast<size_t>(layout.block_count());
  if (width <= 0 || height <= 0 || coefficients.block_counts.size() != block_count ||
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
  PaddedFrame frame = padded_frame(layout);
  predict_and_reconstruct(coefficients, layout, &frame);
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
