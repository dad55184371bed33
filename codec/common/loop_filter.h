// SPDX-License-Identifier: BSD-2-Clause
// In-loop deblocking (docs/codec.md, section 5.8), in the manner of H.265 section 8.7.2:
// edges on the 8x8 grid of each plane, a boundary strength per 4-sample edge segment
// that the frame codec derives from its coding decisions, thresholds beta and tc from
// the quantizer index, the on/off and strong/normal decisions from the samples. The
// filter knows nothing of macroblocks or block sizes: the frame codec describes the edges
// in a DeblockMap, so a new partition or transform size only changes how the map is
// filled. Bit-exact integer arithmetic; the pixel work is in the dsp table.
//
// Threading: every function is reentrant; filter different frames on different threads.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace svc::codec {

// Boundary strengths of a frame on the luma 4x4 grid of its macroblock-padded size:
// 0 no filtering, 1 residual or motion differs, 2 an intra block on either side.
// Entries off the 8x8 grid (odd unit coordinates across the edge) are ignored, as are
// those of the frame's first column (vertical) and first row (horizontal).
struct DeblockMap {
  int units_x = 0, units_y = 0;     // padded luma size / 4
  std::vector<uint8_t> vertical;    // per unit, row-major: its left edge
  std::vector<uint8_t> horizontal;  // per unit, row-major: its top edge

  // A map of padded_width x padded_height luma samples with every edge at `strength`.
  static DeblockMap uniform(int padded_width, int padded_height, uint8_t strength);
  uint8_t& left(int ux, int uy) { return vertical[static_cast<size_t>(uy) * units_x + ux]; }
  uint8_t& top(int ux, int uy) { return horizontal[static_cast<size_t>(uy) * units_x + ux]; }
  uint8_t left(int ux, int uy) const { return vertical[static_cast<size_t>(uy) * units_x + ux]; }
  uint8_t top(int ux, int uy) const { return horizontal[static_cast<size_t>(uy) * units_x + ux]; }
};

// A plane the filter works on in place: the whole macroblock-padded plane.
struct PlaneView {
  uint8_t* data = nullptr;
  int stride = 0;
  int width = 0, height = 0;
};

// The H.265-style parameter Q of the thresholds for a quantizer index:
// clip((3 qindex + 8) >> 4, 2, 53) - 2, the QP whose step matches the index's.
int deblock_qp(int qindex);
// beta and tc (8-bit samples) for a quantizer index and a boundary strength 1 or 2.
int deblock_beta(int qindex);
int deblock_tc(int qindex, int strength);

// Filters luma (planes[0]) and both chroma planes of a 4:2:0 frame in place: in each
// plane every vertical edge first, then every horizontal edge. planes[0] must be
// 4 map.units_x x 4 map.units_y samples and the chroma planes half that; a map or plane
// of another size is left unfiltered.
void deblock_frame(const DeblockMap& map, int qindex, const std::array<PlaneView, 3>& planes);

}  // namespace svc::codec
