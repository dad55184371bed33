// SPDX-License-Identifier: BSD-2-Clause
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "spatial/reprojection.h"

namespace svc {
namespace {

Camera look_down_z(glm::dvec3 eye) {
  Camera camera;
  const glm::dmat4 view = glm::lookAt(eye, eye + glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
  const double* m = glm::value_ptr(view);
  std::copy(m, m + 16, camera.world_to_camera.begin());
  camera.frustum = {-0.05, 0.05, -0.05, 0.05, 0.05, 100.0};
  return camera;
}

FlowField flow_of(int w, int h, const std::vector<float>& dx, const std::vector<float>& dy) {
  FlowField flow;
  flow.width = w;
  flow.height = h;
  flow.dx = dx;
  flow.dy = dy;
  flow.valid.assign(dx.size(), 1);
  return flow;
}

TEST(SpatialWarpNodes, AffineFlowGivesTheFlowAtEachCorner) {
  // flow(x, y) = (0.3 + 0.02 x - 0.01 y, -1.2 + 0.015 y): nodes sample it at the corner
  // points (16 i - 0.5, 16 j - 0.5), to the nearest 1/8 pel.
  const int w = 40, h = 35;
  std::vector<float> dx(static_cast<size_t>(w * h)), dy(dx.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      dx[static_cast<size_t>(y * w + x)] = static_cast<float>(0.3 + 0.02 * x - 0.01 * y);
      dy[static_cast<size_t>(y * w + x)] = static_cast<float>(-1.2 + 0.015 * y);
    }
  }
  const codec::WarpField field = warp_nodes(flow_of(w, h, dx, dy));
  ASSERT_EQ(field.nodes_x, 4);
  ASSERT_EQ(field.nodes_y, 4);
  for (int j = 0; j < field.nodes_y; ++j) {
    for (int i = 0; i < field.nodes_x; ++i) {
      // The mean of the 2x2 pixels around the corner, coordinates clamped to the face.
      const double px = std::clamp(16 * i - 1, 0, w - 1) * 0.5 + std::clamp(16 * i, 0, w - 1) * 0.5;
      const double py = std::clamp(16 * j - 1, 0, h - 1) * 0.5 + std::clamp(16 * j, 0, h - 1) * 0.5;
      EXPECT_NEAR(field.at(i, j).x, 8 * (0.3 + 0.02 * px - 0.01 * py), 0.51) << i << "," << j;
      EXPECT_NEAR(field.at(i, j).y, 8 * (-1.2 + 0.015 * py), 0.51) << i << "," << j;
    }
  }
}

TEST(SpatialWarpNodes, DepthEdgeNodesFollowOneSurface) {
  // Left of x = 16 near (depth 1), right far (depth 4); the reference is 0.25 to the
  // right: disparities -6 and -1.5 pixels (24 px focal length). Nodes on the edge take
  // one of the two, never a blend.
  const int w = 48, h = 32;
  std::vector<float> depth(static_cast<size_t>(w * h));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) depth[static_cast<size_t>(y * w + x)] = x < 16 ? 1.0f : 4.0f;
  }
  const FlowField flow = compute_flow(look_down_z({0, 0, 0}), look_down_z({0.25, 0, 0}), w, h, depth);
  const codec::WarpField field = warp_nodes(flow);
  for (int j = 0; j < field.nodes_y; ++j) {
    EXPECT_EQ(field.at(0, j).x, -48);  // near
    EXPECT_TRUE(field.at(1, j).x == -48 || field.at(1, j).x == -12) << field.at(1, j).x;
    EXPECT_EQ(field.at(2, j).x, -12);  // far
    for (int i = 0; i < field.nodes_x; ++i) EXPECT_EQ(field.at(i, j).y, 0);
  }
}

TEST(SpatialWarpNodes, InvalidFlowIsFilledFromNeighboursAndBadSizesGiveNothing) {
  const int w = 64, h = 16;
  std::vector<float> dx(static_cast<size_t>(w * h), 2.0f), dy(dx.size(), -1.0f);
  FlowField flow = flow_of(w, h, dx, dy);
  for (int y = 0; y < h; ++y) {
    for (int x = 24; x < 64; ++x) flow.valid[static_cast<size_t>(y * w + x)] = 0;
  }
  const codec::WarpField field = warp_nodes(flow);
  ASSERT_EQ(field.nodes.size(), 10u);
  for (const codec::WarpNode& node : field.nodes) EXPECT_EQ(node, (codec::WarpNode{16, -8}));
  flow.dx.pop_back();
  EXPECT_TRUE(warp_nodes(flow).empty());
  EXPECT_TRUE(warp_nodes(FlowField{}).empty());
}

}  // namespace
}  // namespace svc
