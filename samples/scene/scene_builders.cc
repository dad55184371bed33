// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene_builders.h"

namespace svc::samples::detail {

namespace {

// A box given by its extent along the facade's axes: [a0, a1] along it, [c0, c1] across
// it (in world units, any order), [y0, y1] vertically.
Primitive facade_box(const Facade& f, double a0, double a1, double c0, double c1, double y0, double y1,
                     uint16_t material) {
  const int across = f.along == 0 ? 2 : 0;
  Vec3 lo, hi;
  lo[f.along] = std::min(a0, a1);
  hi[f.along] = std::max(a0, a1);
  lo[across] = std::min(c0, c1);
  hi[across] = std::max(c0, c1);
  lo.y = y0;
  hi.y = y1;
  return make_box(lo, hi, material);
}

}  // namespace

void add_facade(std::vector<Primitive>* prims, const Facade& f, Random* rng) {
  constexpr double kWall = 0.3, kRecess = 0.18;
  const double front = f.plane, back_of_wall = f.plane - f.facing * kWall;
  // The building's core behind the wall, and the cornice along its top.
  prims->push_back(facade_box(f, f.from, f.to, back_of_wall, f.plane - f.facing * f.depth, 0, f.height, f.wall));
  prims->push_back(facade_box(f, f.from - 0.1, f.to + 0.1, front, front + f.facing * 0.35, f.height - 0.35,
                              f.height - 0.1, f.trim));

  const int floors = std::max(1, static_cast<int>(std::floor(f.height / f.storey)));
  const int windows = std::max(1, static_cast<int>(std::floor((f.to - f.from) / f.window_pitch)));
  const double pitch = (f.to - f.from) / windows;
  for (int floor = 0; floor < floors; ++floor) {
    const double y0 = floor * f.storey, y1 = floor + 1 == floors ? f.height - 0.35 : y0 + f.storey;
    const bool shop = f.shop_front && floor == 0;
    const double width = shop ? pitch * 0.75 : std::min(f.window_width, pitch * 0.7);
    const double bottom = y0 + (shop ? 0.3 : 0.9), top = y0 + std::min(f.storey - 0.5, shop ? 2.7 : 2.3);
    std::vector<Opening> openings;
    for (int k = 0; k < windows; ++k) {
      const double c = f.from + (k + 0.5) * pitch;
      openings.push_back({c - width / 2, c + width / 2, bottom, top});
      // The pane, set back in the opening, and the sill below it.
      prims->push_back(facade_box(f, c - width / 2, c + width / 2, front - f.facing * kRecess,
                                  front - f.facing * (kRecess + 0.03), bottom, top, f.glass));
      prims->push_back(facade_box(f, c - width / 2 - 0.06, c + width / 2 + 0.06, front, front + f.facing * 0.06,
                                  bottom - 0.08, bottom, f.trim));
      if (f.balconies && floor > 0 && rng->chance(0.35)) {
        const double reach = front + f.facing * 0.9;
        prims->push_back(
            facade_box(f, c - width / 2 - 0.3, c + width / 2 + 0.3, front, reach, y0 - 0.02, y0 + 0.14, f.trim));
        prims->push_back(facade_box(f, c - width / 2 - 0.3, c + width / 2 + 0.3, reach - f.facing * 0.04, reach,
                                    y0 + 0.14, y0 + 1.05, f.trim));
      }
    }
    add_wall_band(prims, f.along, std::min(front, back_of_wall), std::max(front, back_of_wall), f.from, f.to, y0,
                  y1, openings, f.wall);
  }
}

void add_tree(std::vector<Primitive>* prims, double x, double z, double height, uint16_t bark, uint16_t leaves) {
  const double trunk = height * 0.45, radius = height * 0.28;
  prims->push_back(make_cylinder(1, z, x, height * 0.03, 0.0, trunk + 0.3, bark));
  prims->push_back(make_cylinder(1, z, x, radius, trunk, trunk + (height - trunk) * 0.65, leaves));
  prims->push_back(make_cylinder(1, z, x, radius * 0.65, trunk + (height - trunk) * 0.65, height, leaves));
}

void add_lamp_post(std::vector<Primitive>* prims, double x, double z, double height, uint16_t metal) {
  prims->push_back(make_cylinder(1, z, x, 0.07, 0.0, height, metal));
  prims->push_back(make_cylinder(1, z, x, 0.13, 0.0, 0.5, metal));
  prims->push_back(box_at(x, z, 0.16, 0.16, height, height + 0.35, metal));
}

}  // namespace svc::samples::detail
