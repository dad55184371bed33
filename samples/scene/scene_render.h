// Deterministic CPU ray caster for the sample scenes: one ray per pixel through the pixel
// centre, procedural textures filtered by the pixel footprint, sun and lamp light with
// hard shadows, and a sky for rays that hit nothing. Internal to svc_scene. Pure
// functions of their arguments: safe to call from several threads on one Scene.
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>

#include "scene/scene_layout.h"

namespace svc::samples::detail {

// View matrix (OpenGL convention, world to camera) of face `face` (0..5 = px nx py ny pz
// nz) of a cube map centred at `eye`, oriented as docs/input-format.md tabulates.
glm::dmat4 face_view_matrix(const Vec3& eye, int face);

// World-space direction (not unit: its component along the view axis is 1) of the ray
// through pixel (i, j) of a `size` x `size` face with a 90-degree field of view.
Vec3 pixel_ray_direction(const glm::dmat4& view, int size, int i, int j);

// Rays whose eye depth reaches this are treated as escaping to the sky; it lies inside
// the manifest's far plane.
inline constexpr double kMaxDepth = 95.0;
inline constexpr double kNearPlane = 0.05;
inline constexpr double kFarPlane = 100.0;

// Renders one square face seen from `eye` through `view` (which must be
// face_view_matrix(eye, face)): `rgb` receives size*size*3 sRGB bytes, row 0 at the top;
// `depth` size*size eye-space z values, +inf where the ray saw sky.
void render_face(const Scene& scene, const Vec3& eye, const glm::dmat4& view, int size, uint8_t* rgb, float* depth);

}  // namespace svc::samples::detail
