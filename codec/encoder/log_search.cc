// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/log_search.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <span>
#include <vector>

#include "codec/common/motion_compensation.h"
#include "codec/encoder/sad.h"

namespace svc::codec {
namespace {

class MacroblockSearch {
 public:
  MacroblockSearch(const uint8_t* source, int source_stride, const ImageYCbCr420& reference, int mb_x, int mb_y)
      : source_(source), source_stride_(source_stride), reference_(reference), mb_x_(mb_x), mb_y_(mb_y) {}

  // SAD of a vector in quarter-pel units.
  int sad(int x, int y) {
    ++evaluations_;
    return sad_macroblock_luma(reference_, mb_x_, mb_y_,
                               MotionVector{static_cast<int16_t>(x), static_cast<int16_t>(y)}, source_,
                               source_stride_);
  }
  int64_t evaluations() const { return evaluations_; }

 private:
  const uint8_t* source_;
  int source_stride_;
  const ImageYCbCr420& reference_;
  int mb_x_, mb_y_;
  int64_t evaluations_ = 0;
};

MotionVector search_macroblock(MacroblockSearch& search, const LogSearchParams& params, int window) {
  int cx = 0, cy = 0;
  int best = search.sad(0, 0);
  int step = window >= 2 ? 1 << (std::bit_width(static_cast<unsigned>(window)) - 2) : 1;
  auto inside = [&](int x, int y) { return std::abs(x) <= window && std::abs(y) <= window; };
  // Scores centre + offsets * step; moves the centre to the best. Returns whether it moved.
  auto round = [&](std::span<const std::array<int, 2>> offsets, int distance) {
    int bx = cx, by = cy;
    for (const auto& d : offsets) {
      const int x = cx + d[0] * distance, y = cy + d[1] * distance;
      if (!inside(x, y)) continue;
      const int value = search.sad(4 * x, 4 * y);
      if (value < best) {
        best = value;
        bx = x;
        by = y;
      }
    }
    const bool moved = bx != cx || by != cy;
    cx = bx;
    cy = by;
    return moved;
  };
  static constexpr std::array<std::array<int, 2>, 4> kCross = {{{-1, 0}, {1, 0}, {0, -1}, {0, 1}}};
  static constexpr std::array<std::array<int, 2>, 8> kSquare = {
      {{-1, -1}, {0, -1}, {1, -1}, {-1, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}}};
  if (params.pattern == LogSearchPattern::kNinePoint) {
    for (; step >= 1; step /= 2) round(kSquare, step);
  } else {
    // Each move strictly lowers the SAD, so the loop ends; the cap only bounds the work.
    for (int iteration = 0; step > 1 && iteration < 4 * window + 8; ++iteration) {
      const bool moved = round(kCross, step);
      if (!moved || std::abs(cx) == window || std::abs(cy) == window) step /= 2;
    }
    round(kSquare, 1);  // final step: the full 3x3 neighbourhood
  }
  int hx = 4 * cx, hy = 4 * cy;
  if (params.half_pel) {
    const int ix = hx, iy = hy;
    for (const auto& d : kSquare) {
      const int value = search.sad(ix + 2 * d[0], iy + 2 * d[1]);
      if (value < best) {
        best = value;
        hx = ix + 2 * d[0];
        hy = iy + 2 * d[1];
      }
    }
  }
  return MotionVector{static_cast<int16_t>(hx), static_cast<int16_t>(hy)};
}

}  // namespace

FaceCandidates log_search_candidates(const ImageYCbCr420& source, const ImageYCbCr420& reference,
                                     const LogSearchParams& params, LogSearchStats* stats) {
  const int width = source.width, height = source.height;
  if (width <= 0 || height <= 0 || reference.width != width || reference.height != height ||
      source.y.size() != static_cast<size_t>(width) * height ||
      reference.y.size() != static_cast<size_t>(width) * height) {
    return {};
  }
  const int mbs_x = (width + 15) / 16, mbs_y = (height + 15) / 16;
  const int stride = 16 * mbs_x;
  // Source luma padded to whole macroblocks as the coders pad it.
  std::vector<uint8_t> padded(static_cast<size_t>(stride) * 16 * mbs_y);
  for (int y = 0; y < 16 * mbs_y; ++y) {
    const uint8_t* row = source.y.data() + static_cast<size_t>(std::min(y, height - 1)) * width;
    uint8_t* dst = padded.data() + static_cast<size_t>(y) * stride;
    std::copy_n(row, width, dst);
    std::fill(dst + width, dst + stride, row[width - 1]);
  }
  const int window = std::clamp(params.window, 1, 1024);
  FaceCandidates candidates(static_cast<size_t>(mbs_x) * mbs_y);
  for (int my = 0; my < mbs_y; ++my) {
    for (int mx = 0; mx < mbs_x; ++mx) {
      MacroblockSearch search(padded.data() + static_cast<size_t>(16 * my) * stride + 16 * mx, stride, reference,
                              mx, my);
      candidates[static_cast<size_t>(my) * mbs_x + mx] = {search_macroblock(search, params, window)};
      if (stats != nullptr) stats->sad_evaluations += search.evaluations();
    }
  }
  return candidates;
}

}  // namespace svc::codec
