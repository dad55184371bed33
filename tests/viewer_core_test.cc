// SPDX-License-Identifier: BSD-2-Clause
// What svc-viewer computes without OpenGL (samples/viewer): the cube map texels taken
// through each face's camera, the depth mesh, the path walk and the view conventions.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "viewer/cell_images.h"
#include "viewer/depth_mesh.h"
#include "viewer/navigation.h"
#include "viewer/overlay_text.h"
#include "viewer/view.h"

namespace svc::viewer {
namespace {

// svc-scene's face orientations (docs/input-format.md): view axis and up vector.
const glm::dvec3 kAxis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const glm::dvec3 kUp[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};

Camera cube_camera(const glm::dvec3& centre, const glm::dvec3& axis, const glm::dvec3& up) {
  const glm::dmat4 view = glm::lookAt(centre, centre + axis, up);
  Camera camera;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) camera.world_to_camera[c * 4 + r] = view[c][r];
  }
  camera.frustum = {-0.05, 0.05, -0.05, 0.05, 0.05, 100};
  return camera;
}

// A cell at `centre` whose faces look along the six axes with up vectors `ups`, each
// pixel coloured by `colour` of its direction and given depth by `depth` (if any).
CellImages make_cell(const glm::dvec3& centre, const glm::dvec3 (&ups)[6], int size,
                     const std::function<std::array<uint8_t, 4>(glm::dvec3)>& colour,
                     const std::function<float(int face, int x, int y)>& depth = {}) {
  CellImages cell;
  cell.centre = centre;
  cell.width = cell.height = size;
  for (int f = 0; f < kFaceCount; ++f) {
    cell.cameras[f] = face_camera(cube_camera(centre, kAxis[f], ups[f]));
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        const auto rgba = colour(pixel_direction(cell.cameras[f], size, size, x + 0.5, y + 0.5));
        cell.rgba[f].insert(cell.rgba[f].end(), rgba.begin(), rgba.end());
        if (depth) cell.depth[f].push_back(depth(f, x, y));
      }
    }
  }
  return cell;
}

// A colour that depends on the direction alone, different for nearby pixels.
std::array<uint8_t, 4> direction_colour(glm::dvec3 d) {
  d = glm::normalize(d);
  auto level = [](double v) { return static_cast<uint8_t>(static_cast<int>(std::lround(v * 1000 + 2000)) % 251); };
  return {level(d.x), level(d.y), level(d.z), 255};
}

TEST(ViewerCubeMap, TexelsFollowTheCamerasWhateverTheFacesUpVectors) {
  // The same world seen through faces turned about their axes and mirrored up vectors:
  // the cube map, built through the cameras, comes out the same.
  const glm::dvec3 turned[6] = {{0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}, {-1, 0, 0}, {0, -1, 0}};
  const CellImages standard = make_cell({1, 2, 3}, kUp, 16, direction_colour);
  const CellImages other = make_cell({1, 2, 3}, turned, 16, direction_colour);
  EXPECT_NE(standard.rgba[0], other.rgba[0]) << "the faces themselves differ";
  for (int target = 0; target < kCubeTargets; ++target) {
    const std::vector<uint8_t> a = cube_map_face(standard, target, 16), b = cube_map_face(other, target, 16);
    EXPECT_EQ(a, b) << "target " << target;
    // And each texel holds the world's colour in OpenGL's direction for it.
    for (int row = 0; row < 16; row += 5) {
      for (int column = 0; column < 16; column += 5) {
        const auto expected = direction_colour(cube_texel_direction(target, (column + 0.5) / 16, (row + 0.5) / 16));
        const size_t at = (static_cast<size_t>(row) * 16 + column) * 4;
        EXPECT_EQ(std::vector<uint8_t>(a.begin() + at, a.begin() + at + 4),
                  std::vector<uint8_t>(expected.begin(), expected.end()))
            << "target " << target << " texel " << column << "," << row;
      }
    }
  }
}

TEST(ViewerCubeMap, OpenGLTableCornersPointWhereTheSpecificationSays) {
  // Texel (s, t) = (0, 0) of each face, from the specification's table 8.19.
  const glm::dvec3 corners[6] = {{1, 1, 1}, {-1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {-1, 1, 1}, {1, 1, -1}};
  for (int target = 0; target < kCubeTargets; ++target) {
    EXPECT_EQ(cube_texel_direction(target, 0, 0), corners[target]) << "target " << target;
  }
}

TEST(ViewerCubeMap, LayoutIsReusedOnlyForCamerasThatDifferInPosition) {
  const CellImages a = make_cell({0, 0, 0}, kUp, 8, direction_colour);
  const CellImages moved = make_cell({5, 0, 0}, kUp, 8, direction_colour);
  const glm::dvec3 turned[6] = {{0, 0, 1}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  const CellImages rotated = make_cell({0, 0, 0}, turned, 8, direction_colour);
  const CubeMapLayout layout(a, 8);
  EXPECT_TRUE(layout.fits(moved));
  EXPECT_FALSE(layout.fits(rotated));
  EXPECT_FALSE(layout.fits(make_cell({0, 0, 0}, kUp, 6, direction_colour)));
  for (int target = 0; target < kCubeTargets; ++target)
    EXPECT_EQ(layout.face(moved, target), cube_map_face(moved, target, 8));
}

// Every face sees a wall 2 units away, square on: eye depth 2 everywhere; and the -z face
// also a block 1 unit away over its middle.
float box_depth(int face, int x, int y) {
  const bool block = face == static_cast<int>(Face::kNZ) && x >= 6 && x < 10 && y >= 6 && y < 10;
  return block ? 1.0f : 2.0f;
}

TEST(ViewerDepthMesh, VerticesLieOnTheSurfacesTheDepthDescribes) {
  const CellImages cell = make_cell({1, 2, 3}, kUp, 16, direction_colour, box_depth);
  const DepthMesh mesh = build_depth_mesh(cell);
  ASSERT_FALSE(mesh.positions.empty());
  int on_block = 0;
  for (size_t v = 0; v < mesh.positions.size(); v += 3) {
    const glm::dvec3 p(mesh.positions[v], mesh.positions[v + 1], mesh.positions[v + 2]);
    const double extent = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (std::abs(p.z + 1) < 1e-5) {
      ++on_block;
      continue;
    }
    EXPECT_NEAR(extent, 2.0, 1e-5) << p.x << "," << p.y << "," << p.z;
  }
  EXPECT_EQ(on_block, 16);  // the block's 4 x 4 pixel centres
}

TEST(ViewerDepthMesh, TrianglesAcrossADepthStepAreDropped) {
  const CellImages cell = make_cell({0, 0, 0}, kUp, 16, direction_colour, box_depth);
  const DepthMesh mesh = build_depth_mesh(cell);
  // Each face: 18 x 18 vertices (16 pixel centres and two edges), 17 x 17 quads of two
  // triangles. The block's 4 x 4 vertices touch 5 x 5 quads, 3 x 3 of them inside it: 16
  // on its rim, whose 32 triangles all join the two depths but for the two that the
  // diagonal (top right to bottom left) leaves on the wall at two of the rim's corners.
  EXPECT_EQ(mesh.triangles_dropped, 30u);
  EXPECT_EQ(mesh.indices.size() / 3, 6u * 17 * 17 * 2 - mesh.triangles_dropped);
  // No kept triangle spans both depths.
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    int near = 0;
    for (int k = 0; k < 3; ++k) near += std::abs(mesh.positions[mesh.indices[t + k] * 3 + 2] + 1) < 1e-5;
    EXPECT_TRUE(near == 0 || near == 3);
  }
}

TEST(ViewerDepthMesh, SkyAndFacesWithoutDepthGiveNoTriangles) {
  const auto sky = [](int, int, int) { return std::numeric_limits<float>::infinity(); };
  EXPECT_TRUE(build_depth_mesh(make_cell({0, 0, 0}, kUp, 8, direction_colour, sky)).indices.empty());
  EXPECT_TRUE(build_depth_mesh(make_cell({0, 0, 0}, kUp, 8, direction_colour)).positions.empty());
}

TEST(ViewerDepthMesh, LargeFacesGetAVertexEveryFewPixels) {
  EXPECT_EQ(mesh_step(64), 1);
  EXPECT_EQ(mesh_step(128), 1);
  EXPECT_EQ(mesh_step(256), 2);
  EXPECT_EQ(mesh_step(1024), 8);
}

TEST(ViewerPath, WalksTheWaypointsAtItsSpeed) {
  const PathWalk walk({{0, 0, 0}, {2, 0, 0}, {2, 0, 0}, {2, 0, 4}}, 2.0);
  EXPECT_DOUBLE_EQ(walk.duration(), 3.0);
  PathWalk::Sample s = walk.at(0.5);
  EXPECT_EQ(s.position, glm::dvec3(1, 0, 0));
  EXPECT_EQ(s.velocity, glm::dvec3(2, 0, 0));
  EXPECT_FALSE(s.finished);
  s = walk.at(2.0);  // past the repeated waypoint
  EXPECT_EQ(s.position, glm::dvec3(2, 0, 2));
  EXPECT_EQ(s.velocity, glm::dvec3(0, 0, 2));
  s = walk.at(10);
  EXPECT_EQ(s.position, glm::dvec3(2, 0, 4));
  EXPECT_TRUE(s.finished);
  EXPECT_EQ(s.velocity, glm::dvec3(0.0));
}

TEST(ViewerView, YawAndPitchFollowTheDocumentedConventions) {
  auto forward = [](double yaw, double pitch) { return view_basis(Pose{{0, 0, 0}, yaw, pitch}).forward; };
  auto near = [](glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) < 1e-12; };
  EXPECT_TRUE(near(forward(0, 0), {0, 0, -1}));
  EXPECT_TRUE(near(forward(90, 0), {-1, 0, 0}));
  EXPECT_TRUE(near(forward(180, 0), {0, 0, 1}));
  EXPECT_GT(forward(0, 30).y, 0.49);
  const ViewBasis b = view_basis(Pose{{0, 0, 0}, 30, 20});
  EXPECT_NEAR(glm::dot(b.right, glm::dvec3(0, 1, 0)), 0, 1e-12);
  EXPECT_GT(b.up.y, 0);
  Pose p;
  look_along({-1, 1, 0}, &p);
  EXPECT_NEAR(p.yaw_degrees, 90, 1e-9);
  EXPECT_NEAR(p.pitch_degrees, 45, 1e-9);
}

TEST(ViewerOverlay, TextIsDrawnInWhiteOnADarkBox) {
  const TextImage image = render_text({"P99 1.0 MS", "?"}, 2);
  EXPECT_EQ(image.width, (10 * 6 + 8) * 2);
  EXPECT_EQ(image.height, (2 * 10 + 5) * 2);
  int white = 0;
  for (size_t k = 0; k < image.rgba.size(); k += 4) white += image.rgba[k] == 255 && image.rgba[k + 3] == 255;
  EXPECT_GT(white, 100);
  EXPECT_EQ(image.rgba[3], 160);  // the box's corner
  // An unknown character draws as '?', lower case as capitals.
  EXPECT_EQ(render_text({"~"}, 1).rgba, render_text({"?"}, 1).rgba);
  EXPECT_EQ(render_text({"ms"}, 1).rgba, render_text({"MS"}, 1).rgba);
}

}  // namespace
}  // namespace svc::viewer
