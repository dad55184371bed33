// SPDX-License-Identifier: BSD-2-Clause
// Intra frame encoding: each luma macroblock and chroma block chosen by the intra
// search (codec/encoder/intra_search.h) and written as the syntax orders them, then the
// in-loop filters decided on the finished reconstruction.
#include "codec/encoder/intra_encoder.h"

#include <algorithm>
#include <memory>

#include "codec/common/context_priors.h"
#include "codec/common/intra_planes.h"
#include "codec/encoder/cdef_search.h"
#include "codec/encoder/distortion.h"
#include "codec/encoder/intra_search.h"
#include "codec/encoder/intra_syntax_writer.h"
#include "codec/encoder/range_encoder.h"
#include "codec/encoder/rate_distortion.h"

namespace svc::codec {
namespace {

using namespace intra;

// SSE per bit of an intra frame's decisions (docs/encoder.md).
constexpr double kIntraFrameLambdaFactor = 0.085;
// SSE per bit of an intra frame's CDEF decision (docs/encoder.md).
constexpr double kIntraCdefLambdaFactor = 0.12;

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

// Chooses CDEF for the deblocked frame, filters it and writes the syntax when the
// filter pays. Returns whether it did.
bool apply_cdef_choice(RangeEncoder& encoder, PaddedFrame* frame, const ImageYCbCr420& source, int qindex,
                       bool every_candidate) {
  CdefSource visible;
  visible.planes = {source.y.data(), source.cb.data(), source.cr.data()};
  visible.strides = {source.width, (source.width + 1) / 2, (source.width + 1) / 2};
  visible.width = source.width;
  visible.height = source.height;
  const CdefParams params =
      choose_cdef(frame->views(), visible, qindex, {}, rd_lambda(qindex, kIntraCdefLambdaFactor), every_candidate);
  if (params.presets.empty()) return false;
  write_cdef_syntax(encoder, params, cdef_units(frame->widths[0]), cdef_units(frame->heights[0]));
  cdef_intra(frame, params, qindex);
  return true;
}

int64_t frame_error(const PaddedFrame& frame, const ImageYCbCr420& source) {
  const int cw = (source.width + 1) / 2, ch = (source.height + 1) / 2;
  return squared_error(frame.planes[0].data(), frame.widths[0], source.y.data(), source.width, source.width,
                       source.height) +
         squared_error(frame.planes[1].data(), frame.widths[1], source.cb.data(), cw, cw, ch) +
         squared_error(frame.planes[2].data(), frame.widths[2], source.cr.data(), cw, cw, ch);
}

}  // namespace

std::vector<uint8_t> encode_intra_frame(const ImageYCbCr420& source, const CodingParams& params,
                                        ImageYCbCr420* reconstruction, SyntaxBits* syntax) {
  const int width = source.width, height = source.height;
  const size_t chroma_size = static_cast<size_t>((width + 1) / 2) * static_cast<size_t>((height + 1) / 2);
  if (width <= 0 || height <= 0 || width > kMaxFrameDimension || height > kMaxFrameDimension ||
      source.y.size() != static_cast<size_t>(width) * static_cast<size_t>(height) ||
      source.cb.size() != chroma_size || source.cr.size() != chroma_size) {
    return {};
  }
  const int qindex = std::clamp(params.qindex, kMinQIndex, kMaxQIndex);
  MacroblockEncoder search(params, qindex, static_cast<float>(rd_lambda(qindex, kIntraFrameLambdaFactor)));
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
  SyntaxBits account;
  if (syntax != nullptr) {
    account.add(SyntaxElement::kHeader, 8.0 * static_cast<double>(bytes.size()));
    encoder.set_account(&account);
  }
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
  if (syntax != nullptr) {
    account.current = SyntaxElement::kHeader;
    *syntax = account;
  }
  if (reconstruction != nullptr) crop(frame, width, height, reconstruction);
  return bytes;
}

}  // namespace svc::codec
