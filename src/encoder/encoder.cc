// SPDX-License-Identifier: BSD-2-Clause
#include "svc/encoder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "codec/common/bframe.h"
#include "codec/common/cube_padding.h"
#include "codec/common/depth.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/syntax_account.h"
#include "common/parallel.h"
#include "database/database.h"
#include "encoder/cell_visibility.h"
#include "encoder/coding_pipeline.h"
#include "encoder/encode_plan.h"
#include "output/writer.h"
#include "reader/shared_cache.h"
#include "spatial/placement.h"

namespace svc {

namespace {

Status validate_settings(const EncoderSettings& settings) {
  if (settings.qindex < 0 && (settings.quality < 1 || settings.quality > 100)) {
    return Status(ErrorCode::kInvalidArgument,
                  "quality " + std::to_string(settings.quality) + " is outside 1..100");
  }
  if (settings.qindex < -1 || settings.qindex > codec::kMaxQIndex) {
    return Status(ErrorCode::kInvalidArgument, "quantizer index " + std::to_string(settings.qindex) +
                                                   " is outside " + std::to_string(codec::kMinQIndex) + ".." +
                                                   std::to_string(codec::kMaxQIndex) + " (or -1 for the quality)");
  }
  if (settings.b_qindex_offset < -1 || settings.b_qindex_offset > codec::kMaxQIndex) {
    return Status(ErrorCode::kInvalidArgument,
                  "B-face quantizer offset " + std::to_string(settings.b_qindex_offset) + " is outside 0.." +
                      std::to_string(codec::kMaxQIndex) + " (or -1 to choose it per database)");
  }
  if (settings.cube_border_units < 1 || settings.cube_border_units > codec::kMaxCubeBorderUnits) {
    return Status(ErrorCode::kInvalidArgument, "cube border of " + std::to_string(settings.cube_border_units) +
                                                   " units is outside 1.." +
                                                   std::to_string(codec::kMaxCubeBorderUnits));
  }
  if (settings.threads < 0 || settings.threads > 1024) {
    return Status(ErrorCode::kInvalidArgument,
                  "thread count " + std::to_string(settings.threads) + " is outside 0..1024");
  }
  for (int32_t s : settings.i_spacing) {
    if (s < 1 || s > 1024) {
      return Status(ErrorCode::kInvalidArgument, "I-cube spacing " + std::to_string(s) + " is outside 1..1024");
    }
  }
  if (settings.depth_max_error < 0 || settings.depth_max_error > codec::kMaxDepthError) {
    return Status(ErrorCode::kInvalidArgument,
                  "depth maximum error " + std::to_string(settings.depth_max_error) + " is outside 0..255");
  }
  return Status::Ok();
}

PlacementSettings placement_settings_of(const EncoderSettings& settings) {
  PlacementSettings placement;
  placement.i_spacing = settings.intra_only ? std::array<int32_t, 3>{1, 1, 1} : settings.i_spacing;
  const bool intra_only = placement.i_spacing == std::array<int32_t, 3>{1, 1, 1};
  placement.layout = settings.layout == CubeLayout::kVisibility && !intra_only ? Layout::kVisibility
                                                                               : Layout::kRegular;
  placement.visibility_references = settings.tools.visibility_references && !intra_only;
  return placement;
}

// The pairs whose reference `wanted` accepts.
template <typename Wanted>
std::vector<std::pair<uint32_t, uint32_t>> pairs_to(const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                                                    Wanted wanted) {
  std::vector<std::pair<uint32_t, uint32_t>> kept;
  for (const auto& pair : pairs) {
    if (wanted(pair.second)) kept.push_back(pair);
  }
  return kept;
}

// Which cells are I-cubes, and the references of every B-cube.
Result<std::vector<CellPlacement>> place_database(const DatabaseManifest& manifest,
                                                  const PlacementSettings& settings, int threads) {
  std::vector<CellIndex> cells;
  for (const ManifestCell& source : manifest.cells) cells.push_back(source.index);
  if (settings.layout == Layout::kRegular && !settings.visibility_references) {
    return place_cubes(cells, manifest.grid.dims, settings, manifest.grid.spacing);
  }
  std::vector<std::optional<size_t>> sources(cells.size());
  for (size_t c = 0; c < cells.size(); ++c) sources[c] = c;
  VisibilityMeter meter(manifest, std::move(sources), threads, reference_cache_bytes());
  VisibilityTable table = meter.empty_table();
  // First what the lattice's I-cubes see, then, for the cells in reach of a cell that
  // could become an I-cube, what the lattice and those cells see: most cells never can,
  // and their pairs would cost most of the time.
  SVC_ASSIGN_OR_RETURN(const auto pairs, reach_pairs(cells, settings.i_spacing));
  PlacementSettings regular;
  regular.i_spacing = settings.i_spacing;
  SVC_ASSIGN_OR_RETURN(const auto lattice, place_cubes(cells, manifest.grid.dims, regular, manifest.grid.spacing));
  SVC_RETURN_IF_ERROR(meter.measure(pairs_to(pairs, [&](uint32_t k) { return lattice[k].intra; }), &table));
  if (settings.layout == Layout::kVisibility) {
    SVC_ASSIGN_OR_RETURN(const auto candidates,
                         layout_candidates(cells, manifest.grid.dims, settings, manifest.grid.spacing, table));
    std::vector<uint8_t> is_candidate(cells.size(), 0), near_candidate(cells.size(), 0);
    for (uint32_t k : candidates) is_candidate[k] = 1;
    for (const auto& [cell, reference] : pairs) near_candidate[cell] |= is_candidate[reference];
    // The table keeps counts, not what each reference sees, so a cell measured again
    // is measured with every reference it may need.
    std::vector<std::pair<uint32_t, uint32_t>> again;
    for (const auto& pair : pairs) {
      if (near_candidate[pair.first] && (lattice[pair.second].intra || is_candidate[pair.second]))
        again.push_back(pair);
    }
    SVC_RETURN_IF_ERROR(meter.measure(again, &table));
  }
  return place_cubes(cells, manifest.grid.dims, settings, manifest.grid.spacing, &table);
}

// Every frame's type and references, from the placement of the database's cubes.
Status plan_frames(const DatabaseManifest& manifest, const EncoderSettings& settings, ContainerIndex& index) {
  const PlacementSettings placement_settings = placement_settings_of(settings);
  index.coding.i_spacing = placement_settings.i_spacing;
  SVC_ASSIGN_OR_RETURN(std::vector<CellPlacement> placement,
                       place_database(manifest, placement_settings, resolve_thread_count(settings.threads)));
  index.frames.resize(manifest.cells.size() * kFaceCount);
  for (size_t cell = 0; cell < manifest.cells.size(); ++cell) {
    for (int f = 0; f < kFaceCount; ++f) {
      FrameRecord& record = index.frames[cell * kFaceCount + f];
      record.cell = static_cast<uint32_t>(cell);
      record.face = static_cast<Face>(f);
      record.type = placement[cell].intra ? FaceType::kIntra : FaceType::kPredicted;
      for (uint32_t ref_cell : placement[cell].references)
        record.references.push_back(ref_cell * kFaceCount + static_cast<uint32_t>(f));
      record.cube_references = record.type == FaceType::kPredicted && uses_cube_references(index, settings.tools);
    }
  }
  return Status::Ok();
}

// Placement's sampled depth and pair tables (some hundred bytes a cell) are freed by
// now, but the allocator keeps the pages; coding allocates on other threads' heaps and
// would not reuse them. Handing them back keeps them out of the coding's peak.
void return_freed_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

// The manifest entries (face files and cameras) of the cells coded lately, in the
// pipeline's cache type. Each of a cell's faces, as it loads, and every B-face using its
// cameras (its own and its references') needs the cell's entry, which was otherwise
// parsed again for each. 32 cells hold a B-cube and its two reference cubes for a few
// cubes coded side by side.
using CellSourceCache = reader_internal::SharedCache<CellSource>;
// Its budget: 32 cells, each path counted at 128 bytes.
constexpr uint64_t kCachedCellBytes =
    32 * (sizeof(CellSource) + 2 * kFaceCount * 128 + CellSourceCache::kEntryOverhead);

uint64_t cell_source_bytes(const CellSource& cell) {
  uint64_t bytes = sizeof(CellSource);
  for (const FaceSource& face : cell.faces) bytes += face.color_path.capacity() + face.depth_path.capacity();
  return bytes;
}

}  // namespace

EncoderSettings default_encoder_settings() { return EncoderSettings{}; }

int qindex_for_quality(int quality) {
  // The index is logarithmic in the step, so an even spread gives every quality step the
  // same relative change of step size. Integer rounding half up, the same on every machine.
  const int steps_from_best = 100 - std::clamp(quality, 1, 100);
  return (steps_from_best * codec::kMaxQIndex * 2 + 99) / (2 * 99);
}

Result<EncodePlan> plan_encode(const std::filesystem::path& db_dir, const EncoderSettings& settings) {
  SVC_RETURN_IF_ERROR(validate_settings(settings));
  EncodePlan plan;
  SVC_ASSIGN_OR_RETURN(plan.manifest, load_manifest(db_dir, ManifestOptions{settings.allow_outside_paths}));
  DatabaseManifest& manifest = plan.manifest;
  if (manifest.cells.empty()) {
    return Status(ErrorCode::kBadInput, (manifest.root / "manifest.json").string() + " lists no cells");
  }
  // The index holds no cameras: they stay in the manifest, read again when a face is
  // coded and when the index is written (cell_cameras).
  ContainerIndex& index = plan.index;
  index.cells.reserve(manifest.cells.size());
  for (const ManifestCell& cell : manifest.cells) index.cells.push_back({cell.index, cell.position});
  const int qindex = settings.qindex >= 0 ? settings.qindex : qindex_for_quality(settings.quality);
  index.face_width = static_cast<uint32_t>(manifest.face_width);
  index.face_height = static_cast<uint32_t>(manifest.face_height);
  index.grid = manifest.grid;
  // A manifest may leave the spacing of a one-cell axis at 0; distances along it never
  // matter, and the container wants every spacing positive.
  for (int axis = 0; axis < 3; ++axis) {
    if (!(manifest.grid.spacing[axis] > 0)) manifest.grid.spacing[axis] = index.grid.spacing[axis] = 1.0;
  }
  index.depth_mode = manifest.depth_mode;
  index.up_axis = manifest.up_axis;
  index.coding.quality = settings.qindex >= 0 ? 0 : static_cast<uint32_t>(settings.quality);
  index.coding.qindex = static_cast<uint32_t>(qindex);
  index.coding.motion = settings.motion;
  index.depth = settings.depth;
  index.depth_max_error = settings.depth ? settings.depth_max_error : 0;

  SVC_RETURN_IF_ERROR(plan_frames(manifest, settings, index));
  return_freed_memory();
  return plan;
}

Status code_planned_frames(EncodePlan& plan, std::vector<uint32_t> frames, const FaceSink& sink,
                           const EncoderSettings& settings, const EncodeProgress& progress) {
  CodingJob job;
  job.index = &plan.index;
  job.frames = std::move(frames);
  // From the whole database, so that every part of a sharded encode chooses alike.
  std::vector<uint32_t> all(plan.index.frames.size());
  std::iota(all.begin(), all.end(), 0u);
  job.trial_frames = trial_frames(plan.index, all);
  job.b_qindex_offset = settings.b_qindex_offset;
  job.cube_border_units = settings.cube_border_units;
  CellSourceCache cells(kCachedCellBytes, &cell_source_bytes);
  const auto cell_of = [&](uint32_t frame) {
    const uint32_t cell = frame / kFaceCount;
    return cells.get(cell, reader_internal::Origin::kCaller, [&]() -> Result<CellSourceCache::Pointer> {
      SVC_ASSIGN_OR_RETURN(CellSource parsed, read_cell(plan.manifest, cell));
      return std::make_shared<const CellSource>(std::move(parsed));
    });
  };
  job.load = [&](uint32_t frame) -> Result<FaceData> {
    SVC_ASSIGN_OR_RETURN(const CellSourceCache::Pointer cell, cell_of(frame));
    return load_face(plan.manifest, *cell, static_cast<Face>(frame % kFaceCount));
  };
  job.camera = [&](uint32_t frame) -> Result<Camera> {
    SVC_ASSIGN_OR_RETURN(const CellSourceCache::Pointer cell, cell_of(frame));
    return cell->faces[frame % kFaceCount].camera;
  };
  job.tools = settings.tools;
  job.append = sink.append;
  job.open_written = sink.open_written;
  job.threads = resolve_thread_count(settings.threads);
  job.progress = progress;
  SVC_RETURN_IF_ERROR(code_faces(job));
  plan.prediction += job.prediction;
  if (job.b_qindex >= 0) plan.b_qindex = job.b_qindex;
  for (size_t t = 0; t < 2; ++t) plan.syntax[t] += job.syntax[t];
  return Status::Ok();
}

Result<CellCameras> cell_cameras(const DatabaseManifest& manifest, size_t cell) {
  SVC_ASSIGN_OR_RETURN(const CellSource source, read_cell(manifest, cell));
  CellCameras cameras;
  for (int f = 0; f < kFaceCount; ++f) cameras[f] = source.faces[f].camera;
  return cameras;
}

static_assert(kSyntaxElementCount == codec::kSyntaxElements);

std::vector<std::string> syntax_element_names() {
  std::vector<std::string> names;
  for (size_t e = 0; e < kSyntaxElementCount; ++e)
    names.emplace_back(codec::syntax_element_name(static_cast<codec::SyntaxElement>(e)));
  return names;
}

PredictionSummary& PredictionSummary::operator+=(const PredictionSummary& other) {
  mb_leaving_face += other.mb_leaving_face;
  mb_warp += other.mb_warp;
  for (size_t k = 0; k < 2; ++k) {
    screened_sse[k] += other.screened_sse[k];
    screened_pixels[k] += other.screened_pixels[k];
  }
  return *this;
}

EncodeSummary summarize_encode(const EncodePlan& plan, uint64_t frames) {
  EncodeSummary summary;
  summary.cells = plan.index.cells.size();
  summary.faces = frames;
  summary.qindex = static_cast<int>(plan.index.coding.qindex);
  summary.raw_bytes = uint64_t{3} * plan.index.face_width * plan.index.face_height * frames;
  summary.intra = plan.index.stats[0];
  summary.predicted = plan.index.stats[1];
  summary.prediction = plan.prediction;
  summary.b_qindex = plan.b_qindex;
  for (size_t e = 0; e < kSyntaxElementCount; ++e) {
    summary.intra_syntax_bytes[e] = plan.syntax[0].bits[e] / 8;
    summary.predicted_syntax_bytes[e] = plan.syntax[1].bits[e] / 8;
  }
  return summary;
}

Result<EncodeSummary> encode_database(const std::filesystem::path& db_dir, const std::filesystem::path& out_path,
                                      const EncoderSettings& settings, const EncodeProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  SVC_ASSIGN_OR_RETURN(EncodePlan plan, plan_encode(db_dir, settings));
  SVC_ASSIGN_OR_RETURN(auto writer, ContainerWriter::create(out_path));
  std::vector<uint32_t> frames(plan.index.frames.size());
  for (size_t frame = 0; frame < frames.size(); ++frame) frames[frame] = static_cast<uint32_t>(frame);
  FaceSink sink;
  sink.append = [&](std::span<const uint8_t> payload) { return writer->append_frame(payload); };
  sink.open_written = [&] { return writer->open_written(); };
  SVC_RETURN_IF_ERROR(code_planned_frames(plan, std::move(frames), sink, settings, progress));
  SVC_ASSIGN_OR_RETURN(const std::vector<uint8_t> index_payload,
                       serialize_index(plan.index, [&](size_t cell) { return cell_cameras(plan.manifest, cell); }));
  SVC_RETURN_IF_ERROR(writer->finish(index_payload));

  EncodeSummary summary = summarize_encode(plan, plan.index.frames.size());
  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(out_path, ec);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
