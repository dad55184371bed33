// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/loop_filter.h"

#include <algorithm>

#include "codec/common/dsp/dsp.h"

namespace svc::codec {
namespace {

// H.265 Table 8-12: beta' for Q = 0..51 and tc' for Q = 0..53 (8-bit samples).
constexpr std::array<uint8_t, 52> kBeta = {
    0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  0,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15,
    16, 17, 18, 20, 22, 24, 26, 28, 30, 32, 34, 36, 38, 40, 42, 44, 46, 48, 50, 52, 54, 56, 58, 60, 62, 64,
};
constexpr std::array<uint8_t, 54> kTc = {
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1,  1,  1,  1,  1,  1,  1,  1,  1,
    2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 5, 5, 6, 6, 7, 8, 9, 10, 11, 13, 14, 16, 18, 20, 22, 24,
};

bool plane_fits(const PlaneView& plane, int width, int height) {
  return plane.data != nullptr && plane.width == width && plane.height == height && plane.stride >= width;
}

// tc per boundary strength, 0 where a strength leaves its segments alone.
struct SegmentTc {
  uint8_t of_strength[3];
  uint8_t operator()(uint8_t strength) const { return of_strength[std::min<int>(strength, 2)]; }
};

// Luma: edges every 8 samples, a segment per 4x4 unit; one kernel call per edge, with
// the tc of each of its segments (an edge of tc 0 throughout is skipped).
void deblock_luma_plane(const DeblockMap& map, int qindex, const PlaneView& plane) {
  const dsp::DspTable& dsp = dsp::get_dsp();
  const int beta = deblock_beta(qindex);
  const SegmentTc tc_of{
      {0, static_cast<uint8_t>(deblock_tc(qindex, 1)), static_cast<uint8_t>(deblock_tc(qindex, 2))}};
  if (tc_of.of_strength[1] == 0 && tc_of.of_strength[2] == 0) return;
  std::vector<uint8_t> tc(static_cast<size_t>(std::max(map.units_x, map.units_y)));
  for (int ux = 2; ux < map.units_x; ux += 2) {
    uint8_t any = 0;
    for (int uy = 0; uy < map.units_y; ++uy) any |= tc[uy] = tc_of(map.left(ux, uy));
    if (any != 0) dsp.deblock_luma(plane.data + 4 * ux, 1, plane.stride, map.units_y, beta, tc.data());
  }
  for (int uy = 2; uy < map.units_y; uy += 2) {
    uint8_t any = 0;
    for (int ux = 0; ux < map.units_x; ++ux) any |= tc[ux] = tc_of(map.top(ux, uy));
    if (any != 0) {
      dsp.deblock_luma(plane.data + static_cast<ptrdiff_t>(4 * uy) * plane.stride, plane.stride, 1, map.units_x,
                       beta, tc.data());
    }
  }
}

// Chroma: edges every 8 chroma samples (16 luma), only where the strength is 2; a
// segment of 4 chroma samples takes the strength of the luma unit at its first sample.
// Both planes share each edge's tc.
void deblock_chroma_planes(const DeblockMap& map, int qindex, const PlaneView& cb, const PlaneView& cr) {
  const dsp::DspTable& dsp = dsp::get_dsp();
  const SegmentTc tc_of{{0, 0, static_cast<uint8_t>(deblock_tc(qindex, 2))}};
  if (tc_of.of_strength[2] == 0) return;
  std::vector<uint8_t> tc(static_cast<size_t>(std::max(map.units_x, map.units_y) / 2));
  const int segments_down = map.units_y / 2, segments_across = map.units_x / 2;
  for (int ux = 4; ux < map.units_x; ux += 4) {
    uint8_t any = 0;
    for (int j = 0; j < segments_down; ++j) any |= tc[j] = tc_of(map.left(ux, 2 * j));
    if (any == 0) continue;
    for (const PlaneView* plane : {&cb, &cr})
      dsp.deblock_chroma(plane->data + 2 * ux, 1, plane->stride, segments_down, tc.data());
  }
  for (int uy = 4; uy < map.units_y; uy += 4) {
    uint8_t any = 0;
    for (int j = 0; j < segments_across; ++j) any |= tc[j] = tc_of(map.top(2 * j, uy));
    if (any == 0) continue;
    for (const PlaneView* plane : {&cb, &cr}) {
      dsp.deblock_chroma(plane->data + static_cast<ptrdiff_t>(2 * uy) * plane->stride, plane->stride, 1,
                         segments_across, tc.data());
    }
  }
}

}  // namespace

DeblockMap DeblockMap::uniform(int padded_width, int padded_height, uint8_t strength) {
  DeblockMap map;
  map.units_x = std::max(0, padded_width / 4);
  map.units_y = std::max(0, padded_height / 4);
  const size_t units = static_cast<size_t>(map.units_x) * map.units_y;
  map.vertical.assign(units, strength);
  map.horizontal.assign(units, strength);
  return map;
}

int deblock_qp(int qindex) { return std::clamp((3 * qindex + 8) >> 4, 2, 53) - 2; }

int deblock_beta(int qindex) { return kBeta[std::min(deblock_qp(qindex), 51)]; }

int deblock_tc(int qindex, int strength) {
  return kTc[std::clamp(deblock_qp(qindex) + 2 * (std::clamp(strength, 1, 2) - 1), 0, 53)];
}

void deblock_frame(const DeblockMap& map, int qindex, const std::array<PlaneView, 3>& planes) {
  const size_t units = static_cast<size_t>(map.units_x) * map.units_y;
  if (map.units_x <= 0 || map.units_y <= 0 || map.vertical.size() != units || map.horizontal.size() != units)
    return;
  if (map.units_x % 2 != 0 || map.units_y % 2 != 0) return;  // chroma would not be whole units
  if (!plane_fits(planes[0], 4 * map.units_x, 4 * map.units_y)) return;
  for (int p = 1; p < 3; ++p) {
    if (!plane_fits(planes[p], 2 * map.units_x, 2 * map.units_y)) return;
  }
  deblock_luma_plane(map, qindex, planes[0]);
  deblock_chroma_planes(map, qindex, planes[1], planes[2]);
}

}  // namespace svc::codec
