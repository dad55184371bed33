// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene_texture.h"

#include <algorithm>
#include <cmath>

namespace svc::samples::detail {

namespace {

int power_of_two_at_most(int n) {
  int p = 1;
  while (p * 2 <= n && p * 2 <= Texture::kMaxSize) p *= 2;
  return p;
}

// Shrinks `count` samples spaced `stride` apart (of `lines` interleaved runs) to
// `target` by area averaging: each output covers an equal share of the input, partial
// input texels weighted by their overlap.
std::vector<float> shrink_axis(const std::vector<float>& in, int count, int target, int stride, int lines) {
  if (count == target) return in;
  std::vector<float> out(in.size() / count * target);
  const double ratio = static_cast<double>(count) / target;
  for (int line = 0; line < lines; ++line) {
    for (int k = 0; k < target; ++k) {
      const double from = k * ratio, to = (k + 1) * ratio;
      double sum = 0;
      for (int s = static_cast<int>(from); s < count && s < to; ++s) {
        const double weight = std::min<double>(s + 1, to) - std::max<double>(s, from);
        sum += weight * in[static_cast<size_t>(s) * stride + line];
      }
      out[static_cast<size_t>(k) * stride + line] = static_cast<float>(sum / ratio);
    }
  }
  return out;
}

inline int wrap(int i, int n) {
  const int m = i % n;
  return m < 0 ? m + n : m;
}

}  // namespace

// 2x2 averages of `fine` (1x2 or 2x1 once one side is down to a texel).
Texture::Level Texture::halve(const Level& fine) {
  Level coarse{std::max(1, fine.width / 2), std::max(1, fine.height / 2), {}};
  coarse.rgb.resize(static_cast<size_t>(coarse.width) * coarse.height * 3);
  const int sx = fine.width / coarse.width, sy = fine.height / coarse.height;
  for (int y = 0; y < coarse.height; ++y) {
    for (int x = 0; x < coarse.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int dy = 0; dy < sy; ++dy) {
          for (int dx = 0; dx < sx; ++dx) {
            sum += fine.rgb[(static_cast<size_t>(y * sy + dy) * fine.width + x * sx + dx) * 3 + c];
          }
        }
        coarse.rgb[(static_cast<size_t>(y) * coarse.width + x) * 3 + c] = static_cast<float>(sum / (sx * sy));
      }
    }
  }
  return coarse;
}

Texture::Texture(int width, int height, const std::vector<float>& rgb) {
  const int w = power_of_two_at_most(width), h = power_of_two_at_most(height);
  // Columns first (stride 3 within a row, one run per channel), then rows.
  std::vector<float> rows(static_cast<size_t>(height) * w * 3);
  for (int y = 0; y < height; ++y) {
    const std::vector<float> row(rgb.begin() + static_cast<size_t>(y) * width * 3,
                                 rgb.begin() + static_cast<size_t>(y + 1) * width * 3);
    const std::vector<float> shrunk = shrink_axis(row, width, w, 3, 3);
    std::copy(shrunk.begin(), shrunk.end(), rows.begin() + static_cast<size_t>(y) * w * 3);
  }
  levels_.push_back({w, h, shrink_axis(rows, height, h, w * 3, w * 3)});
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    levels_.push_back(halve(levels_.back()));
  }
}

glm::dvec3 Texture::texel(int level, int x, int y) const {
  const Level& l = levels_[level];
  const float* p = &l.rgb[(static_cast<size_t>(wrap(y, l.height)) * l.width + wrap(x, l.width)) * 3];
  return {p[0], p[1], p[2]};
}

glm::dvec3 Texture::mean() const { return texel(levels() - 1, 0, 0); }

glm::dvec3 Texture::bilinear(int level, double u, double v) const {
  const Level& l = levels_[level];
  // Texel centres at half-integers; v runs upwards while rows run down.
  const double x = u * l.width - 0.5, y = -v * l.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const double ax = x - fx, ay = y - fy;
  const glm::dvec3 top = texel(level, ix, iy) * (1 - ax) + texel(level, ix + 1, iy) * ax;
  const glm::dvec3 bottom = texel(level, ix, iy + 1) * (1 - ax) + texel(level, ix + 1, iy + 1) * ax;
  return top * (1 - ay) + bottom * ay;
}

glm::dvec3 Texture::sample(double u, double v, double footprint) const {
  // Wrap early so that far-away coordinates keep their precision.
  u -= std::floor(u);
  v -= std::floor(v);
  const double texels = footprint * std::max(levels_[0].width, levels_[0].height);
  const double lod = texels > 1 ? std::log2(texels) : 0.0;
  const int last = levels() - 1;
  if (lod >= last) return mean();
  const int fine = static_cast<int>(lod);
  const double blend = lod - fine;
  const glm::dvec3 a = bilinear(fine, u, v);
  if (blend <= 0) return a;
  return a * (1 - blend) + bilinear(fine + 1, u, v) * blend;
}

}  // namespace svc::samples::detail
