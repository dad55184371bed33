// SPDX-License-Identifier: BSD-2-Clause
// The ray caster's accelerated traversals (BVH, per-tile frustum culling) against the
// plain every-primitive reference, and the primitive intersections against known answers.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "scene/scene_geometry.h"
#include "scene/scene_layout.h"
#include "scene/scene_render.h"

namespace svc::samples::detail {
namespace {

TEST(SceneGeometry, BoxAndCylinderIntersectionsAreExact) {
  const Primitive box = make_box({-1, 0, 2}, {1, 1, 3}, 0);
  Hit hit;
  ASSERT_TRUE(intersect(box, make_ray({0, 0.5, 0}, {0, 0, 1}), 0, 100, &hit));
  EXPECT_DOUBLE_EQ(hit.t, 2.0);
  EXPECT_EQ(hit.normal, Vec3(0, 0, -1));
  EXPECT_FALSE(intersect(box, make_ray({0, 0.5, 0}, {0, 0, -1}), 0, 100, &hit));

  // A vertical column of radius 0.5 at x = 3, z = 0.
  const Primitive column = make_cylinder(1, 0.0, 3.0, 0.5, 0.0, 4.0, 0);
  ASSERT_TRUE(intersect(column, make_ray({0, 1, 0}, {1, 0, 0}), 0, 100, &hit));
  EXPECT_NEAR(hit.t, 2.5, 1e-12);
  EXPECT_NEAR(hit.normal.x, -1.0, 1e-12);
  EXPECT_FALSE(intersect(column, make_ray({0, 5, 0}, {1, 0, 0}), 0, 100, &hit));
  EXPECT_TRUE(contains(column, {3.2, 1, 0.1}));
  EXPECT_FALSE(contains(column, {3.6, 1, 0}));

  // A pipe along z at x = 0, y = 2, seen from below: the ray meets its underside.
  const Primitive pipe = make_cylinder(2, 0.0, 2.0, 0.25, -5.0, 5.0, 0);
  ASSERT_TRUE(intersect(pipe, make_ray({0, 0, 1}, {0, 1, 0}), 0, 100, &hit));
  EXPECT_NEAR(hit.t, 1.75, 1e-12);
  EXPECT_NEAR(hit.normal.y, -1.0, 1e-12);
}

// Rays of whole faces from several cells of both scenes.
class SceneTraversal : public ::testing::TestWithParam<SceneKind> {};

TEST_P(SceneTraversal, AcceleratedClosestHitsMatchTheReference) {
  SceneOptions options;
  options.kind = GetParam();
  options.grid = {5, 1, 4};
  const Scene scene = build_scene(options);
  const auto& prims = scene.bvh.primitives();
  ASSERT_GT(prims.size(), 20u);
  const int size = 24, tile = 8;
  int compared = 0, hits = 0;
  std::vector<Candidate> candidates;
  for (int cell = 0; cell < 20; cell += 3) {
    const Vec3 eye = scene.cell_position(cell % 5, 0, cell / 5);
    for (int face = 0; face < 6; ++face) {
      const glm::dmat4 view = face_view_matrix(eye, face);
      for (int tj = 0; tj < size; tj += tile) {
        for (int ti = 0; ti < size; ti += tile) {
          const Vec3 corners[4] = {pixel_ray_direction(view, size, ti, tj),
                                   pixel_ray_direction(view, size, ti + tile - 1, tj),
                                   pixel_ray_direction(view, size, ti + tile - 1, tj + tile - 1),
                                   pixel_ray_direction(view, size, ti, tj + tile - 1)};
          frustum_candidates(prims, eye, corners, &candidates);
          EXPECT_LE(candidates.size(), prims.size());
          for (int j = tj; j < tj + tile; ++j) {
            for (int i = ti; i < ti + tile; ++i) {
              const Ray ray = make_ray(eye, pixel_ray_direction(view, size, i, j));
              Hit reference, culled, bvh;
              const bool r = closest_brute_force(prims, ray, kNearPlane, kMaxDepth, &reference);
              const bool c = closest_among(prims, candidates, ray, kNearPlane, kMaxDepth, &culled);
              const bool b = scene.bvh.closest(ray, kNearPlane, kMaxDepth, &bvh);
              ASSERT_EQ(r, c);
              ASSERT_EQ(r, b);
              ++compared;
              if (!r) continue;
              ++hits;
              ASSERT_EQ(reference.t, culled.t);
              ASSERT_EQ(reference.primitive, culled.primitive);
              ASSERT_EQ(reference.t, bvh.t);
              ASSERT_EQ(reference.primitive, bvh.primitive);
              // Shadow queries agree with the reference too.
              const Vec3 p = ray.origin + ray.dir * reference.t + reference.normal * 1e-5;
              const Ray shadow = make_ray(p, scene.sun_dir);
              Hit blocker;
              EXPECT_EQ(scene.bvh.occluded(shadow, 1e-5, 1e4),
                        closest_brute_force(prims, shadow, 1e-5, 1e4, &blocker));
            }
          }
        }
      }
    }
  }
  EXPECT_GT(hits, compared / 2);
}

INSTANTIATE_TEST_SUITE_P(BothKinds, SceneTraversal, ::testing::Values(SceneKind::kHall, SceneKind::kHouse));

TEST(SceneGeometry, EyeDepthIsTheRayParameter) {
  // The view-axis component of a pixel ray is 1, so the hit parameter is eye-space z.
  const glm::dmat4 view = face_view_matrix({1, 2, 3}, 4);
  for (int j = 0; j < 16; j += 5) {
    for (int i = 0; i < 16; i += 5) {
      const Vec3 d = pixel_ray_direction(view, 16, i, j);
      const glm::dvec4 in_camera = view * glm::dvec4(Vec3(1, 2, 3) + d * 2.5, 1.0);
      EXPECT_NEAR(-in_camera.z, 2.5, 1e-12);
      EXPECT_NEAR(in_camera.x / -in_camera.z, (i + 0.5) / 16 * 2 - 1, 1e-12);
      EXPECT_NEAR(in_camera.y / -in_camera.z, 1 - (j + 0.5) / 16 * 2, 1e-12);
    }
  }
}

}  // namespace
}  // namespace svc::samples::detail
