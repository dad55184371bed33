// SPDX-License-Identifier: BSD-2-Clause
// Procedural architectural scenes written as svc-input databases: the built-in data
// that `svc demo`, the tests and the benchmarks run on.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "svc/status.h"
#include "svc/types.h"

namespace svc::samples {

enum class SceneKind : uint8_t {
  kHall = 0,       // open hall: columns, pipes, textured walls and floor, sky
  kHouse = 1,      // rooms behind walls with doorways
  kStreet = 2,     // a street between facades with windows, balconies, kerbs and lamp posts
  kInterior = 3,   // one furnished room: shelves, chairs, tables and many small objects
  kColonnade = 4,  // a courtyard ringed by a colonnade: rows of columns and arches
  kPlaza = 5,      // an open square with buildings and trees in the distance under the sky
};
inline constexpr int kSceneKinds = 6;

const char* scene_kind_name(SceneKind kind);
bool parse_scene_kind(const std::string& name, SceneKind* out);
// "hall, house, street, ...": every name parse_scene_kind takes.
std::string scene_kind_names();

struct SceneOptions {
  SceneKind kind = SceneKind::kHall;
  std::array<int, 3> grid{9, 1, 9};  // cells along x, y (layers), z
  std::array<double, 3> spacing{0.5, 1.0, 0.5};
  // Centre of cell (0,0,0); the scene is built around the grid wherever it lies. Unset:
  // the grid is centred on the vertical axis, its lowest layer at eye height.
  std::optional<std::array<double, 3>> origin;
  // When set, generate_scene writes one cell (a 1x1x1 grid) whose cameras stand at this
  // world point of the scene the grid, spacing and origin above describe: the view from
  // between the cells of that grid, as a ground truth. A grid of one cell would describe
  // a different scene, since each scene is built around its grid.
  std::optional<std::array<double, 3>> eye;
  int face_size = 256;  // square faces, pixels
  uint32_t seed = 1;    // texture and layout variation
  bool sparse = false;  // drop cells that fall inside solid geometry
  int threads = 1;      // faces rendered at once; the output bytes do not depend on it
  // Photographic variant: a folder of images (searched recursively) mapped onto the
  // surfaces and the sky in place of the procedural patterns; empty for procedural.
  std::filesystem::path textures;
  // Rendering as users' renderers render: n x n colour samples per pixel (depth always
  // from the one ray through the pixel centre), and the exposure in stops above the
  // sample scenes' (daylight renders: about +1).
  int supersample = 1;
  double exposure_stops = 0.0;
  // Texture filtering that keeps detail at grazing angles, as renderers' anisotropic
  // filtering does; and the size of one repeat of each photographic texture, relative
  // to its default (0.5: twice the detail per metre).
  bool anisotropic = false;
  double texture_scale = 1.0;
};

// Checks ranges: grid 1..1024 per axis and at most 1,000,000 cells, spacing finite in
// (0, 100], origin and eye finite, face_size 4..8192, threads 1..256, supersample 1..4,
// exposure_stops in [-4, 4], texture_scale in [0.1, 10]. kInvalidArgument naming the field.
Status validate_scene_options(const SceneOptions& options);

// Where each grid cell falls in the scene the options describe (all cells, sparse or not),
// in the order the manifest lists them (x fastest, then z, then y).
struct SceneCellInfo {
  CellIndex index;
  std::array<double, 3> position{};  // camera centre: origin + index * spacing
  int room = 0;                      // house: room holding the centre; hall: 0; -1 outside
  bool inside_solid = false;         // centre inside geometry: left out of sparse databases
};
Result<std::vector<SceneCellInfo>> describe_scene_cells(const SceneOptions& options);

// One face rendered in memory, exactly as generate_scene writes it.
struct SceneFace {
  ImageRGB8 color;                           // sRGB, row 0 at the top
  std::vector<float> depth;                  // eye-space z, +inf where the ray saw sky
  std::array<double, 16> world_to_camera{};  // column-major OpenGL view matrix
};
Result<SceneFace> render_scene_face(const SceneOptions& options, CellIndex cell, Face face);

// Grid origin, spacing and projection the generator uses, as written to the manifest.
std::array<double, 3> scene_grid_origin(const SceneOptions& options);
inline constexpr double kSceneFovYDegrees = 90.0;
inline constexpr double kSceneNear = 0.05;
inline constexpr double kSceneFar = 100.0;

// Called after each cell is written: (cells done, cells total); returning false stops
// the work (generate_scene then returns kCancelled).
using SceneProgress = std::function<bool(int, int)>;

// Writes manifest.json, PNG color and OpenEXR depth (eye_z, channel "Z") for every
// cell into `out_dir` (created if missing). Deterministic: the same options give the
// same bytes, whatever `threads` is. Files: cells/X_Y_Z/{px,nx,py,ny,pz,nz}.{png,exr};
// the manifest is written last, so a failed run leaves no manifest (what it did write
// stays: write into a staging folder to leave nothing). Errors name the file that could
// not be written. The progress callback runs on the calling thread.
Status generate_scene(const SceneOptions& options, const std::filesystem::path& out_dir,
                      const SceneProgress& progress = {});

}  // namespace svc::samples
