// SPDX-License-Identifier: BSD-2-Clause
// The built scene: primitives, materials, rooms and lights of a hall or a house, sized
// to the grid of SceneOptions. Internal to svc_scene. A Scene is immutable once built and
// may be rendered from several threads at once.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_geometry.h"
#include "scene/scene_texture.h"

namespace svc::samples::detail {

enum class Pattern : uint8_t {
  kTiles,     // square tiles with grout lines
  kBricks,    // running-bond bricks with mortar
  kPlanks,    // wooden planks of random length, grain along u
  kConcrete,  // cast concrete with formwork panel joints
  kPlaster,   // painted plaster: soft blotches and fine grain
  kStripes,   // striped wallpaper (stripes along v)
  kMetal,     // painted metal with joints every few metres along u
  kGround,    // grass and earth outside
  kPanels,    // ceiling panels in a thin frame grid
  kPaving,    // stone setts or paving slabs in rows
  kFabric,    // woven cloth: upholstery, rugs, curtains
  kLeaves,    // foliage seen as a mass of leaves
  kGlass,     // window glass: dark, with a faint sky reflection towards the top
};

struct Material {
  Pattern pattern = Pattern::kPlaster;
  Vec3 base{0.5};          // linear albedo
  Vec3 second{0.3};        // grout, mortar, gap, second stripe or earth color
  double scale = 1;        // element size in metres (tile, brick length, plank width, period)
  double variation = 0.1;  // per-element brightness variation
  uint32_t seed = 0;
  // Photographic scenes: index into Scene::textures (-1: the procedural pattern), the
  // size in metres of one repeat of the image, and a gain that brings the image's mean
  // brightness near the procedural material's, which the lighting is balanced for.
  int texture = -1;
  double texture_metres = 1;
  double texture_gain = 1;
};

// Material ids resolved by the room the surface faces (house walls, floor, ceiling).
inline constexpr uint16_t kRoomWall = 0xFFF0;
inline constexpr uint16_t kRoomFloor = 0xFFF1;
inline constexpr uint16_t kRoomCeiling = 0xFFF2;

struct Room {
  uint16_t wall = 0, floor = 0, ceiling = 0;
  bool has_lamp = false;
  Vec3 lamp{0.0};
  double ambient = 0.3;  // sky light reaching the room
};

struct Scene {
  SceneKind kind = SceneKind::kHall;
  std::vector<Material> materials;
  Bvh bvh;
  // An infinite ground plane outside the building (not in the BVH).
  double ground_y = -0.02;
  uint16_t ground_material = 0;
  Vec3 sun_dir{0.0, 1.0, 0.0};  // unit, towards the sun
  Vec3 sun_color{1.0};
  double ambient_outdoor = 0.55;
  double ambient_indoor = 0.3;

  // House rooms: an rx x rz arrangement split at interior wall centre lines.
  double lo_x = 0, hi_x = 0, lo_z = 0, hi_z = 0;  // interior bounds of the building
  std::vector<double> cuts_x, cuts_z;             // ascending
  std::vector<Room> rooms;                        // index rz * rooms_x + rx
  uint16_t exterior_wall = 0;

  // Photographic scenes: the images materials refer to, their file names relative to
  // the texture folder, and the image shown over the sky (-1: procedural clouds).
  std::vector<Texture> textures;
  std::vector<std::string> texture_names;
  int sky_texture = -1;
  double sky_texture_gain = 1;

  // Grid the scene was built around.
  Vec3 origin{0.0}, spacing{1.0};
  std::array<int, 3> dims{1, 1, 1};

  Vec3 cell_position(int ix, int iy, int iz) const { return origin + Vec3(ix, iy, iz) * spacing; }
  // Room holding (x, z), or -1 outside the building; the hall and the interior are one room
  // (0); the street, colonnade and plaza lie outdoors (-1 everywhere).
  int room_at(double x, double z) const;
};

// Builds the scene for validated options.
Scene build_scene(const SceneOptions& options);

}  // namespace svc::samples::detail
