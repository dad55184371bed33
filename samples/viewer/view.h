// SPDX-License-Identifier: BSD-2-Clause
// Where the viewer stands and looks, and the matrices that follow from it.
//
// Conventions (world y up, as the svc-input manifests are): yaw 0 looks along -z, yaw
// grows turning left (90 looks along -x), pitch grows looking up; angles in degrees. The
// output image's pixel (i, j), row 0 at the top, looks along
//   forward + right * (2 (i + 0.5) / W - 1) * tan(fov_y / 2) * W / H
//           + up * (1 - 2 (j + 0.5) / H) * tan(fov_y / 2),
// right = forward x (0, 1, 0) normalised, up = right x forward: OpenGL's pixel centres
// through a symmetric perspective of vertical field of view fov_y.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace svc::viewer {

struct Pose {
  glm::dvec3 position{0, 0, 0};
  double yaw_degrees = 0;
  double pitch_degrees = 0;
};

struct ViewBasis {
  glm::dvec3 forward, right, up;  // unit vectors, world coordinates
};

// Pitch is kept within +-89 degrees so that the basis stays defined.
ViewBasis view_basis(const Pose& pose);
// World-to-eye rotation alone: the eye at the origin looking along -z.
glm::dmat4 view_rotation(const ViewBasis& basis);
// glFrustum of a symmetric perspective.
glm::dmat4 perspective(double fov_y_degrees, double aspect, double near_plane, double far_plane);
// Yaw and pitch (degrees) that look along `direction` (any length but zero).
void look_along(const glm::dvec3& direction, Pose* pose);

}  // namespace svc::viewer
