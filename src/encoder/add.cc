// svc add: cells of a database appended to an existing .svc file (include/svc/encoder.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>

#include "codec/bframe_codec.h"
#include "codec/color.h"
#include "codec/frame_codec.h"
#include "codec/log_search.h"
#include "common/parallel.h"
#include "container/container.h"
#include "database/database.h"
#include "encoder/face_coding.h"
#include "spatial/placement.h"
#include "spatial/reprojection.h"
#include "svc/encoder.h"

namespace svc {

namespace {

constexpr const char* kAxis[3] = {"x", "y", "z"};

std::string cell_face_name(const CellIndex& c, Face face) {
  return cell_label(c) + " face " + face_name(face);
}

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

}  // namespace

Result<AddSummary> add_to_database(const std::filesystem::path& svc_file, const std::filesystem::path& db_dir,
                                   const AddSettings& settings, const EncodeProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (settings.threads < 0 || settings.threads > 1024) {
    return Status(ErrorCode::kInvalidArgument, "thread count " + std::to_string(settings.threads) +
                                                   " is outside 0..1024");
  }
  SVC_ASSIGN_OR_RETURN(auto updater, ContainerUpdater::open(svc_file));
  const ContainerIndex& old = updater->committed().index;
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db_dir));
  if (manifest.cells.empty()) {
    return Status(ErrorCode::kBadInput, (manifest.root / "manifest.json").string() + " lists no cells");
  }

  // Compatibility: same faces, same conventions, same grid lattice.
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

  // The union of cells, in index order; `origin` tells where each came from.
  struct UnionCell {
    CellIndex index;
    int64_t old_cell = -1;   // ordinal in the old index
    int64_t source = -1;     // ordinal in the manifest, for new cells
  };
  std::map<std::array<int32_t, 3>, size_t> old_by_key;
  for (size_t c = 0; c < old.cells.size(); ++c) old_by_key.emplace(key_of(old.cells[c].index), c);
  std::vector<UnionCell> cells;
  cells.reserve(old.cells.size() + manifest.cells.size());
  for (size_t c = 0; c < old.cells.size(); ++c) cells.push_back({old.cells[c].index, static_cast<int64_t>(c), -1});
  AddSummary summary;
  summary.cells_before = old.cells.size();
  for (size_t s = 0; s < manifest.cells.size(); ++s) {
    if (old_by_key.count(key_of(manifest.cells[s].index))) {
      ++summary.cells_present;
      continue;
    }
    cells.push_back({manifest.cells[s].index, -1, static_cast<int64_t>(s)});
  }
  summary.cells_added = cells.size() - old.cells.size();
  summary.grid_dims = old.grid.dims;
  summary.generation = updater->committed().generation;
  summary.file_bytes = updater->file().size();
  if (summary.cells_added == 0) return summary;  // nothing to do: the file is not touched

  const ReaderLimits limits;
  if (cells.size() > limits.max_cells) {
    return mismatch(svc_file, std::to_string(cells.size()) + " cells would exceed the reader's limit of " +
                                  std::to_string(limits.max_cells));
  }
  std::sort(cells.begin(), cells.end(), [](const UnionCell& a, const UnionCell& b) { return cell_less(a.index, b.index); });
  // Old frame numbers move with their cells.
  std::vector<uint32_t> new_cell_of_old(old.cells.size());
  for (size_t c = 0; c < cells.size(); ++c) {
    if (cells[c].old_cell >= 0) new_cell_of_old[static_cast<size_t>(cells[c].old_cell)] = static_cast<uint32_t>(c);
  }

  // Placement over the union. Existing cells keep their types; a new cell takes the type
  // the rules give it.
  std::vector<CellIndex> indices;
  for (const UnionCell& cell : cells) indices.push_back(cell.index);
  PlacementSettings placement_settings;
  placement_settings.i_spacing = old.coding.i_spacing;
  SVC_ASSIGN_OR_RETURN(std::vector<CellPlacement> placement,
                       place_cubes(indices, grid.dims, placement_settings, grid.spacing));
  // intra[c][f]: face f of union cell c is (or will be) an I-face.
  std::vector<std::array<bool, kFaceCount>> intra(cells.size());
  for (size_t c = 0; c < cells.size(); ++c) {
    for (int f = 0; f < kFaceCount; ++f) {
      intra[c][f] = cells[c].old_cell >= 0
                        ? old.frames[static_cast<size_t>(cells[c].old_cell) * kFaceCount + f].kind == FrameKind::kIntra
                        : placement[c].intra;
    }
  }
  // References of each new B-cube, per face: the nearest two I-faces in reach. A new
  // cell with a face that has none becomes an I-cube. New I-cubes decided here can give
  // later cells references, so iterate until nothing changes (each round only turns
  // B-cubes into I-cubes, so it ends).
  const auto& s = old.coding.i_spacing;
  std::vector<std::array<std::vector<uint32_t>, kFaceCount>> references(cells.size());
  for (bool changed = true; changed;) {
    changed = false;
    std::map<std::array<int32_t, 3>, std::vector<uint32_t>> intra_by_group;
    for (size_t c = 0; c < cells.size(); ++c) {
      const CellIndex& i = cells[c].index;
      if (std::any_of(intra[c].begin(), intra[c].end(), [](bool b) { return b; })) {
        intra_by_group[{i.x / s[0], i.y / s[1], i.z / s[2]}].push_back(static_cast<uint32_t>(c));
      }
    }
    for (size_t c = 0; c < cells.size(); ++c) {
      if (cells[c].old_cell >= 0 || intra[c][0]) continue;
      const CellIndex& here = cells[c].index;
      bool every_face_has_one = true;
      for (int f = 0; f < kFaceCount; ++f) {
        // The reach rule of spatial/placement.h, over the I-faces of this face direction.
        std::vector<ReferenceCandidate> in_reach;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            for (int dx = -1; dx <= 1; ++dx) {
              const auto it = intra_by_group.find(
                  {here.x / s[0] + dx, here.y / s[1] + dy, here.z / s[2] + dz});
              if (it == intra_by_group.end()) continue;
              for (uint32_t other : it->second) {
                if (intra[other][f]) in_reach.push_back({cells[other].index, other});
              }
            }
          }
        }
        auto& refs = references[c][f];
        refs = nearest_references(here, in_reach, grid.spacing);
        if (refs.empty()) every_face_has_one = false;
      }
      if (!every_face_has_one) {
        intra[c].fill(true);
        for (auto& refs : references[c]) refs.clear();
        changed = true;
      }
    }
  }

  // Frames to code, I-faces first (B-faces predict from their reconstructions).
  std::vector<uint32_t> intra_frames, predicted_frames;
  for (size_t c = 0; c < cells.size(); ++c) {
    if (cells[c].old_cell >= 0) continue;
    for (int f = 0; f < kFaceCount; ++f) {
      const uint32_t frame = static_cast<uint32_t>(c * kFaceCount + f);
      (intra[c][f] ? intra_frames : predicted_frames).push_back(frame);
    }
    (intra[c][0] ? summary.intra_cells_added : summary.predicted_cells_added) += 1;
  }
  const size_t total_faces = intra_frames.size() + predicted_frames.size();

  // Reconstructions of every I-face a new B-face uses, by new frame number. Old ones are
  // decoded from the file now, before anything is written.
  std::unordered_map<uint32_t, ImageYCbCr420> reconstructions;
  const int width = static_cast<int>(old.face_width), height = static_cast<int>(old.face_height);
  for (uint32_t frame : predicted_frames) {
    const size_t c = frame / kFaceCount;
    const int f = static_cast<int>(frame % kFaceCount);
    for (uint32_t ref_cell : references[c][f]) {
      const uint32_t ref_frame = ref_cell * kFaceCount + static_cast<uint32_t>(f);
      if (cells[ref_cell].old_cell < 0 || reconstructions.count(ref_frame)) continue;
      const FrameRecord& record = old.frames[static_cast<size_t>(cells[ref_cell].old_cell) * kFaceCount + f];
      const std::string what = cell_face_name(cells[ref_cell].index, static_cast<Face>(f));
      SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, read_frame_payload(updater->file(), record, what));
      ImageYCbCr420 image;
      Status status = codec::decode_intra_frame(payload, width, height, &image);
      if (!status.ok()) {
        return status.with_context(svc_file.string() + ": " + what + " (chunk at byte offset " +
                                   std::to_string(record.chunk_offset) + "), needed as a reference");
      }
      reconstructions.emplace(ref_frame, std::move(image));
    }
  }

  // The new index: old frames renumbered, new ones filled in as they are coded.
  ContainerIndex index;
  index.face_width = old.face_width;
  index.face_height = old.face_height;
  index.grid = grid;
  index.depth_mode = old.depth_mode;
  index.up_axis = old.up_axis;
  index.coding = old.coding;
  index.stats = old.stats;
  index.cells.resize(cells.size());
  index.frames.resize(cells.size() * kFaceCount);
  for (size_t c = 0; c < cells.size(); ++c) {
    CellRecord& record = index.cells[c];
    if (cells[c].old_cell >= 0) {
      record = old.cells[static_cast<size_t>(cells[c].old_cell)];
      for (int f = 0; f < kFaceCount; ++f) {
        FrameRecord frame = old.frames[static_cast<size_t>(cells[c].old_cell) * kFaceCount + f];
        frame.cell = static_cast<uint32_t>(c);
        for (uint32_t& ref : frame.references) {
          ref = new_cell_of_old[ref / kFaceCount] * kFaceCount + ref % kFaceCount;
        }
        index.frames[c * kFaceCount + f] = std::move(frame);
      }
    } else {
      const CellSource& source = manifest.cells[static_cast<size_t>(cells[c].source)];
      record.index = source.index;
      record.position = source.position;
      for (int f = 0; f < kFaceCount; ++f) record.cameras[f] = source.faces[f].camera;
    }
  }

  const codec::CodingParams params{static_cast<int>(old.coding.quant_scale)};
  codec::BFrameParams b_params;
  b_params.quant_scale = codec::suggested_b_quant_scale(params.quant_scale);
  const int threads = resolve_thread_count(settings.threads);
  uint64_t faces_done = 0;
  auto record_frame = [&](uint32_t frame, FrameKind kind, const std::vector<uint8_t>& payload) -> Status {
    const size_t c = frame / kFaceCount;
    const Face face = static_cast<Face>(frame % kFaceCount);
    SVC_ASSIGN_OR_RETURN(uint64_t offset, updater->append_frame(payload));
    FrameRecord& record = index.frames[frame];
    record.cell = static_cast<uint32_t>(c);
    record.face = face;
    record.kind = kind;
    record.chunk_offset = offset;
    record.payload_size = static_cast<uint32_t>(payload.size());
    for (uint32_t ref_cell : references[c][static_cast<int>(face)]) {
      record.references.push_back(ref_cell * kFaceCount + static_cast<uint32_t>(face));
    }
    FrameTypeRecord& stats = index.stats[static_cast<int>(kind)];
    stats.faces += 1;
    stats.bytes += payload.size();
    ++faces_done;
    if (progress && !progress(faces_done, total_faces)) {
      return Status(ErrorCode::kCancelled, "add cancelled after " + cell_face_name(cells[c].index, face));
    }
    return Status::Ok();
  };
  auto load = [&](uint32_t frame) -> Result<FaceData> {
    const size_t source = static_cast<size_t>(cells[frame / kFaceCount].source);
    return load_face(manifest, source, static_cast<Face>(frame % kFaceCount));
  };

  struct CodedIntra {
    std::vector<uint8_t> payload;
    ImageYCbCr420 reconstruction;
  };
  auto encode_intra = [&](size_t k) -> Result<CodedIntra> {
    SVC_ASSIGN_OR_RETURN(FaceData data, load(intra_frames[k]));
    const ImageYCbCr420 ycc = codec::rgb_to_ycbcr420(data.color.pixels.data(), data.color.width, data.color.height);
    CodedIntra coded;
    coded.payload = codec::encode_intra_frame(ycc, params, &coded.reconstruction);
    return coded;
  };
  auto store_intra = [&](size_t k, CodedIntra& coded) -> Status {
    SVC_RETURN_IF_ERROR(record_frame(intra_frames[k], FrameKind::kIntra, coded.payload));
    const codec::BlockLayout layout = codec::block_layout(width, height);
    index.stats[0].mb_intra += uint64_t(layout.luma_blocks_x / 2) * uint64_t(layout.luma_blocks_y / 2);
    reconstructions.emplace(intra_frames[k], std::move(coded.reconstruction));
    return Status::Ok();
  };
  SVC_RETURN_IF_ERROR(ordered_parallel_map<CodedIntra>(intra_frames.size(), threads, encode_intra, store_intra));

  auto encode_predicted = [&](size_t k) -> Result<CodedPredictedFace> {
    const uint32_t frame = predicted_frames[k];
    const size_t c = frame / kFaceCount;
    const int f = static_cast<int>(frame % kFaceCount);
    SVC_ASSIGN_OR_RETURN(FaceData data, load(frame));
    std::vector<FaceReference> refs;
    for (uint32_t ref_cell : references[c][f]) {
      refs.push_back({&reconstructions.at(ref_cell * kFaceCount + static_cast<uint32_t>(f)),
                      &index.cells[ref_cell].cameras[f]});
    }
    return code_predicted_face(data, index.cells[c].cameras[f], refs, old.coding.motion == MotionSource::kDepth,
                               b_params, cell_face_name(cells[c].index, static_cast<Face>(f)));
  };
  auto store_predicted = [&](size_t k, CodedPredictedFace& coded) -> Status {
    SVC_RETURN_IF_ERROR(record_frame(predicted_frames[k], FrameKind::kPredicted, coded.payload));
    FrameTypeRecord& stats = index.stats[1];
    stats.mb_intra += coded.stats.mb_intra;
    stats.mb_forward += coded.stats.mb_forward;
    stats.mb_backward += coded.stats.mb_backward;
    stats.mb_bidirectional += coded.stats.mb_bidirectional;
    stats.mb_skipped += coded.stats.mb_skipped;
    stats.candidate_vectors += coded.candidates.candidates;
    stats.candidate_macroblocks += coded.candidates.macroblocks;
    return Status::Ok();
  };
  SVC_RETURN_IF_ERROR(
      ordered_parallel_map<CodedPredictedFace>(predicted_frames.size(), threads, encode_predicted, store_predicted));

  std::error_code size_error;
  const uint64_t size_before = std::filesystem::file_size(svc_file, size_error);
  SVC_RETURN_IF_ERROR(updater->commit(index));
  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(svc_file, ec);
  summary.bytes_appended = summary.file_bytes > size_before ? summary.file_bytes - size_before : 0;
  summary.faces_added = total_faces;
  summary.generation = updater->committed().generation + 1;
  summary.grid_dims = grid.dims;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
