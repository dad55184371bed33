// SPDX-License-Identifier: BSD-2-Clause
// Pieces the scene layouts are built from: a portable random source, walls with
// openings, materials and lattices of positions between cell centres. Internal to svc_scene.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "scene/scene_layout.h"

namespace svc::samples::detail {

// SplitMix64: small, fast and identical everywhere (std distributions are not).
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x1234567ull) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0);
  }
  int below(int n) { return static_cast<int>(next() % static_cast<uint64_t>(n)); }
  bool chance(double p) { return uniform(0, 1) < p; }

 private:
  uint64_t state_;
};

struct Opening {
  double from, to;     // along the wall
  double bottom, top;  // heights
};

// A band [y0, y1] of a wall running along axis `along` (0 = x, 2 = z), occupying
// [across0, across1] on the other horizontal axis and [from, to] along its length, with
// rectangular openings cut through it. Openings must lie inside and not overlap.
inline void add_wall_band(std::vector<Primitive>* prims, int along, double across0, double across1, double from,
                          double to, double y0, double y1, std::vector<Opening> openings, uint16_t material) {
  std::sort(openings.begin(), openings.end(), [](const Opening& a, const Opening& b) { return a.from < b.from; });
  auto box = [&](double a0, double a1, double b0, double b1) {
    if (a1 - a0 <= 1e-9 || b1 - b0 <= 1e-9) return;
    Vec3 lo, hi;
    lo[along] = a0;
    hi[along] = a1;
    const int across = along == 0 ? 2 : 0;
    lo[across] = across0;
    hi[across] = across1;
    lo.y = b0;
    hi.y = b1;
    prims->push_back(make_box(lo, hi, material));
  };
  double cursor = from;
  for (const Opening& o : openings) {
    box(cursor, o.from, y0, y1);
    box(o.from, o.to, y0, o.bottom);
    box(o.from, o.to, o.top, y1);
    cursor = o.to;
  }
  box(cursor, to, y0, y1);
}

// A wall standing on the floor: the band [0, height].
inline void add_wall(std::vector<Primitive>* prims, int along, double across0, double across1, double from,
                     double to, double height, std::vector<Opening> openings, uint16_t material) {
  add_wall_band(prims, along, across0, across1, from, to, 0, height, std::move(openings), material);
}

inline uint16_t add_material(Scene* scene, const Material& m) {
  scene->materials.push_back(m);
  scene->materials.back().seed = static_cast<uint32_t>(scene->materials.size() * 7919u + m.seed);
  return static_cast<uint16_t>(scene->materials.size() - 1);
}

inline Material mat(Pattern pattern, Vec3 base, Vec3 second, double scale, double variation) {
  Material m;
  m.pattern = pattern;
  m.base = base;
  m.second = second;
  m.scale = scale;
  m.variation = variation;
  return m;
}

// Lattice positions origin + (phase + offset + k * period) * spacing inside (lo, hi),
// with a period of about `every` metres. An offset of 0.5 puts the lattice between
// cell centres, where no camera stands.
inline std::vector<double> lattice(double origin, double spacing, double lo, double hi, double every,
                                   double offset) {
  const int period = std::max(2, static_cast<int>(std::lround(every / spacing)));
  const int phase = period / 2;
  std::vector<double> out;
  const double step = period * spacing;
  const double first = origin + (phase + offset) * spacing;
  const int k_lo = static_cast<int>(std::floor((lo - first) / step)) - 1;
  const int k_hi = static_cast<int>(std::ceil((hi - first) / step)) + 1;
  for (int k = k_lo; k <= k_hi; ++k) {
    const double p = first + k * step;
    if (p > lo && p < hi) out.push_back(p);
  }
  return out;
}

// The floor plan the cameras stand on: cell centres span [x0, x1] x [z0, z1], the highest
// layer at eye height `top_eye`.
struct GridFootprint {
  double x0, x1, z0, z1, top_eye;
  double centre_x() const { return (x0 + x1) / 2; }
  double centre_z() const { return (z0 + z1) / 2; }
  // True when the rectangle (centre, half sizes) comes within `clearance` of the plan.
  bool near(double x, double z, double half_x, double half_z, double clearance) const {
    return x + half_x > x0 - clearance && x - half_x < x1 + clearance && z + half_z > z0 - clearance &&
           z - half_z < z1 + clearance;
  }
};
inline GridFootprint grid_footprint(const SceneOptions& options, const Scene& scene) {
  const Vec3 last = scene.cell_position(options.grid[0] - 1, options.grid[1] - 1, options.grid[2] - 1);
  return {scene.origin.x, last.x, scene.origin.z, last.z, last.y};
}

// A box from its centre on the floor plan, its half sizes and its vertical extent.
inline Primitive box_at(double x, double z, double half_x, double half_z, double y0, double y1, uint16_t material) {
  return make_box({x - half_x, y0, z - half_z}, {x + half_x, y1, z + half_z}, material);
}

// The street front of a building: a solid block behind the plane `plane` on the
// horizontal axis `across` (the one `along` is not), its front facing `facing` (+1 or -1
// along `across`), spanning [from, to] along `along`; storeys of `storey` metres with
// windows recessed into the wall (glass set back, a sill below), optional balconies on the
// upper floors, a shop front of larger panes on the ground floor, and a cornice.
struct Facade {
  int along = 0;
  double plane = 0;
  int facing = 1;
  double from = 0, to = 0;
  double height = 10, storey = 3.2, depth = 8;
  double window_width = 1.2, window_pitch = 2.6;
  uint16_t wall = 0, glass = 0, trim = 0;
  bool balconies = false;
  bool shop_front = false;
};
void add_facade(std::vector<Primitive>* prims, const Facade& facade, Random* rng);

// A tree: trunk and a canopy of two stacked cylinders of leaves, standing at (x, z).
void add_tree(std::vector<Primitive>* prims, double x, double z, double height, uint16_t bark, uint16_t leaves);

// A street lamp: a thin post and a lamp head, standing at (x, z).
void add_lamp_post(std::vector<Primitive>* prims, double x, double z, double height, uint16_t metal);

// Builders of the layouts besides the hall and the house (scene_layout.cc).
void build_street(const SceneOptions& options, Scene* scene);
void build_interior(const SceneOptions& options, Scene* scene);
void build_colonnade(const SceneOptions& options, Scene* scene);
void build_plaza(const SceneOptions& options, Scene* scene);

}  // namespace svc::samples::detail
