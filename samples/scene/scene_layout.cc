// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene_layout.h"

#include "scene/scene_builders.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace svc::samples::detail {

namespace {

void build_hall(const SceneOptions& options, Scene* scene) {
  Random rng(options.seed * 2654435761u + 17);
  const double top_eye = scene->origin.y + (options.grid[1] - 1) * options.spacing[1];
  const double extent_x = (options.grid[0] - 1) * options.spacing[0];
  const double extent_z = (options.grid[2] - 1) * options.spacing[2];
  const double hx = extent_x / 2 + 4.0, hz = extent_z / 2 + 4.0;
  const double height = std::max(5.0, top_eye + 2.6);
  // Cameras stand in the open: columns and crates keep this far from the footprint of
  // the cell grid (as the navigable region of a real impostor database would be).
  const double clearance = 0.9;
  auto near_cameras = [&](double x, double z, double half_x, double half_z) {
    return std::abs(x) < extent_x / 2 + clearance + half_x && std::abs(z) < extent_z / 2 + clearance + half_z;
  };
  const double wall = 0.3;
  scene->lo_x = -hx;
  scene->hi_x = hx;
  scene->lo_z = -hz;
  scene->hi_z = hz;

  const uint16_t floor_tiles =
      add_material(scene, mat(Pattern::kTiles, {0.40, 0.38, 0.35}, {0.16, 0.15, 0.14}, 0.6, 0.10));
  const uint16_t bricks =
      add_material(scene, mat(Pattern::kBricks, {0.34, 0.12, 0.07}, {0.46, 0.44, 0.40}, 0.25, 0.30));
  const uint16_t concrete =
      add_material(scene, mat(Pattern::kConcrete, {0.42, 0.41, 0.39}, {0.30, 0.29, 0.28}, 1.2, 0.08));
  const uint16_t roof =
      add_material(scene, mat(Pattern::kPanels, {0.55, 0.55, 0.56}, {0.25, 0.25, 0.27}, 1.0, 0.05));
  const uint16_t column =
      add_material(scene, mat(Pattern::kConcrete, {0.55, 0.53, 0.50}, {0.40, 0.39, 0.37}, 0.9, 0.05));
  const uint16_t plinth =
      add_material(scene, mat(Pattern::kConcrete, {0.30, 0.30, 0.31}, {0.22, 0.22, 0.23}, 0.5, 0.05));
  const uint16_t red_pipe =
      add_material(scene, mat(Pattern::kMetal, {0.42, 0.07, 0.04}, {0.15, 0.03, 0.02}, 3.0, 0.1));
  const uint16_t grey_pipe =
      add_material(scene, mat(Pattern::kMetal, {0.33, 0.35, 0.37}, {0.15, 0.15, 0.16}, 2.5, 0.1));
  const uint16_t green_pipe =
      add_material(scene, mat(Pattern::kMetal, {0.10, 0.26, 0.14}, {0.04, 0.10, 0.05}, 2.0, 0.1));
  const uint16_t beam = add_material(scene, mat(Pattern::kMetal, {0.10, 0.17, 0.32}, {0.04, 0.07, 0.12}, 4.0, 0.1));
  const uint16_t crate =
      add_material(scene, mat(Pattern::kPlanks, {0.46, 0.31, 0.15}, {0.10, 0.07, 0.04}, 0.14, 0.25));
  const uint16_t crate_dark =
      add_material(scene, mat(Pattern::kPlanks, {0.30, 0.18, 0.09}, {0.07, 0.05, 0.03}, 0.11, 0.2));
  scene->ground_material =
      add_material(scene, mat(Pattern::kGround, {0.13, 0.17, 0.06}, {0.22, 0.18, 0.12}, 1.0, 0.2));

  std::vector<Primitive> prims;
  // Floor slab; the ground plane outside lies just below its top.
  prims.push_back(make_box({-hx - wall, -0.3, -hz - wall}, {hx + wall, 0.0, hz + wall}, floor_tiles));

  // Walls: windows in three of them, the -x wall solid brick.
  const double sill = 1.1, head = height - 1.2;
  auto windows = [&](double from, double to) {
    std::vector<Opening> out;
    const int count = static_cast<int>(std::floor((to - from - 1.0) / 3.0));
    for (int k = 0; k < count; ++k) {
      const double c = from + (k + 0.5) * (to - from) / count;
      out.push_back({c - 0.8, c + 0.8, sill, head});
    }
    return out;
  };
  add_wall(&prims, 0, hz, hz + wall, -hx - wall, hx + wall, height, windows(-hx, hx), bricks);
  add_wall(&prims, 0, -hz - wall, -hz, -hx - wall, hx + wall, height, windows(-hx, hx), bricks);
  add_wall(&prims, 2, hx, hx + wall, -hz, hz, height, windows(-hz, hz), concrete);
  add_wall(&prims, 2, -hx - wall, -hx, -hz, hz, height, {}, bricks);

  // Roof with rows of skylights, steel beams along their edges.
  {
    const int lights = std::max(1, static_cast<int>(std::floor(2 * hz / 3.5)));
    double cursor = -hz - wall;
    for (int k = 0; k < lights; ++k) {
      const double c = -hz + (k + 0.5) * 2 * hz / lights;
      const double z0 = c - 0.7, z1 = c + 0.7;
      prims.push_back(make_box({-hx - wall, height, cursor}, {hx + wall, height + 0.3, z0}, roof));
      prims.push_back(make_box({-hx - wall, height, z0}, {-hx + 1.0, height + 0.3, z1}, roof));
      prims.push_back(make_box({hx - 1.0, height, z0}, {hx + wall, height + 0.3, z1}, roof));
      prims.push_back(make_box({-hx, height - 0.35, z0 - 0.2}, {hx, height, z0}, beam));
      prims.push_back(make_box({-hx, height - 0.35, z1}, {hx, height, z1 + 0.2}, beam));
      cursor = z1;
    }
    prims.push_back(make_box({-hx - wall, height, cursor}, {hx + wall, height + 0.3, hz + wall}, roof));
  }

  // Columns about 3 m apart around the cameras' footprint.
  const double radius = 0.22;
  const auto column_x = lattice(scene->origin.x, options.spacing[0], -hx + 0.6, hx - 0.6, 3.0, 0.5);
  const auto column_z = lattice(scene->origin.z, options.spacing[2], -hz + 0.6, hz - 0.6, 3.0, 0.5);
  struct Disc {
    double x, z, r;
  };
  std::vector<Disc> keep_out;
  for (double x : column_x) {
    for (double z : column_z) {
      if (near_cameras(x, z, 0.32, 0.32)) continue;
      prims.push_back(make_cylinder(1, z, x, radius, 0.0, height, column));
      prims.push_back(make_box({x - 0.32, 0.0, z - 0.32}, {x + 0.32, 0.28, z + 0.32}, plinth));
      prims.push_back(make_box({x - 0.3, height - 0.3, z - 0.3}, {x + 0.3, height, z + 0.3}, plinth));
      keep_out.push_back({x, z, 0.45});
    }
  }
  // A sparse hall also has tall storage racks standing on some cell centres; those
  // cells lie inside solid geometry and are left out of the grid.
  if (options.sparse) {
    const auto rack_x = lattice(scene->origin.x, options.spacing[0], -hx + 0.6, hx - 0.6, 2.0, 0.0);
    const auto rack_z = lattice(scene->origin.z, options.spacing[2], -hz + 0.6, hz - 0.6, 2.0, 0.0);
    for (double x : rack_x) {
      for (double z : rack_z) {
        bool clear = true;
        for (const Disc& c : keep_out) {
          if (std::abs(x - c.x) < 0.3 + c.r && std::abs(z - c.z) < 0.3 + c.r) clear = false;
        }
        if (!clear) continue;
        prims.push_back(make_box({x - 0.3, 0.0, z - 0.3}, {x + 0.3, 2.3, z + 0.3}, crate_dark));
        keep_out.push_back({x, z, 0.4});
      }
    }
  }

  // Pipes along the walls and across the ceiling, one riser in a corner.
  prims.push_back(make_cylinder(0, height - 0.9, hz - 0.25, 0.12, -hx, hx, red_pipe));
  prims.push_back(make_cylinder(0, height - 1.25, hz - 0.2, 0.07, -hx, hx, grey_pipe));
  prims.push_back(make_cylinder(2, -hx + 0.3, std::max(2.8, top_eye + 1.2), 0.15, -hz, hz, green_pipe));
  prims.push_back(make_cylinder(0, height - 0.6, -0.4 * hz, 0.18, -hx, hx, grey_pipe));
  prims.push_back(make_cylinder(1, hz - 0.25, hx - 0.25, 0.09, 0.0, height, red_pipe));

  // Crates, some stacked, kept off the columns and walls.
  const int crates = std::max(2, static_cast<int>(4 * hx * hz / 7.0));
  for (int i = 0; i < crates; ++i) {
    for (int attempt = 0; attempt < 12; ++attempt) {
      const double w = rng.uniform(0.45, 0.95), d = rng.uniform(0.45, 0.95);
      const double h = rng.uniform(0.45, 0.9);
      const double x = rng.uniform(-hx + w / 2 + 0.1, hx - w / 2 - 0.1);
      const double z = rng.uniform(-hz + d / 2 + 0.1, hz - d / 2 - 0.1);
      bool clear = !near_cameras(x, z, w / 2, d / 2);
      for (const Disc& c : keep_out) {
        if (std::abs(x - c.x) < w / 2 + c.r && std::abs(z - c.z) < d / 2 + c.r) clear = false;
      }
      if (!clear) continue;
      const uint16_t m = rng.chance(0.5) ? crate : crate_dark;
      prims.push_back(make_box({x - w / 2, 0.0, z - d / 2}, {x + w / 2, h, z + d / 2}, m));
      if (rng.chance(0.4)) {
        const double s = rng.uniform(0.6, 0.9);
        const double h2 = std::min(rng.uniform(0.35, 0.6), 1.4 - h);
        const double ox = rng.uniform(-0.05, 0.05);
        prims.push_back(make_box({x + ox - s * w / 2, h, z - s * d / 2},
                                 {x + ox + s * w / 2, h + h2, z + s * d / 2}, m == crate ? crate_dark : crate));
      }
      keep_out.push_back({x, z, std::max(w, d) / 2 + 0.1});
      break;
    }
  }

  scene->rooms.push_back(Room{});
  scene->ambient_indoor = 0.42;
  scene->bvh = Bvh(std::move(prims));
}

// Interior wall centre lines between cells: the cells split into rooms about 2.4 m wide.
// Walls fall between groups of three cells where the grid allows, so that each 3x3
// group of the default I/B layout lies in one room; cells on either side of a wall
// still see different rooms.
std::vector<double> room_cuts(int cells, double origin, double spacing) {
  const int rooms = std::clamp(static_cast<int>(std::lround(cells * spacing / 2.4)), 1, cells);
  std::vector<double> cuts;
  int previous = -1;
  for (int r = 1; r < rooms; ++r) {
    int last_cell = cells * r / rooms - 1;
    if (cells >= 6)
      last_cell = std::clamp(static_cast<int>(std::lround((last_cell + 1) / 3.0)) * 3 - 1, 0, cells - 2);
    if (last_cell <= previous) continue;
    previous = last_cell;
    cuts.push_back(origin + (last_cell + 0.5) * spacing);
  }
  return cuts;
}

void build_house(const SceneOptions& options, Scene* scene) {
  Random rng(options.seed * 2246822519u + 3);
  const double top_eye = scene->origin.y + (options.grid[1] - 1) * options.spacing[1];
  const double sx = options.spacing[0], sz = options.spacing[2];
  const double margin = 0.55;
  scene->lo_x = scene->origin.x - 0.5 * sx - margin;
  scene->hi_x = scene->origin.x + (options.grid[0] - 0.5) * sx + margin;
  scene->lo_z = scene->origin.z - 0.5 * sz - margin;
  scene->hi_z = scene->origin.z + (options.grid[2] - 0.5) * sz + margin;
  scene->cuts_x = room_cuts(options.grid[0], scene->origin.x, sx);
  scene->cuts_z = room_cuts(options.grid[2], scene->origin.z, sz);
  const int rooms_x = static_cast<int>(scene->cuts_x.size()) + 1;
  const int rooms_z = static_cast<int>(scene->cuts_z.size()) + 1;
  const double ceiling = std::max(2.7, top_eye + 1.0);
  const double wall_top = ceiling + 0.15;
  const double inner = 0.12, outer = 0.25;
  const double door_height = std::min(2.1, ceiling - 0.3);

  // Room styles; neighbours get different ones (indices step by 2 and 3 modulo a prime).
  const std::vector<Material> wall_styles = {
      mat(Pattern::kPlaster, {0.72, 0.68, 0.60}, {0.6, 0.56, 0.5}, 1.0, 0.05),
      mat(Pattern::kStripes, {0.45, 0.55, 0.62}, {0.62, 0.68, 0.70}, 0.16, 0.05),
      mat(Pattern::kBricks, {0.40, 0.16, 0.09}, {0.55, 0.52, 0.48}, 0.25, 0.3),
      mat(Pattern::kPlaster, {0.50, 0.62, 0.46}, {0.4, 0.5, 0.36}, 1.0, 0.05),
      mat(Pattern::kPlanks, {0.40, 0.25, 0.12}, {0.12, 0.07, 0.03}, 0.18, 0.2),
      mat(Pattern::kStripes, {0.70, 0.55, 0.30}, {0.74, 0.68, 0.50}, 0.10, 0.05),
      mat(Pattern::kPlaster, {0.68, 0.36, 0.26}, {0.55, 0.28, 0.2}, 1.0, 0.05),
  };
  const std::vector<Material> floor_styles = {
      mat(Pattern::kPlanks, {0.45, 0.28, 0.13}, {0.12, 0.07, 0.03}, 0.15, 0.25),
      mat(Pattern::kTiles, {0.55, 0.53, 0.50}, {0.22, 0.21, 0.20}, 0.3, 0.12),
      mat(Pattern::kConcrete, {0.30, 0.12, 0.10}, {0.25, 0.10, 0.08}, 4.0, 0.05),
      mat(Pattern::kPlanks, {0.62, 0.47, 0.30}, {0.2, 0.14, 0.08}, 0.12, 0.2),
      mat(Pattern::kTiles, {0.20, 0.22, 0.26}, {0.45, 0.45, 0.45}, 0.45, 0.15),
  };
  std::vector<uint16_t> wall_ids, floor_ids;
  for (const auto& m : wall_styles) wall_ids.push_back(add_material(scene, m));
  for (const auto& m : floor_styles) floor_ids.push_back(add_material(scene, m));
  const uint16_t ceiling_paint =
      add_material(scene, mat(Pattern::kPlaster, {0.78, 0.78, 0.76}, {0.7, 0.7, 0.68}, 1.0, 0.03));
  scene->exterior_wall =
      add_material(scene, mat(Pattern::kConcrete, {0.55, 0.52, 0.46}, {0.45, 0.43, 0.38}, 1.5, 0.05));
  const uint16_t wood =
      add_material(scene, mat(Pattern::kPlanks, {0.28, 0.16, 0.08}, {0.08, 0.05, 0.02}, 0.2, 0.15));
  const uint16_t painted =
      add_material(scene, mat(Pattern::kPlaster, {0.62, 0.62, 0.58}, {0.5, 0.5, 0.46}, 1.0, 0.03));
  scene->ground_material =
      add_material(scene, mat(Pattern::kGround, {0.13, 0.17, 0.06}, {0.22, 0.18, 0.12}, 1.0, 0.2));

  std::vector<double> bx = {scene->lo_x}, bz = {scene->lo_z};
  bx.insert(bx.end(), scene->cuts_x.begin(), scene->cuts_x.end());
  bz.insert(bz.end(), scene->cuts_z.begin(), scene->cuts_z.end());
  bx.push_back(scene->hi_x);
  bz.push_back(scene->hi_z);

  // Which rooms are open to the sky (0), have a skylight (1) or a closed ceiling (2).
  const int room_count = rooms_x * rooms_z;
  std::vector<int> roof_kind(room_count, 2);
  for (int r = 0; r < room_count; ++r) {
    const double u = rng.uniform(0, 1);
    roof_kind[r] = u < 0.25 ? 0 : (u < 0.5 ? 1 : 2);
  }
  if (room_count == 1) {
    roof_kind[0] = 1;
  } else if (std::count(roof_kind.begin(), roof_kind.end(), 2) == room_count) {
    roof_kind[rng.below(room_count)] = 0;
  }

  const uint32_t style_offset = options.seed % 7;
  for (int rz = 0; rz < rooms_z; ++rz) {
    for (int rx = 0; rx < rooms_x; ++rx) {
      const int r = rz * rooms_x + rx;
      Room room;
      room.wall = wall_ids[(rx * 2 + rz * 3 + style_offset) % wall_ids.size()];
      room.floor = floor_ids[(rx * 3 + rz * 2 + style_offset) % floor_ids.size()];
      room.ceiling = ceiling_paint;
      room.has_lamp = roof_kind[r] != 0;
      room.lamp = Vec3((bx[rx] + bx[rx + 1]) / 2, ceiling - 0.35, (bz[rz] + bz[rz + 1]) / 2);
      room.ambient = roof_kind[r] == 0 ? 0.42 : (roof_kind[r] == 1 ? 0.3 : 0.22);
      scene->rooms.push_back(room);
    }
  }

  std::vector<Primitive> prims;
  prims.push_back(make_box({scene->lo_x - outer, -0.2, scene->lo_z - outer},
                           {scene->hi_x + outer, 0.0, scene->hi_z + outer}, kRoomFloor));

  // Regions furniture must keep clear of: in front of doors and windows.
  struct Area {
    double x0, z0, x1, z1;
  };
  std::vector<Area> keep_clear;

  // Interior walls with one door per room pair.
  auto door_in = [&](double from, double to) {
    const double width = std::min(0.9, to - from - 0.4);
    std::vector<Opening> out;
    if (width < 0.5) return out;
    const double c = rng.uniform(from + 0.2 + width / 2, to - 0.2 - width / 2);
    out.push_back({c - width / 2, c + width / 2, 0.0, door_height});
    return out;
  };
  for (size_t i = 0; i < scene->cuts_x.size(); ++i) {
    const double x = scene->cuts_x[i];
    for (int rz = 0; rz < rooms_z; ++rz) {
      auto doors = door_in(bz[rz], bz[rz + 1]);
      for (const auto& d : doors) keep_clear.push_back({x - 0.9, d.from - 0.1, x + 0.9, d.to + 0.1});
      add_wall(&prims, 2, x - inner / 2, x + inner / 2, bz[rz], bz[rz + 1], wall_top, doors, kRoomWall);
    }
  }
  for (size_t i = 0; i < scene->cuts_z.size(); ++i) {
    const double z = scene->cuts_z[i];
    for (int rx = 0; rx < rooms_x; ++rx) {
      auto doors = door_in(bx[rx], bx[rx + 1]);
      for (const auto& d : doors) keep_clear.push_back({d.from - 0.1, z - 0.9, d.to + 0.1, z + 0.9});
      add_wall(&prims, 0, z - inner / 2, z + inner / 2, bx[rx], bx[rx + 1], wall_top, doors, kRoomWall);
    }
  }

  // Outer walls with a window in most room segments.
  const double sill = 0.9, head = ceiling - 0.5;
  auto window_in = [&](double from, double to) {
    const double width = std::min(1.3, to - from - 0.6);
    std::vector<Opening> out;
    if (width < 0.5 || rng.chance(0.2)) return out;
    const double c = rng.uniform(from + 0.3 + width / 2, to - 0.3 - width / 2);
    out.push_back({c - width / 2, c + width / 2, sill, head});
    return out;
  };
  for (int side = 0; side < 2; ++side) {
    const double z = side == 0 ? scene->lo_z : scene->hi_z;
    const double z0 = side == 0 ? z - outer : z, z1 = side == 0 ? z : z + outer;
    std::vector<Opening> openings;
    for (int rx = 0; rx < rooms_x; ++rx) {
      for (const auto& w : window_in(bx[rx], bx[rx + 1])) {
        openings.push_back(w);
        keep_clear.push_back({w.from - 0.1, z - 0.7, w.to + 0.1, z + 0.7});
      }
    }
    add_wall(&prims, 0, z0, z1, scene->lo_x - outer, scene->hi_x + outer, wall_top, openings, kRoomWall);
  }
  for (int side = 0; side < 2; ++side) {
    const double x = side == 0 ? scene->lo_x : scene->hi_x;
    const double x0 = side == 0 ? x - outer : x, x1 = side == 0 ? x : x + outer;
    std::vector<Opening> openings;
    for (int rz = 0; rz < rooms_z; ++rz) {
      for (const auto& w : window_in(bz[rz], bz[rz + 1])) {
        openings.push_back(w);
        keep_clear.push_back({x - 0.7, w.from - 0.1, x + 0.7, w.to + 0.1});
      }
    }
    add_wall(&prims, 2, x0, x1, scene->lo_z, scene->hi_z, wall_top, openings, kRoomWall);
  }

  // Ceilings: closed, with a skylight, or none.
  for (int rz = 0; rz < rooms_z; ++rz) {
    for (int rx = 0; rx < rooms_x; ++rx) {
      const int kind = roof_kind[rz * rooms_x + rx];
      if (kind == 0) continue;
      const double x0 = bx[rx], x1 = bx[rx + 1], z0 = bz[rz], z1 = bz[rz + 1];
      const double y0 = ceiling, y1 = ceiling + 0.15;
      if (kind == 2) {
        prims.push_back(make_box({x0, y0, z0}, {x1, y1, z1}, kRoomCeiling));
        continue;
      }
      const double hx0 = x0 + 0.3 * (x1 - x0), hx1 = x1 - 0.3 * (x1 - x0);
      const double hz0 = z0 + 0.3 * (z1 - z0), hz1 = z1 - 0.3 * (z1 - z0);
      prims.push_back(make_box({x0, y0, z0}, {x1, y1, hz0}, kRoomCeiling));
      prims.push_back(make_box({x0, y0, hz1}, {x1, y1, z1}, kRoomCeiling));
      prims.push_back(make_box({x0, y0, hz0}, {hx0, y1, hz1}, kRoomCeiling));
      prims.push_back(make_box({hx1, y0, hz0}, {x1, y1, hz1}, kRoomCeiling));
    }
  }

  // Furniture: a wardrobe against a wall and a table or a low cabinet.
  auto clear_of = [&](double x0, double z0, double x1, double z1) {
    for (const Area& a : keep_clear) {
      if (x0 < a.x1 && x1 > a.x0 && z0 < a.z1 && z1 > a.z0) return false;
    }
    return true;
  };
  for (int rz = 0; rz < rooms_z; ++rz) {
    for (int rx = 0; rx < rooms_x; ++rx) {
      const double x0 = bx[rx] + (rx > 0 ? inner / 2 : 0), x1 = bx[rx + 1] - (rx + 1 < rooms_x ? inner / 2 : 0);
      const double z0 = bz[rz] + (rz > 0 ? inner / 2 : 0), z1 = bz[rz + 1] - (rz + 1 < rooms_z ? inner / 2 : 0);
      // Wardrobe: 1.0 wide, 0.6 deep, 2.0 tall, its back on one of the four walls.
      for (int attempt = 0; attempt < 8; ++attempt) {
        const int side = rng.below(4);
        const bool along_x = side < 2;  // back on a wall of constant z
        const double span = along_x ? x1 - x0 : z1 - z0;
        if (span < 1.2 || (along_x ? z1 - z0 : x1 - x0) < 1.4) break;
        const double c = rng.uniform((along_x ? x0 : z0) + 0.55, (along_x ? x1 : z1) - 0.55);
        double ax0, ax1, az0, az1;
        if (along_x) {
          ax0 = c - 0.5;
          ax1 = c + 0.5;
          az0 = side == 0 ? z0 : z1 - 0.6;
          az1 = side == 0 ? z0 + 0.6 : z1;
        } else {
          az0 = c - 0.5;
          az1 = c + 0.5;
          ax0 = side == 2 ? x0 : x1 - 0.6;
          ax1 = side == 2 ? x0 + 0.6 : x1;
        }
        if (!clear_of(ax0, az0, ax1, az1)) continue;
        prims.push_back(make_box({ax0, 0.0, az0}, {ax1, 2.0, az1}, wood));
        keep_clear.push_back({ax0 - 0.3, az0 - 0.3, ax1 + 0.3, az1 + 0.3});
        break;
      }
      // Table in the room, or a cabinet.
      for (int attempt = 0; attempt < 8; ++attempt) {
        const bool table = rng.chance(0.6);
        const double w = table ? 1.1 : 0.8, d = table ? 0.7 : 0.45;
        if (x1 - x0 < w + 0.4 || z1 - z0 < d + 0.4) break;
        const double cx = rng.uniform(x0 + w / 2 + 0.2, x1 - w / 2 - 0.2);
        const double cz = rng.uniform(z0 + d / 2 + 0.2, z1 - d / 2 - 0.2);
        const double tx0 = cx - w / 2, tx1 = cx + w / 2, tz0 = cz - d / 2, tz1 = cz + d / 2;
        if (!clear_of(tx0, tz0, tx1, tz1)) continue;
        if (table) {
          prims.push_back(make_box({tx0, 0.72, tz0}, {tx1, 0.77, tz1}, wood));
          for (int leg = 0; leg < 4; ++leg) {
            const double lx = leg & 1 ? tx1 - 0.06 : tx0, lz = leg & 2 ? tz1 - 0.06 : tz0;
            prims.push_back(make_box({lx, 0.0, lz}, {lx + 0.06, 0.72, lz + 0.06}, painted));
          }
        } else {
          prims.push_back(make_box({tx0, 0.0, tz0}, {tx1, 0.85, tz1}, painted));
        }
        keep_clear.push_back({tx0 - 0.2, tz0 - 0.2, tx1 + 0.2, tz1 + 0.2});
        break;
      }
    }
  }

  scene->ambient_indoor = 0.25;
  scene->bvh = Bvh(std::move(prims));
}

}  // namespace

int Scene::room_at(double x, double z) const {
  if (x < lo_x || x > hi_x || z < lo_z || z > hi_z) return -1;
  if (kind != SceneKind::kHouse) return 0;
  const int rx = static_cast<int>(std::upper_bound(cuts_x.begin(), cuts_x.end(), x) - cuts_x.begin());
  const int rz = static_cast<int>(std::upper_bound(cuts_z.begin(), cuts_z.end(), z) - cuts_z.begin());
  return rz * (static_cast<int>(cuts_x.size()) + 1) + rx;
}

Scene build_scene(const SceneOptions& options) {
  Scene scene;
  scene.kind = options.kind;
  scene.dims = options.grid;
  scene.spacing = Vec3(options.spacing[0], options.spacing[1], options.spacing[2]);
  // The grid is centred on the scene's vertical axis with its lowest layer at eye height.
  const auto origin = scene_grid_origin(options);
  scene.origin = Vec3(origin[0], origin[1], origin[2]);
  scene.sun_dir = glm::normalize(Vec3(0.38, 0.82, 0.42));
  scene.sun_color = Vec3(1.0, 0.93, 0.82) * 1.7;
  switch (options.kind) {
    case SceneKind::kHall: build_hall(options, &scene); break;
    case SceneKind::kHouse: build_house(options, &scene); break;
    case SceneKind::kStreet: build_street(options, &scene); break;
    case SceneKind::kInterior: build_interior(options, &scene); break;
    case SceneKind::kColonnade: build_colonnade(options, &scene); break;
    case SceneKind::kPlaza: build_plaza(options, &scene); break;
  }
  return scene;
}

}  // namespace svc::samples::detail
