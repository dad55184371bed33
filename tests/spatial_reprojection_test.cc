// SPDX-License-Identifier: BSD-2-Clause
#include "spatial/reprojection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace svc {
namespace {

// The rounding macroblock_candidates applies to a flow in pixels: each component to the
// nearest quarter pixel (halves away from zero), saturated at +-32767.
codec::MotionVector quantize_flow(double dx, double dy) {
  auto to_quarter_pel = [](double d) -> int16_t {
    const double quarter_pels = std::round(d * codec::kVectorUnitsPerPixel);  // halves away from zero
    if (!(quarter_pels > -32767.0)) return -32767;                            // NaN saturates low
    if (quarter_pels > 32767.0) return 32767;
    return static_cast<int16_t>(quarter_pels);
  };
  return codec::MotionVector{to_quarter_pel(dx), to_quarter_pel(dy)};
}

constexpr double kPi = 3.14159265358979323846;
constexpr float kInf = std::numeric_limits<float>::infinity();

Camera camera_from_view(const glm::dmat4& view, double half_width = 1.0, double half_height = 1.0,
                        double near_plane = 0.05, double far_plane = 100.0) {
  Camera camera;
  const double* m = glm::value_ptr(view);
  std::copy(m, m + 16, camera.world_to_camera.begin());
  // Symmetric frustum: half extents given at unit distance (1 = 90 degrees).
  camera.frustum = {-half_width * near_plane,
                    half_width * near_plane,
                    -half_height * near_plane,
                    half_height * near_plane,
                    near_plane,
                    far_plane};
  return camera;
}

Camera look(glm::dvec3 eye, glm::dvec3 forward, glm::dvec3 up) {
  return camera_from_view(glm::lookAt(eye, eye + forward, up));
}

size_t at(int w, int i, int j) { return static_cast<size_t>(j) * static_cast<size_t>(w) + i; }

// Independent projection of a world point into a camera's pixel-index coordinates.
glm::dvec2 project_to_pixel(const Camera& camera, glm::dvec3 world, int w, int h) {
  const glm::dmat4 view = glm::make_mat4(camera.world_to_camera.data());
  const Frustum& f = camera.frustum;
  const glm::dmat4 proj = glm::frustum(f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane);
  const glm::dvec3 window = glm::project(world, view, proj, glm::dvec4(0, 0, w, h));
  return {window.x - 0.5, h - window.y - 0.5};
}

// World point seen at pixel (i, j) of `camera` at eye depth z.
glm::dvec3 unproject(const Camera& camera, int i, int j, int w, int h, double z) {
  const Frustum& f = camera.frustum;
  const double x = f.left + (i + 0.5) / w * (f.right - f.left);
  const double y = f.bottom + (1.0 - (j + 0.5) / h) * (f.top - f.bottom);
  const glm::dvec4 p_cam(x * z / f.near_plane, y * z / f.near_plane, -z, 1.0);
  return glm::dvec3(glm::inverse(glm::make_mat4(camera.world_to_camera.data())) * p_cam);
}

FlowField constant_flow(int w, int h, float dx, float dy) {
  FlowField flow;
  flow.width = w;
  flow.height = h;
  flow.dx.assign(static_cast<size_t>(w * h), dx);
  flow.dy.assign(static_cast<size_t>(w * h), dy);
  flow.valid.assign(static_cast<size_t>(w * h), 1);
  return flow;
}

TEST(SpatialReprojection, IdenticalCamerasGiveZeroFlow) {
  const Camera camera = look({1, 2, 3}, {0.3, -0.2, 1}, {0, 1, 0});
  const int w = 24, h = 17;
  std::vector<float> depth(static_cast<size_t>(w * h));
  for (size_t k = 0; k < depth.size(); ++k) depth[k] = 0.5f + static_cast<float>(k % 13);
  depth[3] = kInf;
  depth[4] = std::numeric_limits<float>::quiet_NaN();
  depth[5] = 0.0f;
  const FlowField flow = compute_flow(camera, camera, w, h, depth);
  ASSERT_EQ(flow.width, w);
  ASSERT_EQ(flow.height, h);
  for (size_t k = 0; k < depth.size(); ++k) {
    ASSERT_TRUE(flow.valid[k]) << k;
    EXPECT_NEAR(flow.dx[k], 0.0f, 1e-6);
    EXPECT_NEAR(flow.dy[k], 0.0f, 1e-6);
  }
}

TEST(SpatialReprojection, SidewaysTranslationGivesDisparityOfEyeDepth) {
  // Both look down -z; the reference sits b to the right. Every pixel of a plane at eye
  // depth z moves left by f*b/z with f = w/2 pixels (90 degree field of view). Flow is
  // the same at every pixel only when depth is eye z (radial depth would bend it).
  const int w = 64, h = 48;
  const double b = 0.25, z = 4.0;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera reference = look({b, 0, 0}, {0, 0, -1}, {0, 1, 0});
  Camera current_wide = current;
  // Non-square pixels' aspect: a 4:3 face with 90 degrees horizontally.
  current_wide.frustum.bottom = -0.75 * current.frustum.near_plane;
  current_wide.frustum.top = 0.75 * current.frustum.near_plane;
  Camera reference_wide = reference;
  reference_wide.frustum = current_wide.frustum;
  const std::vector<float> depth(static_cast<size_t>(w * h), static_cast<float>(z));
  const FlowField flow = compute_flow(current_wide, reference_wide, w, h, depth);
  const double expected = -(w / 2.0) * b / z;
  for (size_t k = 0; k < depth.size(); ++k) {
    ASSERT_TRUE(flow.valid[k]);
    EXPECT_NEAR(flow.dx[k], expected, 1e-4);
    EXPECT_NEAR(flow.dy[k], 0.0, 1e-4);
  }
  // Background does not move under translation.
  const FlowField sky = compute_flow(current_wide, reference_wide, w, h, std::vector<float>(depth.size(), kInf));
  for (size_t k = 0; k < depth.size(); ++k) {
    ASSERT_TRUE(sky.valid[k]);
    EXPECT_NEAR(sky.dx[k], 0.0, 1e-4);
    EXPECT_NEAR(sky.dy[k], 0.0, 1e-4);
  }
}

TEST(SpatialReprojection, YawRotationMovesBackgroundByAngle) {
  // The reference is turned 10 degrees to the left; a background pixel at horizontal
  // angle theta (right positive) appears at theta + 10 degrees. The centre row of an
  // odd-height face has y_ndc = 0, where the motion is purely horizontal.
  const int w = 64, h = 33;
  const double yaw = 10.0 * kPi / 180.0;
  const Camera current = look({2, 1, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera reference = look({2, 1, 0}, {-std::sin(yaw), 0, -std::cos(yaw)}, {0, 1, 0});
  std::vector<float> depth(static_cast<size_t>(w * h), kInf);
  const FlowField flow = compute_flow(current, reference, w, h, depth);
  const int j = h / 2;
  for (int i = 0; i < w; ++i) {
    const double x_ndc = (i + 0.5) / w * 2 - 1;
    const double theta = std::atan(x_ndc);
    const double u = (std::tan(theta + yaw) + 1) * w / 2 - 0.5;
    const size_t k = at(w, i, j);
    ASSERT_TRUE(flow.valid[k]);
    EXPECT_NEAR(flow.dx[k], u - i, 1e-4) << i;
    EXPECT_NEAR(flow.dy[k], 0.0, 1e-4) << i;
  }
  // Elsewhere, against an independent projection of the direction from far away.
  for (int jj = 0; jj < h; jj += 4) {
    for (int i = 0; i < w; i += 5) {
      const glm::dvec3 far_point = unproject(current, i, jj, w, h, 1e7);
      const glm::dvec2 expected = project_to_pixel(reference, far_point, w, h);
      const size_t k = at(w, i, jj);
      EXPECT_NEAR(flow.dx[k], expected.x - i, 1e-3);
      EXPECT_NEAR(flow.dy[k], expected.y - jj, 1e-3);
    }
  }
}

TEST(SpatialReprojection, ForwardThenBackwardReturnsToThePixel) {
  // Scene: the plane y = -1.5 (a floor) seen whole by two cameras looking down.
  const int w = 48, h = 48;
  const Camera a = look({0, 0, 0}, {0.1, -2.0, -1}, {0, 1, 0});
  const Camera b = look({0.3, 0.1, -0.2}, {-0.05, -1.9, -1}, {0, 1, 0});
  auto floor_depth = [&](const Camera& camera) {
    std::vector<float> depth(static_cast<size_t>(w * h), kInf);
    for (int j = 0; j < h; ++j) {
      for (int i = 0; i < w; ++i) {
        const glm::dvec3 eye = unproject(camera, i, j, w, h, 0.0);
        const glm::dvec3 at1 = unproject(camera, i, j, w, h, 1.0);
        const double dy = at1.y - eye.y;
        if (dy < -1e-9) depth[at(w, i, j)] = static_cast<float>((-1.5 - eye.y) / dy);
      }
    }
    return depth;
  };
  const FlowField forward = compute_flow(a, b, w, h, floor_depth(a));
  const FlowField backward = compute_flow(b, a, w, h, floor_depth(b));
  int checked = 0;
  for (int j = 0; j < h; j += 3) {
    for (int i = 0; i < w; i += 3) {
      const size_t k = at(w, i, j);
      ASSERT_TRUE(forward.valid[k]);
      const double u = i + forward.dx[k], v = j + forward.dy[k];
      if (u < 1 || v < 1 || u > w - 2 || v > h - 2) continue;
      // Bilinear sample of the backward flow at the landing point.
      const int i0 = static_cast<int>(std::floor(u)), j0 = static_cast<int>(std::floor(v));
      const double fu = u - i0, fv = v - j0;
      auto sample = [&](const std::vector<float>& f) {
        return (1 - fu) * (1 - fv) * f[at(w, i0, j0)] + fu * (1 - fv) * f[at(w, i0 + 1, j0)] +
               (1 - fu) * fv * f[at(w, i0, j0 + 1)] + fu * fv * f[at(w, i0 + 1, j0 + 1)];
      };
      EXPECT_NEAR(u + sample(backward.dx), i, 0.02) << i << "," << j;
      EXPECT_NEAR(v + sample(backward.dy), j, 0.02) << i << "," << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(SpatialReprojection, PointsBehindTheReferenceCameraAreInvalid) {
  const int w = 16, h = 16;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera opposite = look({0, 0, 0}, {0, 0, 1}, {0, 1, 0});
  std::vector<float> depth(static_cast<size_t>(w * h), 3.0f);
  for (int i = 0; i < w; ++i) depth[at(w, i, 0)] = kInf;  // sky row: behind as well
  const FlowField flow = compute_flow(current, opposite, w, h, depth);
  for (size_t k = 0; k < depth.size(); ++k) EXPECT_FALSE(flow.valid[k]) << k;
  for (const auto& list : macroblock_candidates(flow)) EXPECT_TRUE(list.empty());

  // A reference 5 units ahead: the plane at depth 3 is behind it, sky is not.
  const Camera ahead = look({0, 0, -5}, {0, 0, -1}, {0, 1, 0});
  const FlowField partial = compute_flow(current, ahead, w, h, depth);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) EXPECT_EQ(partial.valid[at(w, i, j)], j == 0 ? 1 : 0);
  }
}

TEST(SpatialReprojection, DepthAtOrBeyondFarPlaneIsBackground) {
  const int w = 8, h = 8;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera moved = look({1, 0, 0}, {0, 0, -1}, {0, 1, 0});
  for (float z : {100.0f, 1e6f, -2.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), kInf}) {
    const FlowField flow = compute_flow(current, moved, w, h, std::vector<float>(static_cast<size_t>(w * h), z));
    for (size_t k = 0; k < flow.dx.size(); ++k) {
      ASSERT_TRUE(flow.valid[k]);
      EXPECT_NEAR(flow.dx[k], 0.0, 1e-5) << z;
    }
  }
}

TEST(SpatialReprojection, WrongDepthSizeGivesAllInvalid) {
  const Camera camera;
  const FlowField flow = compute_flow(camera, camera, 4, 4, std::vector<float>(15, 1.0f));
  ASSERT_EQ(flow.valid.size(), 16u);
  for (uint8_t v : flow.valid) EXPECT_EQ(v, 0);
}

TEST(SpatialReprojection, FastPathMatchesReferenceImplementation) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int round = 0; round < 12; ++round) {
    const int w = 20 + static_cast<int>(rng() % 30), h = 10 + static_cast<int>(rng() % 30);
    const glm::dvec3 eye_a(uni(rng), uni(rng), uni(rng));
    const glm::dvec3 forward_a(uni(rng), uni(rng), -1.0);
    const glm::dvec3 eye_b = eye_a + 0.5 * glm::dvec3(uni(rng), uni(rng), uni(rng));
    const glm::dvec3 forward_b = forward_a + 0.3 * glm::dvec3(uni(rng), uni(rng), uni(rng));
    Camera a = look(eye_a, forward_a, {0, 1, 0});
    Camera b = look(eye_b, forward_b, {0.1 * uni(rng), 1, 0});
    // An off-centre frustum for the reference, as a face may carry its own.
    b.frustum = {-0.04, 0.06, -0.05, 0.03, 0.05, 50.0};
    std::vector<float> depth(static_cast<size_t>(w * h));
    for (auto& z : depth) {
      const unsigned pick = rng() % 10;
      z = pick == 0 ? kInf : pick == 1 ? 120.0f : static_cast<float>(0.3 + 20.0 * (uni(rng) + 1));
    }
    const FlowField fast = compute_flow(a, b, w, h, depth);
    const FlowField plain = compute_flow_reference(a, b, w, h, depth);
    for (size_t k = 0; k < depth.size(); ++k) {
      ASSERT_EQ(fast.valid[k], plain.valid[k]) << round << " " << k;
      if (!fast.valid[k]) continue;
      const double tolerance = 1e-4 * (1.0 + std::abs(plain.dx[k]) + std::abs(plain.dy[k]));
      EXPECT_NEAR(fast.dx[k], plain.dx[k], tolerance) << round << " " << k;
      EXPECT_NEAR(fast.dy[k], plain.dy[k], tolerance) << round << " " << k;
    }
    EXPECT_EQ(macroblock_candidates(fast).size(), macroblock_candidates(plain).size());
  }
}

// The overload that fills a caller's field gives the same field whatever the field held
// before: another size, other flows, invalid pixels where the new flow is valid.
TEST(SpatialReprojection, FlowIntoReusedFieldMatchesFreshField) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  FlowField reused;
  for (int round = 0; round < 8; ++round) {
    const int w = 16 + static_cast<int>(rng() % 40), h = 16 + static_cast<int>(rng() % 40);
    const Camera a = look({uni(rng), uni(rng), uni(rng)}, {uni(rng), uni(rng), -1.0}, {0, 1, 0});
    const Camera b = look({uni(rng), uni(rng), uni(rng)}, {uni(rng), uni(rng), -1.0}, {0, 1, 0});
    std::vector<float> depth(static_cast<size_t>(w * h));
    for (auto& z : depth) z = rng() % 7 == 0 ? kInf : static_cast<float>(0.5 + 10.0 * (uni(rng) + 1));
    const FlowField fresh = compute_flow(a, b, w, h, depth);
    compute_flow(a, b, w, h, depth, &reused);
    ASSERT_EQ(reused.width, w);
    ASSERT_EQ(reused.height, h);
    EXPECT_EQ(reused.dx, fresh.dx) << round;
    EXPECT_EQ(reused.dy, fresh.dy) << round;
    EXPECT_EQ(reused.valid, fresh.valid) << round;
  }
  // A depth of the wrong size leaves every pixel invalid, also in a field that held flow.
  compute_flow(look({0, 0, 0}, {0, 0, -1}, {0, 1, 0}), look({1, 0, 0}, {0, 0, -1}, {0, 1, 0}), 8, 8,
               std::vector<float>(5, 1.0f), &reused);
  ASSERT_EQ(reused.valid.size(), 64u);
  for (uint8_t v : reused.valid) EXPECT_EQ(v, 0);
}

// Face cameras of the input format (docs/input-format.md): axis looked along, up vector.
struct FaceAxes {
  Face face;
  glm::dvec3 forward, up;
};
constexpr double kOne = 1.0;
const FaceAxes kCubeFaces[] = {
    {Face::kPX, {kOne, 0, 0}, {0, 1, 0}},  {Face::kNX, {-kOne, 0, 0}, {0, 1, 0}},
    {Face::kPY, {0, kOne, 0}, {0, 0, -1}}, {Face::kNY, {0, -kOne, 0}, {0, 0, 1}},
    {Face::kPZ, {0, 0, kOne}, {0, 1, 0}},  {Face::kNZ, {0, 0, -kOne}, {0, 1, 0}},
};

TEST(SpatialReprojection, CubeFacesOfNeighbouringCellsAgreeWithProjection) {
  // Cells 0.5 apart along x and along z; each face's point must land in the
  // neighbouring cell's same face where an independent projection puts it.
  const int w = 32, h = 32;
  const glm::dvec3 cell_a(-1.0, 1.7, 0.5);
  for (glm::dvec3 step : {glm::dvec3(0.5, 0, 0), glm::dvec3(0, 0, 0.5)}) {
    for (const FaceAxes& axes : kCubeFaces) {
      const Camera a = look(cell_a, axes.forward, axes.up);
      const Camera b = look(cell_a + step, axes.forward, axes.up);
      std::vector<float> depth(static_cast<size_t>(w * h));
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) depth[at(w, i, j)] = static_cast<float>(2.0 + 0.1 * i);
      const FlowField flow = compute_flow(a, b, w, h, depth);
      for (int j = 1; j < h; j += 7) {
        for (int i = 2; i < w; i += 9) {
          const size_t k = at(w, i, j);
          const glm::dvec3 world = unproject(a, i, j, w, h, depth[k]);
          const glm::dvec2 expected = project_to_pixel(b, world, w, h);
          ASSERT_TRUE(flow.valid[k]);
          EXPECT_NEAR(i + flow.dx[k], expected.x, 1e-3) << face_name(axes.face);
          EXPECT_NEAR(j + flow.dy[k], expected.y, 1e-3) << face_name(axes.face);
        }
      }
    }
  }
  // Orientation check by hand: px looks along +x with +y up, so +z is to its right.
  // Stepping the camera +z moves what it sees to the left; stepping +x (towards the
  // view) spreads the image out from the centre.
  const Camera px_a = look(cell_a, {1, 0, 0}, {0, 1, 0});
  const Camera px_right = look(cell_a + glm::dvec3(0, 0, 0.5), {1, 0, 0}, {0, 1, 0});
  const Camera px_ahead = look(cell_a + glm::dvec3(0.5, 0, 0), {1, 0, 0}, {0, 1, 0});
  const std::vector<float> depth(static_cast<size_t>(w * h), 3.0f);
  const FlowField sideways = compute_flow(px_a, px_right, w, h, depth);
  const FlowField forward = compute_flow(px_a, px_ahead, w, h, depth);
  EXPECT_NEAR(sideways.dx[at(w, 5, 5)], -(w / 2.0) * 0.5 / 3.0, 1e-4);
  EXPECT_GT(forward.dx[at(w, w - 1, h / 2)], 0.0f);
  EXPECT_LT(forward.dx[at(w, 0, h / 2)], 0.0f);
  EXPECT_LT(forward.dy[at(w, w / 2, 0)], 0.0f);  // top row moves up
  EXPECT_GT(forward.dy[at(w, w / 2, h - 1)], 0.0f);
}

TEST(SpatialReprojection, QuantizeRoundsToNearestQuarterPixel) {
  EXPECT_EQ(quantize_flow(0.0, 0.0), (codec::MotionVector{0, 0}));
  EXPECT_EQ(quantize_flow(0.12, -0.12), (codec::MotionVector{0, 0}));
  EXPECT_EQ(quantize_flow(0.125, -0.125), (codec::MotionVector{1, -1}));  // halves away from 0
  EXPECT_EQ(quantize_flow(0.13, -0.37), (codec::MotionVector{1, -1}));
  EXPECT_EQ(quantize_flow(0.375, -0.38), (codec::MotionVector{2, -2}));
  EXPECT_EQ(quantize_flow(3.1, -7.9), (codec::MotionVector{12, -32}));
  EXPECT_EQ(quantize_flow(1e9, -1e9), (codec::MotionVector{32767, -32767}));
}

TEST(SpatialReprojection, ConstantFlowGivesOneCandidatePerMacroblock) {
  const FlowField flow = constant_flow(40, 20, 1.26f, -0.74f);  // 3 x 2 macroblocks, padded
  const auto candidates = macroblock_candidates(flow);
  ASSERT_EQ(candidates.size(), 6u);
  for (const auto& list : candidates) {
    EXPECT_EQ(list, (codec::CandidateList{{5, -3}}));
  }
  EXPECT_DOUBLE_EQ(candidate_stats(candidates).mean_per_macroblock(), 1.0);
}

TEST(SpatialReprojection, CandidatesAreDistinctMostFrequentFirst) {
  FlowField flow = constant_flow(32, 16, 0.0f, 0.0f);  // two macroblocks
  // Left macroblock: 100 pixels of (1, 0) px, 100 of (0, 1) px, 56 of (0.5, 0) px with
  // two of those invalid. Right macroblock: pixels outside the face do not exist, and
  // values that round alike merge.
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const int n = j * 16 + i;
      const size_t k = at(32, i, j);
      if (n < 100) {
        flow.dx[k] = 1.0f;
      } else if (n < 200) {
        flow.dy[k] = 1.1f;
      } else {
        flow.dx[k] = 0.5f;
        if (n >= 254) flow.valid[k] = 0;
      }
    }
  }
  for (int j = 0; j < 16; ++j)
    for (int i = 16; i < 32; ++i) flow.dx[at(32, i, j)] = (i % 2) ? 2.1f : 1.9f;
  const auto candidates = macroblock_candidates(flow);
  ASSERT_EQ(candidates.size(), 2u);
  // Equal counts: (4, 0) quarter-pels has y 0 < 4, so it precedes (0, 4).
  EXPECT_EQ(candidates[0], (codec::CandidateList{{4, 0}, {0, 4}, {2, 0}}));
  EXPECT_EQ(candidates[1], (codec::CandidateList{{8, 0}}));
  const CandidateStats stats = candidate_stats(candidates);
  EXPECT_EQ(stats.macroblocks, 2u);
  EXPECT_EQ(stats.candidates, 4u);
  EXPECT_DOUBLE_EQ(stats.mean_per_macroblock(), 2.0);
}

TEST(SpatialReprojection, CandidateCountIsCappedAndRangeBounded) {
  FlowField flow = constant_flow(16, 16, 0.0f, 0.0f);
  // 256 distinct vectors; a few pixels repeat (5, 5) so it ranks first.
  for (int n = 0; n < 256; ++n) {
    flow.dx[static_cast<size_t>(n)] = static_cast<float>(n % 16);
    flow.dy[static_cast<size_t>(n)] = static_cast<float>(n / 16) * 0.5f;
  }
  for (int n = 0; n < 3; ++n) {
    flow.dx[static_cast<size_t>(n)] = 5.0f;
    flow.dy[static_cast<size_t>(n)] = 2.5f;
  }
  auto candidates = macroblock_candidates(flow);
  ASSERT_EQ(candidates.size(), 1u);
  ASSERT_EQ(candidates[0].size(), static_cast<size_t>(kMaxCandidatesPerMacroblock));
  EXPECT_EQ(candidates[0][0], (codec::MotionVector{20, 10}));
  // The rest in (y, x) order of their quarter-pel values, smallest first.
  EXPECT_EQ(candidates[0][1], (codec::MotionVector{12, 0}));

  // Components beyond 4*max(w, h) = 64 quarter-pels (16 px) contribute nothing.
  FlowField far = constant_flow(16, 16, 40.0f, 0.0f);
  far.dx[0] = 16.0f;  // exactly at the bound: kept
  candidates = macroblock_candidates(far);
  EXPECT_EQ(candidates[0], (codec::CandidateList{{64, 0}}));
}

// Plain counting with a map: the oracle for macroblock_candidates (size 16) and
// block_candidates (size 8; the grid padded to whole macroblocks).
codec::FaceCandidates plain_candidates(const FlowField& flow, int size = 16) {
  const int mbs_x = (flow.width + 15) / 16 * (16 / size), mbs_y = (flow.height + 15) / 16 * (16 / size);
  const int limit = 4 * std::max(flow.width, flow.height);
  codec::FaceCandidates out;
  for (int mby = 0; mby < mbs_y; ++mby) {
    for (int mbx = 0; mbx < mbs_x; ++mbx) {
      std::map<std::pair<int, int>, int> counts;  // (y, x) -> pixels
      for (int j = mby * size; j < std::min(flow.height, mby * size + size); ++j) {
        for (int i = mbx * size; i < std::min(flow.width, mbx * size + size); ++i) {
          const size_t k = at(flow.width, i, j);
          if (!flow.valid[k]) continue;
          const codec::MotionVector v = quantize_flow(flow.dx[k], flow.dy[k]);
          if (std::abs(v.x) > limit || std::abs(v.y) > limit) continue;
          ++counts[{v.y, v.x}];
        }
      }
      std::vector<std::pair<int, std::pair<int, int>>> ranked;
      for (const auto& [yx, count] : counts) ranked.push_back({-count, yx});
      std::sort(ranked.begin(), ranked.end());
      codec::CandidateList list;
      for (size_t r = 0; r < ranked.size() && r < kMaxCandidatesPerMacroblock; ++r) {
        list.push_back(
            {static_cast<int16_t>(ranked[r].second.second), static_cast<int16_t>(ranked[r].second.first)});
      }
      out.push_back(list);
    }
  }
  return out;
}

TEST(SpatialReprojection, CandidatesMatchPlainCounting) {
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  for (int round = 0; round < 20; ++round) {
    const int w = 8 + static_cast<int>(rng() % 60), h = 8 + static_cast<int>(rng() % 60);
    // Spreads from smooth (a few vectors) to chaotic (wide boxes, many vectors).
    const float spread = round % 4 == 0 ? 0.3f : round % 4 == 1 ? 2.0f : round % 4 == 2 ? 20.0f : 80.0f;
    FlowField flow = constant_flow(w, h, 0.0f, 0.0f);
    for (size_t k = 0; k < flow.dx.size(); ++k) {
      flow.dx[k] = 3.0f + spread * noise(rng);
      flow.dy[k] = -1.0f + spread * noise(rng);
      flow.valid[k] = rng() % 10 != 0;
    }
    EXPECT_EQ(macroblock_candidates(flow), plain_candidates(flow)) << "round " << round;
    EXPECT_EQ(block_candidates(flow), plain_candidates(flow, 8)) << "round " << round;
  }
}

TEST(SpatialReprojection, BlockCandidatesFollowEachBlocksOwnPixels) {
  // Left 8 columns move by (1, 0) px, the rest by (-2, 0.5): the macroblock list holds
  // both, each 8x8 block only its own.
  FlowField flow = constant_flow(24, 16, -2.0f, 0.5f);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 8; ++x) {
      flow.dx[at(24, x, y)] = 1.0f;
      flow.dy[at(24, x, y)] = 0.0f;
    }
  }
  const codec::FaceCandidates blocks = block_candidates(flow);
  ASSERT_EQ(blocks.size(), 4u * 2u);  // 2 macroblocks padded: 4 x 2 blocks
  const codec::CandidateList left{{4, 0}}, right{{-8, 2}};
  EXPECT_EQ(blocks[0], left);
  EXPECT_EQ(blocks[4], left);
  EXPECT_EQ(blocks[1], right);
  EXPECT_EQ(blocks[2], right);
  EXPECT_TRUE(blocks[3].empty());  // past the face
  EXPECT_EQ(macroblock_candidates(flow)[0].size(), 2u);
}

// The vectorised rounding against the plain one on the values where rounding is delicate:
// exact eighth pixels (halves of a quarter-pel), their float neighbours, the range bound,
// NaN and infinities; widths that are not a multiple of four exercise the scalar tail.
TEST(SpatialReprojection, CandidatesMatchPlainCountingOnEdgeValues) {
  std::vector<float> edges;
  for (float base : {0.125f, 0.375f, 1.125f, 7.875f, 15.875f, 16.0f, 16.125f}) {
    for (float sign : {1.0f, -1.0f}) {
      const float v = sign * base;
      edges.insert(edges.end(), {v, std::nextafter(v, 0.0f), std::nextafter(v, 2 * v)});
    }
  }
  edges.insert(edges.end(),
               {0.0f, -0.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                -std::numeric_limits<float>::infinity(), 1e30f, -1e30f, 3e-39f});
  std::mt19937 rng(11);
  for (int round = 0; round < 12; ++round) {
    const int w = 5 + round * 3, h = 7 + round;  // the bound, max(w, h) px, passes 16 at round 4
    FlowField flow = constant_flow(w, h, 0.0f, 0.0f);
    for (size_t k = 0; k < flow.dx.size(); ++k) {
      flow.dx[k] = edges[rng() % edges.size()];
      flow.dy[k] = edges[rng() % edges.size()];
      flow.valid[k] = rng() % 8 != 0;
    }
    EXPECT_EQ(macroblock_candidates(flow), plain_candidates(flow)) << "round " << round;
    EXPECT_EQ(block_candidates(flow), plain_candidates(flow, 8)) << "round " << round;
  }
}

TEST(SpatialReprojection, ParallaxOfTwoDepthsGivesTwoCandidates) {
  // Sideways motion over a face split between a near and a far plane: the macroblocks
  // on the split hold both disparities, the others one.
  const int w = 48, h = 16;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera reference = look({0.5, 0, 0}, {0, 0, -1}, {0, 1, 0});
  std::vector<float> depth(static_cast<size_t>(w * h));
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) depth[at(w, i, j)] = i < 24 ? 2.0f : 6.0f;
  const auto candidates = macroblock_candidates(compute_flow(current, reference, w, h, depth));
  ASSERT_EQ(candidates.size(), 3u);
  // f*b/z = 24*0.5/2 = 6 px (24 quarter-pels), 24*0.5/6 = 2 px (8 quarter-pels).
  EXPECT_EQ(candidates[0], (codec::CandidateList{{-24, 0}}));
  EXPECT_EQ(candidates[1], (codec::CandidateList{{-24, 0}, {-8, 0}}));
  EXPECT_EQ(candidates[2], (codec::CandidateList{{-8, 0}}));
}

// A wall 5 units in front of the current camera, seen by a reference 1 unit behind it:
// visible unless something nearer hides it in the reference's depth.
TEST(SpatialReprojection, VisibilityFollowsTheReferenceDepth) {
  const int w = 32, h = 32;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera behind = look({0, 0, 1}, {0, 0, -1}, {0, 1, 0});
  const std::vector<float> wall(static_cast<size_t>(w * h), 5.0f);
  // The reference sees the same wall at eye depth 6: every pixel lands inside its face.
  std::vector<uint8_t> seen =
      visible_in_reference(current, behind, w, h, wall, std::vector<float>(wall.size(), 6.0f));
  for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 1) << k;
  // A screen 0.5 in front of the reference hides the wall; so does background.
  seen = visible_in_reference(current, behind, w, h, wall, std::vector<float>(wall.size(), 0.5f));
  for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 0) << k;
  seen = visible_in_reference(current, behind, w, h, wall, std::vector<float>(wall.size(), kInf));
  for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 0) << k;
  // Depth 6.2 is 3 % off the point's reference depth of 6: another surface.
  seen = visible_in_reference(current, behind, w, h, wall, std::vector<float>(wall.size(), 6.2f));
  for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 0) << k;
  // Hidden in the left half of the reference only: the current pixels landing there are unseen.
  std::vector<float> half_hidden(wall.size(), 6.0f);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w / 2; ++i) half_hidden[at(w, i, j)] = 0.5f;
  }
  seen = visible_in_reference(current, behind, w, h, wall, half_hidden);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const glm::dvec2 landing = project_to_pixel(behind, unproject(current, i, j, w, h, 5.0), w, h);
      if (landing.x < w / 2 - 2) EXPECT_EQ(seen[at(w, i, j)], 0) << i << "," << j;
      if (landing.x > w / 2 + 1) EXPECT_EQ(seen[at(w, i, j)], 1) << i << "," << j;
    }
  }
}

TEST(SpatialReprojection, VisibilityEndsAtTheReferenceFaceAndMatchesBackground) {
  const int w = 32, h = 32;
  const Camera current = look({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const Camera ahead = look({0, 0, -2}, {0, 0, -1}, {0, 1, 0});
  // The current face's edges look past the nearer reference's face: unseen there.
  const std::vector<float> wall(static_cast<size_t>(w * h), 5.0f);
  std::vector<uint8_t> seen =
      visible_in_reference(current, ahead, w, h, wall, std::vector<float>(wall.size(), 3.0f));
  EXPECT_EQ(seen[at(w, 0, 0)], 0);
  EXPECT_EQ(seen[at(w, w - 1, h / 2)], 0);
  EXPECT_EQ(seen[at(w, w / 2, h / 2)], 1);
  EXPECT_EQ(seen[at(w, w / 2 - 1, h / 2 - 1)], 1);
  // Background is seen where it lands on background, whatever the distance between cameras.
  const std::vector<float> sky(wall.size(), kInf);
  seen = visible_in_reference(current, ahead, w, h, sky, sky);
  for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 1) << k;
  seen = visible_in_reference(current, ahead, w, h, sky, std::vector<float>(wall.size(), 3.0f));
  for (size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 0) << k;
  // Sizes that do not match: nothing seen, no reads outside the inputs.
  seen = visible_in_reference(current, ahead, w, h, wall, std::vector<float>(10, 3.0f));
  ASSERT_EQ(seen.size(), wall.size());
  for (uint8_t s : seen) EXPECT_EQ(s, 0);
}

}  // namespace
}  // namespace svc
