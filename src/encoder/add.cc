// SPDX-License-Identifier: BSD-2-Clause
// svc add: cells of a database appended to an existing .svc file (include/svc/encoder.h).
// What is its own: the compatibility checks, the merge of old and new cells, the types
// and references of new cells, and the crash-safe commit. Coding is the encoder's
// (encoder/coding_pipeline.h), reference choice the placement rules' (spatial/placement.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "common/parallel.h"
#include "database/database.h"
#include "encoder/cell_visibility.h"
#include "encoder/coding_pipeline.h"
#include "output/updater.h"
#include "spatial/placement.h"
#include "svc/encoder.h"

namespace svc {

namespace {

constexpr const char* kAxis[3] = {"x", "y", "z"};

bool cell_less(const CellIndex& a, const CellIndex& b) {
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.x < b.x;
}

std::array<int32_t, 3> key_of(const CellIndex& c) { return {c.x, c.y, c.z}; }

bool nearly_equal(double a, double b, double scale) { return std::abs(a - b) <= 1e-9 * scale; }

Status mismatch(const std::filesystem::path& svc_file, const std::string& what) {
  return Status(ErrorCode::kBadInput, "cannot add to " + svc_file.string() + ": " + what);
}

// Same faces, same conventions, same grid lattice. Returns the grid grown to both.
Result<GridSpec> compatible_grid(const std::filesystem::path& svc_file, const ContainerIndex& old,
                                 const DatabaseManifest& manifest) {
  if (static_cast<uint32_t>(manifest.face_width) != old.face_width ||
      static_cast<uint32_t>(manifest.face_height) != old.face_height) {
    return mismatch(svc_file, "the database's faces are " + std::to_string(manifest.face_width) + "x" +
                                  std::to_string(manifest.face_height) + ", the file's " +
                                  std::to_string(old.face_width) + "x" + std::to_string(old.face_height));
  }
  if (manifest.depth_mode != old.depth_mode) {
    return mismatch(svc_file, "the database's depth mode differs from the file's");
  }
  if (manifest.up_axis != old.up_axis) {
    return mismatch(svc_file, "the database's up axis differs from the file's");
  }
  GridSpec grid = old.grid;
  for (int axis = 0; axis < 3; ++axis) {
    // As the encoder does: an unset spacing (one-cell axis) reads as 1.
    const double spacing = manifest.grid.spacing[axis] > 0 ? manifest.grid.spacing[axis] : 1.0;
    const double scale = std::max(std::abs(spacing), std::abs(old.grid.spacing[axis]));
    if (!nearly_equal(spacing, old.grid.spacing[axis], scale)) {
      return mismatch(svc_file, std::string("grid spacing along ") + kAxis[axis] + " is " +
                                    std::to_string(spacing) + " in the database, " +
                                    std::to_string(old.grid.spacing[axis]) + " in the file");
    }
    if (!nearly_equal(manifest.grid.origin[axis], old.grid.origin[axis],
                      std::max({1.0, std::abs(manifest.grid.origin[axis]), old.grid.spacing[axis]}))) {
      return mismatch(svc_file, std::string("grid origin along ") + kAxis[axis] + " is " +
                                    std::to_string(manifest.grid.origin[axis]) + " in the database, " +
                                    std::to_string(old.grid.origin[axis]) + " in the file");
    }
    grid.dims[axis] = std::max(old.grid.dims[axis], manifest.grid.dims[axis]);
  }
  return grid;
}

// A cell of the merged file and where it came from.
struct UnionCell {
  CellIndex index;
  int64_t old_cell = -1;  // ordinal in the old index
  int64_t source = -1;    // ordinal in the manifest, for new cells
};

// Old cells and the manifest's cells not in the file, in index order (y, z, x).
std::vector<UnionCell> merge_cells(const ContainerIndex& old, const DatabaseManifest& manifest,
                                   AddSummary* summary) {
  std::map<std::array<int32_t, 3>, size_t> old_by_key;
  for (size_t c = 0; c < old.cells.size(); ++c) old_by_key.emplace(key_of(old.cells[c].index), c);
  std::vector<UnionCell> cells;
  cells.reserve(old.cells.size() + manifest.cells.size());
  for (size_t c = 0; c < old.cells.size(); ++c) cells.push_back({old.cells[c].index, static_cast<int64_t>(c), -1});
  for (size_t s = 0; s < manifest.cells.size(); ++s) {
    if (old_by_key.count(key_of(manifest.cells[s].index))) {
      ++summary->cells_present;
      continue;
    }
    cells.push_back({manifest.cells[s].index, -1, static_cast<int64_t>(s)});
  }
  summary->cells_added = cells.size() - old.cells.size();
  std::sort(cells.begin(), cells.end(),
            [](const UnionCell& a, const UnionCell& b) { return cell_less(a.index, b.index); });
  return cells;
}

// Per union cell and face: whether it is an I-face, and a new B-face's references (union
// cell ordinals).
struct NewCellTypes {
  std::vector<std::array<bool, kFaceCount>> intra;
  std::vector<std::array<std::vector<uint32_t>, kFaceCount>> references;
};

// What the cubes see of the new cells, from the database's depth: every union cell the
// database holds (new cells, and old ones it holds again) has samples.
Result<VisibilityTable> new_cell_visibility(const std::vector<UnionCell>& cells, const DatabaseManifest& manifest,
                                            const ContainerIndex& old, int threads) {
  std::vector<CellIndex> indices;
  for (const UnionCell& cell : cells) indices.push_back(cell.index);
  SVC_ASSIGN_OR_RETURN(auto pairs, reach_pairs(indices, old.coding.i_spacing));
  std::erase_if(pairs, [&](const auto& pair) { return cells[pair.first].old_cell >= 0; });
  // Depth is loaded only for the cells the pairs name.
  std::vector<std::optional<size_t>> sources(cells.size());
  for (const auto& [cell, reference] : pairs) {
    for (uint32_t c : {cell, reference}) {
      sources[c] = cells[c].source >= 0 ? std::optional<size_t>(static_cast<size_t>(cells[c].source))
                                        : find_cell(manifest, cells[c].index);
    }
  }
  return measure_visibility(manifest, sources, pairs, threads);
}

// The references of a new B-face among `candidates`: the pair that sees most when the
// table knows what each of them sees of the cell, else the nearest two.
std::vector<uint32_t> new_cell_references(const UnionCell& cell, uint32_t ordinal,
                                          const std::vector<ReferenceCandidate>& candidates, const GridSpec& grid,
                                          const VisibilityTable& table) {
  for (const ReferenceCandidate& candidate : candidates) {
    if (!table.has(ordinal, candidate.id)) return nearest_references(cell.index, candidates, grid.spacing);
  }
  return visible_references(cell.index, candidates, grid.spacing, [&](uint32_t first, uint32_t second) {
    return table.seen_by_either(ordinal, first, second);
  });
}

// Existing cells keep their types; a new cell takes the type the placement rules give
// it over the union (the regular lattice), and becomes an I-cube when a face has no
// I-face in reach; a new B-face's references are chosen by new_cell_references. New
// I-cubes can give later cells references, so this repeats until nothing changes (each
// round only turns B-cubes into I-cubes, so it ends).
Result<NewCellTypes> type_new_cells(const std::vector<UnionCell>& cells, const ContainerIndex& old,
                                    const GridSpec& grid, const VisibilityTable& table) {
  std::vector<CellIndex> indices;
  for (const UnionCell& cell : cells) indices.push_back(cell.index);
  PlacementSettings placement_settings;
  placement_settings.i_spacing = old.coding.i_spacing;
  SVC_ASSIGN_OR_RETURN(std::vector<CellPlacement> placement,
                       place_cubes(indices, grid.dims, placement_settings, grid.spacing));
  NewCellTypes types;
  types.intra.resize(cells.size());
  types.references.resize(cells.size());
  for (size_t c = 0; c < cells.size(); ++c) {
    for (int f = 0; f < kFaceCount; ++f) {
      types.intra[c][f] = cells[c].old_cell >= 0
                              ? old.frames[static_cast<size_t>(cells[c].old_cell) * kFaceCount + f].type ==
                                    FaceType::kIntra
                              : placement[c].intra;
    }
  }
  for (bool changed = true; changed;) {
    changed = false;
    // Old I-faces of one direction need not lie in the same cells as another's.
    std::vector<ReachIndex> reach(kFaceCount, ReachIndex(old.coding.i_spacing));
    for (size_t c = 0; c < cells.size(); ++c) {
      for (int f = 0; f < kFaceCount; ++f) {
        if (types.intra[c][f]) reach[f].add({cells[c].index, static_cast<uint32_t>(c)});
      }
    }
    for (size_t c = 0; c < cells.size(); ++c) {
      if (cells[c].old_cell >= 0 || types.intra[c][0]) continue;
      bool every_face_has_one = true;
      for (int f = 0; f < kFaceCount; ++f) {
        types.references[c][f] =
            new_cell_references(cells[c], static_cast<uint32_t>(c), reach[f].in_reach(cells[c].index), grid, table);
        if (types.references[c][f].empty()) every_face_has_one = false;
      }
      if (!every_face_has_one) {
        types.intra[c].fill(true);
        for (auto& refs : types.references[c]) refs.clear();
        changed = true;
      }
    }
  }
  return types;
}

// The merged index: old frames renumbered with their cells, new frames typed and
// referenced but not coded yet.
Result<ContainerIndex> merged_index(const ContainerIndex& old, const std::vector<UnionCell>& cells,
                                    const DatabaseManifest& manifest, const GridSpec& grid,
                                    const NewCellTypes& types) {
  std::vector<uint32_t> new_cell_of_old(old.cells.size());
  for (size_t c = 0; c < cells.size(); ++c) {
    if (cells[c].old_cell >= 0) new_cell_of_old[static_cast<size_t>(cells[c].old_cell)] = static_cast<uint32_t>(c);
  }
  ContainerIndex index;
  index.face_width = old.face_width;
  index.face_height = old.face_height;
  index.grid = grid;
  index.depth_mode = old.depth_mode;
  index.up_axis = old.up_axis;
  index.coding = old.coding;
  index.depth = old.depth;
  index.depth_max_error = old.depth_max_error;
  index.stats = old.stats;
  index.cells.resize(cells.size());
  index.cameras.resize(cells.size());
  index.frames.resize(cells.size() * kFaceCount);
  for (size_t c = 0; c < cells.size(); ++c) {
    CellRecord& record = index.cells[c];
    if (cells[c].old_cell >= 0) {
      record = old.cells[static_cast<size_t>(cells[c].old_cell)];
      index.cameras[c] = old.cameras[static_cast<size_t>(cells[c].old_cell)];
      for (int f = 0; f < kFaceCount; ++f) {
        FrameRecord frame = old.frames[static_cast<size_t>(cells[c].old_cell) * kFaceCount + f];
        frame.cell = static_cast<uint32_t>(c);
        for (uint32_t& ref : frame.references) {
          ref = new_cell_of_old[ref / kFaceCount] * kFaceCount + ref % kFaceCount;
        }
        index.frames[c * kFaceCount + f] = std::move(frame);
      }
      continue;
    }
    SVC_ASSIGN_OR_RETURN(const CellSource source, read_cell(manifest, static_cast<size_t>(cells[c].source)));
    record.index = source.index;
    record.position = source.position;
    for (int f = 0; f < kFaceCount; ++f) {
      index.cameras[c][f] = source.faces[f].camera;
      FrameRecord& frame = index.frames[c * kFaceCount + f];
      frame.cell = static_cast<uint32_t>(c);
      frame.face = static_cast<Face>(f);
      frame.type = types.intra[c][f] ? FaceType::kIntra : FaceType::kPredicted;
      for (uint32_t ref_cell : types.references[c][f]) {
        frame.references.push_back(ref_cell * kFaceCount + static_cast<uint32_t>(f));
      }
    }
  }
  return index;
}

}  // namespace

Result<AddSummary> add_to_database(const std::filesystem::path& svc_file, const std::filesystem::path& db_dir,
                                   const AddSettings& settings, const EncodeProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (settings.threads < 0 || settings.threads > 1024) {
    return Status(ErrorCode::kInvalidArgument,
                  "thread count " + std::to_string(settings.threads) + " is outside 0..1024");
  }
  SVC_ASSIGN_OR_RETURN(auto updater, ContainerUpdater::open(svc_file));
  // Measured once open has cut off what an interrupted update left, before any face is
  // appended: the growth from here is what this add wrote.
  std::error_code size_error;
  const uint64_t size_before = std::filesystem::file_size(svc_file, size_error);
  if (size_error) return Status(ErrorCode::kIoError, "cannot read the size of " + svc_file.string());
  const ContainerIndex& old = updater->committed().index;
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest,
                       load_manifest(db_dir, ManifestOptions{settings.allow_outside_paths}));
  if (manifest.cells.empty()) {
    return Status(ErrorCode::kBadInput, (manifest.root / "manifest.json").string() + " lists no cells");
  }
  SVC_ASSIGN_OR_RETURN(GridSpec grid, compatible_grid(svc_file, old, manifest));

  AddSummary summary;
  summary.cells_before = old.cells.size();
  const std::vector<UnionCell> cells = merge_cells(old, manifest, &summary);
  summary.grid_dims = old.grid.dims;
  summary.generation = updater->committed().generation;
  summary.file_bytes = size_before;
  if (summary.cells_added == 0) return summary;  // nothing to do: the file is not touched

  const ReaderLimits limits;
  if (cells.size() > limits.max_cells) {
    return mismatch(svc_file, std::to_string(cells.size()) + " cells would exceed the reader's limit of " +
                                  std::to_string(limits.max_cells));
  }
  SVC_ASSIGN_OR_RETURN(VisibilityTable visibility,
                       new_cell_visibility(cells, manifest, old, resolve_thread_count(settings.threads)));
  SVC_ASSIGN_OR_RETURN(NewCellTypes types, type_new_cells(cells, old, grid, visibility));
  SVC_ASSIGN_OR_RETURN(ContainerIndex index, merged_index(old, cells, manifest, grid, types));

  CodingJob job;
  job.index = &index;
  for (size_t c = 0; c < cells.size(); ++c) {
    if (cells[c].old_cell >= 0) continue;
    for (int f = 0; f < kFaceCount; ++f) {
      FrameRecord& frame = index.frames[c * kFaceCount + f];
      frame.cube_references = frame.type == FaceType::kPredicted && uses_cube_references(index, job.tools);
      job.frames.push_back(static_cast<uint32_t>(c * kFaceCount + f));
    }
    (types.intra[c][0] ? summary.intra_cells_added : summary.predicted_cells_added) += 1;
  }
  job.trial_frames = trial_frames(index, job.frames);  // only the new cells' sources are at hand
  job.load = [&](uint32_t frame) {
    const size_t source = static_cast<size_t>(cells[frame / kFaceCount].source);
    return load_face(manifest, source, static_cast<Face>(frame % kFaceCount));
  };
  job.camera = [&](uint32_t frame) -> Result<Camera> {
    return index.cameras[frame / kFaceCount][frame % kFaceCount];
  };
  job.append = [&](std::span<const uint8_t> payload) { return updater->append_frame(payload); };
  // Old references are read from the file too: decoding gives the encoder's reconstruction.
  job.open_written = [&] { return ReadOnlyFile::open(svc_file); };
  job.threads = resolve_thread_count(settings.threads);
  job.action = "add";
  job.progress = progress;
  SVC_RETURN_IF_ERROR(code_faces(job));

  SVC_RETURN_IF_ERROR(updater->commit(index));
  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(svc_file, ec);
  summary.bytes_appended = summary.file_bytes > size_before ? summary.file_bytes - size_before : 0;
  summary.faces_added = job.frames.size();
  summary.generation = updater->committed().generation + 1;
  summary.grid_dims = grid.dims;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
