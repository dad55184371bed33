// SPDX-License-Identifier: BSD-2-Clause
// Camera arithmetic shared by the spatial parts: the transform between two cameras'
// spaces and the projection terms of a frustum.
//
// Threading: pure functions; safe to call concurrently.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "svc/types.h"

namespace svc {

// Current camera space -> reference camera space (view matrices taken as affine).
inline glm::dmat4 current_to_reference(const Camera& current, const Camera& reference) {
  return glm::make_mat4(reference.world_to_camera.data()) *
         glm::inverse(glm::make_mat4(current.world_to_camera.data()));
}

// glFrustum's projection of a camera-space point (x, y, z), z < 0:
// x_ndc = -(p00 x / z) - p02, y_ndc = -(p11 y / z) - p12.
struct ProjectionTerms {
  double p00, p02, p11, p12;
};

inline ProjectionTerms projection_terms(const Frustum& f) {
  return {2.0 * f.near_plane / (f.right - f.left), (f.right + f.left) / (f.right - f.left),
          2.0 * f.near_plane / (f.top - f.bottom), (f.top + f.bottom) / (f.top - f.bottom)};
}

}  // namespace svc
