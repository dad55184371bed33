// SPDX-License-Identifier: BSD-2-Clause
// The colonnade: a paved courtyard open to the sky, ringed on all four sides by an arcade
// of columns under the upper storeys of the surrounding building; a fountain basin and
// planted trees in the court. Repeated structure at every depth.
#include "scene/scene_builders.h"

namespace svc::samples::detail {

namespace {

struct ColonnadeMaterials {
  uint16_t paving, column, stone, wall, upper_wall, glass, trim, water, bark, leaves, planter;
};

ColonnadeMaterials colonnade_materials(Scene* scene) {
  ColonnadeMaterials m;
  m.paving = add_material(scene, mat(Pattern::kPaving, {0.62, 0.58, 0.50}, {0.35, 0.33, 0.30}, 0.45, 0.12));
  m.column = add_material(scene, mat(Pattern::kConcrete, {0.80, 0.76, 0.68}, {0.6, 0.57, 0.5}, 0.6, 0.04));
  m.stone = add_material(scene, mat(Pattern::kConcrete, {0.66, 0.62, 0.55}, {0.5, 0.47, 0.42}, 0.9, 0.06));
  m.wall = add_material(scene, mat(Pattern::kPlaster, {0.76, 0.60, 0.42}, {0.66, 0.5, 0.34}, 1.0, 0.05));
  m.upper_wall = add_material(scene, mat(Pattern::kBricks, {0.60, 0.32, 0.20}, {0.72, 0.70, 0.64}, 0.26, 0.25));
  m.glass = add_material(scene, mat(Pattern::kGlass, {0.10, 0.12, 0.15}, {0.30, 0.26, 0.20}, 0.5, 0.0));
  m.trim = add_material(scene, mat(Pattern::kConcrete, {0.84, 0.82, 0.78}, {0.7, 0.68, 0.64}, 0.7, 0.03));
  m.water = add_material(scene, mat(Pattern::kGlass, {0.12, 0.22, 0.26}, {0.12, 0.22, 0.26}, 100.0, 0.0));
  m.bark = add_material(scene, mat(Pattern::kPlanks, {0.25, 0.18, 0.12}, {0.1, 0.08, 0.05}, 0.2, 0.1));
  m.leaves = add_material(scene, mat(Pattern::kLeaves, {0.18, 0.34, 0.10}, {0.05, 0.13, 0.04}, 1.0, 0.1));
  m.planter = add_material(scene, mat(Pattern::kBricks, {0.45, 0.22, 0.14}, {0.6, 0.58, 0.54}, 0.22, 0.2));
  return m;
}

// One side of the arcade: columns on the line `line` along `along`, the lintel and the
// floor above them, the back wall with doors and the upper storeys' facade.
void add_arcade_side(std::vector<Primitive>* prims, int along, double line, int facing, double from, double to,
                     const ColonnadeMaterials& m, Random* rng) {
  constexpr double kDepth = 3.2, kHeight = 3.8, kPitch = 2.4, kRadius = 0.24;
  const int across = along == 0 ? 2 : 0;
  auto box = [&](double a0, double a1, double c0, double c1, double y0, double y1, uint16_t material) {
    Vec3 lo, hi;
    lo[along] = a0;
    hi[along] = a1;
    lo[across] = std::min(c0, c1);
    hi[across] = std::max(c0, c1);
    lo.y = y0;
    hi.y = y1;
    prims->push_back(make_box(lo, hi, material));
  };
  const double back = line - facing * kDepth;
  const int columns = std::max(2, static_cast<int>(std::round((to - from) / kPitch)));
  for (int k = 0; k <= columns; ++k) {
    const double a = from + k * (to - from) / columns;
    const double x = along == 0 ? a : line, z = along == 0 ? line : a;
    prims->push_back(make_cylinder(1, z, x, kRadius, 0.35, kHeight - 0.35, m.column));
    box(a - 0.34, a + 0.34, line - 0.34, line + 0.34, 0, 0.35, m.stone);
    box(a - 0.34, a + 0.34, line - 0.34, line + 0.34, kHeight - 0.35, kHeight - 0.2, m.stone);
  }
  // Lintel, the arcade's ceiling and floor, and the back wall with a door in every other bay.
  box(from - 0.4, to + 0.4, line - 0.4, line + 0.4, kHeight - 0.2, kHeight + 0.4, m.trim);
  box(from - 0.4, to + 0.4, line, back, kHeight + 0.2, kHeight + 0.4, m.stone);
  box(from - 0.4, to + 0.4, line + facing * 0.4, back, -0.1, 0.05, m.stone);
  std::vector<Opening> doors;
  for (int k = 0; k < columns; k += 2) {
    const double c = from + (k + 0.5) * (to - from) / columns;
    doors.push_back({c - 0.6, c + 0.6, 0.05, 2.5});
    box(c - 0.6, c + 0.6, back - facing * 0.15, back - facing * 0.2, 0.05, 2.5, m.glass);
  }
  add_wall(prims, along, std::min(back, back - facing * 0.3), std::max(back, back - facing * 0.3), from - 0.4,
           to + 0.4, kHeight + 0.2, doors, m.wall);
  // Upper storeys over the arcade, their front on the column line.
  Facade f;
  f.along = along;
  f.plane = line + facing * 0.4;
  f.facing = facing;
  f.from = from - 0.4;
  f.to = to + 0.4;
  f.height = 3.4 * (2 + rng->below(2)) + 0.6;
  f.storey = 3.4;
  f.depth = 8;
  f.window_width = 1.0;
  f.window_pitch = kPitch;
  f.wall = m.upper_wall;
  f.glass = m.glass;
  f.trim = m.trim;
  f.balconies = rng->chance(0.5);
  std::vector<Primitive> storeys;
  add_facade(&storeys, f, rng);
  // Lift the facade onto the arcade.
  for (Primitive& p : storeys) {
    p.lo.y += kHeight + 0.4;
    p.hi.y += kHeight + 0.4;
  }
  prims->insert(prims->end(), storeys.begin(), storeys.end());
}

}  // namespace

void build_colonnade(const SceneOptions& options, Scene* scene) {
  Random rng(options.seed * 2246822519u + 47);
  const GridFootprint plan = grid_footprint(options, *scene);
  const ColonnadeMaterials m = colonnade_materials(scene);
  scene->ground_material = m.paving;
  scene->lo_x = 1;  // outdoors everywhere: no room
  scene->hi_x = -1;

  const double margin = 3.0;
  const double x0 = plan.x0 - margin, x1 = plan.x1 + margin, z0 = plan.z0 - margin, z1 = plan.z1 + margin;
  std::vector<Primitive> prims;
  add_arcade_side(&prims, 0, z0, 1, x0, x1, m, &rng);
  add_arcade_side(&prims, 0, z1, -1, x0, x1, m, &rng);
  add_arcade_side(&prims, 2, x0, 1, z0, z1, m, &rng);
  add_arcade_side(&prims, 2, x1, -1, z0, z1, m, &rng);
  // Corner piers close the arcades' ends.
  for (double cx : {x0, x1}) {
    for (double cz : {z0, z1}) prims.push_back(box_at(cx, cz, 0.5, 0.5, 0.0, 4.2, m.stone));
  }
  // A low round basin in the court and trees in planters near its corners.
  const double bx = plan.centre_x(), bz = plan.centre_z();
  prims.push_back(make_cylinder(1, bz, bx, 1.3, 0.0, 0.5, m.stone));
  prims.push_back(make_cylinder(1, bz, bx, 1.15, 0.5, 0.52, m.water));
  prims.push_back(make_cylinder(1, bz, bx, 0.12, 0.5, 1.15, m.stone));
  for (double cx : {x0 + 1.2, x1 - 1.2}) {
    for (double cz : {z0 + 1.2, z1 - 1.2}) {
      prims.push_back(box_at(cx, cz, 0.5, 0.5, 0.0, 0.55, m.planter));
      add_tree(&prims, cx, cz, rng.uniform(4.5, 6.0), m.bark, m.leaves);
    }
  }
  scene->bvh = Bvh(std::move(prims));
}

}  // namespace svc::samples::detail
