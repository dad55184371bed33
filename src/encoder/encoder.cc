#include "svc/encoder.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "codec/color.h"
#include "codec/bframe_codec.h"
#include "codec/frame_codec.h"
#include "codec/log_search.h"
#include "common/parallel.h"
#include "container/container.h"
#include "database/database.h"
#include "encoder/face_coding.h"
#include "spatial/placement.h"
#include "spatial/reprojection.h"

namespace svc {

namespace {

std::string cell_face_name(const CellIndex& c, Face face) {
  return "cell (" + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) +
         ") face " + face_name(face);
}

Status validate_settings(const EncoderSettings& settings) {
  if (settings.quant_scale == 0 && (settings.quality < 1 || settings.quality > 100)) {
    return Status(ErrorCode::kInvalidArgument,
                  "quality " + std::to_string(settings.quality) + " is outside 1..100");
  }
  if (settings.quant_scale != 0 &&
      (settings.quant_scale < codec::kMinQuantScale || settings.quant_scale > codec::kMaxQuantScale)) {
    return Status(ErrorCode::kInvalidArgument, "quantiser scale " + std::to_string(settings.quant_scale) +
                                                   " is outside " + std::to_string(codec::kMinQuantScale) +
                                                   ".." + std::to_string(codec::kMaxQuantScale));
  }
  if (settings.threads < 0 || settings.threads > 1024) {
    return Status(ErrorCode::kInvalidArgument, "thread count " + std::to_string(settings.threads) +
                                                   " is outside 0..1024");
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

int quant_scale_for_quality(int quality) {
  quality = std::clamp(quality, 1, 100);
  // 100 -> 1 (finest), 75 (the default) -> 4, 50 -> 16, geometric in between: each
  // quality step scales the step size by the same factor. Below 50 the scale rises
  // linearly to kMaxQuantScale at 1, so every quality keeps a distinct meaning. The
  // scale is the I-faces'; B-faces use suggested_b_quant_scale of it (2.5x).
  double scale;
  if (quality >= 50) {
    scale = std::pow(4.0, (100.0 - quality) / 25.0);
  } else {
    scale = 16.0 + (50.0 - quality) * (codec::kMaxQuantScale - 16.0) / 49.0;
  }
  return std::clamp(static_cast<int>(std::lround(scale)), codec::kMinQuantScale, codec::kMaxQuantScale);
}

Result<EncodeSummary> encode_database(const std::filesystem::path& db_dir,
                                      const std::filesystem::path& out_path,
                                      const EncoderSettings& settings, const EncodeProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  SVC_RETURN_IF_ERROR(validate_settings(settings));
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db_dir));
  if (manifest.cells.empty()) {
    return Status(ErrorCode::kBadInput, (manifest.root / "manifest.json").string() + " lists no cells");
  }
  const int quant_scale =
      settings.quant_scale != 0 ? settings.quant_scale : quant_scale_for_quality(settings.quality);
  const codec::CodingParams params{quant_scale};
  codec::BFrameParams b_params;
  b_params.quant_scale = codec::suggested_b_quant_scale(quant_scale);

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
  index.coding.quality = settings.quant_scale != 0 ? 0 : static_cast<uint32_t>(settings.quality);
  index.coding.quant_scale = static_cast<uint32_t>(quant_scale);
  index.coding.motion =
      settings.motion == MotionSearch::kDepth ? MotionSource::kDepth : MotionSource::kLogSearch;
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
  summary.quant_scale = quant_scale;
  summary.raw_bytes = uint64_t{3} * manifest.face_width * manifest.face_height * face_count;

  // Placement: which cells are I-cubes, and the references of every B-cube.
  PlacementSettings placement_settings;
  placement_settings.i_spacing = settings.intra_only ? std::array<int32_t, 3>{1, 1, 1} : settings.i_spacing;
  index.coding.i_spacing = placement_settings.i_spacing;
  std::vector<CellIndex> cell_indices;
  for (const CellSource& source : manifest.cells) cell_indices.push_back(source.index);
  SVC_ASSIGN_OR_RETURN(std::vector<CellPlacement> placement,
                       place_cubes(cell_indices, manifest.grid.dims, placement_settings, manifest.grid.spacing));

  // Faces in coding order: every I-face first (B-faces predict from their
  // reconstructions), then every B-face; each group in cell order.
  std::vector<uint32_t> intra_frames, predicted_frames;
  for (size_t cell = 0; cell < manifest.cells.size(); ++cell) {
    for (int f = 0; f < kFaceCount; ++f) {
      const uint32_t frame = static_cast<uint32_t>(cell * kFaceCount + f);
      (placement[cell].intra ? intra_frames : predicted_frames).push_back(frame);
    }
  }
  // Reconstructed I-faces, by frame number, as the decoder will see them.
  std::unordered_map<uint32_t, ImageYCbCr420> reconstructions;
  uint64_t faces_done = 0;

  auto record_frame = [&](uint32_t frame, FrameKind kind, const std::vector<uint8_t>& payload) -> Status {
    const size_t cell = frame / kFaceCount;
    const Face face = static_cast<Face>(frame % kFaceCount);
    SVC_ASSIGN_OR_RETURN(uint64_t offset, writer->append_frame(payload));
    FrameRecord& record = index.frames[frame];
    record.cell = static_cast<uint32_t>(cell);
    record.face = face;
    record.kind = kind;
    record.chunk_offset = offset;
    record.payload_size = static_cast<uint32_t>(payload.size());
    if (kind == FrameKind::kPredicted) {
      for (uint32_t ref_cell : placement[cell].references) {
        record.references.push_back(ref_cell * kFaceCount + static_cast<uint32_t>(face));
      }
    }
    ++faces_done;
    if (progress && !progress(faces_done, face_count)) {
      return Status(ErrorCode::kCancelled,
                    "encode cancelled after " + cell_face_name(index.cells[cell].index, face));
    }
    return Status::Ok();
  };

  struct CodedIntra {
    std::vector<uint8_t> payload;
    ImageYCbCr420 reconstruction;
  };
  auto encode_intra = [&](size_t k) -> Result<CodedIntra> {
    const uint32_t frame = intra_frames[k];
    SVC_ASSIGN_OR_RETURN(FaceData data, load_face(manifest, frame / kFaceCount, static_cast<Face>(frame % kFaceCount)));
    const ImageYCbCr420 ycc = codec::rgb_to_ycbcr420(data.color.pixels.data(), data.color.width, data.color.height);
    CodedIntra coded;
    coded.payload = codec::encode_intra_frame(ycc, params, &coded.reconstruction);
    return coded;
  };
  auto store_intra = [&](size_t k, CodedIntra& coded) -> Status {
    const uint32_t frame = intra_frames[k];
    SVC_RETURN_IF_ERROR(record_frame(frame, FrameKind::kIntra, coded.payload));
    summary.intra.faces += 1;
    summary.intra.bytes += coded.payload.size();
    if (!predicted_frames.empty()) reconstructions.emplace(frame, std::move(coded.reconstruction));
    return Status::Ok();
  };
  const int threads = resolve_thread_count(settings.threads);
  SVC_RETURN_IF_ERROR(ordered_parallel_map<CodedIntra>(intra_frames.size(), threads, encode_intra, store_intra));

  auto encode_predicted = [&](size_t k) -> Result<CodedPredictedFace> {
    const uint32_t frame = predicted_frames[k];
    const size_t cell = frame / kFaceCount;
    const Face face = static_cast<Face>(frame % kFaceCount);
    SVC_ASSIGN_OR_RETURN(FaceData data, load_face(manifest, cell, face));
    std::vector<FaceReference> refs;
    for (uint32_t ref_cell : placement[cell].references) {
      refs.push_back({&reconstructions.at(ref_cell * kFaceCount + static_cast<uint32_t>(face)),
                      &manifest.cells[ref_cell].faces[static_cast<int>(face)].camera});
    }
    return code_predicted_face(data, manifest.cells[cell].faces[static_cast<int>(face)].camera, refs,
                               settings.motion == MotionSearch::kDepth, b_params,
                               cell_face_name(manifest.cells[cell].index, face));
  };
  auto store_predicted = [&](size_t k, CodedPredictedFace& coded) -> Status {
    SVC_RETURN_IF_ERROR(record_frame(predicted_frames[k], FrameKind::kPredicted, coded.payload));
    FrameTypeStats& s = summary.predicted;
    s.faces += 1;
    s.bytes += coded.payload.size();
    s.mb_intra += coded.stats.mb_intra;
    s.mb_forward += coded.stats.mb_forward;
    s.mb_backward += coded.stats.mb_backward;
    s.mb_bidirectional += coded.stats.mb_bidirectional;
    s.mb_skipped += coded.stats.mb_skipped;
    s.candidate_vectors += coded.candidates.candidates;
    s.candidate_macroblocks += coded.candidates.macroblocks;
    return Status::Ok();
  };
  SVC_RETURN_IF_ERROR(
      ordered_parallel_map<CodedPredictedFace>(predicted_frames.size(), threads, encode_predicted, store_predicted));
  const codec::BlockLayout layout = codec::block_layout(manifest.face_width, manifest.face_height);
  summary.intra.mb_intra = summary.intra.faces * uint64_t(layout.luma_blocks_x / 2) * uint64_t(layout.luma_blocks_y / 2);
  index.stats = {summary.intra, summary.predicted};
  SVC_RETURN_IF_ERROR(writer->finish(index));

  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(out_path, ec);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
