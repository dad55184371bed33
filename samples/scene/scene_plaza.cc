// SPDX-License-Identifier: BSD-2-Clause
// The plaza: an open paved square under a wide sky, benches, lamp posts and a monument
// near the cameras, rows of trees further out, and blocks of buildings at 20-40 m whose
// windows give distant detail.
#include "scene/scene_builders.h"

namespace svc::samples::detail {

namespace {

struct PlazaMaterials {
  uint16_t paving, border, stone, bronze, wood, metal, bark, leaves, glass, trim;
  std::vector<uint16_t> walls;
};

PlazaMaterials plaza_materials(Scene* scene) {
  PlazaMaterials m;
  m.paving = add_material(scene, mat(Pattern::kPaving, {0.60, 0.56, 0.50}, {0.40, 0.37, 0.33}, 0.6, 0.1));
  m.border = add_material(scene, mat(Pattern::kPaving, {0.35, 0.34, 0.33}, {0.25, 0.24, 0.23}, 0.12, 0.15));
  m.stone = add_material(scene, mat(Pattern::kConcrete, {0.72, 0.70, 0.66}, {0.55, 0.53, 0.5}, 0.8, 0.05));
  m.bronze = add_material(scene, mat(Pattern::kMetal, {0.22, 0.30, 0.24}, {0.12, 0.16, 0.12}, 0.5, 0.1));
  m.wood = add_material(scene, mat(Pattern::kPlanks, {0.50, 0.34, 0.18}, {0.15, 0.1, 0.05}, 0.1, 0.2));
  m.metal = add_material(scene, mat(Pattern::kMetal, {0.15, 0.16, 0.15}, {0.08, 0.08, 0.08}, 2.0, 0.05));
  m.bark = add_material(scene, mat(Pattern::kPlanks, {0.25, 0.18, 0.12}, {0.1, 0.08, 0.05}, 0.2, 0.1));
  m.leaves = add_material(scene, mat(Pattern::kLeaves, {0.22, 0.38, 0.12}, {0.07, 0.15, 0.05}, 1.0, 0.1));
  m.glass = add_material(scene, mat(Pattern::kGlass, {0.12, 0.15, 0.20}, {0.28, 0.27, 0.25}, 0.6, 0.0));
  m.trim = add_material(scene, mat(Pattern::kConcrete, {0.82, 0.80, 0.76}, {0.6, 0.6, 0.58}, 0.7, 0.03));
  const std::vector<Material> walls = {
      mat(Pattern::kPlaster, {0.80, 0.70, 0.52}, {0.7, 0.6, 0.44}, 1.0, 0.05),
      mat(Pattern::kBricks, {0.50, 0.24, 0.14}, {0.66, 0.64, 0.60}, 0.26, 0.25),
      mat(Pattern::kConcrete, {0.62, 0.62, 0.60}, {0.45, 0.45, 0.44}, 1.5, 0.05),
      mat(Pattern::kPlaster, {0.62, 0.70, 0.74}, {0.5, 0.58, 0.62}, 1.0, 0.05),
      mat(Pattern::kPlaster, {0.86, 0.84, 0.78}, {0.76, 0.74, 0.7}, 1.0, 0.05),
  };
  for (const Material& w : walls) m.walls.push_back(add_material(scene, w));
  return m;
}

void add_bench(std::vector<Primitive>* prims, double x, double z, bool along_x, const PlazaMaterials& m) {
  const double hx = along_x ? 0.9 : 0.22, hz = along_x ? 0.22 : 0.9;
  prims->push_back(box_at(x, z, hx, hz, 0.42, 0.47, m.wood));
  for (double s : {-0.75, 0.75}) {
    prims->push_back(box_at(x + (along_x ? s : 0), z + (along_x ? 0 : s), along_x ? 0.04 : 0.2,
                            along_x ? 0.2 : 0.04, 0, 0.42, m.metal));
  }
}

}  // namespace

void build_plaza(const SceneOptions& options, Scene* scene) {
  Random rng(options.seed * 3266489917u + 61);
  const GridFootprint plan = grid_footprint(options, *scene);
  const PlazaMaterials m = plaza_materials(scene);
  scene->ground_material =
      add_material(scene, mat(Pattern::kGround, {0.15, 0.22, 0.07}, {0.26, 0.22, 0.14}, 1.0, 0.2));
  scene->lo_x = 1;  // outdoors everywhere: no room
  scene->hi_x = -1;
  const double cx = plan.centre_x(), cz = plan.centre_z();
  const double half = std::max(plan.x1 - plan.x0, plan.z1 - plan.z0) / 2;
  const double square = half + 11;  // paved half-width

  std::vector<Primitive> prims;
  prims.push_back(box_at(cx, cz, square, square, -0.02, 0.01, m.paving));
  for (int side = 0; side < 4; ++side) {  // a border of darker setts
    const double s = side < 2 ? (side == 0 ? -square : square) : 0;
    const double t = side >= 2 ? (side == 2 ? -square : square) : 0;
    prims.push_back(
        box_at(cx + s, cz + t, side < 2 ? 0.4 : square, side < 2 ? square : 0.4, -0.02, 0.015, m.border));
  }
  // A monument beside the cameras: stepped plinth, column and a figure.
  const double mx = plan.x1 + 3.5, mz = cz - 1.0;
  prims.push_back(box_at(mx, mz, 1.4, 1.4, 0, 0.3, m.stone));
  prims.push_back(box_at(mx, mz, 1.0, 1.0, 0.3, 1.8, m.stone));
  prims.push_back(make_cylinder(1, mz, mx, 0.35, 1.8, 4.5, m.stone));
  prims.push_back(box_at(mx, mz, 0.3, 0.25, 4.5, 6.0, m.bronze));
  // Benches and lamp posts round the cameras, trees in two rows further out.
  for (double x = plan.x0 - 1; x <= plan.x1 + 1; x += 3.2) {
    add_bench(&prims, x, plan.z0 - 2.2, true, m);
    add_bench(&prims, x + 1.6, plan.z1 + 2.2, true, m);
  }
  for (double z = plan.z0 - 3; z <= plan.z1 + 3; z += 6) {
    add_lamp_post(&prims, plan.x0 - 2.5, z, 4.2, m.metal);
    add_lamp_post(&prims, plan.x1 + 1.5, z + 3, 4.2, m.metal);
  }
  for (double a = -square + 2; a <= square - 2; a += 5) {
    for (double row : {square - 3.0, square - 7.0, 3.0 - square, 7.0 - square}) {
      if (!rng.chance(0.15)) add_tree(&prims, cx + a, cz + row, rng.uniform(5.5, 8.0), m.bark, m.leaves);
      if (!rng.chance(0.15)) add_tree(&prims, cx + row, cz + a + 2.5, rng.uniform(5.5, 8.0), m.bark, m.leaves);
    }
  }
  // Blocks of buildings round the square, with a street opening on each side.
  const double ring = square + 8;
  for (int side = 0; side < 4; ++side) {
    const int along = side < 2 ? 0 : 2;
    const int facing = side % 2 == 0 ? 1 : -1;
    const double centre = along == 0 ? cx : cz;
    for (double from = centre - ring - 10; from < centre + ring + 10;) {
      const double width = rng.uniform(8, 16);
      if (std::abs(from + width / 2 - centre) < 5) {  // the street into the square
        from += 10;
        continue;
      }
      Facade f;
      f.along = along;
      f.plane = (along == 0 ? cz : cx) - facing * (ring + rng.uniform(0, 6));
      f.facing = facing;
      f.from = from;
      f.to = from + width;
      f.storey = rng.uniform(3.0, 3.6);
      f.height = f.storey * (3 + rng.below(5)) + 0.6;
      f.window_width = rng.uniform(1.0, 1.6);
      f.window_pitch = f.window_width + rng.uniform(0.8, 1.8);
      f.depth = 12;
      f.wall = m.walls[rng.below(static_cast<int>(m.walls.size()))];
      f.glass = m.glass;
      f.trim = m.trim;
      f.balconies = rng.chance(0.4);
      f.shop_front = rng.chance(0.6);
      add_facade(&prims, f, &rng);
      from += width;
    }
  }
  scene->bvh = Bvh(std::move(prims));
}

}  // namespace svc::samples::detail
