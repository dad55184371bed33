// SPDX-License-Identifier: BSD-2-Clause
// Motion vectors and per-macroblock candidate lists shared by the motion sources
// (depth reprojection in src/spatial, image search in codec) and the B-face coder.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace svc::codec {

inline constexpr int kMacroblockSize = 16;

// A luma displacement in quarter-pixel units: the prediction for pixel (x, y) of the
// current face is taken at (x + x/4, y + y/4) in the reference face (chroma reads the
// same numbers in eighth chroma pixels).
struct MotionVector {
  int16_t x = 0;
  int16_t y = 0;
  friend bool operator==(const MotionVector&, const MotionVector&) = default;
};

// A warp node: the displacement of a macroblock corner in 1/8 luma pel (see
// warp_prediction.h). Wider than MotionVector: nodes of large faces exceed 16 bits.
inline constexpr int kWarpNodeUnitsPerPixel = 8;
inline constexpr int kVectorUnitsPerPixel = 4;
struct WarpNode {
  int32_t x = 0;
  int32_t y = 0;
  friend bool operator==(const WarpNode&, const WarpNode&) = default;
};

// Node vectors of a whole face towards one reference: (ceil(w/16) + 1) x (ceil(h/16) + 1)
// nodes, row-major; node (i, j) sits at the corner (16 i, 16 j) of the macroblock grid,
// i.e. at pixel-index coordinates (16 i - 0.5, 16 j - 0.5). Empty when not available.
struct WarpField {
  int nodes_x = 0;
  int nodes_y = 0;
  std::vector<WarpNode> nodes;
  bool empty() const { return nodes.empty(); }
  const WarpNode& at(int i, int j) const { return nodes[static_cast<size_t>(j) * nodes_x + i]; }
};

// Candidate vectors of one macroblock towards one reference, distinct, in the order
// the motion source ranks them (most pixels first).
using CandidateList = std::vector<MotionVector>;

// Candidates for every macroblock of a face (row-major macroblock order) for one
// reference. Faces are padded to whole macroblocks: ceil(w/16) x ceil(h/16) entries.
using FaceCandidates = std::vector<CandidateList>;

}  // namespace svc::codec
