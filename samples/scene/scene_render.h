// SPDX-License-Identifier: BSD-2-Clause
// Deterministic CPU ray caster for the sample scenes: one ray per pixel through the pixel
// centre, or an n x n grid of colour samples per pixel with depth from the centre ray (as
// a renderer with supersampled colour and a one-sample depth buffer gives them); procedural textures filtered by
// the pixel footprint, sun and lamp light with hard shadows, and a sky for rays that hit nothing. Internal to
// svc_scene. Pure functions of their arguments: safe to call from several threads on one Scene.
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

// World-space direction of the ray through the point (x, y) of the face, in pixels from
// its top-left corner (pixel (i, j) spans [i, i + 1) x [j, j + 1)).
Vec3 sample_ray_direction(const glm::dmat4& view, int size, double x, double y);

// Rays whose eye depth reaches this are treated as escaping to the sky; it lies inside
// the manifest's far plane.
inline constexpr double kMaxDepth = 95.0;
inline constexpr double kNearPlane = 0.05;
inline constexpr double kFarPlane = 100.0;

// Linear light times this maps to the tone curve of the sample scenes at exposure 0.
inline constexpr double kBaseExposure = 1.35;

struct RenderSettings {
  int supersample = 1;          // n x n colour samples per pixel
  double exposure_stops = 0.0;  // exposure relative to kBaseExposure, in stops
  // Texture filtering that keeps detail on surfaces seen at grazing angles (as GPUs'
  // anisotropic filtering does) instead of blurring them by the whole footprint.
  bool anisotropic = false;
};

// Renders one square face seen from `eye` through `view` (which must be
// face_view_matrix(eye, face)): `rgb` receives size*size*3 sRGB bytes, row 0 at the top;
// `depth` size*size eye-space z values, +inf where the ray saw sky.
void render_face(const Scene& scene, const Vec3& eye, const glm::dmat4& view, int size,
                 const RenderSettings& settings, uint8_t* rgb, float* depth);

}  // namespace svc::samples::detail
