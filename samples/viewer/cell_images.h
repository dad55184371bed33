// SPDX-License-Identifier: BSD-2-Clause
// One cell's decoded faces with their cameras, and what the viewer derives from them on
// the CPU: which face sees a direction, and the texels of an OpenGL cube map.
//
// Nothing here assumes how a file orients its faces: every direction is mapped to a
// face and a pixel through that face's own camera (view matrix and glFrustum), so faces
// rendered with any up vectors or handedness land where they belong.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "svc/reader.h"

namespace svc::viewer {

struct FaceCamera {
  glm::dmat4 world_to_camera{1.0};
  glm::dmat4 camera_to_world{1.0};
  Frustum frustum;
};
FaceCamera face_camera(const Camera& camera);

struct CellImages {
  CellIndex cell;
  glm::dvec3 centre{0, 0, 0};  // the cameras' centre
  int width = 0, height = 0;   // of every face
  std::array<FaceCamera, kFaceCount> cameras;
  std::array<std::vector<uint8_t>, kFaceCount> rgba;  // width * height * 4, row 0 at the top
  // Eye-space z (distance along the face camera's view axis), +infinity where the face
  // saw nothing; empty when the file holds no depth or it was not asked for.
  std::array<std::vector<float>, kFaceCount> depth;
};

// Where direction `d` (world, from the camera centre) falls on the face: continuous pixel
// coordinates, pixel (i, j) covering [i, i+1) x [j, j+1) with row 0 at the top. Points
// behind the camera give non-finite coordinates.
glm::dvec2 project_direction(const FaceCamera& camera, int width, int height, const glm::dvec3& d);
// The world direction (not normalised) through continuous pixel coordinates (x, y).
glm::dvec3 pixel_direction(const FaceCamera& camera, int width, int height, double x, double y);
// The world point at eye-space depth z on the ray through pixel coordinates (x, y).
glm::dvec3 pixel_point(const FaceCamera& camera, int width, int height, double x, double y, double z);

// The face whose view axis is closest to direction `d`: the one that sees it nearest
// its centre.
int face_for_direction(const CellImages& cell, const glm::dvec3& d);

// Bilinear RGBA sample of face `face` at continuous pixel coordinates, clamped to its
// edges; rounds to 8 bits.
std::array<uint8_t, 4> sample_face(const CellImages& cell, int face, glm::dvec2 p);

// Where sample_face takes a sample: the byte offsets of the four texels around it in the
// face's RGBA and the bilinear weights of the right and lower ones.
struct FaceSample {
  int face = 0;
  std::array<uint32_t, 4> offsets{};  // top left, top right, bottom left, bottom right
  double fx = 0, fy = 0;
};
FaceSample locate_sample(const CellImages& cell, int face, glm::dvec2 p);
std::array<uint8_t, 4> take_sample(const CellImages& cell, const FaceSample& sample);

// OpenGL's cube map faces, in the order of GL_TEXTURE_CUBE_MAP_POSITIVE_X + target.
inline constexpr int kCubeTargets = 6;
// The world direction of texel (s, t) of cube map face `target`, s and t in [0, 1]: the
// OpenGL specification's table of major axes (section 8.13, "Cube Map Texture
// Selection"), inverted.
glm::dvec3 cube_texel_direction(int target, double s, double t);
// The `size` x `size` RGBA texels of cube map face `target`, rows in upload order
// (t = 0 first): each texel is the face pixel its direction falls on, sampled as
// sample_face does (an exact copy when the cameras are a 90-degree cube of size-pixel
// faces).
std::vector<uint8_t> cube_map_face(const CellImages& cell, int target, int size);

// cube_map_face's samples, located once and reused for every cell whose cameras differ
// from the first's in position alone (as a grid's do): a cell then becomes a cube map
// in a copy of its texels, where locating them again would take longer than decoding it.
class CubeMapLayout {
 public:
  CubeMapLayout(const CellImages& cell, int size);
  // Whether `cell` has faces of the same size seen through the same rotations and frusta.
  bool fits(const CellImages& cell) const;
  // cube_map_face(cell, target, size()) for a cell that fits.
  std::vector<uint8_t> face(const CellImages& cell, int target) const;
  int size() const { return size_; }

 private:
  int size_ = 0, face_width_ = 0, face_height_ = 0;
  std::array<FaceCamera, kFaceCount> cameras_;
  std::array<std::vector<FaceSample>, kCubeTargets> samples_;
};

}  // namespace svc::viewer
