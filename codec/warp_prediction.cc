#include "codec/warp_prediction.h"

#include <algorithm>

#include "codec/dsp/dsp.h"

namespace svc::codec {
namespace {

inline int bilinear(int a, int b, int c, int d, int fx, int fy) {
  return ((16 - fx) * (16 - fy) * a + fx * (16 - fy) * b + (16 - fx) * fy * c + fx * fy * d + 128) >> 8;
}

// One plane of a warped block. `size` is 16 (luma) or 8 (chroma); `half` the weight
// denominator (32 or 16) and `shift` the rounding shift (9 or 8). The per-pixel vector
// is affine along a row, so it is stepped incrementally (exactly: integers). Blocks whose
// whole footprint lies inside the plane skip the clamping.
template <int kSize, int kDenominator, int kShift>
void warp_plane(const uint8_t* plane, int width, int height, int x0, int y0, const WarpCorners& n, uint8_t* out) {
  int min_x = n[0].x, max_x = n[0].x, min_y = n[0].y, max_y = n[0].y;
  for (const WarpNode& node : n) {
    min_x = std::min(min_x, node.x);
    max_x = std::max(max_x, node.x);
    min_y = std::min(min_y, node.y);
    max_y = std::max(max_y, node.y);
  }
  // Node units per 1/16 sample: 2 for luma (1/8 pel nodes), 1 for chroma.
  constexpr int kScale = kDenominator == 32 ? 2 : 1;
  const bool inside = ((16 * x0 + kScale * min_x - 1) >> 4) >= 0 && ((16 * y0 + kScale * min_y - 1) >> 4) >= 0 &&
                      ((16 * (x0 + kSize - 1) + kScale * max_x + 1) >> 4) + 1 <= width - 1 &&
                      ((16 * (y0 + kSize - 1) + kScale * max_y + 1) >> 4) + 1 <= height - 1;
  constexpr int kRound = 1 << (kShift - 1);
  for (int v = 0; v < kSize; ++v) {
    const int b = 2 * v + 1;
    // S(a) = left + a * slope for a = 2u + 1, per component.
    const int left_x = (kDenominator - b) * n[0].x + b * n[2].x, right_x = (kDenominator - b) * n[1].x + b * n[3].x;
    const int left_y = (kDenominator - b) * n[0].y + b * n[2].y, right_y = (kDenominator - b) * n[1].y + b * n[3].y;
    const int slope_x = right_x - left_x, slope_y = right_y - left_y;
    int sx = kDenominator * left_x + slope_x, sy = kDenominator * left_y + slope_y;  // a = 1
    const int base_y = 16 * (y0 + v);
    uint8_t* dst = out + v * kSize;
    if (inside) {
      const dsp::WarpRow row{16 * x0, base_y, sx, sy, 2 * slope_x, 2 * slope_y, kShift, kSize};
      dsp::get_dsp().warp_row(plane, width, row, dst);
    } else {
      for (int u = 0; u < kSize; ++u, sx += 2 * slope_x, sy += 2 * slope_y) {
        const int X = 16 * (x0 + u) + ((sx + kRound) >> kShift), Y = base_y + ((sy + kRound) >> kShift);
        const int ix = X >> 4, iy = Y >> 4;
        const int c0 = std::clamp(ix, 0, width - 1), c1 = std::clamp(ix + 1, 0, width - 1);
        const uint8_t* r0 = plane + static_cast<ptrdiff_t>(std::clamp(iy, 0, height - 1)) * width;
        const uint8_t* r1 = plane + static_cast<ptrdiff_t>(std::clamp(iy + 1, 0, height - 1)) * width;
        dst[u] = static_cast<uint8_t>(bilinear(r0[c0], r0[c1], r1[c0], r1[c1], X & 15, Y & 15));
      }
    }
  }
}

}  // namespace

int max_warp_node_component(int width, int height) { return 4 * max_vector_component(width, height); }

void predict_warp_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                  uint8_t* out) {
  warp_plane<16, 32, 9>(reference.y.data(), reference.width, reference.height, 16 * mb_x, 16 * mb_y, corners, out);
}

void predict_warp_macroblock_chroma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                    MacroblockPrediction* out) {
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  warp_plane<8, 16, 8>(reference.cb.data(), cw, ch, 8 * mb_x, 8 * mb_y, corners, out->cb.data());
  warp_plane<8, 16, 8>(reference.cr.data(), cw, ch, 8 * mb_x, 8 * mb_y, corners, out->cr.data());
}

void predict_warp_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                             MacroblockPrediction* out) {
  predict_warp_macroblock_luma(reference, mb_x, mb_y, corners, out->y.data());
  predict_warp_macroblock_chroma(reference, mb_x, mb_y, corners, out);
}

void predict_warp_macroblock_reference(const ImageYCbCr420& reference, int mb_x, int mb_y,
                                       const WarpCorners& corners, MacroblockPrediction* out) {
  auto plane_block = [&](const uint8_t* plane, int width, int height, int size, uint8_t* dst) {
    const long long denominator = 2LL * size, shift = size == 16 ? 9 : 8;
    auto sample = [&](long long u, long long v) -> long long {
      return plane[std::clamp<long long>(v, 0, height - 1) * width + std::clamp<long long>(u, 0, width - 1)];
    };
    auto floor_shift = [](long long value, long long bits) {  // floor(value / 2^bits)
      const long long d = 1LL << bits;
      return value >= 0 ? value / d : -((-value + d - 1) / d);
    };
    for (int v = 0; v < size; ++v) {
      for (int u = 0; u < size; ++u) {
        const long long a = 2 * u + 1, b = 2 * v + 1;
        const long long w0 = (denominator - a) * (denominator - b), w1 = a * (denominator - b),
                        w2 = (denominator - a) * b, w3 = a * b;
        const long long sx = w0 * corners[0].x + w1 * corners[1].x + w2 * corners[2].x + w3 * corners[3].x;
        const long long sy = w0 * corners[0].y + w1 * corners[1].y + w2 * corners[2].y + w3 * corners[3].y;
        const long long X = 16LL * (size * mb_x + u) + floor_shift(sx + (1LL << (shift - 1)), shift);
        const long long Y = 16LL * (size * mb_y + v) + floor_shift(sy + (1LL << (shift - 1)), shift);
        const long long ix = floor_shift(X, 4), iy = floor_shift(Y, 4);
        const long long fx = X - 16 * ix, fy = Y - 16 * iy;
        const long long value = ((16 - fx) * (16 - fy) * sample(ix, iy) + fx * (16 - fy) * sample(ix + 1, iy) +
                                 (16 - fx) * fy * sample(ix, iy + 1) + fx * fy * sample(ix + 1, iy + 1) + 128) /
                                256;
        dst[v * size + u] = static_cast<uint8_t>(value);
      }
    }
  };
  plane_block(reference.y.data(), reference.width, reference.height, 16, out->y.data());
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  plane_block(reference.cb.data(), cw, ch, 8, out->cb.data());
  plane_block(reference.cr.data(), cw, ch, 8, out->cr.data());
}

}  // namespace svc::codec
