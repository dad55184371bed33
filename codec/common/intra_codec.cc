// Intra frame coding: macroblock-padded planes; luma macroblocks in raster order, each
// one 16x16 transform block, four 8x8 or some 8x8 split into four 4x4 (Z order); then the
// 8x8 blocks of Cb and Cr in raster order. Each block is predicted from its reconstructed
// neighbours in a signalled mode (codec/intra_prediction.h) and its residual coded as
// quantized DCT levels by block_coder; then the in-loop filters the header selects
// (deblocking, CDEF) over the whole frame. The decoder's reconstruction (reconstruct_block, apply_loop_filters) is
// also the encoder's, so the two agree bit for bit by construction. The coding of one
// luma macroblock or chroma block (syntax, reconstruction, search) is also what B-frame
// intra macroblocks use (codec/intra_macroblock.h).
#include "codec/common/intra_codec.h"

#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "codec/common/bframe_syntax.h"
#include "codec/common/block_coder.h"
#include "codec/common/cfl.h"
#include "codec/common/context_priors.h"
#include "codec/common/dct.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/image_planes.h"
#include "codec/common/intra_macroblock.h"
#include "codec/common/intra_prediction.h"
#include "codec/common/level_stream.h"
#include "codec/common/loop_filter.h"
#include "codec/common/quant.h"
#include "codec/common/range_coder.h"
#include "codec/encoder/dsp/encoder_dsp.h"
#include "codec/encoder/rdoq.h"

namespace svc::codec {

namespace intra {

SizedQuantizers residual_quantizers(int qindex, ResidualMatrix matrix) {
  SizedQuantizers q;
  for (int s = 0; s < kTransformSizes; ++s)
    q[static_cast<size_t>(s)] = make_residual_quantizer(static_cast<TransformSize>(s), qindex, matrix);
  return q;
}

const Quantizer& quantizer_for(const SizedQuantizers& quantizers, int size) {
  return quantizers[static_cast<size_t>(size_of_shape(size))];
}

}  // namespace intra

namespace {

using namespace intra;

struct PlaneGeometry {
  int width, height;       // visible samples
  int blocks_x, blocks_y;  // padded size in 8x8 blocks
  const uint8_t* pixels;   // source plane (encoder) or nullptr
  int stride() const { return blocks_x * 8; }
  int padded_height() const { return blocks_y * 8; }
  size_t padded_size() const { return static_cast<size_t>(stride()) * blocks_y * 8; }
};

int luma_block_count(LumaPartition partition) {
  int count = 0;
  for_each_luma_block(partition, [&](int, int, int) { ++count; });
  return count;
}

// The quantiser scale of an index as the MPEG-2 quantiser_scale it replaces.
double scale_of(int qindex) { return quantizer_scale_q8(qindex) / 256.0; }

// SSE per bit of an intra frame's decisions, tuned on the photographic scenes (0.085
// since the strips and 8x8 halves; 0.1 and 0.12 measured worse, docs/codec.md 3.2).
float intra_frame_lambda(int qindex) { return static_cast<float>(0.085 * scale_of(qindex) * scale_of(qindex)); }

// out = clip(prediction + inverse transform of type `type` of `coefficients`), or the
// prediction alone when there are none.
// Rows of a fixed width, so that the compiler vectorizes them.
template <int N, int H = N>
void add_residual(const uint8_t* prediction, const int16_t* residual, uint8_t* out, int stride) {
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < N; ++x) {
      const int value = prediction[N * y + x] + residual[N * y + x];
      out[y * stride + x] = static_cast<uint8_t>(std::clamp(value, 0, 255));
    }
  }
}

void reconstruct_block(const uint8_t* prediction, const int16_t* coefficients, TransformType type, int size,
                       uint8_t* out, int stride) {
  if (coefficients == nullptr) {
    const int w = shape_width(size);
    for (int y = 0; y < shape_height(size); ++y)
      std::copy_n(prediction + w * y, w, out + static_cast<ptrdiff_t>(y) * stride);
    return;
  }
  int16_t residual[kMaxTransformArea];
  inverse_transform(size_of_shape(size), type, coefficients, residual);
  if (size == 4) return add_residual<4>(prediction, residual, out, stride);
  if (size == 16) return add_residual<16>(prediction, residual, out, stride);
  if (size == block_shape(16, 8)) return add_residual<16, 8>(prediction, residual, out, stride);
  if (size == block_shape(8, 16)) return add_residual<8, 16>(prediction, residual, out, stride);
  if (size == block_shape(16, 4)) return add_residual<16, 4>(prediction, residual, out, stride);
  if (size == block_shape(4, 16)) return add_residual<4, 16>(prediction, residual, out, stride);
  if (size == block_shape(8, 4)) return add_residual<8, 4>(prediction, residual, out, stride);
  if (size == block_shape(4, 8)) return add_residual<4, 8>(prediction, residual, out, stride);
  add_residual<8>(prediction, residual, out, stride);
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
bool apply_cdef_choice(RangeEncoder& encoder, PaddedFrame* frame, const ImageYCbCr420& source, int qindex,
                       bool every_candidate) {
  const double scale = quantizer_scale_q8(qindex) / 256.0;
  CdefSource visible;
  visible.planes = {source.y.data(), source.cb.data(), source.cr.data()};
  visible.strides = {source.width, (source.width + 1) / 2, (source.width + 1) / 2};
  visible.width = source.width;
  visible.height = source.height;
  const CdefParams params = choose_cdef(frame->views(), visible, qindex, {}, 0.12 * scale * scale, every_candidate);
  if (params.presets.empty()) return false;
  write_cdef_syntax(encoder, params, cdef_units(frame->widths[0]), cdef_units(frame->heights[0]));
  cdef_intra(frame, params, qindex);
  return true;
}

void crop(const PaddedFrame& frame, int width, int height, ImageYCbCr420* out) {
  copy_planes_to_image({frame.planes[0].data(), frame.planes[1].data(), frame.planes[2].data()}, frame.widths,
                       width, height, out);
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

// Predicts and reconstructs, in coding order, the blocks a CoefficientFrame lists, with
// their levels unpacked from it or, when given, from the parse's DecodedLevels.
class BlockReconstructor {
 public:
  BlockReconstructor(const CoefficientFrame& coefficients, const DecodedLevels* decoded)
      : coefficients_(coefficients),
        decoded_(decoded),
        quantizers_(residual_quantizers(coefficients.qindex, coefficients.residual_matrix)) {}

  // The next block: size x size at (x0, y0) of `recon` (stride samples per row); `luma`,
  // for a chroma block, is the reconstructed luma plane (stride 2 * stride).
  void next(PlaneState& state, uint8_t* recon, int stride, int x0, int y0, int size, const uint8_t* luma) {
    const int area = shape_area(size);
    const Quantizer& quantizer = quantizer_for(quantizers_, size);
    const int count = std::min<int>(coefficients_.block_counts[block_number_], area);
    TransformType type = TransformType::kDctDct;
    const int decoded = read_levels(count, size_of_shape(size), &type);
    for (int i = 0; i < decoded; ++i) {
      block_[positions_[i]] = static_cast<int16_t>(dequantize_level(quantizer, positions_[i], values_[i]));
    }
    const int mode_byte = coefficients_.block_modes[block_number_];
    const int16_t* residual = decoded > 0 ? block_ : nullptr;
    if (luma != nullptr && size == 8 && is_cfl_mode_byte(mode_byte)) {
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
      for_each_luma_block(partition, [&](int x, int y, int size) {
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
        reconstructor.next(state, frame->planes[p].data(), plane.stride(), 8 * bx, 8 * by, 8,
                           frame->planes[0].data());
      }
    }
  }
}

// Encoder only: a set of modes to rank (all allowed ones when not given).
struct ModeSet {
  std::array<uint8_t, kIntraModes> modes{};
  int count = 0;
  void add(int mode) {
    if (std::find(modes.begin(), modes.begin() + count, mode) == modes.begin() + count)
      modes[static_cast<size_t>(count++)] = static_cast<uint8_t>(mode);
  }
};

// The bits encode_intra_mode spends on `mode` at the contexts' current state.
float intra_mode_cost(const IntraModeContexts& c, int shape, const ModeCandidates& candidates, int mode) {
  float bits = 0;
  for_each_mode_bit(c, shape, candidates, mode,
                    [&](const AdaptiveBit& model, int bit) { bits += bframe::bit_cost(model, bit); });
  return bits;
}

int block_sse(const uint8_t* source, int stride, const uint8_t* block, int shape) {
  const int w = shape_width(shape);
  int sum = 0;
  for (int y = 0; y < shape_height(shape); ++y) {
    for (int x = 0; x < w; ++x) {
      const int d = source[y * stride + x] - block[w * y + x];
      sum += d * d;
    }
  }
  return sum;
}

// Hadamard SATD of a block of `shape`: the 4x4 or 8x8 kernel, a larger block as the sum
// over its 8x8 tiles, or its 4x4 tiles when a side is 4.
int block_satd(const uint8_t* source, int stride, const uint8_t* prediction, int shape) {
  const dsp::EncoderDspTable& dsp = dsp::get_encoder_dsp();
  if (shape == 4) return dsp.satd_4x4(source, stride, prediction);
  if (shape == 8) return dsp.satd_8x8(source, stride, prediction);
  const int w = shape_width(shape), h = shape_height(shape), t = std::min({w, h, 8});
  const auto satd = t == 8 ? dsp.satd_8x8 : dsp.satd_4x4;
  int sum = 0;
  uint8_t tile[64];
  for (int y = 0; y < h; y += t) {
    for (int x = 0; x < w; x += t) {
      for (int row = 0; row < t; ++row) std::copy_n(prediction + w * (y + row) + x, t, tile + t * row);
      sum += satd(source + y * stride + x, stride, tile);
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
  BlockSearch(const SizedQuantizers& quantizers, const CodingParams& params, float lambda)
      : quantizers_(quantizers),
        modes_(params.directional_intra ? kIntraModes : 2),
        rd_search_(params.rd_intra_search),
        coarse_(params.coarse_mode_search),
        rdoq_(params.rdoq),
        satd_lambda_(std::max(1, static_cast<int>(4 * scale_of(quantizers[0].qindex) + 0.5))),
        lambda_(lambda) {}

  float lambda() const { return lambda_; }

  // Chooses the mode and levels of a size x size block and returns its cost.
  // `candidates` null: the mode is fixed (a Cr block takes its Cb block's). `ranked`: the
  // modes to rank, else every allowed one. `prefix_bits`: bits coded before the mode (a
  // Cb block's CfL flag).
  float choose(const uint8_t* source, int stride, const uint8_t* edge, int size, const PlaneContexts& contexts,
               const ModeCandidates* candidates, int cbf_context, const ModeSet* ranked, BlockChoice* best,
               float prefix_bits = 0) const {
    std::array<int, kSearchedModes> searched;
    searched.fill(-1);
    searched[0] = best->mode;  // a fixed mode is the only one searched
    if (candidates != nullptr)
      searched = preselect(source, stride, edge, size, contexts.modes, *candidates, ranked);
    float best_cost = std::numeric_limits<float>::max(), best_bits = 0;
    for (int mode : searched) {
      if (mode < 0) continue;
      trial_.mode = mode;
      trial_.cfl_alpha = 0;
      const float mode_bits =
          prefix_bits + (candidates != nullptr ? intra_mode_cost(contexts.modes, size, *candidates, mode) : 0);
      intra_predictor(size)(edge, mode, trial_.prediction);
      const float cost =
          evaluate(source, stride, size, contexts, cbf_context, mode_bits, TransformType::kDctDct, &trial_);
      if (cost < best_cost) {
        best_cost = cost;
        best_bits = mode_bits;
        copy_choice(trial_, size, best);
      }
    }
    return choose_transform_type(source, stride, size, contexts, cbf_context, best_bits, best, best_cost);
  }

  // CfL for an 8x8 chroma block with luma AC `ac`: the least-squares alpha and its two
  // neighbours (never 0 for Cb), by rate-distortion cost. Returns the cost.
  float choose_cfl(const uint8_t* source, int stride, const uint8_t* edge, const int16_t* ac,
                   const PlaneContexts& contexts, ChromaPlane plane, int cb_alpha, int cbf_context,
                   BlockChoice* best, float prefix_bits = 0) const {
    const int dc = dc_prediction_8x8(edge);
    const int fit = cfl_least_squares_alpha(ac, source, stride, dc);
    float best_cost = std::numeric_limits<float>::max(), best_bits = 0;
    for (int alpha = fit - 1; alpha <= fit + 1; ++alpha) {
      if (alpha < -kCflMaxAlpha || alpha > kCflMaxAlpha || (plane == ChromaPlane::kCb && alpha == 0)) continue;
      trial_.mode = kCflMode;
      trial_.cfl_alpha = alpha;
      predict_cfl(ac, dc, alpha, trial_.prediction);
      const float bits = prefix_bits + cfl_alpha_bits(contexts.cfl, plane, cb_alpha, alpha);
      const float cost = evaluate(source, stride, 8, contexts, cbf_context, bits, TransformType::kDctDct, &trial_);
      if (cost < best_cost) {
        best_cost = cost;
        best_bits = bits;
        copy_choice(trial_, 8, best);
      }
    }
    return choose_transform_type(source, stride, 8, contexts, cbf_context, best_bits, best, best_cost);
  }

  static void copy_choice(const BlockChoice& from, int size, BlockChoice* to) {
    to->mode = from.mode;
    to->cfl_alpha = from.cfl_alpha;
    to->coded = from.coded;
    to->transform_type = from.transform_type;
    std::copy_n(from.prediction, shape_area(size), to->prediction);
    std::copy_n(from.levels, shape_area(size), to->levels);
  }

 private:
  static constexpr int kSearchedModes = 3;

  std::array<int, kSearchedModes> preselect(const uint8_t* source, int stride, const uint8_t* edge, int size,
                                            const IntraModeContexts& contexts, const ModeCandidates& candidates,
                                            const ModeSet* ranked) const {
    const IntraPredictor predict = intra_predictor(size);
    std::array<std::pair<int, int>, kIntraModes> costs;
    uint8_t prediction[kMaxTransformArea];
    int count = 0;
    auto score = [&](int mode) {
      predict(edge, mode, prediction);
      costs[static_cast<size_t>(count++)] = {
          block_satd(source, stride, prediction, size) +
              static_cast<int>(satd_lambda_ * intra_mode_cost(contexts, size, candidates, mode) + 0.5f),
          mode};
    };
    if (ranked != nullptr) {
      for (int i = 0; i < ranked->count; ++i) score(ranked->modes[static_cast<size_t>(i)]);
    } else if (coarse_ && modes_ == kIntraModes) {
      score_coarse(candidates, score, costs, count);
    } else {
      for (int mode = 0; mode < modes_; ++mode) score(mode);
    }
    // 4x4 blocks are many and each matters little: the best by SATD alone (a second mode
    // gained 0.02 dB PSNR-Y for 20 % more time: `svc encode --intra-only -q 40 --psnr` of
    // 18 cells of the photographic hall).
    const int kept = rd_search_ && size != 4 ? std::min(kSearchedModes, count) : 1;
    std::partial_sort(costs.begin(), costs.begin() + kept, costs.begin() + count);
    std::array<int, kSearchedModes> searched;
    searched.fill(-1);
    for (int i = 0; i < kept; ++i) searched[static_cast<size_t>(i)] = costs[static_cast<size_t>(i)].second;
    return searched;
  }

  // Scores planar, DC, the most probable modes and every fourth angular mode, then the
  // two angular neighbours on each side of the best angular one.
  template <class Score>
  static void score_coarse(const ModeCandidates& candidates, Score& score,
                           const std::array<std::pair<int, int>, kIntraModes>& costs, const int& count) {
    ModeSet scored;
    auto once = [&](int mode) {
      const int before = scored.count;
      scored.add(mode);
      if (scored.count != before) score(mode);
    };
    once(kPlanarMode);
    once(kDcMode);
    for (int mode : candidates) once(mode);
    for (int mode = 2; mode < kIntraModes; mode += 4) once(mode);
    std::pair<int, int> best{std::numeric_limits<int>::max(), -1};
    for (int i = 0; i < count; ++i) {
      if (costs[static_cast<size_t>(i)].second >= 2) best = std::min(best, costs[static_cast<size_t>(i)]);
    }
    for (int offset : {-2, -1, 1, 2}) {
      const int mode = best.second + offset;
      if (best.second >= 2 && mode >= 2 && mode < kIntraModes) once(mode);
    }
  }

  // The best block's levels under each other transform type (where the contexts enable
  // types and the block has levels; the mode stays), by the same cost. Returns the cost.
  float choose_transform_type(const uint8_t* source, int stride, int size, const PlaneContexts& contexts,
                              int cbf_context, float mode_bits, BlockChoice* best, float best_cost) const {
    if (!contexts.types.enabled || !best->coded) return best_cost;
    trial_.mode = best->mode;
    trial_.cfl_alpha = best->cfl_alpha;
    std::copy_n(best->prediction, shape_area(size), trial_.prediction);
    for (int t = 1; t < kTransformTypes; ++t) {
      const float cost =
          evaluate(source, stride, size, contexts, cbf_context, mode_bits, static_cast<TransformType>(t), &trial_);
      if (cost < best_cost && trial_.coded) {
        best_cost = cost;
        copy_choice(trial_, size, best);
      }
    }
    return best_cost;
  }

  // The levels and cost of trial->prediction with transform type `type`.
  float evaluate(const uint8_t* source, int stride, int size, const PlaneContexts& plane_contexts, int cbf_context,
                 float mode_bits, TransformType type, BlockChoice* trial) const {
    const BlockContextSet& contexts = plane_contexts.residual;
    const Quantizer& quantizer = quantizer_for(quantizers_, size);
    const int area = shape_area(size), w = shape_width(size);
    int16_t residual[kMaxTransformArea], coefficients[kMaxTransformArea];
    for (int y = 0; y < shape_height(size); ++y) {
      for (int x = 0; x < w; ++x)
        residual[w * y + x] = static_cast<int16_t>(source[y * stride + x] - trial->prediction[w * y + x]);
    }
    float levels_bits = 0;
    trial->coded = transform_quantize_block_rd(quantizer, residual, rdoq_, contexts, 0, cbf_context, lambda_,
                                               trial->levels, type, &levels_bits) > 0;
    trial->transform_type = trial->coded ? type : TransformType::kDctDct;
    const float uncoded_cost = static_cast<float>(block_sse(source, stride, trial->prediction, size)) +
                               lambda_ * (mode_bits + uncoded_block_bits(contexts, cbf_context));
    if (!trial->coded) return uncoded_cost;
    uint8_t reconstructed[kMaxTransformArea];
    dequantize_block(quantizer, trial->levels, coefficients);
    reconstruct_block(trial->prediction, coefficients, type, size, reconstructed, w);
    const float coded_cost =
        static_cast<float>(block_sse(source, stride, reconstructed, size)) +
        lambda_ * (mode_bits + levels_bits +
                   transform_type_bits(plane_contexts.types, quantizer.size, trial->mode, type));
    if (coded_cost <= uncoded_cost || !rd_search_) return coded_cost;
    trial->coded = false;
    trial->transform_type = TransformType::kDctDct;
    std::fill_n(trial->levels, area, int16_t{0});
    return uncoded_cost;
  }

  const SizedQuantizers& quantizers_;
  int modes_;
  bool rd_search_;  // else the SATD's best mode, its levels as quantized
  bool coarse_;     // angular modes ranked coarse to fine
  bool rdoq_;
  int satd_lambda_;  // SATD units per bit, tuned on the photographic scenes
  float lambda_;     // SSE per bit, tuned on the photographic scenes
  mutable BlockChoice trial_;
};

// Encoder only: codes one block of the plane during the search: chooses it, writes its
// reconstruction into the plane and marks it in `state`. Returns its cost.
class PlaneSearch {
 public:
  PlaneSearch(const BlockSearch& search, const SizedQuantizers& quantizers, const PlaneContexts& contexts,
              const uint8_t* source, uint8_t* recon, int stride)
      : search_(search),
        quantizers_(quantizers),
        contexts_(contexts),
        source_(source),
        recon_(recon),
        stride_(stride) {}

  float code_block(PlaneState& state, int x0, int y0, int size, const ModeSet* ranked, bool fixed_mode,
                   BlockChoice* choice) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(recon_, stride_, x0, y0, size, state.availability(x0, y0, size), edge);
    const auto candidates = state.candidates(x0, y0);
    const size_t offset = static_cast<size_t>(y0) * stride_ + x0;
    const float cost = search_.choose(source_ + offset, stride_, edge, size, contexts_,
                                      fixed_mode ? nullptr : &candidates, state.coded_block_context(x0, y0), ranked,
                                      choice);
    finish_block(state, x0, y0, size, *choice);
    return cost;
  }

  // An 8x8 chroma block in a regular mode, not yet reconstructed: a Cb block's best
  // (`cb` null), or a Cr block in its Cb block's mode.
  float choose_chroma_regular(const PlaneState& state, int x0, int y0, const ChromaMode* cb,
                              BlockChoice* choice) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(recon_, stride_, x0, y0, 8, state.availability(x0, y0, 8), edge);
    const uint8_t* source = source_ + static_cast<size_t>(y0) * stride_ + x0;
    const int cbf_context = state.coded_block_context(x0, y0);
    if (cb != nullptr) {
      choice->mode = cb->mode;
      return search_.choose(source, stride_, edge, 8, contexts_, nullptr, cbf_context, nullptr, choice);
    }
    const auto candidates = state.candidates(x0, y0);
    return search_.choose(source, stride_, edge, 8, contexts_, &candidates, cbf_context, nullptr, choice,
                          cfl_flag_bits(contexts_.cfl, state.cfl_context(x0, y0), false));
  }

  // An 8x8 chroma block in CfL with luma AC `ac`, not yet reconstructed: a Cb block
  // (`cb` null) or a Cr block whose Cb block uses CfL.
  float choose_chroma_cfl(const PlaneState& state, int x0, int y0, const int16_t* ac, const ChromaMode* cb,
                          BlockChoice* choice) const {
    uint8_t edge[dsp::kMaxIntraEdgeSamples];
    build_intra_edge(recon_, stride_, x0, y0, 8, state.availability(x0, y0, 8), edge);
    const uint8_t* source = source_ + static_cast<size_t>(y0) * stride_ + x0;
    const int cbf_context = state.coded_block_context(x0, y0);
    if (cb != nullptr) {
      return search_.choose_cfl(source, stride_, edge, ac, contexts_, ChromaPlane::kCr, cb->alpha, cbf_context,
                                choice);
    }
    return search_.choose_cfl(source, stride_, edge, ac, contexts_, ChromaPlane::kCb, 0, cbf_context, choice,
                              cfl_flag_bits(contexts_.cfl, state.cfl_context(x0, y0), true));
  }

  // Writes the chosen block's reconstruction into the plane and marks it.
  void finish_block(PlaneState& state, int x0, int y0, int size, const BlockChoice& choice) const {
    const size_t offset = static_cast<size_t>(y0) * stride_ + x0;
    int16_t coefficients[kMaxTransformArea];
    if (choice.coded) dequantize_block(quantizer_for(quantizers_, size), choice.levels, coefficients);
    reconstruct_block(choice.prediction, choice.coded ? coefficients : nullptr, choice.transform_type, size,
                      recon_ + offset, stride_);
    state.mark(x0, y0, size, choice.mode, choice.coded);
  }

  float split_bit_cost(const AdaptiveBit& bit, int value) const {
    return search_.lambda() * bframe::bit_cost(bit, value);
  }

  void save(int x0, int y0, int size, uint8_t* out) const {
    for (int y = 0; y < size; ++y) std::copy_n(recon_ + (y0 + y) * stride_ + x0, size, out + size * y);
  }
  void restore(int x0, int y0, int size, const uint8_t* in) const {
    for (int y = 0; y < size; ++y) std::copy_n(in + size * y, size, recon_ + (y0 + y) * stride_ + x0);
  }
  const PlaneContexts& contexts() const { return contexts_; }

 private:
  const BlockSearch& search_;
  const SizedQuantizers& quantizers_;
  const PlaneContexts& contexts_;
  const uint8_t* source_;
  uint8_t* recon_;
  int stride_;
};

// Encoder only: the partition of a luma macroblock by rate-distortion cost. Four 8x8
// blocks come first, each also tried as four 4x4, two 8x4 and two 4x8 blocks when it has
// levels (a block the prediction alone serves gains nothing from splitting) and small
// blocks are allowed; then one 16x16 block whose modes are ranked among those blocks'
// and the most probable ones, two 16x8, two 8x16, four 16x4 and four 4x16 blocks
// (try_partition), the cheapest kept.
class MacroblockSearch {
 public:
  MacroblockSearch(bool transform_sizes, bool small_blocks)
      : sizes_(transform_sizes), small_blocks_(small_blocks) {}

  // Chooses the blocks of macroblock (mbx, mby) of `plane`; returns their cost.
  float choose(const PlaneSearch& plane, PlaneState& state, int mbx, int mby, MacroblockChoice* out, float budget) {
    plane_ = &plane;
    const int x0 = 16 * mbx, y0 = 16 * mby;
    const PlaneContexts& contexts = plane_->contexts();
    const int split_context = state.split_context(x0, y0, 16);
    state.clear(x0, y0, 16);
    split_.partition = kSplit16x16;
    float split_cost = plane_->split_bit_cost(contexts.split_16x16[static_cast<size_t>(split_context)], 1);
    bool over_budget = false;
    for (int i = 0; i < 4 && !over_budget; ++i) {
      split_cost += choose_8x8(state, x0, y0, i);
      if (i < 3 && split_cost >= budget) {
        // The split cannot beat the budget: its other 8x8 blocks are not searched (DC
        // stands in for them in the modes the whole macroblock ranks).
        for (int k = i + 1; k < 4; ++k) split_.blocks[static_cast<size_t>(block_index(k))].mode = kDcMode;
        split_cost = std::numeric_limits<float>::infinity();
        over_budget = true;
      }
    }
    if (!sizes_) {
      *out = split_;
      return split_cost;
    }
    uint8_t saved[kMaxTransformArea];
    plane_->save(x0, y0, 16, saved);
    ModeSet ranked;
    for_each_luma_block(split_.partition, [&, n = 0](int, int, int) mutable {
      ranked.add(split_.blocks[static_cast<size_t>(n++)].mode);
    });
    for (int mode : state.candidates(x0, y0)) ranked.add(mode);
    ranked.add(kPlanarMode);
    ranked.add(kDcMode);
    state.clear(x0, y0, 16);
    BlockChoice& whole = out->blocks[0];
    const float unsplit_bits = plane_->split_bit_cost(contexts.split_16x16[static_cast<size_t>(split_context)], 0);
    const auto& halves_bit = contexts.halves_16x16[static_cast<size_t>(split_context)];
    float whole_cost = unsplit_bits + plane_->split_bit_cost(halves_bit, 0) +
                       plane_->code_block(state, x0, y0, 16, &ranked, false, &whole);
    out->partition = 0;
    // Past the budget, the halves and strips are not tried either.
    for (const bool vertical : {false, true}) {
      if (over_budget) break;
      const auto halves = static_cast<LumaPartition>(kHalves16x16 | (vertical ? kVerticalHalves : 0));
      const auto& strips_bit = contexts.strips[vertical ? 1 : 0];
      const float bits = unsplit_bits + plane_->split_bit_cost(halves_bit, 1) +
                         plane_->split_bit_cost(contexts.vertical_halves, vertical ? 1 : 0);
      try_partition(state, x0, y0, halves, bits + plane_->split_bit_cost(strips_bit, 0), &whole_cost, out);
      try_partition(state, x0, y0, static_cast<LumaPartition>(halves | kStrips),
                    bits + plane_->split_bit_cost(strips_bit, 1), &whole_cost, out);
    }
    if (whole_cost < split_cost) return whole_cost;
    plane_->restore(x0, y0, 16, saved);
    mark_blocks(state, x0, y0, split_);
    *out = split_;
    return split_cost;
  }

 private:
  // 8x8 block i (Z order) of the split macroblock, or its four 4x4 blocks; fills
  // split_.blocks from index 0 on and returns the cost.
  float choose_8x8(PlaneState& state, int mb_x0, int mb_y0, int i) {
    const int x0 = mb_x0 + 8 * (i & 1), y0 = mb_y0 + 8 * (i >> 1);
    const PlaneContexts& contexts = plane_->contexts();
    const auto context = static_cast<size_t>(state.split_context(x0, y0, 8));
    const float unsplit_bits = plane_->split_bit_cost(contexts.split_8x8[context], 0);
    const float halves_bits = unsplit_bits + plane_->split_bit_cost(contexts.halves_8x8[context], 1);
    const int first = block_index(i);
    BlockChoice& whole = split_.blocks[static_cast<size_t>(first)];
    float best_cost = unsplit_bits + plane_->split_bit_cost(contexts.halves_8x8[context], 0) +
                      plane_->code_block(state, x0, y0, 8, nullptr, false, &whole);
    if (!sizes_ || !small_blocks_ || !whole.coded) return best_cost;
    kept_[0] = whole;
    int kept_count = 1;
    LumaPartition best = 0;
    uint8_t best_samples[64];
    plane_->save(x0, y0, 8, best_samples);
    const std::pair<LumaPartition, float> trials[] = {
        {split_8x8_bit(i), plane_->split_bit_cost(contexts.split_8x8[context], 1)},
        {halves_8x8_bit(i), halves_bits + plane_->split_bit_cost(contexts.vertical_8x8, 0)},
        {static_cast<LumaPartition>(halves_8x8_bit(i) | vertical_8x8_bit(i)),
         halves_bits + plane_->split_bit_cost(contexts.vertical_8x8, 1)}};
    for (const auto& [bits, flags_cost] : trials) {
      state.clear(x0, y0, 8);
      float cost = flags_cost;
      int n = 0;
      for_each_quarter_block(static_cast<LumaPartition>(kSplit16x16 | bits), i, [&](int x, int y, int shape) {
        if (cost >= best_cost) return;
        cost += plane_->code_block(state, mb_x0 + x, mb_y0 + y, shape, nullptr, false,
                                   &trial_[static_cast<size_t>(n++)]);
      });
      if (cost < best_cost) {
        best_cost = cost;
        best = bits;
        std::copy_n(trial_.begin(), n, kept_.begin());
        kept_count = n;
        plane_->save(x0, y0, 8, best_samples);
        continue;
      }
      plane_->restore(x0, y0, 8, best_samples);
      mark_quarter(state, mb_x0, mb_y0, i, static_cast<LumaPartition>(kSplit16x16 | best));
    }
    split_.partition |= best;
    std::copy_n(kept_.begin(), kept_count, split_.blocks.begin() + first);
    return best_cost;
  }

  // Marks the blocks of 8x8 block i of the split partition in `state` again (their modes
  // from kept_), after a trial over them.
  void mark_quarter(PlaneState& state, int mb_x0, int mb_y0, int i, LumaPartition partition) const {
    for_each_quarter_block(partition, i, [&, n = 0](int x, int y, int shape) mutable {
      const BlockChoice& b = kept_[static_cast<size_t>(n++)];
      state.mark(mb_x0 + x, mb_y0 + y, shape, b.mode, b.coded);
    });
  }

  // Marks the blocks of `choice` in `state` again, after a trial over them.
  static void mark_blocks(PlaneState& state, int x0, int y0, const MacroblockChoice& choice) {
    for_each_luma_block(choice.partition, [&, n = 0](int x, int y, int shape) mutable {
      const BlockChoice& b = choice.blocks[static_cast<size_t>(n++)];
      state.mark(x0 + x, y0 + y, shape, b.mode, b.coded);
    });
  }

  // Tries the macroblock at (x0, y0) as `partition` (halves or strips), whose flags cost
  // `bits`, and keeps it in *out when it costs less than *best_cost. Each block's
  // trial stops once the partition costs more.
  void try_partition(PlaneState& state, int x0, int y0, LumaPartition partition, float bits, float* best_cost,
                     MacroblockChoice* out) {
    uint8_t best_samples[kMaxTransformArea];
    plane_->save(x0, y0, 16, best_samples);
    state.clear(x0, y0, 16);
    float cost = bits;
    int n = 0;
    for_each_luma_block(partition, [&](int x, int y, int shape) {
      if (cost >= *best_cost) return;
      const ModeSet ranked = covered_modes(state, x0, y0, x, y, shape, *out);
      cost += plane_->code_block(state, x0 + x, y0 + y, shape, &ranked, false, &trial_[static_cast<size_t>(n++)]);
    });
    if (cost < *best_cost) {
      *best_cost = cost;
      out->partition = partition;
      std::copy_n(trial_.begin(), n, out->blocks.begin());
      return;
    }
    // The trial wrote only trial_: the best so far is still in `out`.
    plane_->restore(x0, y0, 16, best_samples);
    mark_blocks(state, x0, y0, *out);
  }

  // The modes a block (x, y, shape within the macroblock at x0, y0) ranks: those of the
  // 8x8 blocks and of the best partition's blocks it overlaps, its most probable modes,
  // planar and DC.
  ModeSet covered_modes(const PlaneState& state, int x0, int y0, int x, int y, int shape,
                        const MacroblockChoice& best) const {
    ModeSet ranked;
    const int w = shape_width(shape), h = shape_height(shape);
    auto add_overlapping = [&](const MacroblockChoice& choice) {
      for_each_luma_block(choice.partition, [&, n = 0](int bx, int by, int b) mutable {
        const int mode = choice.blocks[static_cast<size_t>(n++)].mode;
        if (bx < x + w && x < bx + shape_width(b) && by < y + h && y < by + shape_height(b)) ranked.add(mode);
      });
    };
    add_overlapping(split_);
    add_overlapping(best);
    for (int mode : state.candidates(x0 + x, y0 + y)) ranked.add(mode);
    ranked.add(kPlanarMode);
    ranked.add(kDcMode);
    return ranked;
  }

  // Index in split_.blocks of the first block of 8x8 block i, given the partitions before it.
  int block_index(int i) const {
    int index = 0;
    for (int k = 0; k < i; ++k) for_each_quarter_block(split_.partition, k, [&](int, int, int) { ++index; });
    return index;
  }

  const PlaneSearch* plane_ = nullptr;
  bool sizes_;
  bool small_blocks_;  // 8x8 blocks also tried as 4x4, 8x4 and 4x8 ones
  MacroblockChoice split_;
  std::array<BlockChoice, 4> trial_;  // the blocks of the partition being tried
  std::array<BlockChoice, 4> kept_;   // the best blocks of the 8x8 block being chosen
};

// Parse stage of an intra frame: reads each block's syntax into `frame` and marks it.
class FrameBlockReader final : public BlockReader {
 public:
  FrameBlockReader(RangeDecoder& decoder, PlaneContexts& contexts, PlaneState& state, CoefficientFrame* frame,
                   DecodedLevels* decoded)
      : decoder_(decoder), contexts_(contexts), state_(state), frame_(frame), decoded_(decoded) {}

  bool read(int x0, int y0, int size) override {
    if (!read_block_syntax(decoder_, contexts_, state_, x0, y0, size, &block_)) return false;
    append(x0, y0, size, static_cast<uint8_t>(block_.mode));
    return true;
  }

  // An 8x8 chroma block; a Cb block's mode goes to `cb`, which the Cr block reads.
  bool read_chroma(int x0, int y0, ChromaPlane plane, ChromaMode* cb) {
    if (!read_chroma_block_syntax(decoder_, contexts_, state_, x0, y0, plane, cb, &block_)) return false;
    append(x0, y0, 8, ChromaMode{block_.mode, block_.cfl_alpha}.mode_byte());
    return true;
  }

 private:
  // Marks the block read and appends it to the frame with its mode byte.
  void append(int x0, int y0, int size, uint8_t mode_byte) {
    state_.mark(x0, y0, size, block_.mode, block_.count > 0);
    frame_->append_levels(block_.levels, block_.count, size_of_shape(size), block_.transform_type);
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

// The number of blocks a frame of this layout and these partitions holds.
size_t expected_block_count(const BlockLayout& layout, const std::vector<LumaPartition>& partitions) {
  size_t count = 2 * static_cast<size_t>(layout.chroma_blocks_x) * layout.chroma_blocks_y;
  for (LumaPartition partition : partitions) count += static_cast<size_t>(luma_block_count(partition));
  return count;
}

}  // namespace

namespace intra {

namespace {

// A block's levels, then its transform type when it has levels (out->mode set).
bool read_levels_and_type(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                          TransformSize size, BlockSyntax* out) {
  out->count = 0;
  out->transform_type = TransformType::kDctDct;
  if (!decode_block_levels(decoder, contexts.residual, 0, state.coded_block_context(x0, y0), out->levels,
                           &out->count, size)) {
    return false;
  }
  if (out->count > 0) out->transform_type = decode_transform_type(decoder, contexts.types, size, out->mode);
  return true;
}

}  // namespace

bool read_block_syntax(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                       int size, BlockSyntax* out) {
  out->mode = decode_intra_mode(decoder, contexts.modes, size, state.candidates(x0, y0));
  out->cfl_alpha = 0;
  return read_levels_and_type(decoder, contexts, state, x0, y0, size_of_shape(size), out);
}

bool read_chroma_block_syntax(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int x0,
                              int y0, ChromaPlane plane, ChromaMode* cb, BlockSyntax* out) {
  const ChromaMode mode = decode_chroma_mode(decoder, contexts.cfl, contexts.modes, state.cfl_context(x0, y0),
                                             state.candidates(x0, y0), plane, *cb);
  if (plane == ChromaPlane::kCb) *cb = mode;
  out->mode = mode.mode;
  out->cfl_alpha = mode.alpha;
  return read_levels_and_type(decoder, contexts, state, x0, y0, TransformSize::k8x8, out);
}

bool read_luma_macroblock(RangeDecoder& decoder, PlaneContexts& contexts, const PlaneState& state, int mbx, int mby,
                          BlockReader& reader, LumaPartition* partition) {
  const int x0 = 16 * mbx, y0 = 16 * mby;
  *partition = 0;
  const int split_context = state.split_context(x0, y0, 16);
  if (!decoder.decode(contexts.split_16x16[static_cast<size_t>(split_context)])) {
    if (!decoder.decode(contexts.halves_16x16[static_cast<size_t>(split_context)])) return reader.read(x0, y0, 16);
    const bool vertical = decoder.decode(contexts.vertical_halves) != 0;
    const bool strips = decoder.decode(contexts.strips[vertical ? 1 : 0]) != 0;
    *partition =
        static_cast<LumaPartition>(kHalves16x16 | (vertical ? kVerticalHalves : 0) | (strips ? kStrips : 0));
    bool read = true;
    for_each_luma_block(*partition,
                        [&](int x, int y, int shape) { read = read && reader.read(x0 + x, y0 + y, shape); });
    return read;
  }
  *partition = kSplit16x16;
  for (int i = 0; i < 4; ++i) {
    const int x = x0 + 8 * (i & 1), y = y0 + 8 * (i >> 1);
    const auto context = static_cast<size_t>(state.split_context(x, y, 8));
    if (decoder.decode(contexts.split_8x8[context])) {
      *partition |= split_8x8_bit(i);
    } else if (decoder.decode(contexts.halves_8x8[context])) {
      *partition |= halves_8x8_bit(i);
      if (decoder.decode(contexts.vertical_8x8)) *partition |= vertical_8x8_bit(i);
    }
    bool read = true;
    for_each_quarter_block(*partition, i,
                           [&](int bx, int by, int shape) { read = read && reader.read(x0 + bx, y0 + by, shape); });
    if (!read) return false;
  }
  return true;
}

void reconstruct_block_in_plane(PlaneState& state, uint8_t* plane, int stride, int x0, int y0, int size, int mode,
                                const int16_t* coefficients, TransformType type) {
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
    reconstruct_block_in_plane(state, plane, stride, x0, y0, 8, mode.mode, coefficients, type);
    return;
  }
  uint8_t edge[dsp::kMaxIntraEdgeSamples], prediction[kMaxTransformArea];
  build_intra_edge(plane, stride, x0, y0, 8, state.availability(x0, y0, 8), edge);
  int16_t ac[64];
  cfl_luma_ac(luma, luma_stride, x0, y0, ac);
  predict_cfl(ac, dc_prediction_8x8(edge), mode.alpha, prediction);
  reconstruct_block(prediction, coefficients, type, 8, plane + static_cast<ptrdiff_t>(y0) * stride + x0, stride);
  state.mark(x0, y0, 8, kCflMode, coefficients != nullptr);
}

namespace {

// Writes a block's levels and, when it has levels, its transform type, and marks it.
void write_levels(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0, int size,
                  const BlockChoice& choice) {
  encode_block_levels(encoder, contexts.residual, choice.levels, 0, state.coded_block_context(x0, y0),
                      size_of_shape(size));
  const bool has_levels =
      std::any_of(choice.levels, choice.levels + shape_area(size), [](int16_t l) { return l != 0; });
  if (has_levels)
    encode_transform_type(encoder, contexts.types, size_of_shape(size), choice.mode, choice.transform_type);
  state.mark(x0, y0, size, choice.mode, choice.coded);
}

}  // namespace

void write_block(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0, int size,
                 const BlockChoice& choice) {
  encode_intra_mode(encoder, contexts.modes, size, state.candidates(x0, y0), choice.mode);
  write_levels(encoder, contexts, state, x0, y0, size, choice);
}

void write_chroma_block(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int x0, int y0,
                        ChromaPlane plane, const ChromaMode& cb, const BlockChoice& choice) {
  encode_chroma_mode(encoder, contexts.cfl, contexts.modes, state.cfl_context(x0, y0), state.candidates(x0, y0),
                     plane, cb, choice.chroma_mode());
  write_levels(encoder, contexts, state, x0, y0, 8, choice);
}

namespace {

// The split and halves flags of 8x8 block i of a split macroblock at (x0, y0).
void write_quarter_flags(RangeEncoder& encoder, PlaneContexts& contexts, const PlaneState& state, int x0, int y0,
                         int i, LumaPartition partition) {
  const auto context = static_cast<size_t>(state.split_context(x0 + 8 * (i & 1), y0 + 8 * (i >> 1), 8));
  encoder.encode(contexts.split_8x8[context], (partition & split_8x8_bit(i)) != 0);
  if (partition & split_8x8_bit(i)) return;
  encoder.encode(contexts.halves_8x8[context], (partition & halves_8x8_bit(i)) != 0);
  if (partition & halves_8x8_bit(i)) encoder.encode(contexts.vertical_8x8, (partition & vertical_8x8_bit(i)) != 0);
}

}  // namespace

void write_macroblock(RangeEncoder& encoder, PlaneContexts& contexts, PlaneState& state, int mbx, int mby,
                      const MacroblockChoice& choice) {
  const int x0 = 16 * mbx, y0 = 16 * mby;
  const int split_context = state.split_context(x0, y0, 16);
  encoder.encode(contexts.split_16x16[static_cast<size_t>(split_context)], choice.partition & kSplit16x16);
  if ((choice.partition & kSplit16x16) == 0) {
    encoder.encode(contexts.halves_16x16[static_cast<size_t>(split_context)],
                   (choice.partition & kHalves16x16) != 0);
    if (choice.partition & kHalves16x16) {
      const bool vertical = (choice.partition & kVerticalHalves) != 0;
      encoder.encode(contexts.vertical_halves, vertical);
      encoder.encode(contexts.strips[vertical ? 1 : 0], (choice.partition & kStrips) != 0);
    }
  }
  int n = 0;
  for_each_luma_block(choice.partition, [&](int x, int y, int size) {
    if ((choice.partition & kSplit16x16) && x % 8 == 0 && y % 8 == 0)
      write_quarter_flags(encoder, contexts, state, x0, y0, x / 8 + 2 * (y / 8), choice.partition);
    write_block(encoder, contexts, state, x0 + x, y0 + y, size, choice.blocks[static_cast<size_t>(n++)]);
  });
}

namespace {

// The residual quantizers with the encoder's dead zone for intra residuals: narrower
// than inter residuals' (0.2), tuned on the photographic scenes.
SizedQuantizers encoder_quantizers(int qindex, ResidualMatrix matrix) {
  SizedQuantizers quantizers = residual_quantizers(qindex, matrix);
  for (Quantizer& q : quantizers) q.rounding_dc = q.rounding_ac = 0.25f;
  return quantizers;
}

}  // namespace

struct MacroblockEncoder::Impl {
  Impl(const CodingParams& params, int qindex, float lambda)
      : quantizers(encoder_quantizers(qindex, params.residual_matrix)),
        search(quantizers, params, lambda),
        macroblocks(params.transform_sizes, params.small_blocks),
        cfl(params.cfl) {}

  SizedQuantizers quantizers;
  BlockSearch search;
  MacroblockSearch macroblocks;
  bool cfl;
  BlockChoice cb_trial, cr_trial;
};

MacroblockEncoder::MacroblockEncoder(const CodingParams& params, int qindex, float lambda)
    : impl_(std::make_unique<Impl>(params, std::clamp(qindex, kMinQIndex, kMaxQIndex), lambda)) {}

MacroblockEncoder::~MacroblockEncoder() = default;

float MacroblockEncoder::choose_luma(const PlaneContexts& contexts, PlaneState& state, const uint8_t* source,
                                     uint8_t* recon, int stride, int mbx, int mby, MacroblockChoice* out,
                                     float budget) {
  const PlaneSearch plane(impl_->search, impl_->quantizers, contexts, source, recon, stride);
  return impl_->macroblocks.choose(plane, state, mbx, mby, out, budget);
}

float MacroblockEncoder::choose_chroma(const PlaneContexts& contexts, PlaneState& cb_state, PlaneState& cr_state,
                                       const uint8_t* cb_source, const uint8_t* cr_source, uint8_t* cb_recon,
                                       uint8_t* cr_recon, int stride, const uint8_t* luma, int luma_stride, int x0,
                                       int y0, BlockChoice* cb, BlockChoice* cr) {
  const PlaneSearch cb_plane(impl_->search, impl_->quantizers, contexts, cb_source, cb_recon, stride);
  const PlaneSearch cr_plane(impl_->search, impl_->quantizers, contexts, cr_source, cr_recon, stride);
  float cost = cb_plane.choose_chroma_regular(cb_state, x0, y0, nullptr, cb);
  const ChromaMode cb_regular = cb->chroma_mode();
  cost += cr_plane.choose_chroma_regular(cr_state, x0, y0, &cb_regular, cr);
  if (impl_->cfl && luma != nullptr) {
    // CfL replaces the pair when cheaper; Cr's cost only adds to Cb's.
    int16_t ac[64];
    cfl_luma_ac(luma, luma_stride, x0, y0, ac);
    BlockChoice& cb_trial = impl_->cb_trial;
    BlockChoice& cr_trial = impl_->cr_trial;
    const float cb_cost = cb_plane.choose_chroma_cfl(cb_state, x0, y0, ac, nullptr, &cb_trial);
    if (cb_cost < cost) {
      const ChromaMode cb_mode = cb_trial.chroma_mode();
      const float cfl_cost = cb_cost + cr_plane.choose_chroma_cfl(cr_state, x0, y0, ac, &cb_mode, &cr_trial);
      if (cfl_cost < cost) {
        BlockSearch::copy_choice(cb_trial, 8, cb);
        BlockSearch::copy_choice(cr_trial, 8, cr);
        cost = cfl_cost;
      }
    }
  }
  cb_plane.finish_block(cb_state, x0, y0, 8, *cb);
  cr_plane.finish_block(cr_state, x0, y0, 8, *cr);
  return cost;
}

}  // namespace intra

size_t CoefficientFrame::memory_bytes() const {
  return sizeof(*this) + luma_partitions.capacity() * sizeof(uint16_t) +
         block_counts.capacity() * sizeof(uint16_t) + block_modes.capacity() + levels.capacity() +
         cdef.memory_bytes();
}

namespace {

// Natural position -> scan index, per transform size.
const std::array<uint8_t, kMaxTransformArea>& inverse_scan(TransformSize size) {
  static const auto tables = [] {
    std::array<std::array<uint8_t, kMaxTransformArea>, kTransformSizes> t{};
    for (int s = 0; s < kTransformSizes; ++s) {
      const ScanOrder& order = scan_order(static_cast<TransformSize>(s));
      for (int i = 0; i < order.count; ++i) t[static_cast<size_t>(s)][order.scan[i]] = static_cast<uint8_t>(i);
    }
    return t;
  }();
  return tables[static_cast<size_t>(size)];
}

}  // namespace

void CoefficientFrame::append_levels(const BlockLevel* block_levels, int count, TransformSize size,
                                     TransformType type) {
  if (count <= 0) return;
  const std::array<uint8_t, kMaxTransformArea>& scan_of = inverse_scan(size);
  LevelStreamWriter writer(&levels);
  writer.transform_type(static_cast<int>(type));
  int previous = -1;
  for (int i = 0; i < count; ++i) {
    const int scan = scan_of[block_levels[i].position];
    writer.level(previous, scan, block_levels[i].level);
    previous = scan;
  }
}

int CoefficientFrame::read_levels(size_t* offset, int count, TransformSize size, int* positions, int* values,
                                  TransformType* type) const {
  *type = TransformType::kDctDct;
  if (count <= 0 || *offset >= levels.size()) return 0;
  const ScanOrder& order = scan_order(size);
  LevelStreamReader reader(levels.data() + *offset, levels.size() - *offset);
  *type = static_cast<TransformType>(reader.transform_type());
  int read = 0, previous = -1;
  while (read < count) {
    int scan, value;
    if (!reader.level(previous, &scan, &value) || scan >= order.count) break;
    positions[read] = order.scan[scan];
    values[read++] = value;
    previous = scan;
  }
  *offset += reader.bytes_read();
  return read;
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
  MacroblockEncoder search(params, qindex, intra_frame_lambda(qindex));
  const BlockLayout layout = block_layout(width, height);
  auto planes = planes_of(layout, width, height);
  planes[0].pixels = source.y.data();
  planes[1].pixels = source.cb.data();
  planes[2].pixels = source.cr.data();

  std::vector<uint8_t> bytes = {kIntraSyntaxVersion, static_cast<uint8_t>(qindex),
                                params.residual_matrix == ResidualMatrix::kWeighted ? kIntraWeightedMatrix
                                                                                    : uint8_t{0}};
  bytes.reserve(static_cast<size_t>(width) * height / 4 + 64);
  if (params.transform_types) bytes[kIntraFlagsByte] |= kTransformTypesFlag;
  RangeEncoder encoder(&bytes);
  PlaneContexts luma_contexts, chroma_contexts;
  prime_intra_frame_contexts(luma_contexts, chroma_contexts);
  luma_contexts.types.enabled = chroma_contexts.types.enabled = params.transform_types;
  PaddedFrame frame = padded_frame(layout);

  {
    const PlaneGeometry& luma = planes[0];
    const std::vector<uint8_t> padded_source = pad_plane(luma);
    auto choice = std::make_unique<MacroblockChoice>();
    PlaneState state(luma.stride(), luma.padded_height());
    for (int mby = 0; mby < luma.blocks_y / 2; ++mby) {
      for (int mbx = 0; mbx < luma.blocks_x / 2; ++mbx) {
        search.choose_luma(luma_contexts, state, padded_source.data(), frame.planes[0].data(), luma.stride(), mbx,
                           mby, choice.get());
        write_macroblock(encoder, luma_contexts, state, mbx, mby, *choice);
      }
    }
  }
  {
    // Both chroma blocks of a position are chosen together (a Cb block's mode with its Cr
    // block's cost under it); Cb blocks are written as chosen, the Cr blocks after the
    // last Cb block, as the syntax orders them.
    const PlaneGeometry& chroma = planes[1];
    const std::vector<uint8_t> cb_source = pad_plane(planes[1]), cr_source = pad_plane(planes[2]);
    PlaneState cb_state(chroma.stride(), chroma.padded_height()), cr_state(chroma.stride(), chroma.padded_height());
    const size_t count = static_cast<size_t>(chroma.blocks_x) * chroma.blocks_y;
    std::vector<BlockChoice> cr_choices(count);
    std::vector<ChromaMode> cb_modes(count);
    auto cb = std::make_unique<BlockChoice>();
    for (size_t i = 0; i < count; ++i) {
      const int x0 = 8 * static_cast<int>(i % static_cast<size_t>(chroma.blocks_x));
      const int y0 = 8 * static_cast<int>(i / static_cast<size_t>(chroma.blocks_x));
      search.choose_chroma(chroma_contexts, cb_state, cr_state, cb_source.data(), cr_source.data(),
                           frame.planes[1].data(), frame.planes[2].data(), chroma.stride(), frame.planes[0].data(),
                           planes[0].stride(), x0, y0, cb.get(), &cr_choices[i]);
      write_chroma_block(encoder, chroma_contexts, cb_state, x0, y0, ChromaPlane::kCb, {}, *cb);
      cb_modes[i] = cb->chroma_mode();
    }
    for (size_t i = 0; i < count; ++i) {
      const int x0 = 8 * static_cast<int>(i % static_cast<size_t>(chroma.blocks_x));
      const int y0 = 8 * static_cast<int>(i / static_cast<size_t>(chroma.blocks_x));
      write_chroma_block(encoder, chroma_contexts, cr_state, x0, y0, ChromaPlane::kCr, cb_modes[i], cr_choices[i]);
    }
  }
  // The filters change no block symbol: decide them on the finished reconstruction.
  if (params.deblocking) {
    PaddedFrame filtered = frame;
    deblock_intra(&filtered, qindex);
    if (frame_error(filtered, source) < frame_error(frame, source)) {
      bytes[kIntraFlagsByte] |= kLoopFilterDeblocking;
      frame = std::move(filtered);
    }
  }
  if (params.cdef && apply_cdef_choice(encoder, &frame, source, qindex, params.full_cdef_search))
    bytes[kIntraFlagsByte] |= kLoopFilterCdef;
  observe_intra_frame_contexts(luma_contexts, chroma_contexts);
  encoder.finish();
  if (reconstruction != nullptr) crop(frame, width, height, reconstruction);
  return bytes;
}

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
  if (bytes[0] != kIntraSyntaxVersion) {
    return Status(ErrorCode::kUnsupported, "intra frame: byte 0: syntax version " + std::to_string(bytes[0]) +
                                               " (this build reads " + std::to_string(kIntraSyntaxVersion) + ")");
  }
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

namespace {

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

Status decode_intra_frame(std::span<const uint8_t> bytes, int width, int height, ImageYCbCr420* out) {
  CoefficientFrame coefficients;
  DecodedLevels decoded;
  SVC_RETURN_IF_ERROR(parse_intra_frame(bytes, width, height, &coefficients, &decoded));
  reconstruct_intra_frame(coefficients, out, &decoded);
  return Status::Ok();
}

}  // namespace svc::codec
