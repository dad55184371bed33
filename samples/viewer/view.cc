// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/view.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace svc::viewer {

namespace {

constexpr double kRadians = std::numbers::pi / 180.0;
constexpr double kMaxPitch = 89.0;

}  // namespace

ViewBasis view_basis(const Pose& pose) {
  const double yaw = pose.yaw_degrees * kRadians;
  const double pitch = std::clamp(pose.pitch_degrees, -kMaxPitch, kMaxPitch) * kRadians;
  ViewBasis b;
  b.forward = {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
  b.right = glm::normalize(glm::cross(b.forward, glm::dvec3(0, 1, 0)));
  b.up = glm::cross(b.right, b.forward);
  return b;
}

glm::dmat4 view_rotation(const ViewBasis& b) {
  glm::dmat4 m(1.0);  // rows: right, up, -forward
  for (int c = 0; c < 3; ++c) {
    m[c][0] = b.right[c];
    m[c][1] = b.up[c];
    m[c][2] = -b.forward[c];
  }
  return m;
}

glm::dmat4 perspective(double fov_y_degrees, double aspect, double near_plane, double far_plane) {
  const double top = near_plane * std::tan(fov_y_degrees * kRadians / 2);
  const double right = top * aspect;
  glm::dmat4 m(0.0);
  m[0][0] = near_plane / right;
  m[1][1] = near_plane / top;
  m[2][2] = -(far_plane + near_plane) / (far_plane - near_plane);
  m[2][3] = -1;
  m[3][2] = -2 * far_plane * near_plane / (far_plane - near_plane);
  return m;
}

void look_along(const glm::dvec3& direction, Pose* pose) {
  const glm::dvec3 d = glm::normalize(direction);
  pose->yaw_degrees = std::atan2(-d.x, -d.z) / kRadians;
  pose->pitch_degrees = std::asin(std::clamp(d.y, -1.0, 1.0)) / kRadians;
}

}  // namespace svc::viewer
