// SPDX-License-Identifier: BSD-2-Clause
// How the viewer moves: along a path of waypoints at a steady speed (the path files of
// svc-walkthrough, samples/walkthrough/replay.h), or by keyboard and mouse.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "viewer/view.h"

namespace svc::viewer {

// A polyline walked at a constant speed (world units per second).
class PathWalk {
 public:
  PathWalk(std::vector<glm::dvec3> waypoints, double speed);
  struct Sample {
    glm::dvec3 position{0, 0, 0};
    glm::dvec3 velocity{0, 0, 0};  // zero once the walk is over
    bool finished = false;
  };
  Sample at(double seconds) const;
  double duration() const { return length_ / speed_; }

 private:
  std::vector<glm::dvec3> waypoints_;
  std::vector<double> distance_;  // from the start to each waypoint
  double speed_ = 1, length_ = 0;
};

// Keys held and mouse motion over one frame.
struct FlyInput {
  double forward = 0;                 // +1 W, -1 S
  double right = 0;                   // +1 D, -1 A
  double up = 0;                      // +1 E, -1 Q
  double mouse_dx = 0, mouse_dy = 0;  // pixels
};

// Moves `pose` by one frame of `seconds` at `speed` world units per second and turns it
// by `degrees_per_pixel` of mouse motion; returns the velocity.
glm::dvec3 fly(const FlyInput& input, double seconds, double speed, double degrees_per_pixel, Pose* pose);

}  // namespace svc::viewer
