// SPDX-License-Identifier: BSD-2-Clause
// Analytic primitives and a bounding-volume hierarchy for the sample-scene ray caster.
// Internal to svc_scene. Everything here is plain value code: no allocation while
// tracing, no shared mutable state, so one Bvh may be traced from several threads.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace svc::samples::detail {

using Vec3 = glm::dvec3;

// A ray `origin + t * dir`; `dir` need not be unit length (camera rays keep the view-axis
// component at 1 so that t is the eye-space depth). `inv_dir` caches 1/dir for slab tests.
struct Ray {
  Vec3 origin;
  Vec3 dir;
  Vec3 inv_dir;
};
Ray make_ray(const Vec3& origin, const Vec3& dir);

enum class Shape : uint8_t {
  kBox,       // axis-aligned box [lo, hi]
  kCylinder,  // capped circular cylinder along axis `axis`, spanning [lo, hi] on it
};

struct Primitive {
  Shape shape = Shape::kBox;
  int axis = 1;           // cylinder axis: 0 = x, 1 = y (columns), 2 = z
  uint16_t material = 0;  // index into the scene's material table
  Vec3 lo{0.0}, hi{0.0};  // bounds; for cylinders the bounding box of the cylinder
  double centre_a = 0;    // cylinder centre on the first axis after `axis` ((axis+1)%3)
  double centre_b = 0;    // cylinder centre on the second axis after `axis` ((axis+2)%3)
  double radius = 0;
};

Primitive make_box(const Vec3& lo, const Vec3& hi, uint16_t material);
// Cylinder along `axis` with its centre line through (`centre_a`, `centre_b`) on the other
// two axes (in (axis+1)%3, (axis+2)%3 order), spanning [from, to] along the axis.
Primitive make_cylinder(int axis, double centre_a, double centre_b, double radius, double from, double to,
                        uint16_t material);

struct Hit {
  double t = 0;
  Vec3 normal{0.0};  // geometric outward normal of the surface hit (unit)
  int primitive = -1;
};

// Nearest intersection of `ray` with `prim` in (t_min, t_max); updates `hit` when found.
bool intersect(const Primitive& prim, const Ray& ray, double t_min, double t_max, Hit* hit);
// True when `point` lies strictly inside `prim`.
bool contains(const Primitive& prim, const Vec3& point);

// Binary BVH over a fixed primitive list, split by the surface-area heuristic.
class Bvh {
 public:
  Bvh() = default;
  explicit Bvh(std::vector<Primitive> primitives);

  const std::vector<Primitive>& primitives() const { return primitives_; }
  // Nearest hit in (t_min, t_max); `hit->primitive` indexes primitives().
  bool closest(const Ray& ray, double t_min, double t_max, Hit* hit) const;
  // Any hit in (t_min, t_max): for shadow rays.
  bool occluded(const Ray& ray, double t_min, double t_max) const;
  bool inside_any(const Vec3& point) const;

 private:
  struct Node {
    Vec3 lo, hi;
    int first = 0;  // leaf: first primitive; inner: index of the left child
    int count = 0;  // leaf: number of primitives (> 0); inner: 0, right child = first + 1
  };
  // Fills node `node` with primitives [first, first + count), splitting recursively.
  void build_child(int node, int first, int count, int depth);

  std::vector<Primitive> primitives_;
  std::vector<Node> nodes_;
};

// A primitive that may be hit by rays of a pixel tile, with the distance from the eye to
// its bounds (no hit on it can be nearer).
struct Candidate {
  int index = 0;
  double min_distance = 0;
};

// Primitives whose bounds meet the pyramid from `eye` spanned by the four corner ray
// directions of a tile (in order around the tile), nearest bounds first. Every ray from
// `eye` whose direction is a positive combination of the corners can only hit these.
void frustum_candidates(const std::vector<Primitive>& prims, const Vec3& eye, const Vec3 corners[4],
                        std::vector<Candidate>* out);

// Nearest hit among `candidates` (sorted as frustum_candidates leaves them), stopping once
// the remaining bounds are farther than the best hit. Same result as closest_brute_force
// for rays inside the tile's pyramid.
bool closest_among(const std::vector<Primitive>& prims, const std::vector<Candidate>& candidates, const Ray& ray,
                   double t_min, double t_max, Hit* hit);

// Reference for the Bvh and the tile culling: tests every primitive.
bool closest_brute_force(const std::vector<Primitive>& prims, const Ray& ray, double t_min, double t_max, Hit* hit);

}  // namespace svc::samples::detail
