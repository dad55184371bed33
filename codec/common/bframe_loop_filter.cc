// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/bframe_loop_filter.h"

#include <array>
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

// Strengths of two parallel 8x8 block edges of macroblock `mb` against macroblock
// `other` (mb itself for the edges inside it); near[i] / far[i] the coded flags of the
// blocks on mb's side and the other side of edge i. The motion is compared once for both.
std::array<uint8_t, 2> edge_strengths(const MacroblockInfo& mb, const MacroblockInfo& other,
                                      const std::array<uint8_t, 2>& near, const std::array<uint8_t, 2>& far) {
  if (mb.mode == MacroblockMode::kIntra || other.mode == MacroblockMode::kIntra) return {2, 2};
  const bool coded0 = (near[0] | far[0]) != 0, coded1 = (near[1] | far[1]) != 0;
  const bool differs = !(coded0 && coded1) && &mb != &other && motion_differs(other, mb);
  return {static_cast<uint8_t>(coded0 || differs), static_cast<uint8_t>(coded1 || differs)};
}

// The map's entries for the left and top edges of macroblock (mx, my)'s four 8x8
// blocks; each strength covers the two 4x4 units along its edge.
void fill_macroblock_edges(const FrameState& s, int mx, int my, DeblockMap& map) {
  const MacroblockInfo& mb = s.mb(mx, my);
  const int grid = s.grid_width(0);
  auto coded = [&](int bx, int by) { return s.coded[0][static_cast<size_t>(by) * grid + bx]; };
  const int bx = 2 * mx, by = 2 * my, ux = 4 * mx, uy = 4 * my;
  auto set_left = [&](int column, const std::array<uint8_t, 2>& strength) {
    for (int k = 0; k < 4; ++k) map.left(ux + 2 * column, uy + k) = strength[k >> 1];
  };
  auto set_top = [&](int row, const std::array<uint8_t, 2>& strength) {
    for (int k = 0; k < 4; ++k) map.top(ux + k, uy + 2 * row) = strength[k >> 1];
  };
  const std::array<uint8_t, 2> first_column = {coded(bx, by), coded(bx, by + 1)};
  const std::array<uint8_t, 2> second_column = {coded(bx + 1, by), coded(bx + 1, by + 1)};
  const std::array<uint8_t, 2> first_row = {coded(bx, by), coded(bx + 1, by)};
  const std::array<uint8_t, 2> second_row = {coded(bx, by + 1), coded(bx + 1, by + 1)};
  if (mx > 0)
    set_left(0, edge_strengths(mb, s.mb(mx - 1, my), first_column, {coded(bx - 1, by), coded(bx - 1, by + 1)}));
  // A 16x16 luma residual has no transform edge inside its macroblock, and one
  // macroblock's prediction no step there.
  const bool inner_edges = !mb.luma_16x16;
  if (inner_edges) set_left(1, edge_strengths(mb, mb, second_column, first_column));
  if (my > 0)
    set_top(0, edge_strengths(mb, s.mb(mx, my - 1), first_row, {coded(bx, by - 1), coded(bx + 1, by - 1)}));
  if (inner_edges) set_top(1, edge_strengths(mb, mb, second_row, first_row));
}

}  // namespace

DeblockMap deblock_map(const FrameState& s) {
  DeblockMap map = DeblockMap::uniform(16 * s.mbs_x, 16 * s.mbs_y, 0);
  for (int my = 0; my < s.mbs_y; ++my) {
    for (int mx = 0; mx < s.mbs_x; ++mx) fill_macroblock_edges(s, mx, my, map);
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
