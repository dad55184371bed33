#include "codec/bframe_loop_filter.h"

#include <cstdlib>

namespace svc::codec::bframe {
namespace {

// Whether two non-intra macroblocks predict differently enough to leave a step at their
// common edge: other references, translation against warp, or translations a whole pixel
// or more apart. Two warped macroblocks share the nodes of their common edge, so their
// predictions join.
bool motion_differs(const MacroblockInfo& a, const MacroblockInfo& b) {
  if (reference_mask(a.inter_mode) != reference_mask(b.inter_mode) || a.inter_warp != b.inter_warp) return true;
  if (a.inter_warp) return false;
  for (int r = 0; r < 2; ++r) {
    if (!uses_reference(a.inter_mode, r)) continue;
    if (std::abs(a.vectors[r].x - b.vectors[r].x) >= 4 || std::abs(a.vectors[r].y - b.vectors[r].y) >= 4) {
      return true;
    }
  }
  return false;
}

// Strength of the edge between luma 8x8 blocks (bx0, by0) and (bx1, by1).
uint8_t edge_strength(const FrameState& s, int bx0, int by0, int bx1, int by1) {
  const MacroblockInfo& a = s.mb(bx0 >> 1, by0 >> 1);
  const MacroblockInfo& b = s.mb(bx1 >> 1, by1 >> 1);
  if (a.mode == MacroblockMode::kIntra || b.mode == MacroblockMode::kIntra) return 2;
  const int grid = s.grid_width(0);
  if (s.coded[0][static_cast<size_t>(by0) * grid + bx0] || s.coded[0][static_cast<size_t>(by1) * grid + bx1]) {
    return 1;
  }
  return &a != &b && motion_differs(a, b) ? 1 : 0;
}

}  // namespace

DeblockMap deblock_map(const FrameState& s) {
  DeblockMap map = DeblockMap::uniform(16 * s.mbs_x, 16 * s.mbs_y, 0);
  for (int by = 0; by < 2 * s.mbs_y; ++by) {
    for (int bx = 0; bx < 2 * s.mbs_x; ++bx) {
      const uint8_t left = bx > 0 ? edge_strength(s, bx - 1, by, bx, by) : 0;
      const uint8_t top = by > 0 ? edge_strength(s, bx, by - 1, bx, by) : 0;
      for (int k = 0; k < 2; ++k) {
        map.left(2 * bx, 2 * by + k) = left;
        map.top(2 * bx + k, 2 * by) = top;
      }
    }
  }
  return map;
}

std::array<PlaneView, 3> plane_views(FrameState& s) {
  std::array<PlaneView, 3> views;
  for (int p = 0; p < 3; ++p) {
    const int width = p == 0 ? 16 * s.mbs_x : 8 * s.mbs_x, height = p == 0 ? 16 * s.mbs_y : 8 * s.mbs_y;
    views[p] = PlaneView{s.planes[p].data(), s.strides[p], width, height};
  }
  return views;
}

void deblock_planes(FrameState& s) { deblock_frame(deblock_map(s), s.inter_quantizer.qindex, plane_views(s)); }

std::vector<uint8_t> cdef_skip_map(const FrameState& s) {
  const int grid = s.grid_width(0);
  std::vector<uint8_t> skip(static_cast<size_t>(grid) * 2 * s.mbs_y, 0);
  for (int by = 0; by < 2 * s.mbs_y; ++by) {
    for (int bx = 0; bx < grid; ++bx) {
      const int mx = bx >> 1, my = by >> 1;
      if (s.mb(mx, my).mode == MacroblockMode::kIntra) continue;
      const size_t chroma = static_cast<size_t>(my) * s.grid_width(1) + mx;
      const size_t block = static_cast<size_t>(by) * grid + bx;
      skip[block] = !s.coded[0][block] && !s.coded[1][chroma] && !s.coded[2][chroma];
    }
  }
  return skip;
}

void cdef_planes(FrameState& s, const CdefParams& params) {
  cdef_frame(params, s.inter_quantizer.qindex, cdef_skip_map(s), plane_views(s));
}

}  // namespace svc::codec::bframe
