// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/warp_prediction.h"

#include <algorithm>
#include <array>

namespace svc::codec {
namespace {

template <typename Integer>
Integer bilinear_sum(Integer n0, Integer n1, Integer n2, Integer n3, Integer a, Integer b) {
  return (32 - a) * (32 - b) * n0 + a * (32 - b) * n1 + (32 - a) * b * n2 + a * b * n3;
}

// Predicts `blocks` x `blocks` sub-blocks of `size` x `size` samples of one plane, each
// with the vector at its centre; `span` is the sub-block's extent in half luma pixels.
// Neighbours along a row with the same vector are predicted as one wider block: the same
// samples, with fewer filter passes (the vectors of neighbouring 4x4 sub-blocks often
// round alike).
template <typename Predict>
void warp_plane(const WarpCorners& n, int blocks, int size, int span, int16_t* out, int out_stride,
                Predict predict) {
  for (int q = 0; q < blocks; ++q) {
    int16_t* row = out + q * size * out_stride;
    const auto vector = [&](int p) { return warp_subblock_vector(n, span * p + span / 2, span * q + span / 2); };
    std::array<int, 2> v = vector(0);
    for (int first = 0, p = 1; p <= blocks; ++p) {
      std::array<int, 2> next{};
      if (p < blocks && (next = vector(p)) == v) continue;
      predict(first * size, q * size, (p - first) * size, v[0], v[1], row + first * size);
      first = p;
      v = next;
    }
  }
}

}  // namespace

int max_warp_node_component(int width, int height) { return 2 * max_vector_component(width, height); }

std::array<int, 2> warp_subblock_vector(const WarpCorners& n, int a, int b) {
  // |S| <= 1024 * 2 * 32767: fits int32.
  const int sx = bilinear_sum(n[0].x, n[1].x, n[2].x, n[3].x, a, b);
  const int sy = bilinear_sum(n[0].y, n[1].y, n[2].y, n[3].y, a, b);
  return {(sx + 1024) >> 11, (sy + 1024) >> 11};
}

void predict_warp_macroblock_luma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                  int16_t* out, InterpolationFilter filter) {
  warp_plane(corners, 4, 4, 8, out, 16, [&](int x, int y, int width, int vx, int vy, int16_t* dst) {
    predict_block(reference.y.data(), reference.width, reference.height, PlaneKind::kLuma, 16 * mb_x + x,
                  16 * mb_y + y, width, 4, vx, vy, dst, 16, filter);
  });
}

void predict_warp_macroblock_chroma(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                                    MacroblockIntermediate* out, InterpolationFilter filter) {
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  for (int plane = 0; plane < 2; ++plane) {
    const uint8_t* samples = plane == 0 ? reference.cb.data() : reference.cr.data();
    int16_t* dst_plane = plane == 0 ? out->cb.data() : out->cr.data();
    warp_plane(corners, 2, 4, 16, dst_plane, 8, [&](int x, int y, int width, int vx, int vy, int16_t* dst) {
      predict_block(samples, cw, ch, PlaneKind::kChroma, 8 * mb_x + x, 8 * mb_y + y, width, 4, vx, vy, dst, 8,
                    filter);
    });
  }
}

void predict_warp_macroblock(const ImageYCbCr420& reference, int mb_x, int mb_y, const WarpCorners& corners,
                             MacroblockIntermediate* out, InterpolationFilter filter) {
  predict_warp_macroblock_luma(reference, mb_x, mb_y, corners, out->y.data(), filter);
  predict_warp_macroblock_chroma(reference, mb_x, mb_y, corners, out, filter);
}

void predict_warp_macroblock_reference(const ImageYCbCr420& reference, int mb_x, int mb_y,
                                       const WarpCorners& corners, MacroblockIntermediate* out,
                                       InterpolationFilter filter) {
  auto vector = [&](long long a, long long b) {
    auto component = [&](long long n0, long long n1, long long n2, long long n3) {
      const long long s = bilinear_sum(n0, n1, n2, n3, a, b) + 1024;
      return static_cast<int>(s >= 0 ? s / 2048 : -((-s + 2047) / 2048));  // floor
    };
    return std::array<int, 2>{component(corners[0].x, corners[1].x, corners[2].x, corners[3].x),
                              component(corners[0].y, corners[1].y, corners[2].y, corners[3].y)};
  };
  for (int q = 0; q < 4; ++q) {
    for (int p = 0; p < 4; ++p) {
      const auto v = vector(8 * p + 4, 8 * q + 4);
      predict_block_reference(reference.y.data(), reference.width, reference.height, PlaneKind::kLuma,
                              16 * mb_x + 4 * p, 16 * mb_y + 4 * q, 4, 4, v[0], v[1],
                              out->y.data() + 64 * q + 4 * p, 16, filter);
    }
  }
  const int cw = (reference.width + 1) / 2, ch = (reference.height + 1) / 2;
  for (int q = 0; q < 2; ++q) {
    for (int p = 0; p < 2; ++p) {
      const auto v = vector(16 * p + 8, 16 * q + 8);
      const int x = 8 * mb_x + 4 * p, y = 8 * mb_y + 4 * q, offset = 32 * q + 4 * p;
      predict_block_reference(reference.cb.data(), cw, ch, PlaneKind::kChroma, x, y, 4, 4, v[0], v[1],
                              out->cb.data() + offset, 8, filter);
      predict_block_reference(reference.cr.data(), cw, ch, PlaneKind::kChroma, x, y, 4, 4, v[0], v[1],
                              out->cr.data() + offset, 8, filter);
    }
  }
}

}  // namespace svc::codec
