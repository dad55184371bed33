// SPDX-License-Identifier: BSD-2-Clause
#include "viewer/navigation.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace svc::viewer {

PathWalk::PathWalk(std::vector<glm::dvec3> waypoints, double speed)
    : waypoints_(std::move(waypoints)), speed_(speed) {
  double total = 0;
  for (size_t i = 0; i < waypoints_.size(); ++i) {
    if (i > 0) total += glm::length(waypoints_[i] - waypoints_[i - 1]);
    distance_.push_back(total);
  }
  length_ = total;
}

PathWalk::Sample PathWalk::at(double seconds) const {
  Sample s;
  if (waypoints_.empty()) return s;
  const double travelled = seconds * speed_;
  if (travelled >= length_) {
    s.position = waypoints_.back();
    s.finished = true;
    return s;
  }
  // The segment [i - 1, i] holding the distance travelled, skipping empty segments.
  const size_t i = std::upper_bound(distance_.begin(), distance_.end(), travelled) - distance_.begin();
  const glm::dvec3 a = waypoints_[i - 1], b = waypoints_[i];
  const double f = (travelled - distance_[i - 1]) / (distance_[i] - distance_[i - 1]);
  s.position = a + (b - a) * f;
  s.velocity = glm::normalize(b - a) * speed_;
  return s;
}

glm::dvec3 fly(const FlyInput& input, double seconds, double speed, double degrees_per_pixel, Pose* pose) {
  pose->yaw_degrees -= input.mouse_dx * degrees_per_pixel;
  pose->pitch_degrees = std::clamp(pose->pitch_degrees - input.mouse_dy * degrees_per_pixel, -89.0, 89.0);
  const ViewBasis b = view_basis(*pose);
  // Walking stays level whatever the pitch; Q and E move straight down and up.
  const glm::dvec3 level = glm::normalize(glm::dvec3(b.forward.x, 0, b.forward.z));
  glm::dvec3 direction = level * input.forward + b.right * input.right + glm::dvec3(0, 1, 0) * input.up;
  if (glm::length(direction) == 0) return glm::dvec3(0.0);
  const glm::dvec3 velocity = glm::normalize(direction) * speed;
  pose->position += velocity * seconds;
  return velocity;
}

}  // namespace svc::viewer
