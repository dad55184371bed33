// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/epipolar_lines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "spatial/reprojection.h"

namespace svc {
namespace {

Camera look(glm::dvec3 eye, glm::dvec3 forward, glm::dvec3 up, double left = -1, double right = 1) {
  Camera camera;
  const glm::dmat4 view = glm::lookAt(eye, eye + forward, up);
  const double* m = glm::value_ptr(view);
  std::copy(m, m + 16, camera.world_to_camera.begin());
  const double n = 0.05;
  camera.frustum = {left * n, right * n, -n, n, n, 100.0};
  return camera;
}

struct Axes {
  glm::dvec3 forward, up;
};
constexpr Axes kFaces[] = {{{1, 0, 0}, {0, 1, 0}},  {{-1, 0, 0}, {0, 1, 0}}, {{0, 1, 0}, {0, 0, -1}},
                           {{0, -1, 0}, {0, 0, 1}}, {{0, 0, 1}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}}};

// Every pixel's flow, at random depths in front of both cameras, is a positive multiple of
// the lines' direction at that pixel: parallel within `tolerance` (sine of the angle).
void expect_flow_follows_lines(const Camera& current, const Camera& reference, int w, int h, double tolerance) {
  const codec::EpipolarLines lines = epipolar_lines(current, reference, w, h);
  ASSERT_TRUE(lines.present());
  EXPECT_LE(std::max({std::abs(lines.a), std::abs(lines.bx), std::abs(lines.by)}), 64);
  std::mt19937 rng(3);
  std::vector<float> depth(static_cast<size_t>(w) * h);
  for (float& z : depth) z = 3.0f + static_cast<float>(rng() % 1000) * 0.01f;
  const FlowField flow = compute_flow(current, reference, w, h, depth);
  int checked = 0;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const size_t k = static_cast<size_t>(j) * w + i;
      const double fx = flow.dx[k], fy = flow.dy[k], length = std::hypot(fx, fy);
      if (!flow.valid[k] || length < 0.5) continue;
      const codec::LineDirection d = codec::line_direction(lines, w, h, 2 * i + 1, 2 * j + 1);
      const double dl = std::hypot(static_cast<double>(d.x), static_cast<double>(d.y));
      ASSERT_GT(dl, 0);
      EXPECT_NEAR((fx * d.y - fy * d.x) / (length * dl), 0.0, tolerance) << i << "," << j;
      EXPECT_GT(fx * d.x + fy * d.y, 0.0) << i << "," << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, w * h / 2);
}

TEST(SpatialEpipolarLines, CubeFacesOfGridCellsGetExactSmallIntegers) {
  const int w = 48, h = 48;
  const glm::dvec3 cell(0.25, 1.6, -0.5);
  for (const glm::dvec3 step : {glm::dvec3(0.5, 0, 0), glm::dvec3(1.0, 0, -0.5), glm::dvec3(-1.0, 0, 1.0)}) {
    for (const Axes& axes : kFaces) {
      expect_flow_follows_lines(look(cell, axes.forward, axes.up), look(cell + step, axes.forward, axes.up), w, h,
                                1e-5);
    }
  }
  // Sideways along the view's x axis: the direction is the same everywhere.
  const codec::EpipolarLines sideways = epipolar_lines(look(cell, {0, 0, -1}, {0, 1, 0}),
                                                       look(cell + glm::dvec3(0.5, 0, 0), {0, 0, -1}, {0, 1, 0}), w,
                                                       h);
  EXPECT_EQ(sideways, (codec::EpipolarLines{0, -1, 0}));
}

TEST(SpatialEpipolarLines, OffGridOffsetsAndOffCentreFrustaStayCloseToTheFlow) {
  const int w = 40, h = 32;
  const glm::dvec3 cell(0.1, 1.2, 0.3);
  const glm::dvec3 step(0.37, 0.11, -0.23);
  for (const Axes& axes : kFaces) {
    expect_flow_follows_lines(look(cell, axes.forward, axes.up, -0.7, 1.1),
                              look(cell + step, axes.forward, axes.up, -0.7, 1.1), w, h, 0.03);
  }
}

TEST(SpatialEpipolarLines, NoLinesWherePointsAtInfinityMove) {
  const int w = 32, h = 32;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  EXPECT_FALSE(epipolar_lines(current, current, w, h).present());                                 // the same place
  EXPECT_FALSE(epipolar_lines(current, look({1, 0, 0}, {1, 0, -1}, {0, 1, 0}), w, h).present());  // turned
  EXPECT_FALSE(epipolar_lines(current, look({1, 0, 0}, {0, 0, -1}, {0, 1, 0}, -0.5, 1), w, h).present());
  EXPECT_FALSE(epipolar_lines(current, look({1, 0, 0}, {0, 0, -1}, {0, 1, 0}), 0, h).present());
}

}  // namespace
}  // namespace svc
