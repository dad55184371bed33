// SPDX-License-Identifier: BSD-2-Clause
// svc-input databases (docs/input-format.md): the manifest and the faces it names.
//
// Error behaviour: nothing here throws. Problems with the database's content (bad JSON,
// a missing or ill-typed key, an out-of-range value, an image of the wrong size or an
// unreadable image) come back as ErrorCode::kBadInput, a manifest version other than 1 as
// kUnsupported, sizes above the caps below as kLimitExceeded, missing files or
// directories as kNotFound, and files the operating system refuses to read as kIoError.
// Messages name the manifest file, the cell ("cell (x,y,z)"), the face and the file.
//
// Threading: load_manifest, read_cell and load_face keep no shared mutable state; any
// number of threads may call read_cell and load_face on the same manifest at once (each
// call opens its own manifest stream and OpenImageIO ImageInput; OpenImageIO's shared
// ImageCache is not used).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "container/grid.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

// Caps on untrusted input, checked before anything is allocated from them.
inline constexpr int kMaxFaceSide = 16384;         // face_size[0], face_size[1]
inline constexpr int64_t kMaxGridCells = 1 << 24;  // dims[0] * dims[1] * dims[2]
inline constexpr int kMaxImageChannels = 4096;     // channels in one color/depth file

struct FaceSource {
  std::string color_path;  // relative to the database root (or absolute), as the manifest names it
  std::string depth_path;
  Camera camera;  // view matrix and frustum (per-face or global projection)
};

// Bit (1 << face) set: the cell lists that face (all six unless ManifestOptions::
// allow_partial_cells).
inline constexpr uint8_t kAllFacesListed = (1 << kFaceCount) - 1;
inline bool lists_face(uint8_t listed_faces, Face face) {
  return (listed_faces >> static_cast<int>(face) & 1) != 0;
}

struct CellSource {
  CellIndex index;
  std::array<double, 3> position{0, 0, 0};
  std::array<FaceSource, kFaceCount> faces;  // indexed by Face; empty paths where not listed
  uint8_t listed_faces = kAllFacesListed;
};

// A listed cell as the manifest keeps it: its index, its position, and where its entry
// lies in manifest.json. Its face sources (paths, cameras) are read again from there when
// needed (read_cell) rather than held, so a manifest costs a few bytes a cell however
// large the database.
struct ManifestCell {
  CellIndex index;
  uint32_t listed_at = 0;  // position in the manifest's "cells" array
  std::array<double, 3> position{0, 0, 0};
  uint64_t entry_offset = 0;  // of the cell's JSON object in manifest.json
  uint64_t entry_size = 0;    // its bytes, braces included
  uint8_t listed_faces = kAllFacesListed;
};

struct DatabaseManifest {
  std::filesystem::path root;           // the database directory
  std::filesystem::path manifest_file;  // manifest.json (or the file given)
  GridSpec grid;
  int face_width = 0;
  int face_height = 0;
  DepthMode depth_mode = DepthMode::kEyeZ;
  UpAxis up_axis = UpAxis::kY;
  std::optional<Frustum> projection;  // the global projection, when the manifest has one
  std::vector<ManifestCell> cells;    // sorted by (y, z, x) cell index, no duplicates
};

// A face whose files fail load_manifest's file checks (outside the folder, missing).
struct FaceFileProblem {
  CellIndex cell;
  Face face = Face::kPX;
  Status status;
};

struct ManifestOptions {
  // Face files may lie outside the database folder (absolute paths, "../"). Off by
  // default: a manifest from elsewhere must not pull arbitrary files into an .svc file.
  bool allow_outside_paths = false;
  // A cell may list some of its six faces (what `svc decode --face` writes); the encoder
  // codes whole cubes and leaves this off. A cell listing none is refused either way.
  bool allow_partial_cells = false;
  // When given, every face whose files fail the file checks is appended here, in cell
  // order then face order, and the load goes on; otherwise the first such face ends the
  // load with its error.
  std::vector<FaceFileProblem>* file_problems = nullptr;
};

// Reads and validates manifest.json: JSON syntax (errors give line and column), required
// keys, value ranges, cell indices inside the grid and unique, all six faces present
// (some of them, with options.allow_partial_cells),
// finite view matrices whose last row is (0,0,0,1) and whose rotation part is orthonormal
// (within 1e-3), valid frusta, referenced files exist and lie inside the database folder
// (unless options.allow_outside_paths; a path that leaves it is kBadInput). Keys the
// format does not describe are ignored. `db_dir` is the database directory; a path to
// the manifest file itself is accepted too (the root is then its parent directory). An
// empty cell list is rejected.
// The file is read as a stream, twice (the keys other than the cells, then the cells one
// at a time): memory holds one cell's entry at a time, never the whole document. Each
// cell's full sources go to `visit_cell`, when given, once, in the manifest's order
// (`listed_at` of `cells_listed`) and before the checks across cells (duplicates,
// files); an error it returns ends the load with that error.
using CellVisitor = std::function<Status(const CellSource& cell, size_t listed_at, size_t cells_listed)>;
Result<DatabaseManifest> load_manifest(const std::filesystem::path& db_dir, const ManifestOptions& options = {},
                                       const CellVisitor& visit_cell = {});

// The full sources of manifest.cells[cell_ordinal], read again from its entry in
// manifest.json. A cell_ordinal out of range is kInvalidArgument; an entry that no longer
// reads as that cell (the file changed since load_manifest) is kBadInput naming the cell
// and the offset. Thread-safe: each call opens the file on its own.
Result<CellSource> read_cell(const DatabaseManifest& manifest, size_t cell_ordinal);

// One face's pixels. Depth is converted to eye-space z (distance along the view axis,
// positive); pixels that saw no geometry (+inf, NaN, <= 0, >= far) hold +infinity.
struct FaceData {
  ImageRGB8 color;
  std::vector<float> depth;  // width * height, row 0 at the top
};

// Loads color and depth of one face of manifest.cells[cell_ordinal] (read_cell, then the
// overload below).
// Color: channels R, G, B by name (or "<layer>.R/G/B"), else the first three channels;
// a one- or two-channel image (grey, grey + alpha) is grey, expanded to RGB; other
// channels are ignored. 8-bit values are taken as they are; other integer types are
// rescaled to 8 bits with rounding (still display values); half/float/double are linear
// and converted to 8-bit sRGB (exact sRGB curve, clamped, rounded).
// Depth: channel "Z", else any "*.Z", else "depth", else "Y", else the only channel of a
// one-channel image; it must be half, float or double. In radial mode each value is
// turned into eye z along the pixel centre's ray through the face frustum; the
// background test (inf, NaN, <= 0, eye z >= far) is made after that conversion.
// A cell_ordinal or face out of range, or a face the cell does not list, is
// kInvalidArgument. Thread-safe.
Result<FaceData> load_face(const DatabaseManifest& manifest, size_t cell_ordinal, Face face);
// The same for a cell whose sources the caller has read already. Thread-safe.
Result<FaceData> load_face(const DatabaseManifest& manifest, const CellSource& cell, Face face);
// The depth of load_face alone, without reading or converting the color (unless the
// two share a file): for passes that look at geometry only. Same errors for the depth
// file. Thread-safe.
Result<std::vector<float>> load_face_depth(const DatabaseManifest& manifest, const CellSource& cell, Face face);

// The color of load_face alone, without reading the depth (unless the two share a
// file): what a color-only codec reads. Same errors for the color file. Thread-safe.
Result<ImageRGB8> load_face_color(const DatabaseManifest& manifest, size_t cell_ordinal, Face face);

// Sets OpenImageIO's process-wide reading options that suit load_face: OpenEXR files
// decoded on the calling thread (the loaders run on the caller's workers; OpenEXR's
// pool only adds hand-offs for faces this small) and through OpenEXR's core library
// (the same values, float depth in less than half the time). Loading works without it;
// the svc tools call it once at start-up. It changes every OpenImageIO reader of the
// process, so an application embedding the loaders decides whether to call it.
// Not thread-safe against reads running at the same time.
void configure_image_loading();

// Where a manifest path lives on disk: absolute paths as they are, relative paths under
// manifest.root.
std::filesystem::path resolve_database_path(const DatabaseManifest& manifest, const std::string& manifest_path);

// Ordinal of the cell with this index in manifest.cells, or nullopt for a hole in the grid.
std::optional<size_t> find_cell(const DatabaseManifest& manifest, const CellIndex& index);

// The sRGB transfer function applied to a linear value, clamped to [0,1] (NaN -> 0) and
// rounded to 8 bits: the conversion load_face uses for float color.
uint8_t linear_to_srgb8(float linear) noexcept;

// Symmetric glFrustum for a vertical field of view and aspect = width / height.
Frustum symmetric_frustum(double fov_y_degrees, double aspect, double near_plane, double far_plane) noexcept;

}  // namespace svc
