// SPDX-License-Identifier: BSD-2-Clause
// The intra mode decision (docs/encoder.md): partitions, prediction modes, transform
// types and levels of intra macroblocks by rate-distortion cost.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>

#include "codec/common/intra_macroblock.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/intra_syntax_writer.h"

namespace svc::codec {

// The CfL alpha of least squared error between `source` and the prediction, rounded
// and clamped to the alpha range.
int cfl_least_squares_alpha(const int16_t* ac, const uint8_t* source, ptrdiff_t stride, int dc);

}  // namespace svc::codec

namespace svc::codec::intra {

// The intra rate-distortion search (docs/encoder.md) for the
// blocks of one macroblock at one qindex. Each call chooses, reconstructs the choice
// into `recon` (a padded plane whose reconstructed neighbours it predicts from; `source`
// the padded source plane, same stride), marks it in `state` and returns its cost,
// SSE + lambda * bits. Contexts are read, not updated (write_* does that).
class MacroblockEncoder {
 public:
  // `params` supplies the tools (modes, RD search, RDOQ, transform sizes); `lambda` the
  // squared error per bit of every decision. Transform types are searched where the
  // contexts enable them (PlaneContexts::types).
  MacroblockEncoder(const CodingParams& params, int qindex, float lambda);
  ~MacroblockEncoder();
  MacroblockEncoder(const MacroblockEncoder&) = delete;
  MacroblockEncoder& operator=(const MacroblockEncoder&) = delete;

  // The luma blocks of macroblock (mbx, mby) and their cost. `budget`: the cost the
  // macroblock must beat to be chosen at all (a B-face's best inter option). Once the
  // four 8x8 blocks' running cost reaches it, the rest of them, the halves and the strips
  // are not searched: only the 16x16 block may still come in under it (mode ranking as
  // with the whole split, DC for the blocks not searched). Infinite: the full search.
  // `partition` (optional): search only that partition, its blocks' modes, transform
  // types and levels chosen again (a B-face's intra winner quantized by RDOQ).
  float choose_luma(const PlaneContexts& contexts, PlaneState& state, const uint8_t* source, uint8_t* recon,
                    int stride, int mbx, int mby, MacroblockChoice* out,
                    float budget = std::numeric_limits<float>::infinity(),
                    const LumaPartition* partition = nullptr);
  // The Cb and the Cr block at (x0, y0) of the chroma planes (`cb_*`, `cr_*`, each with
  // its own neighbour state; same stride). A Cb block's mode is chosen with its Cr
  // block's cost under it: the best regular mode with Cr in that mode, against CfL (when
  // `luma`, the reconstructed luma, luma_stride samples a row, is given and the params
  // allow it) with each plane's own alpha. Returns the pair's cost.
  float choose_chroma(const PlaneContexts& contexts, PlaneState& cb_state, PlaneState& cr_state,
                      const uint8_t* cb_source, const uint8_t* cr_source, uint8_t* cb_recon, uint8_t* cr_recon,
                      int stride, const uint8_t* luma, int luma_stride, int x0, int y0, BlockChoice* cb,
                      BlockChoice* cr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace svc::codec::intra
