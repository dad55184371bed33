// SPDX-License-Identifier: BSD-2-Clause
// Optical flow from depth and cameras (dissertation section 4.2.3.2) and the
// per-macroblock candidate motion vectors derived from it.
//
// Conventions (docs/input-format.md): pixel (i, j) has its centre at NDC
// x = (i + 0.5) / w * 2 - 1, y = 1 - (j + 0.5) / h * 2; a camera's world_to_camera is an
// OpenGL view matrix (looking down -z) and its frustum the glFrustum parameters. The
// view matrices are taken as affine (rotation, translation, uniform scale): their last
// row is assumed to be 0 0 0 1.
//
// Threading: pure functions of their arguments; safe to call concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/common/motion.h"
#include "svc/types.h"

namespace svc {

// Per-pixel flow from the current face to a reference face, in pixels: the point seen at
// pixel (i, j) of the current face is seen at (i + dx, j + dy) of the reference face,
// both in pixel-index coordinates (centre of pixel i is at i).
struct FlowField {
  int width = 0;
  int height = 0;
  std::vector<float> dx, dy;   // width * height, row-major, row 0 at the top
  std::vector<uint8_t> valid;  // 0 where the point falls behind the reference camera
};

// depth: eye-space z per pixel of the current face (positive distance along the view
// axis, row-major, row 0 at the top). A pixel whose depth is +inf, NaN, <= 0 or >= the
// current camera's far plane saw no geometry; it is treated as a point at infinity and
// reprojected as a direction (rotation-only flow, exact for sky). Points at or behind
// the reference camera's plane are invalid; points that land outside the reference face
// are valid (their flow says where they went). Both faces are width x height pixels.
// Preconditions: width, height >= 0; depth.size() == width * height. When the size does
// not match, the result has the given size with every pixel invalid. Cost: a few dozen
// flops a pixel (no per-pixel matrix products or inverses).
FlowField compute_flow(const Camera& current, const Camera& reference, int width, int height,
                       const std::vector<float>& depth);

// The same into `out`, reusing its storage: nothing is allocated or cleared when `out`
// already has the size, so a caller computing many flows can keep one field. `out`
// must not be null.
void compute_flow(const Camera& current, const Camera& reference, int width, int height,
                  const std::vector<float>& depth, FlowField* out);

// Plain implementation of compute_flow, following the dissertation's matrices literally
// (V^-1 of the current camera, V of the reference, as full 4x4 products per pixel). Kept
// as the reference the fast path is tested against; same contract.
FlowField compute_flow_reference(const Camera& current, const Camera& reference, int width, int height,
                                 const std::vector<float>& depth);

// Which pixels of the current face show something the reference face shows too: the
// point (or, for background, the direction) lands inside the reference face, in front of
// its camera, and is not hidden there, i.e. one of the 3x3 reference pixels around where
// it lands holds an eye depth within kVisibilityTolerance (relative) of the point's depth
// in the reference camera. A background pixel counts as seen when it lands on background.
// It bounds what prediction from that reference can do: an unseen pixel (occluded, or
// outside the face) must be coded without it. depth and reference_depth follow
// compute_flow's conventions (eye z, +inf or another background value where nothing was
// hit). Returns width * height flags (1: seen); all zero when a size does not match.
// A diagnostic for benchmarks and tools, not used by the encoder.
inline constexpr double kVisibilityTolerance = 0.02;
std::vector<uint8_t> visible_in_reference(const Camera& current, const Camera& reference, int width, int height,
                                          const std::vector<float>& depth,
                                          const std::vector<float>& reference_depth);

// Most candidates kept per macroblock (the most frequent ones), bounding the encoder's
// work on chaotic blocks (foliage, depth edges); the dissertation reports ~5 on average.
inline constexpr int kMaxCandidatesPerMacroblock = 32;

// Distinct quarter-pixel vectors of each 16x16 macroblock, most frequent first (ties: by
// smaller y, then smaller x). Faces are padded to whole macroblocks: ceil(w/16) x
// ceil(h/16) lists in row-major macroblock order; pixels outside the face and invalid
// pixels contribute nothing, so a list may be empty. A pixel whose quantized vector has
// a component beyond +-4*max(w, h) quarter pixels (a displacement larger than the face)
// contributes nothing either. At most kMaxCandidatesPerMacroblock vectors per list.
codec::FaceCandidates macroblock_candidates(const FlowField& flow);

// The same for each 8x8 block (the candidates of macroblock partitions): 2 ceil(w/16) x
// 2 ceil(h/16) lists in row-major block order, same ranking, rules and limit.
codec::FaceCandidates block_candidates(const FlowField& flow);

// The warp node field of a face (codec/common/motion.h, WarpField): per macroblock corner, the
// flow at the corner point (16 i - 0.5, 16 j - 0.5) in 1/8 pel, rounded to nearest. Where
// the 2x2 pixels around the corner agree within half a pixel the node is their mean (the
// bilinear flow at the corner, exact for planes); across a depth discontinuity it is the
// flow of the pixel of the surrounding 4x4 that is closest to the others (the majority
// surface), so the node follows one surface instead of blending two. Coordinates past
// the face are clamped to it. Nodes without a valid pixel near them take the mean of
// their valid neighbour nodes (0 when none).
codec::WarpField warp_nodes(const FlowField& flow);

// Counts over one or more faces' candidate lists, for reporting (the dissertation's
// "average number of unique motion vectors per macroblock").
struct CandidateStats {
  size_t macroblocks = 0;                  // all macroblocks seen
  size_t macroblocks_with_candidates = 0;  // those with at least one candidate
  size_t candidates = 0;                   // total candidates over all macroblocks
  // Mean candidates per macroblock that has any (0 when none has).
  double mean_per_macroblock() const {
    return macroblocks_with_candidates == 0
               ? 0.0
               : static_cast<double>(candidates) / static_cast<double>(macroblocks_with_candidates);
  }
  CandidateStats& operator+=(const CandidateStats& other) {
    macroblocks += other.macroblocks;
    macroblocks_with_candidates += other.macroblocks_with_candidates;
    candidates += other.candidates;
    return *this;
  }
};

CandidateStats candidate_stats(const codec::FaceCandidates& candidates);

}  // namespace svc
