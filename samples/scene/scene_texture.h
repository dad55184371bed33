// SPDX-License-Identifier: BSD-2-Clause
// A photographic texture for the sample-scene ray caster: linear-light RGB in a mip-map
// pyramid, sampled trilinearly with wrap-around so that surfaces far away or seen at a
// grazing angle average their texels instead of aliasing. Internal to svc_scene.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace svc::samples::detail {

class Texture {
 public:
  Texture() = default;
  // `rgb`: width * height * 3 linear values, row 0 at the top. The pyramid starts at the
  // largest power-of-two size not above the image (at most kMaxSize) and halves by 2x2
  // averages down to one texel.
  Texture(int width, int height, const std::vector<float>& rgb);

  static constexpr int kMaxSize = 1024;

  // Color at (u, v) in texture repeats (u to the right, v upwards, period 1). `footprint`
  // is the pixel's size in repeats: it picks the mip levels.
  glm::dvec3 sample(double u, double v, double footprint) const;
  glm::dvec3 mean() const;
  int levels() const { return static_cast<int>(levels_.size()); }
  int width(int level) const { return levels_[level].width; }
  int height(int level) const { return levels_[level].height; }
  // Texel (x, y) of `level`, coordinates wrapped.
  glm::dvec3 texel(int level, int x, int y) const;

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<float> rgb;
  };
  static Level halve(const Level& fine);
  glm::dvec3 bilinear(int level, double u, double v) const;

  std::vector<Level> levels_;
};

}  // namespace svc::samples::detail
