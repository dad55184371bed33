// SPDX-License-Identifier: BSD-2-Clause
#include "encoder/coding_pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <string>

#include "codec/common/bframe.h"
#include "codec/common/cube_padding.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/depth_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "codec/encoder/depth_encoder.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/rgb_to_ycbcr.h"
#include "codec/encoder/search_planes.h"
#include "common/parallel.h"
#include "encoder/face_coding.h"
#include "reader/depth_decode.h"
#include "reader/face_decode.h"
#include "reader/shared_cache.h"

namespace svc {

namespace {

struct CodedIntra {
  std::vector<uint8_t> payload;
  ImageYCbCr420 reconstruction;
  codec::SyntaxBits syntax;
  std::vector<uint8_t> depth_payload;  // empty without depth
};

uint64_t image_bytes(const ImageYCbCr420& image) { return image.y.size() + image.cb.size() + image.cr.size(); }
uint64_t depth_bytes(const std::vector<uint16_t>& codes) { return codes.size() * sizeof(uint16_t); }

using ReferenceCache = reader_internal::SharedCache<ImageYCbCr420>;
using DepthCache = reader_internal::SharedCache<std::vector<uint16_t>>;
using SearchPlanesCache = reader_internal::SharedCache<codec::SearchPlanes>;

uint64_t search_planes_bytes(const codec::SearchPlanes& planes) { return planes.bytes(); }

class Pipeline {
 public:
  explicit Pipeline(CodingJob& job)
      : job_(job),
        index_(*job.index),
        references_(reference_cache_bytes(), &image_bytes),
        padded_(reference_cache_bytes(), &image_bytes),
        search_planes_(reference_cache_bytes(), &search_planes_bytes),
        depth_references_(reference_cache_bytes(), &depth_bytes) {
    for (uint32_t frame : job.frames) {
      (index_.frames[frame].type == FaceType::kIntra ? intra_ : predicted_).push_back(frame);
    }
    intra_params_.qindex = static_cast<int>(index_.coding.qindex);
    intra_params_.directional_intra = job.tools.intra_directional;
    intra_params_.rd_intra_search = job.tools.intra_rd_search;
    intra_params_.rdoq = job.tools.rdoq;
    intra_params_.coarse_mode_search = !job.tools.full_intra_mode_search;
    intra_params_.transform_sizes = job.tools.transform_sizes;
    intra_params_.cfl = job.tools.cfl;
    intra_params_.transform_types = job.tools.transform_types;
    intra_params_.residual_matrix = job.tools.weighted_quant_matrix ? codec::ResidualMatrix::kWeighted
                                                                    : codec::ResidualMatrix::kFlat;
    b_params_.qindex = codec::b_qindex_for_offset(intra_params_.qindex, job.b_qindex_offset >= 0
                                                                            ? job.b_qindex_offset
                                                                            : codec::kBQIndexOffset);
    b_params_.warp = job.tools.warped_prediction;
    b_params_.sub_pel_refinement = job.tools.sub_pel_refinement;
    b_params_.quarter_pel = job.tools.quarter_pel;
    b_params_.rdoq = job.tools.rdoq;
    intra_params_.deblocking = b_params_.deblocking = job.tools.deblocking;
    intra_params_.cdef = b_params_.cdef = job.tools.cdef;
    intra_params_.full_cdef_search = b_params_.full_cdef_search = job.tools.full_cdef_search;
    b_params_.switchable_filter = job.tools.switchable_filter;
    b_params_.full_filter_search = job.tools.full_filter_search;
    b_params_.skip_exit_bits = job.tools.early_skip ? codec::kEarlySkipBits : 0;
    b_params_.partitions = job.tools.partitions;
    b_params_.vector_predictors = job.tools.vector_predictors;
    b_params_.epipolar_lines = job.tools.epipolar_lines;
    b_params_.inter_transform_sizes = job.tools.inter_transform_sizes;
    b_params_.full_inter_split_search = job.tools.full_inter_split_search;
    b_params_.intra_prediction = job.tools.b_intra_prediction && job.tools.intra_directional;
    b_params_.intra_rd_search = job.tools.intra_rd_search;
    b_params_.intra_transform_sizes = job.tools.transform_sizes;
    b_params_.intra_small_blocks = job.tools.b_intra_small_blocks;
    b_params_.intra_cfl = job.tools.cfl;
    b_params_.intra_transform_types = job.tools.transform_types;
    // Narrowed: the first stage's cheapest halves or strips and smaller partition only.
    const bool full = job.tools.full_intra_partition_search;
    intra_params_.rectangular_trials = b_params_.intra_rectangular_trials = full ? codec::kRectangularPartitions
                                                                                 : 1;
    intra_params_.small_trials = b_params_.intra_small_trials = full ? codec::kSmallPartitions : 1;
    b_params_.keep_intra_partition = !job.tools.rdoq_intra_partition_search;
  }

  Status run() {
    SVC_RETURN_IF_ERROR(ordered_parallel_map<CodedIntra>(
        intra_.size(), job_.threads, [&](size_t k) { return code_intra(intra_[k]); },
        [&](size_t k, CodedIntra& coded) { return store_intra(intra_[k], coded); }));
    if (predicted_.empty()) return Status::Ok();
    SVC_ASSIGN_OR_RETURN(written_, job_.open_written());
    SVC_RETURN_IF_ERROR(choose_b_qindex());
    job_.b_qindex = b_params_.qindex;
    return ordered_parallel_map<CodedPredictedFace>(
        predicted_.size(), job_.threads,
        [&](size_t k) -> Result<CodedPredictedFace> {
          // The trial's faces are already coded when their index stayed.
          const auto trial = trial_coded_.find(predicted_[k]);
          if (trial != trial_coded_.end()) return std::move(trial->second);
          return code_predicted(predicted_[k]);
        },
        [&](size_t k, CodedPredictedFace& coded) { return store_predicted(predicted_[k], coded); });
  }

 private:
  Result<CodedIntra> code_intra(uint32_t frame) const {
    SVC_ASSIGN_OR_RETURN(FaceData data, job_.load(frame));
    const ImageYCbCr420 ycc = codec::rgb_to_ycbcr420(data.color.pixels.data(), data.color.width, data.color.height);
    CodedIntra coded;
    coded.payload = codec::encode_intra_frame(ycc, intra_params_, &coded.reconstruction, &coded.syntax);
    SVC_RETURN_IF_ERROR(check_intra_payload(coded.payload, coded.reconstruction, frame_name(frame)));
    if (index_.depth) {
      SVC_ASSIGN_OR_RETURN(const std::vector<uint16_t> codes, source_depth_codes(frame, data));
      coded.depth_payload =
          std::move(codec::encode_depth(codes, width(), height(), index_.depth_max_error, nullptr).payload);
    }
    return coded;
  }

  int width() const { return static_cast<int>(index_.face_width); }
  int height() const { return static_cast<int>(index_.face_height); }

  Result<std::vector<uint16_t>> source_depth_codes(uint32_t frame, const FaceData& data) const {
    SVC_ASSIGN_OR_RETURN(const Camera camera, job_.camera(frame));
    return codec::inverse_depth_codes(data.depth, camera.frustum.near_plane);
  }

  // Reads and decodes reference depth through the pipeline's cache.
  class DepthSource : public CodedDepthSource {
   public:
    DepthSource(Pipeline& pipeline, const ReadOnlyFile& file)
        : CodedDepthSource(file, pipeline.index_), pipeline_(pipeline) {}
    Result<std::vector<uint8_t>> depth_payload(uint32_t frame) override {
      return read_frame_depth(file_, index_.frames[frame], frame_label(index_, frame));
    }
    Result<DepthPointer> intra_depth(uint32_t frame) override { return pipeline_.depth_reference(frame); }
    Result<Camera> camera(uint32_t frame) override { return pipeline_.job_.camera(frame); }

   private:
    Pipeline& pipeline_;
  };

  // A reference I-face's depth as the decoder will see it: decoded from the file when
  // it is there, else coded again from its source (the same codes).
  Result<DepthPointer> depth_reference(uint32_t frame) {
    return depth_references_.get(frame, reader_internal::Origin::kCaller, [&]() -> Result<DepthPointer> {
      if (index_.frames[frame].chunk_offset != 0) {
        DepthSource source(*this, *written_);
        return decode_indexed_depth(*written_, index_, frame, source);
      }
      SVC_ASSIGN_OR_RETURN(FaceData data, job_.load(frame));
      SVC_ASSIGN_OR_RETURN(const std::vector<uint16_t> codes, source_depth_codes(frame, data));
      return DepthPointer(std::make_shared<const std::vector<uint16_t>>(
          codec::encode_depth(codes, width(), height(), index_.depth_max_error, nullptr).reconstructed));
    });
  }

  // A B-face's depth: predicted from its reference cubes' depth, or coded on its own
  // when that is smaller (docs/encoder.md, "Depth").
  Result<std::vector<uint8_t>> code_predicted_depth(uint32_t frame, const FaceData& data, const Camera& camera) {
    SVC_ASSIGN_OR_RETURN(const std::vector<uint16_t> codes, source_depth_codes(frame, data));
    DepthSource source(*this, *written_);
    SVC_ASSIGN_OR_RETURN(const ReferenceDepths references, reference_depths(index_, frame, source));
    codec::DepthPrediction prediction;
    codec::predict_depth(references.references, camera, width(), height(), &prediction);
    std::vector<uint8_t> inter =
        codec::encode_depth(codes, width(), height(), index_.depth_max_error, &prediction).payload;
    std::vector<uint8_t> intra =
        codec::encode_depth(codes, width(), height(), index_.depth_max_error, nullptr).payload;
    return intra.size() < inter.size() ? std::move(intra) : std::move(inter);
  }

  Status store_intra(uint32_t frame, CodedIntra& coded) {
    SVC_RETURN_IF_ERROR(store(frame, coded.payload, coded.depth_payload));
    job_.syntax[0] += coded.syntax;
    const codec::BlockLayout layout =
        codec::block_layout(static_cast<int>(index_.face_width), static_cast<int>(index_.face_height));
    index_.stats[0].mb_intra += uint64_t(layout.luma_blocks_x / 2) * uint64_t(layout.luma_blocks_y / 2);
    return Status::Ok();
  }

  // A reference I-face as the decoder will see it: decoded from the file when it is
  // there, else coded again from its source (same bytes, same reconstruction).
  Result<FacePointer> reference(uint32_t frame) {
    return references_.get(frame, reader_internal::Origin::kCaller, [&]() -> Result<FacePointer> {
      if (index_.frames[frame].chunk_offset != 0) {
        FileCodedFaceSource source(*written_, index_);
        return source.intra_face(frame);
      }
      SVC_ASSIGN_OR_RETURN(CodedIntra coded, code_intra(frame));
      return FacePointer(std::make_shared<const ImageYCbCr420>(std::move(coded.reconstruction)));
    });
  }

  // A reference I-face padded with the adjacent faces of its cube, as the decoder builds
  // it for a B-face with cube references (docs/codec.md 5.7).
  Result<FacePointer> padded_reference(const FrameRecord& record, uint32_t ref) {
    return padded_.get(ref, reader_internal::Origin::kCaller, [&]() -> Result<FacePointer> {
      std::vector<FacePointer> held;
      codec::CubeFaces cube{};
      for (uint32_t dependency : frame_dependencies(record)) {
        if (dependency / kFaceCount != ref / kFaceCount) continue;
        SVC_ASSIGN_OR_RETURN(FacePointer face, reference(dependency));
        cube[dependency % kFaceCount] = face.get();
        held.push_back(std::move(face));
      }
      auto padded = std::make_shared<ImageYCbCr420>();
      const Status status = codec::pad_cube_face(cube, record.face, job_.cube_border_units, padded.get());
      if (!status.ok()) return Status(ErrorCode::kInternal, frame_name(ref) + ": " + status.message());
      return FacePointer(std::move(padded));
    });
  }

  // The motion search's planes of a reference as `code_predicted` uses it (padded or
  // bare), built once for all the B-faces that predict from it.
  Result<std::shared_ptr<const codec::SearchPlanes>> search_planes(const FrameRecord& record, uint32_t ref,
                                                                   const ImageYCbCr420& image) {
    const uint32_t key = 2 * ref + (record.cube_references ? 1 : 0);
    return search_planes_.get(key, reader_internal::Origin::kCaller,
                              [&]() -> Result<std::shared_ptr<const codec::SearchPlanes>> {
                                return codec::b_frame_search_planes(image);
                              });
  }

  // Codes the trial B-faces at the default offset and adapts every B-face's qindex to
  // the share of their macroblocks coded intra (docs/encoder.md 5).
  Status choose_b_qindex() {
    if (job_.trial_frames.empty() || job_.b_qindex_offset >= 0) return Status::Ok();
    uint64_t intra = 0, macroblocks = 0;
    std::map<uint32_t, CodedPredictedFace> coded_faces;
    SVC_RETURN_IF_ERROR(ordered_parallel_map<CodedPredictedFace>(
        job_.trial_frames.size(), job_.threads, [&](size_t k) { return code_predicted(job_.trial_frames[k]); },
        [&](size_t k, CodedPredictedFace& coded) {
          intra += static_cast<uint64_t>(coded.stats.mb_intra);
          macroblocks += static_cast<uint64_t>(coded.stats.macroblocks);
          coded_faces[job_.trial_frames[k]] = std::move(coded);
          return Status::Ok();
        }));
    if (macroblocks == 0) return Status::Ok();
    const int trial_qindex = b_params_.qindex;
    b_params_.qindex = codec::adapted_b_qindex(intra_params_.qindex, double(intra) / double(macroblocks));
    if (b_params_.qindex == trial_qindex) trial_coded_ = std::move(coded_faces);
    return Status::Ok();
  }

  Result<CodedPredictedFace> code_predicted(uint32_t frame) {
    const FrameRecord& record = index_.frames[frame];
    SVC_ASSIGN_OR_RETURN(FaceData data, job_.load(frame));
    SVC_ASSIGN_OR_RETURN(const Camera camera, job_.camera(frame));
    std::vector<FacePointer> held;  // keeps the references alive while the cache may evict them
    std::vector<std::shared_ptr<const codec::SearchPlanes>> held_planes;  // and their search planes
    std::array<Camera, FrameReferences::kCapacity> ref_cameras;
    std::vector<FaceReference> refs;
    for (size_t r = 0; r < record.references.size(); ++r) {
      const uint32_t ref = record.references[r];
      SVC_ASSIGN_OR_RETURN(FacePointer image,
                           record.cube_references ? padded_reference(record, ref) : reference(ref));
      SVC_ASSIGN_OR_RETURN(ref_cameras[r], job_.camera(ref));
      SVC_ASSIGN_OR_RETURN(std::shared_ptr<const codec::SearchPlanes> planes, search_planes(record, ref, *image));
      held.push_back(image);
      held_planes.push_back(planes);
      refs.push_back({image.get(), &ref_cameras[r], planes.get()});
    }
    SVC_ASSIGN_OR_RETURN(CodedPredictedFace coded,
                         code_predicted_face(data, camera, refs, index_.coding.motion == MotionSearch::kDepth,
                                             b_params_, frame_name(frame)));
    if (index_.depth) {
      SVC_ASSIGN_OR_RETURN(coded.depth_payload, code_predicted_depth(frame, data, camera));
    }
    return coded;
  }

  Status store_predicted(uint32_t frame, const CodedPredictedFace& coded) {
    SVC_RETURN_IF_ERROR(store(frame, coded.payload, coded.depth_payload));
    FrameRecord& record = index_.frames[frame];
    if (record.cube_references) record.border_edges = pack_border_edges(coded.border_edges);
    FaceTypeStats& s = index_.stats[1];
    s.mb_intra += coded.stats.mb_intra;
    s.mb_forward += coded.stats.mb_forward;
    s.mb_backward += coded.stats.mb_backward;
    s.mb_bidirectional += coded.stats.mb_bidirectional;
    s.mb_skipped += coded.stats.mb_skipped;
    PredictionSummary& prediction = job_.prediction;
    prediction.mb_leaving_face += static_cast<uint64_t>(coded.stats.mb_leaving_face);
    prediction.mb_warp += static_cast<uint64_t>(coded.stats.mb_warp);
    for (size_t k = 0; k < 2; ++k) {
      prediction.screened_sse[k] += static_cast<uint64_t>(coded.stats.screened_prediction_sse[k]);
      prediction.screened_pixels[k] += static_cast<uint64_t>(coded.stats.screened_prediction_pixels[k]);
    }
    job_.syntax[1] += coded.stats.syntax;
    s.candidate_vectors += coded.candidates.candidates;
    s.candidate_macroblocks += coded.candidates.macroblocks;
    return Status::Ok();
  }

  // Appends the chunk and the depth chunk after it, fills in the frame record and
  // reports progress.
  Status store(uint32_t frame, const std::vector<uint8_t>& payload, const std::vector<uint8_t>& depth_payload) {
    SVC_ASSIGN_OR_RETURN(uint64_t offset, job_.append(payload));
    FrameRecord& record = index_.frames[frame];
    record.chunk_offset = offset;
    record.payload_size = static_cast<uint32_t>(payload.size());
    if (index_.depth) {
      SVC_ASSIGN_OR_RETURN(uint64_t depth_offset, job_.append(depth_payload));
      if (depth_offset != offset + color_chunk_bytes(record)) {
        return Status(ErrorCode::kInternal, frame_name(frame) + ": depth chunk not right after the face's");
      }
      record.depth_size = static_cast<uint32_t>(depth_payload.size());
    }
    FaceTypeStats& stats = index_.stats[static_cast<int>(record.type)];
    stats.faces += 1;
    stats.bytes += payload.size();
    ++done_;
    if (job_.progress && !job_.progress(done_, job_.frames.size())) {
      return Status(ErrorCode::kCancelled, std::string(job_.action) + " cancelled after " + frame_name(frame));
    }
    return Status::Ok();
  }

  std::string frame_name(uint32_t frame) const {
    const FrameRecord& record = index_.frames[frame];
    return face_label(index_.cells[record.cell].index, record.face);
  }

  CodingJob& job_;
  ContainerIndex& index_;
  ReferenceCache references_;
  std::unique_ptr<ReadOnlyFile> written_;
  std::vector<uint32_t> intra_, predicted_;
  ReferenceCache padded_;            // padded reference I-faces, by frame
  SearchPlanesCache search_planes_;  // by 2 frame + (1 when padded)
  DepthCache depth_references_;      // reference I-faces' depth, by frame
  codec::CodingParams intra_params_;
  codec::BFrameParams b_params_;
  // The trial B-faces when they were coded at the index every B-face keeps
  // (choose_b_qindex); those of this job are stored from here.
  std::map<uint32_t, CodedPredictedFace> trial_coded_;
  uint64_t done_ = 0;
};

}  // namespace

uint64_t reference_cache_bytes() {
  const char* text = std::getenv("SVC_REFERENCE_CACHE_BYTES");
  if (text == nullptr) return kReferenceCacheBytes;
  char* end = nullptr;
  const unsigned long long bytes = std::strtoull(text, &end, 10);
  if (end == text || *end != '\0' || bytes == 0 || bytes > kReferenceCacheBytes) return kReferenceCacheBytes;
  return bytes;
}

bool uses_cube_references(const ContainerIndex& index, const CodingTools& tools) {
  return tools.cube_references &&
         codec::cube_padding_possible(static_cast<int>(index.face_width), static_cast<int>(index.face_height));
}

namespace {

// Squared distance from a B-cube to its nearest reference cube (0 without positions).
double squared_reference_distance(const ContainerIndex& index, uint32_t cell) {
  const size_t frame = size_t{cell} * kFaceCount;
  if (frame >= index.frames.size() || cell >= index.cells.size()) return 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (uint32_t ref : index.frames[frame].references) {
    if (ref >= index.frames.size() || index.frames[ref].cell >= index.cells.size()) continue;
    const uint32_t ref_cell = index.frames[ref].cell;
    double d = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double delta = index.cells[cell].position[axis] - index.cells[ref_cell].position[axis];
      d += delta * delta;
    }
    nearest = std::min(nearest, d);
  }
  return std::isfinite(nearest) ? nearest : 0;
}

}  // namespace

std::vector<uint32_t> trial_frames(const ContainerIndex& index, std::span<const uint32_t> frames) {
  std::map<uint32_t, uint32_t> faces_of_cell;  // B-faces in `frames`, by cell
  for (uint32_t frame : frames) {
    if (frame < index.frames.size() && index.frames[frame].type == FaceType::kPredicted)
      ++faces_of_cell[index.frames[frame].cell];
  }
  // Ordered by distance to the nearest reference, so that the trial takes near and far
  // B-cubes in the proportions the database has them (cell order alone may take only
  // the nearest, which predict best).
  std::vector<std::pair<double, uint32_t>> cubes;
  for (const auto& [cell, faces] : faces_of_cell) {
    if (faces == kFaceCount) cubes.emplace_back(squared_reference_distance(index, cell), cell);
  }
  std::sort(cubes.begin(), cubes.end());
  const size_t chosen = std::min(kTrialCubes, cubes.size());
  std::vector<uint32_t> cells;
  for (size_t k = 0; k < chosen; ++k) cells.push_back(cubes[(2 * k + 1) * cubes.size() / (2 * chosen)].second);
  std::sort(cells.begin(), cells.end());
  std::vector<uint32_t> trial;
  for (uint32_t cell : cells) {
    for (uint32_t f = 0; f < kFaceCount; ++f) trial.push_back(cell * kFaceCount + f);
  }
  return trial;
}

Status code_faces(CodingJob& job) { return Pipeline(job).run(); }

}  // namespace svc
