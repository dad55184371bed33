// SPDX-License-Identifier: BSD-2-Clause
// The street: a road between two rows of buildings of different heights and materials,
// with sidewalks, parked cars, trees and lamp posts, running far beyond the cell grid
// along x so that it recedes into the distance.
#include "scene/scene_builders.h"

namespace svc::samples::detail {

namespace {

struct StreetMaterials {
  std::vector<uint16_t> walls;
  uint16_t glass, trim, sidewalk, kerb, car_paint[3], tyre, metal, bark, leaves;
};

StreetMaterials street_materials(Scene* scene) {
  StreetMaterials m;
  const std::vector<Material> walls = {
      mat(Pattern::kBricks, {0.42, 0.18, 0.10}, {0.62, 0.60, 0.56}, 0.24, 0.3),
      mat(Pattern::kPlaster, {0.78, 0.72, 0.60}, {0.7, 0.64, 0.5}, 1.0, 0.05),
      mat(Pattern::kConcrete, {0.55, 0.54, 0.52}, {0.40, 0.40, 0.39}, 1.5, 0.06),
      mat(Pattern::kPlaster, {0.70, 0.50, 0.38}, {0.6, 0.4, 0.3}, 1.0, 0.05),
      mat(Pattern::kBricks, {0.55, 0.45, 0.32}, {0.70, 0.68, 0.62}, 0.30, 0.2),
      mat(Pattern::kConcrete, {0.72, 0.70, 0.64}, {0.55, 0.54, 0.5}, 0.8, 0.04),
  };
  for (const Material& w : walls) m.walls.push_back(add_material(scene, w));
  m.glass = add_material(scene, mat(Pattern::kGlass, {0.10, 0.13, 0.17}, {0.25, 0.24, 0.22}, 0.6, 0.0));
  m.trim = add_material(scene, mat(Pattern::kConcrete, {0.80, 0.78, 0.74}, {0.6, 0.6, 0.58}, 0.7, 0.03));
  m.sidewalk = add_material(scene, mat(Pattern::kTiles, {0.52, 0.50, 0.47}, {0.32, 0.31, 0.30}, 0.5, 0.08));
  m.kerb = add_material(scene, mat(Pattern::kConcrete, {0.62, 0.61, 0.58}, {0.45, 0.45, 0.43}, 1.0, 0.05));
  m.car_paint[0] = add_material(scene, mat(Pattern::kMetal, {0.55, 0.06, 0.05}, {0.1, 0.1, 0.1}, 1.1, 0.05));
  m.car_paint[1] = add_material(scene, mat(Pattern::kMetal, {0.08, 0.15, 0.40}, {0.1, 0.1, 0.1}, 1.1, 0.05));
  m.car_paint[2] = add_material(scene, mat(Pattern::kMetal, {0.75, 0.75, 0.74}, {0.1, 0.1, 0.1}, 1.1, 0.05));
  m.tyre = add_material(scene, mat(Pattern::kMetal, {0.05, 0.05, 0.05}, {0.02, 0.02, 0.02}, 1.0, 0.0));
  m.metal = add_material(scene, mat(Pattern::kMetal, {0.16, 0.18, 0.16}, {0.08, 0.08, 0.08}, 2.0, 0.05));
  m.bark = add_material(scene, mat(Pattern::kPlanks, {0.25, 0.18, 0.12}, {0.1, 0.08, 0.05}, 0.2, 0.1));
  m.leaves = add_material(scene, mat(Pattern::kLeaves, {0.20, 0.36, 0.10}, {0.06, 0.14, 0.04}, 1.0, 0.1));
  return m;
}

// A parked car along x, centred at (x, z).
void add_car(std::vector<Primitive>* prims, double x, double z, uint16_t paint, const StreetMaterials& m) {
  prims->push_back(box_at(x, z, 2.1, 0.88, 0.3, 0.95, paint));
  prims->push_back(box_at(x - 0.2, z, 1.1, 0.8, 0.95, 1.45, paint));
  prims->push_back(box_at(x - 0.2, z, 1.0, 0.82, 1.0, 1.38, m.glass));
  for (double wx : {x - 1.35, x + 1.35})
    prims->push_back(make_cylinder(2, 0.33, wx, 0.33, z - 0.9, z + 0.9, m.tyre));
}

}  // namespace

void build_street(const SceneOptions& options, Scene* scene) {
  Random rng(options.seed * 3266489917u + 29);
  const GridFootprint plan = grid_footprint(options, *scene);
  const StreetMaterials m = street_materials(scene);
  scene->ground_material =
      add_material(scene, mat(Pattern::kPaving, {0.30, 0.30, 0.31}, {0.18, 0.18, 0.18}, 0.14, 0.15));
  scene->lo_x = 1;  // outdoors everywhere: no room
  scene->hi_x = -1;

  // Cameras stand on the road; parking lanes, sidewalks and facades lie beyond them.
  const double lane = 2.4, sidewalk = 2.8;
  const double kerb_lo = plan.z0 - 0.8 - lane, kerb_hi = plan.z1 + 0.8 + lane;
  const double front_lo = kerb_lo - sidewalk, front_hi = kerb_hi + sidewalk;
  const double reach = (plan.x1 - plan.x0) / 2 + 45;
  const double x_lo = plan.centre_x() - reach, x_hi = plan.centre_x() + reach;

  std::vector<Primitive> prims;
  for (int side = 0; side < 2; ++side) {
    const double kerb = side == 0 ? kerb_lo : kerb_hi, front = side == 0 ? front_lo : front_hi;
    prims.push_back(make_box({x_lo, 0.0, std::min(kerb, front)}, {x_hi, 0.15, std::max(kerb, front)}, m.sidewalk));
    prims.push_back(make_box({x_lo, 0.0, kerb - 0.15}, {x_hi, 0.16, kerb + 0.15}, m.kerb));
    // Buildings 6-11 m wide, 2-6 storeys, each its own material.
    for (double x = x_lo; x < x_hi;) {
      Facade f;
      f.along = 0;
      f.plane = front;
      f.facing = side == 0 ? 1 : -1;
      f.from = x;
      f.to = std::min(x_hi, x + rng.uniform(6.0, 11.0));
      f.storey = rng.uniform(3.0, 3.5);
      f.height = f.storey * (2 + rng.below(5)) + 0.6;
      f.window_width = rng.uniform(0.9, 1.5);
      f.window_pitch = f.window_width + rng.uniform(1.0, 1.8);
      f.wall = m.walls[rng.below(static_cast<int>(m.walls.size()))];
      f.glass = m.glass;
      f.trim = m.trim;
      f.balconies = rng.chance(0.5);
      f.shop_front = rng.chance(0.5);
      add_facade(&prims, f, &rng);
      x = f.to;
    }
    // Lamp posts and trees along the kerb, cars in the parking lane.
    const double post_z = kerb + (side == 0 ? -0.5 : 0.5);
    for (double x = x_lo + 4; x < x_hi; x += 12) add_lamp_post(&prims, x, post_z, 4.5, m.metal);
    for (double x = x_lo + 10; x < x_hi; x += 12) {
      if (rng.chance(0.6))
        add_tree(&prims, x, post_z - (side == 0 ? 0.6 : -0.6), rng.uniform(5, 7), m.bark, m.leaves);
    }
    const double car_z = kerb + (side == 0 ? 1.2 : -1.2);
    for (double x = x_lo + 3; x < x_hi - 3; x += rng.uniform(5.2, 9.0)) {
      if (rng.chance(0.7)) add_car(&prims, x, car_z, m.car_paint[rng.below(3)], m);
    }
  }
  // Buildings across both ends close the view with facades in the distance.
  for (int end = 0; end < 2; ++end) {
    Facade f;
    f.along = 2;
    f.plane = end == 0 ? x_lo : x_hi;
    f.facing = end == 0 ? 1 : -1;
    f.from = front_lo - 10;
    f.to = front_hi + 10;
    f.height = 16.6;
    f.wall = m.walls[end * 2];
    f.glass = m.glass;
    f.trim = m.trim;
    add_facade(&prims, f, &rng);
  }
  scene->bvh = Bvh(std::move(prims));
}

}  // namespace svc::samples::detail
