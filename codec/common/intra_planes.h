// SPDX-License-Identifier: BSD-2-Clause
// The macroblock-padded planes of an intra frame, shared by its reconstruction, its
// decoder and its encoder (internal to codec/).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/common/cdef.h"
#include "codec/common/intra_frame.h"
#include "codec/common/loop_filter.h"
#include "codec/common/transform_size.h"
#include "codec/common/transform_type.h"
#include "svc/types.h"

namespace svc::codec::intra {

struct PlaneGeometry {
  int width, height;       // visible samples
  int blocks_x, blocks_y;  // padded size in 8x8 blocks
  const uint8_t* pixels;   // source plane (encoder) or nullptr
  int stride() const { return blocks_x * 8; }
  int padded_height() const { return blocks_y * 8; }
  size_t padded_size() const { return static_cast<size_t>(stride()) * blocks_y * 8; }
};

std::array<PlaneGeometry, 3> planes_of(const BlockLayout& layout, int width, int height);

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

PaddedFrame padded_frame(const BlockLayout& layout);
void deblock_intra(PaddedFrame* frame, int qindex);
// CDEF of an intra frame: no block is skipped (every block has a DC level).
void cdef_intra(PaddedFrame* frame, const CdefParams& params, int qindex);
// The visible part of the frame into `out`.
void crop(const PaddedFrame& frame, int width, int height, ImageYCbCr420* out);

// out = clip(prediction + inverse transform of type `type` of `coefficients`), or the
// prediction alone when there are none; a block of `size`.
void reconstruct_block(const uint8_t* prediction, const int16_t* coefficients, TransformType type,
                       TransformSize size, uint8_t* out, int stride);

}  // namespace svc::codec::intra
