// SPDX-License-Identifier: BSD-2-Clause
// The furnished interior: one room around the cell grid with daylight through tall
// windows, bookshelves full of books along the walls, pictures, a sofa, and tables,
// chairs and small objects standing among the cameras below eye height.
#include "scene/scene_builders.h"

namespace svc::samples::detail {

namespace {

struct InteriorMaterials {
  uint16_t wall, floor, ceiling, wood, dark_wood, fabric, rug, glass, metal, pot, leaves;
  std::vector<uint16_t> books, things, pictures;
};

InteriorMaterials interior_materials(Scene* scene) {
  InteriorMaterials m;
  m.wall = add_material(scene, mat(Pattern::kStripes, {0.74, 0.70, 0.60}, {0.80, 0.77, 0.68}, 0.12, 0.05));
  m.floor = add_material(scene, mat(Pattern::kPlanks, {0.52, 0.36, 0.20}, {0.16, 0.10, 0.05}, 0.14, 0.25));
  m.ceiling = add_material(scene, mat(Pattern::kPlaster, {0.85, 0.85, 0.83}, {0.8, 0.8, 0.78}, 1.0, 0.03));
  m.wood = add_material(scene, mat(Pattern::kPlanks, {0.45, 0.28, 0.14}, {0.14, 0.08, 0.04}, 0.2, 0.15));
  m.dark_wood = add_material(scene, mat(Pattern::kPlanks, {0.22, 0.12, 0.06}, {0.07, 0.04, 0.02}, 0.15, 0.1));
  m.fabric = add_material(scene, mat(Pattern::kFabric, {0.30, 0.42, 0.55}, {0.18, 0.25, 0.34}, 0.004, 0.05));
  m.rug = add_material(scene, mat(Pattern::kFabric, {0.55, 0.16, 0.12}, {0.75, 0.62, 0.40}, 0.01, 0.05));
  m.glass = add_material(scene, mat(Pattern::kGlass, {0.55, 0.65, 0.75}, {0.85, 0.85, 0.82}, 0.7, 0.0));
  m.metal = add_material(scene, mat(Pattern::kMetal, {0.62, 0.60, 0.56}, {0.3, 0.3, 0.3}, 1.0, 0.05));
  m.pot = add_material(scene, mat(Pattern::kConcrete, {0.55, 0.30, 0.18}, {0.4, 0.2, 0.1}, 0.3, 0.05));
  m.leaves = add_material(scene, mat(Pattern::kLeaves, {0.22, 0.40, 0.12}, {0.06, 0.15, 0.04}, 1.0, 0.1));
  const Vec3 book_colors[] = {{0.50, 0.08, 0.06}, {0.08, 0.20, 0.42}, {0.12, 0.32, 0.14}, {0.70, 0.62, 0.42},
                              {0.15, 0.12, 0.10}, {0.60, 0.40, 0.10}, {0.40, 0.12, 0.35}, {0.82, 0.80, 0.76}};
  for (const Vec3& c : book_colors)
    m.books.push_back(add_material(scene, mat(Pattern::kPlaster, c, c * 0.8, 1, 0.05)));
  const Vec3 thing_colors[] = {{0.85, 0.84, 0.80}, {0.20, 0.35, 0.60}, {0.75, 0.55, 0.15}, {0.30, 0.30, 0.32}};
  for (const Vec3& c : thing_colors)
    m.things.push_back(add_material(scene, mat(Pattern::kMetal, c, c * 0.6, 0.5, 0.05)));
  const Vec3 picture_colors[] = {{0.25, 0.40, 0.55}, {0.60, 0.45, 0.25}, {0.30, 0.45, 0.25}};
  for (const Vec3& c : picture_colors)
    m.pictures.push_back(add_material(scene, mat(Pattern::kConcrete, c, c * 0.5, 0.4, 0.3)));
  return m;
}

// A bookshelf with its back against the wall at `wall` on the axis across `along`, centred
// at `c` along it, opening towards `facing` (+1 or -1).
void add_bookshelf(std::vector<Primitive>* prims, double c, double wall, int along, int facing,
                   const InteriorMaterials& m, Random* rng) {
  const double width = 1.0, depth = 0.34, height = 2.1, board = 0.025;
  auto box = [&](double a0, double a1, double d0, double d1, double y0, double y1, uint16_t material) {
    Vec3 lo, hi;
    const int across = along == 0 ? 2 : 0;
    lo[along] = a0;
    hi[along] = a1;
    lo[across] = std::min(wall + facing * d0, wall + facing * d1);
    hi[across] = std::max(wall + facing * d0, wall + facing * d1);
    lo.y = y0;
    hi.y = y1;
    prims->push_back(make_box(lo, hi, material));
  };
  const double a0 = c - width / 2, a1 = c + width / 2;
  box(a0, a0 + board, 0, depth, 0, height, m.wood);
  box(a1 - board, a1, 0, depth, 0, height, m.wood);
  box(a0, a1, 0, board, 0, height, m.dark_wood);
  for (int shelf = 0; shelf <= 5; ++shelf) {
    const double y = 0.08 + shelf * 0.4;
    box(a0, a1, 0, depth, y - board, y, m.wood);
    if (shelf == 5) break;
    // Books of varied width, height and colour, now and then a gap or a leaning stack.
    for (double a = a0 + board; a < a1 - board - 0.05;) {
      const double w = rng->uniform(0.018, 0.055);
      if (rng->chance(0.06)) {
        a += rng->uniform(0.05, 0.15);
        continue;
      }
      const double h = rng->uniform(0.17, 0.33), d = rng->uniform(0.17, 0.27);
      const uint16_t book = m.books[rng->below(static_cast<int>(m.books.size()))];
      box(a, std::min(a + w, a1 - board), board + 0.01, board + 0.01 + d, y, y + h, book);
      a += w + 0.002;
    }
  }
}

// A table with four legs, and cups, bottles, bowls and boxes on it.
void add_table(std::vector<Primitive>* prims, double x, double z, double hx, double hz, const InteriorMaterials& m,
               Random* rng) {
  const double top = 0.74;
  prims->push_back(box_at(x, z, hx, hz, top, top + 0.04, m.wood));
  for (int leg = 0; leg < 4; ++leg) {
    const double lx = x + (leg & 1 ? hx - 0.04 : -hx + 0.04), lz = z + (leg & 2 ? hz - 0.04 : -hz + 0.04);
    prims->push_back(box_at(lx, lz, 0.03, 0.03, 0, top, m.dark_wood));
  }
  const int objects = 3 + rng->below(5);
  for (int k = 0; k < objects; ++k) {
    const double ox = rng->uniform(x - hx + 0.1, x + hx - 0.1), oz = rng->uniform(z - hz + 0.1, z + hz - 0.1);
    const uint16_t thing = m.things[rng->below(static_cast<int>(m.things.size()))];
    const double base = top + 0.04;
    switch (rng->below(4)) {
      case 0: prims->push_back(make_cylinder(1, oz, ox, 0.04, base, base + 0.1, thing)); break;   // cup
      case 1: prims->push_back(make_cylinder(1, oz, ox, 0.035, base, base + 0.3, thing)); break;  // bottle
      case 2: prims->push_back(make_cylinder(1, oz, ox, 0.12, base, base + 0.06, thing)); break;  // bowl
      default:
        prims->push_back(box_at(ox, oz, rng->uniform(0.05, 0.15), rng->uniform(0.05, 0.12), base,
                                base + rng->uniform(0.03, 0.15), m.books[rng->below(8)]));  // book or box
    }
  }
}

// A chair facing direction `dir` (0..3: +x, -x, +z, -z).
void add_chair(std::vector<Primitive>* prims, double x, double z, int dir, const InteriorMaterials& m) {
  prims->push_back(box_at(x, z, 0.22, 0.22, 0.43, 0.47, m.wood));
  for (int leg = 0; leg < 4; ++leg) {
    prims->push_back(
        box_at(x + (leg & 1 ? 0.19 : -0.19), z + (leg & 2 ? 0.19 : -0.19), 0.02, 0.02, 0, 0.43, m.wood));
  }
  const double bx = dir == 0 ? x - 0.2 : dir == 1 ? x + 0.2 : x, bz = dir == 2 ? z - 0.2 : dir == 3 ? z + 0.2 : z;
  prims->push_back(box_at(bx, bz, dir < 2 ? 0.02 : 0.22, dir < 2 ? 0.22 : 0.02, 0.47, 0.95, m.wood));
}

}  // namespace

void build_interior(const SceneOptions& options, Scene* scene) {
  Random rng(options.seed * 2654435761u + 101);
  const GridFootprint plan = grid_footprint(options, *scene);
  const InteriorMaterials m = interior_materials(scene);
  const double margin = 1.5, wall = 0.2;
  const double x0 = plan.x0 - margin, x1 = plan.x1 + margin, z0 = plan.z0 - margin, z1 = plan.z1 + margin;
  const double ceiling = std::max(3.0, plan.top_eye + 1.3);
  scene->lo_x = x0;
  scene->hi_x = x1;
  scene->lo_z = z0;
  scene->hi_z = z1;
  scene->ground_material =
      add_material(scene, mat(Pattern::kGround, {0.16, 0.22, 0.08}, {0.25, 0.21, 0.14}, 1.0, 0.2));

  std::vector<Primitive> prims;
  prims.push_back(make_box({x0 - wall, -0.2, z0 - wall}, {x1 + wall, 0.0, z1 + wall}, m.floor));
  prims.push_back(make_box({x0 - wall, ceiling, z0 - wall}, {x1 + wall, ceiling + 0.2, z1 + wall}, m.ceiling));
  // Tall windows in the +z and +x walls let the sun in; the other two walls hold shelves.
  auto windows = [&](double from, double to) {
    std::vector<Opening> out;
    for (double c = from + 1.6; c < to - 1.0; c += 2.6) out.push_back({c - 0.6, c + 0.6, 0.7, ceiling - 0.4});
    return out;
  };
  add_wall(&prims, 0, z1, z1 + wall, x0 - wall, x1 + wall, ceiling, windows(x0, x1), m.wall);
  add_wall(&prims, 2, x1, x1 + wall, z0, z1, ceiling, windows(z0, z1), m.wall);
  add_wall(&prims, 0, z0 - wall, z0, x0 - wall, x1 + wall, ceiling, {}, m.wall);
  add_wall(&prims, 2, x0 - wall, x0, z0, z1, ceiling, {}, m.wall);
  for (double c = x0 + 0.7; c + 0.6 < x1; c += rng.uniform(1.05, 1.6)) add_bookshelf(&prims, c, z0, 0, 1, m, &rng);
  for (double c = z0 + 1.4; c + 1.3 < z1; c += rng.uniform(1.05, 1.9)) {
    if (rng.chance(0.75)) {
      add_bookshelf(&prims, c, x0, 2, 1, m, &rng);
    } else {  // a picture between the shelves
      prims.push_back(make_box({x0, 1.3, c - 0.4}, {x0 + 0.03, 1.9, c + 0.4}, m.dark_wood));
      prims.push_back(make_box({x0 + 0.03, 1.35, c - 0.35}, {x0 + 0.04, 1.85, c + 0.35}, m.pictures[rng.below(3)]));
    }
  }
  // A sofa under the +z windows, a rug in the middle, plants in the corners.
  prims.push_back(
      make_box({plan.centre_x() - 1.1, 0.0, z1 - 0.9}, {plan.centre_x() + 1.1, 0.45, z1 - 0.05}, m.fabric));
  prims.push_back(
      make_box({plan.centre_x() - 1.1, 0.45, z1 - 0.25}, {plan.centre_x() + 1.1, 0.9, z1 - 0.05}, m.fabric));
  prims.push_back(make_box({plan.x0 - 0.5, 0.0, plan.z0 - 0.5}, {plan.x1 + 0.5, 0.012, plan.z1 + 0.5}, m.rug));
  for (double cx : {x0 + 0.4, x1 - 0.4}) {
    for (double cz : {z0 + 0.4, z1 - 0.4}) {
      if (cx < x0 + 1 && cz < z0 + 1) continue;  // the shelves' corner
      prims.push_back(make_cylinder(1, cz, cx, 0.18, 0.0, 0.4, m.pot));
      prims.push_back(make_cylinder(1, cz, cx, 0.3, 0.4, 1.3, m.leaves));
    }
  }
  // Tables with chairs among the cameras, below eye height: near objects at many depths.
  const double top_allowed = scene->origin.y - 0.4;
  if (top_allowed > 1.0) {
    for (double tz = plan.z0 + 0.3; tz < plan.z1 + 0.3; tz += rng.uniform(1.8, 2.6)) {
      for (double tx = plan.x0 + 0.3; tx < plan.x1 + 0.3; tx += rng.uniform(1.8, 2.8)) {
        if (rng.chance(0.3)) continue;
        const double hx = rng.uniform(0.35, 0.6), hz = rng.uniform(0.3, 0.45);
        add_table(&prims, tx, tz, hx, hz, m, &rng);
        if (rng.chance(0.7)) add_chair(&prims, tx - hx - 0.3, tz, 0, m);
        if (rng.chance(0.5)) add_chair(&prims, tx, tz + hz + 0.3, 3, m);
      }
    }
  }
  // A ceiling lamp: the shade and the light under it.
  prims.push_back(make_cylinder(1, plan.centre_z(), plan.centre_x(), 0.25, ceiling - 0.45, ceiling - 0.3, m.metal));
  prims.push_back(make_cylinder(1, plan.centre_z(), plan.centre_x(), 0.01, ceiling - 0.3, ceiling, m.metal));
  Room room;
  room.has_lamp = true;
  room.lamp = Vec3(plan.centre_x(), ceiling - 0.55, plan.centre_z());
  room.ambient = 0.34;
  scene->rooms.push_back(room);
  scene->ambient_indoor = 0.34;
  scene->bvh = Bvh(std::move(prims));
}

}  // namespace svc::samples::detail
