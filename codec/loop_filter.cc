#include "codec/loop_filter.h"

#include <algorithm>

#include "codec/dsp/dsp.h"

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

// Luma: edges every 8 samples, a segment per 4x4 unit.
void deblock_luma_plane(const DeblockMap& map, int qindex, const PlaneView& plane) {
  const dsp::DspTable& dsp = dsp::get_dsp();
  const int beta = deblock_beta(qindex);
  const int tc[3] = {0, deblock_tc(qindex, 1), deblock_tc(qindex, 2)};
  for (int uy = 0; uy < map.units_y; ++uy) {
    for (int ux = 2; ux < map.units_x; ux += 2) {
      const int strength = std::min<int>(map.left(ux, uy), 2);
      if (tc[strength] == 0) continue;
      dsp.deblock_luma(plane.data + static_cast<ptrdiff_t>(4 * uy) * plane.stride + 4 * ux, 1, plane.stride, beta,
                       tc[strength]);
    }
  }
  for (int uy = 2; uy < map.units_y; uy += 2) {
    for (int ux = 0; ux < map.units_x; ++ux) {
      const int strength = std::min<int>(map.top(ux, uy), 2);
      if (tc[strength] == 0) continue;
      dsp.deblock_luma(plane.data + static_cast<ptrdiff_t>(4 * uy) * plane.stride + 4 * ux, plane.stride, 1, beta,
                       tc[strength]);
    }
  }
}

// Chroma: edges every 8 chroma samples (16 luma), only where the strength is 2; a
// segment of 4 chroma samples takes the strength of the luma unit at its first sample.
void deblock_chroma_plane(const DeblockMap& map, int qindex, const PlaneView& plane) {
  const dsp::DspTable& dsp = dsp::get_dsp();
  const int tc = deblock_tc(qindex, 2);
  if (tc == 0) return;
  for (int uy = 0; uy < map.units_y; uy += 2) {
    for (int ux = 4; ux < map.units_x; ux += 4) {
      if (map.left(ux, uy) < 2) continue;
      dsp.deblock_chroma(plane.data + static_cast<ptrdiff_t>(2 * uy) * plane.stride + 2 * ux, 1, plane.stride, tc);
    }
  }
  for (int uy = 4; uy < map.units_y; uy += 4) {
    for (int ux = 0; ux < map.units_x; ux += 2) {
      if (map.top(ux, uy) < 2) continue;
      dsp.deblock_chroma(plane.data + static_cast<ptrdiff_t>(2 * uy) * plane.stride + 2 * ux, plane.stride, 1, tc);
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
  deblock_chroma_plane(map, qindex, planes[1]);
  deblock_chroma_plane(map, qindex, planes[2]);
}

}  // namespace svc::codec
