#include "svc/encoder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "codec/bframe_codec.h"
#include "codec/intra_codec.h"
#include "common/parallel.h"
#include "container/writer.h"
#include "database/database.h"
#include "encoder/coding_pipeline.h"
#include "spatial/placement.h"

namespace svc {

namespace {

Status validate_settings(const EncoderSettings& settings) {
  if (settings.qindex < 0 && (settings.quality < 1 || settings.quality > 100)) {
    return Status(ErrorCode::kInvalidArgument,
                  "quality " + std::to_string(settings.quality) + " is outside 1..100");
  }
  if (settings.qindex < -1 || settings.qindex > codec::kMaxQIndex) {
    return Status(ErrorCode::kInvalidArgument, "quantiser index " + std::to_string(settings.qindex) +
                                                   " is outside " + std::to_string(codec::kMinQIndex) + ".." +
                                                   std::to_string(codec::kMaxQIndex) + " (or -1 for the quality)");
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
  return Status::Ok();
}

}  // namespace

EncoderSettings default_encoder_settings() { return EncoderSettings{}; }

int qindex_for_quality(int quality) {
  // The index is logarithmic in the step, so an even spread gives every quality step the
  // same relative change of step size. Integer rounding half up, the same on every machine.
  const int steps_from_best = 100 - std::clamp(quality, 1, 100);
  return (steps_from_best * codec::kMaxQIndex * 2 + 99) / (2 * 99);
}

Result<EncodeSummary> encode_database(const std::filesystem::path& db_dir, const std::filesystem::path& out_path,
                                      const EncoderSettings& settings, const EncodeProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  SVC_RETURN_IF_ERROR(validate_settings(settings));
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db_dir));
  if (manifest.cells.empty()) {
    return Status(ErrorCode::kBadInput, (manifest.root / "manifest.json").string() + " lists no cells");
  }
  const int qindex = settings.qindex >= 0 ? settings.qindex : qindex_for_quality(settings.quality);
  SVC_ASSIGN_OR_RETURN(auto writer, ContainerWriter::create(out_path));

  ContainerIndex index;
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
  index.cells.reserve(manifest.cells.size());
  for (const CellSource& source : manifest.cells) {
    CellRecord cell;
    cell.index = source.index;
    cell.position = source.position;
    for (int f = 0; f < kFaceCount; ++f) cell.cameras[f] = source.faces[f].camera;
    index.cells.push_back(cell);
  }

  const size_t face_count = manifest.cells.size() * kFaceCount;
  index.frames.resize(face_count);
  EncodeSummary summary;
  summary.cells = manifest.cells.size();
  summary.faces = face_count;
  summary.qindex = qindex;
  summary.raw_bytes = uint64_t{3} * manifest.face_width * manifest.face_height * face_count;

  // Placement: which cells are I-cubes, and the references of every B-cube.
  PlacementSettings placement_settings;
  placement_settings.i_spacing = settings.intra_only ? std::array<int32_t, 3>{1, 1, 1} : settings.i_spacing;
  index.coding.i_spacing = placement_settings.i_spacing;
  std::vector<CellIndex> cell_indices;
  for (const CellSource& source : manifest.cells) cell_indices.push_back(source.index);
  SVC_ASSIGN_OR_RETURN(std::vector<CellPlacement> placement,
                       place_cubes(cell_indices, manifest.grid.dims, placement_settings, manifest.grid.spacing));

  CodingJob job;
  job.index = &index;
  for (size_t cell = 0; cell < manifest.cells.size(); ++cell) {
    for (int f = 0; f < kFaceCount; ++f) {
      const uint32_t frame = static_cast<uint32_t>(cell * kFaceCount + f);
      FrameRecord& record = index.frames[frame];
      record.cell = static_cast<uint32_t>(cell);
      record.face = static_cast<Face>(f);
      record.type = placement[cell].intra ? FaceType::kIntra : FaceType::kPredicted;
      for (uint32_t ref_cell : placement[cell].references)
        record.references.push_back(ref_cell * kFaceCount + static_cast<uint32_t>(f));
      job.frames.push_back(frame);
    }
  }
  job.load = [&](uint32_t frame) {
    return load_face(manifest, frame / kFaceCount, static_cast<Face>(frame % kFaceCount));
  };
  job.append = [&](std::span<const uint8_t> payload) { return writer->append_frame(payload); };
  job.tools = settings.tools;
  job.threads = resolve_thread_count(settings.threads);
  job.progress = progress;
  SVC_RETURN_IF_ERROR(code_faces(job));
  summary.intra = index.stats[0];
  summary.predicted = index.stats[1];
  SVC_RETURN_IF_ERROR(writer->finish(index));

  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(out_path, ec);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
