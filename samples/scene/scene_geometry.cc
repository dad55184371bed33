// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace svc::samples::detail {

namespace {

// Huge but finite, so that (bound - origin) * inv stays a number when a direction
// component is exactly zero.
constexpr double kInvZero = 1e300;

// Slab test of a box; returns the entry/exit interval clipped to (t_min, t_max).
inline bool slab(const Vec3& lo, const Vec3& hi, const Ray& ray, double t_min, double t_max, double* t_enter) {
  // Branch-free min/max per axis; compiles to minsd/maxsd.
  const double ax = (lo.x - ray.origin.x) * ray.inv_dir.x, bx = (hi.x - ray.origin.x) * ray.inv_dir.x;
  const double ay = (lo.y - ray.origin.y) * ray.inv_dir.y, by = (hi.y - ray.origin.y) * ray.inv_dir.y;
  const double az = (lo.z - ray.origin.z) * ray.inv_dir.z, bz = (hi.z - ray.origin.z) * ray.inv_dir.z;
  const double t0 = std::max(std::max(std::min(ax, bx), std::min(ay, by)), std::max(std::min(az, bz), t_min));
  const double t1 = std::min(std::min(std::max(ax, bx), std::max(ay, by)), std::min(std::max(az, bz), t_max));
  *t_enter = t0;
  return t0 <= t1;
}

bool intersect_box(const Primitive& p, const Ray& ray, double t_min, double t_max, Hit* hit) {
  // Entry and exit of each slab, tracking which axis bounds the entry/exit.
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  int axis_in = 0, axis_out = 0;
  for (int a = 0; a < 3; ++a) {
    double near_t = (p.lo[a] - ray.origin[a]) * ray.inv_dir[a];
    double far_t = (p.hi[a] - ray.origin[a]) * ray.inv_dir[a];
    if (near_t > far_t) std::swap(near_t, far_t);
    if (near_t > t_in) {
      t_in = near_t;
      axis_in = a;
    }
    if (far_t < t_out) {
      t_out = far_t;
      axis_out = a;
    }
  }
  if (t_in > t_out) return false;
  double t;
  int axis;
  double sign;
  if (t_in > t_min && t_in < t_max) {
    t = t_in;
    axis = axis_in;
    sign = ray.dir[axis] > 0 ? -1.0 : 1.0;
  } else if (t_in <= t_min && t_out > t_min && t_out < t_max) {
    // Origin inside the box (a camera placed in solid geometry): the far side is seen.
    t = t_out;
    axis = axis_out;
    sign = ray.dir[axis] > 0 ? 1.0 : -1.0;
  } else {
    return false;
  }
  hit->t = t;
  hit->normal = Vec3(0.0);
  hit->normal[axis] = sign;
  return true;
}

bool intersect_cylinder(const Primitive& p, const Ray& ray, double t_min, double t_max, Hit* hit) {
  const int ax = p.axis, a = (ax + 1) % 3, b = (ax + 2) % 3;
  const double oa = ray.origin[a] - p.centre_a, ob = ray.origin[b] - p.centre_b;
  const double da = ray.dir[a], db = ray.dir[b];
  const double r2 = p.radius * p.radius;
  const double lo = p.lo[ax], hi = p.hi[ax];
  bool found = false;
  double best = t_max;
  Vec3 normal(0.0);

  const double qa = da * da + db * db;
  if (qa > 0) {
    const double qb = oa * da + ob * db;
    const double qc = oa * oa + ob * ob - r2;
    const double disc = qb * qb - qa * qc;
    if (disc >= 0) {
      const double s = std::sqrt(disc);
      const double roots[2] = {(-qb - s) / qa, (-qb + s) / qa};
      for (double t : roots) {
        if (t <= t_min || t >= best) continue;
        const double h = ray.origin[ax] + t * ray.dir[ax];
        if (h < lo || h > hi) continue;
        best = t;
        found = true;
        normal = Vec3(0.0);
        normal[a] = (oa + t * da) / p.radius;
        normal[b] = (ob + t * db) / p.radius;
        break;
      }
    }
  }
  // End caps.
  if (ray.dir[ax] != 0) {
    for (int end = 0; end < 2; ++end) {
      const double plane = end == 0 ? lo : hi;
      const double t = (plane - ray.origin[ax]) / ray.dir[ax];
      if (t <= t_min || t >= best) continue;
      const double pa = oa + t * da, pb = ob + t * db;
      if (pa * pa + pb * pb > r2) continue;
      best = t;
      found = true;
      normal = Vec3(0.0);
      normal[ax] = end == 0 ? -1.0 : 1.0;
    }
  }
  if (!found) return false;
  hit->t = best;
  hit->normal = normal;
  return true;
}

// Keeps the nearest hit; on an exact tie (coplanar faces of touching boxes) the lower
// primitive index wins, so that every traversal order picks the same surface.
inline bool consider(const Primitive& prim, int index, const Ray& ray, double t_min, Hit* best, bool found) {
  Hit candidate;
  const double limit = found ? std::nextafter(best->t, std::numeric_limits<double>::infinity()) : best->t;
  if (!intersect(prim, ray, t_min, limit, &candidate)) return false;
  if (found && candidate.t == best->t && index > best->primitive) return false;
  candidate.primitive = index;
  *best = candidate;
  return true;
}

}  // namespace

Ray make_ray(const Vec3& origin, const Vec3& dir) {
  Ray ray{origin, dir, Vec3(0.0)};
  for (int a = 0; a < 3; ++a) ray.inv_dir[a] = dir[a] != 0 ? 1.0 / dir[a] : kInvZero;
  return ray;
}

Primitive make_box(const Vec3& lo, const Vec3& hi, uint16_t material) {
  Primitive p;
  p.shape = Shape::kBox;
  p.material = material;
  p.lo = glm::min(lo, hi);
  p.hi = glm::max(lo, hi);
  return p;
}

Primitive make_cylinder(int axis, double centre_a, double centre_b, double radius, double from, double to,
                        uint16_t material) {
  Primitive p;
  p.shape = Shape::kCylinder;
  p.axis = axis;
  p.material = material;
  p.centre_a = centre_a;
  p.centre_b = centre_b;
  p.radius = radius;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  p.lo[axis] = std::min(from, to);
  p.hi[axis] = std::max(from, to);
  p.lo[a] = centre_a - radius;
  p.hi[a] = centre_a + radius;
  p.lo[b] = centre_b - radius;
  p.hi[b] = centre_b + radius;
  return p;
}

bool intersect(const Primitive& prim, const Ray& ray, double t_min, double t_max, Hit* hit) {
  return prim.shape == Shape::kBox ? intersect_box(prim, ray, t_min, t_max, hit)
                                   : intersect_cylinder(prim, ray, t_min, t_max, hit);
}

bool contains(const Primitive& prim, const Vec3& point) {
  for (int a = 0; a < 3; ++a) {
    if (!(point[a] > prim.lo[a] && point[a] < prim.hi[a])) return false;
  }
  if (prim.shape == Shape::kBox) return true;
  const int a = (prim.axis + 1) % 3, b = (prim.axis + 2) % 3;
  const double da = point[a] - prim.centre_a, db = point[b] - prim.centre_b;
  return da * da + db * db < prim.radius * prim.radius;
}

Bvh::Bvh(std::vector<Primitive> primitives) : primitives_(std::move(primitives)) {
  if (primitives_.empty()) return;
  nodes_.reserve(2 * primitives_.size());
  nodes_.emplace_back();
  build_child(0, 0, static_cast<int>(primitives_.size()), 0);
}

namespace {

// Past this depth splits are balanced, so a tree is at most kMaxSahDepth + log2(n) deep
// and the traversal stacks below cannot overflow for any primitive count that fits memory.
constexpr int kMaxSahDepth = 40;
constexpr int kStackSize = kMaxSahDepth + 70;

double half_area(const Vec3& lo, const Vec3& hi) {
  const Vec3 e = glm::max(hi - lo, Vec3(0.0));
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

}  // namespace

void Bvh::build_child(int node, int first, int count, int depth) {
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int i = first; i < first + count; ++i) {
    lo = glm::min(lo, primitives_[i].lo);
    hi = glm::max(hi, primitives_[i].hi);
  }
  nodes_[node].lo = lo;
  nodes_[node].hi = hi;
  nodes_[node].first = first;
  nodes_[node].count = count;
  if (count <= 1) return;

  // Surface-area heuristic over every split of the centroid order on each axis: large
  // slabs (floor, roof, walls) end up near the root instead of bloating every subtree.
  double best_cost = half_area(lo, hi) * count;
  int best_axis = -1, best_split = 0;
  std::vector<double> right_area(count);
  for (int axis = 0; axis < 3; ++axis) {
    std::stable_sort(primitives_.begin() + first, primitives_.begin() + first + count,
                     [axis](const Primitive& l, const Primitive& r) {
                       return l.lo[axis] + l.hi[axis] < r.lo[axis] + r.hi[axis];
                     });
    Vec3 rlo(std::numeric_limits<double>::infinity()), rhi(-std::numeric_limits<double>::infinity());
    for (int i = count - 1; i > 0; --i) {
      rlo = glm::min(rlo, primitives_[first + i].lo);
      rhi = glm::max(rhi, primitives_[first + i].hi);
      right_area[i] = half_area(rlo, rhi);
    }
    Vec3 llo(std::numeric_limits<double>::infinity()), lhi(-std::numeric_limits<double>::infinity());
    for (int i = 1; i < count; ++i) {
      llo = glm::min(llo, primitives_[first + i - 1].lo);
      lhi = glm::max(lhi, primitives_[first + i - 1].hi);
      // Traversal of an inner node costs about one primitive test.
      const double cost = half_area(lo, hi) + half_area(llo, lhi) * i + right_area[i] * (count - i);
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = i;
      }
    }
  }
  if (depth >= kMaxSahDepth) {
    // Deep, lopsided trees could overflow the traversal stack: split at the median.
    best_axis = 0;
    best_split = count / 2;
  }
  if (best_axis < 0) return;  // a leaf is cheapest
  // Deterministic: the same stable sort as when the split was chosen.
  std::stable_sort(primitives_.begin() + first, primitives_.begin() + first + count,
                   [best_axis](const Primitive& l, const Primitive& r) {
                     return l.lo[best_axis] + l.hi[best_axis] < r.lo[best_axis] + r.hi[best_axis];
                   });
  const int left = static_cast<int>(nodes_.size());
  nodes_[node].first = left;
  nodes_[node].count = 0;
  nodes_.emplace_back();
  nodes_.emplace_back();
  build_child(left, first, best_split, depth + 1);
  build_child(left + 1, first + best_split, count - best_split, depth + 1);
}

bool Bvh::closest(const Ray& ray, double t_min, double t_max, Hit* hit) const {
  if (nodes_.empty()) return false;
  struct Entry {
    int node;
    double t;
  };
  Entry stack[kStackSize];
  int top = 0;
  double t_root;
  if (!slab(nodes_[0].lo, nodes_[0].hi, ray, t_min, t_max, &t_root)) return false;
  stack[top++] = {0, t_root};
  bool found = false;
  hit->t = t_max;
  while (top > 0) {
    const Entry entry = stack[--top];
    if (entry.t > hit->t) continue;
    const Node& node = nodes_[entry.node];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        if (consider(primitives_[i], i, ray, t_min, hit, found)) found = true;
      }
      continue;
    }
    const double best = found ? std::nextafter(hit->t, std::numeric_limits<double>::infinity()) : hit->t;
    // Visit the nearer child first so that `best` shrinks early.
    double t_left, t_right;
    const int l = node.first, r = node.first + 1;
    const bool hit_left = slab(nodes_[l].lo, nodes_[l].hi, ray, t_min, best, &t_left);
    const bool hit_right = slab(nodes_[r].lo, nodes_[r].hi, ray, t_min, best, &t_right);
    if (hit_left && hit_right) {
      if (t_left <= t_right) {
        stack[top++] = {r, t_right};
        stack[top++] = {l, t_left};
      } else {
        stack[top++] = {l, t_left};
        stack[top++] = {r, t_right};
      }
    } else if (hit_left) {
      stack[top++] = {l, t_left};
    } else if (hit_right) {
      stack[top++] = {r, t_right};
    }
  }
  return found;
}

bool Bvh::occluded(const Ray& ray, double t_min, double t_max) const {
  if (nodes_.empty()) return false;
  int stack[kStackSize];
  int top = 0;
  stack[top++] = 0;
  Hit scratch;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    double t_enter;
    if (!slab(node.lo, node.hi, ray, t_min, t_max, &t_enter)) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        if (intersect(primitives_[i], ray, t_min, t_max, &scratch)) return true;
      }
      continue;
    }
    stack[top++] = node.first;
    stack[top++] = node.first + 1;
  }
  return false;
}

bool Bvh::inside_any(const Vec3& point) const {
  for (const Primitive& p : primitives_) {
    if (contains(p, point)) return true;
  }
  return false;
}

void frustum_candidates(const std::vector<Primitive>& prims, const Vec3& eye, const Vec3 corners[4],
                        std::vector<Candidate>* out) {
  out->clear();
  const Vec3 centre = corners[0] + corners[1] + corners[2] + corners[3];
  Vec3 normals[4];
  for (int k = 0; k < 4; ++k) {
    normals[k] = glm::cross(corners[k], corners[(k + 1) % 4]);
    if (glm::dot(normals[k], centre) < 0) normals[k] = -normals[k];
  }
  for (size_t i = 0; i < prims.size(); ++i) {
    // Slightly enlarged bounds keep the test conservative against rounding.
    const Vec3 lo = prims[i].lo - 1e-6 - eye, hi = prims[i].hi + 1e-6 - eye;
    bool outside = false;
    for (int k = 0; k < 4 && !outside; ++k) {
      const Vec3& n = normals[k];
      // The box corner farthest along the inward normal.
      const Vec3 v(n.x >= 0 ? hi.x : lo.x, n.y >= 0 ? hi.y : lo.y, n.z >= 0 ? hi.z : lo.z);
      outside = glm::dot(n, v) < 0;
    }
    if (outside) continue;
    const Vec3 nearest = glm::clamp(Vec3(0.0), lo, hi);
    out->push_back({static_cast<int>(i), glm::length(nearest)});
  }
  std::stable_sort(out->begin(), out->end(),
                   [](const Candidate& a, const Candidate& b) { return a.min_distance < b.min_distance; });
}

bool closest_among(const std::vector<Primitive>& prims, const std::vector<Candidate>& candidates, const Ray& ray,
                   double t_min, double t_max, Hit* hit) {
  const double dir_length = glm::length(ray.dir);
  bool found = false;
  hit->t = t_max;
  for (const Candidate& c : candidates) {
    if (c.min_distance > hit->t * dir_length) break;
    if (consider(prims[c.index], c.index, ray, t_min, hit, found)) found = true;
  }
  return found;
}

bool closest_brute_force(const std::vector<Primitive>& prims, const Ray& ray, double t_min, double t_max,
                         Hit* hit) {
  bool found = false;
  hit->t = t_max;
  for (size_t i = 0; i < prims.size(); ++i) {
    if (consider(prims[i], static_cast<int>(i), ray, t_min, hit, found)) found = true;
  }
  return found;
}

}  // namespace svc::samples::detail
