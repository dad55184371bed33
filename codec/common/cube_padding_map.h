// SPDX-License-Identifier: BSD-2-Clause
// Internal to the cube padding (codec/cube_padding.h) and its tests. The rule of
// docs/codec.md 5.7 picks, per border sample, a source face and a 1/16-sample position
// with 64-bit divisions; that geometry depends only on (face, plane size, border), never
// on the samples. So each geometry is worked out once with the rule into a BorderMap of
// ready bilinear taps, kept in a small process-wide cache, and every padding of a plane
// of that geometry only applies the taps. The rule itself stays as the plain reference
// that the maps must match sample for sample.
//
// All functions are thread-safe.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "codec/common/dsp/dsp.h"
#include "svc/types.h"

namespace svc::codec::cube_padding_internal {

// One plane (luma, cb or cr) of each cube face, indexed by Face; null where not needed.
using FacePlanes = std::array<const std::vector<uint8_t>*, kFaceCount>;

// Where border sample (i, j) (outside 0..n-1 on either axis) of face `face`, padded with
// n x n planes, is read: face `face` of the cube at 1/16-sample position (x16, y16).
struct BorderSource {
  int face;
  int x16, y16;
};
BorderSource border_source(int face, int n, int i, int j);

// The reference: plane `face` (n x n samples) with `border` samples on each side, each
// border sample by border_source and the edge-clamped bilinear filter of 10.6.
void pad_plane_reference(const FacePlanes& planes, int face, int n, int border, std::vector<uint8_t>* out);

// Consecutive border samples of the padded plane read from one source face.
struct BorderRun {
  size_t offset;  // of the first sample in the padded plane
  uint32_t count;
  int face;
};

// The taps of every border sample of a padded plane, run after run, as the kernel
// dsp::DspTable::pad_sample_run reads them: per sample, the top-left sample of a 2 x 2
// block of the source plane and the block's bilinear weights, with the edge clamp folded
// in. Where the reference clamps a tap onto its neighbour, that tap's weight moves onto
// the neighbour, which gives the same sum; the block is moved inside the plane where it
// would reach past the last row or column.
struct BorderMap {
  std::vector<BorderRun> runs;
  std::vector<uint32_t> indices;
  std::vector<dsp::BilinearWeights> weights;
};

// Planes the maps cover: a 2 x 2 block needs two samples a side, and the kernel's
// indices must stay below 2^31 (SIMD gathers take signed offsets). The reference pads
// other planes.
inline constexpr int kMinMappedPlaneSide = 2;
inline constexpr int kMaxMappedPlaneSide = 46340;

// For kMinMappedPlaneSide <= n <= kMaxMappedPlaneSide.
BorderMap build_border_map(int face, int n, int border);

// The map of (face, n, border), built on first use. The cache is dropped whole when it
// would exceed kMaxCachedBorderMaps maps or kMaxCachedBorderMapBytes: a file has one
// face size, so six faces x two plane sizes is the working set (about 50 MB for
// 2048-sample faces with a 64-sample border), and a stream of sizes cannot grow it
// without bound.
inline constexpr size_t kMaxCachedBorderMaps = 32;
inline constexpr size_t kMaxCachedBorderMapBytes = size_t{64} << 20;
std::shared_ptr<const BorderMap> cached_border_map(int face, int n, int border);
size_t cached_border_map_count();

// Same samples as pad_plane_reference: the face copied row by row, the border from the
// cached map.
void pad_plane(const FacePlanes& planes, int face, int n, int border, std::vector<uint8_t>* out);

}  // namespace svc::codec::cube_padding_internal
