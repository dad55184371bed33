#include "encoder/coding_pipeline.h"

#include <string>

#include "codec/bframe_codec.h"
#include "codec/color.h"
#include "codec/intra_codec.h"
#include "common/parallel.h"
#include "encoder/face_coding.h"

namespace svc {

namespace {

struct CodedIntra {
  std::vector<uint8_t> payload;
  ImageYCbCr420 reconstruction;
};

class Pipeline {
 public:
  explicit Pipeline(CodingJob& job) : job_(job), index_(*job.index) {
    for (uint32_t frame : job.frames) {
      (index_.frames[frame].type == FaceType::kIntra ? intra_ : predicted_).push_back(frame);
    }
    intra_params_.quant_scale = static_cast<int>(index_.coding.quant_scale);
    b_params_.quant_scale = codec::suggested_b_quant_scale(intra_params_.quant_scale);
    b_params_.warp = job.tools.warped_prediction;
    b_params_.sub_pel_refinement = job.tools.sub_pel_refinement;
    b_params_.quarter_pel = job.tools.quarter_pel;
    b_params_.switchable_filter = job.tools.switchable_filter;
  }

  Status run() {
    SVC_RETURN_IF_ERROR(ordered_parallel_map<CodedIntra>(
        intra_.size(), job_.threads, [&](size_t k) { return code_intra(intra_[k]); },
        [&](size_t k, CodedIntra& coded) { return store_intra(intra_[k], coded); }));
    return ordered_parallel_map<CodedPredictedFace>(
        predicted_.size(), job_.threads, [&](size_t k) { return code_predicted(predicted_[k]); },
        [&](size_t k, CodedPredictedFace& coded) { return store_predicted(predicted_[k], coded); });
  }

 private:
  Result<CodedIntra> code_intra(uint32_t frame) const {
    SVC_ASSIGN_OR_RETURN(FaceData data, job_.load(frame));
    const ImageYCbCr420 ycc = codec::rgb_to_ycbcr420(data.color.pixels.data(), data.color.width, data.color.height);
    CodedIntra coded;
    coded.payload = codec::encode_intra_frame(ycc, intra_params_, &coded.reconstruction);
    return coded;
  }

  Status store_intra(uint32_t frame, CodedIntra& coded) {
    SVC_RETURN_IF_ERROR(store(frame, coded.payload));
    const codec::BlockLayout layout =
        codec::block_layout(static_cast<int>(index_.face_width), static_cast<int>(index_.face_height));
    index_.stats[0].mb_intra += uint64_t(layout.luma_blocks_x / 2) * uint64_t(layout.luma_blocks_y / 2);
    // Kept only while a B-face may still use it.
    if (!predicted_.empty()) job_.reconstructions.emplace(frame, std::move(coded.reconstruction));
    return Status::Ok();
  }

  Result<CodedPredictedFace> code_predicted(uint32_t frame) const {
    const FrameRecord& record = index_.frames[frame];
    const int f = static_cast<int>(record.face);
    SVC_ASSIGN_OR_RETURN(FaceData data, job_.load(frame));
    std::vector<FaceReference> refs;
    for (uint32_t ref : record.references) {
      refs.push_back({&job_.reconstructions.at(ref), &index_.cells[index_.frames[ref].cell].cameras[f]});
    }
    return code_predicted_face(data, index_.cells[record.cell].cameras[f], refs,
                               index_.coding.motion == MotionSearch::kDepth, b_params_, frame_name(frame));
  }

  Status store_predicted(uint32_t frame, const CodedPredictedFace& coded) {
    SVC_RETURN_IF_ERROR(store(frame, coded.payload));
    FaceTypeStats& s = index_.stats[1];
    s.mb_intra += coded.stats.mb_intra;
    s.mb_forward += coded.stats.mb_forward;
    s.mb_backward += coded.stats.mb_backward;
    s.mb_bidirectional += coded.stats.mb_bidirectional;
    s.mb_skipped += coded.stats.mb_skipped;
    s.candidate_vectors += coded.candidates.candidates;
    s.candidate_macroblocks += coded.candidates.macroblocks;
    return Status::Ok();
  }

  // Appends the chunk, fills in the frame record and reports progress.
  Status store(uint32_t frame, const std::vector<uint8_t>& payload) {
    SVC_ASSIGN_OR_RETURN(uint64_t offset, job_.append(payload));
    FrameRecord& record = index_.frames[frame];
    record.chunk_offset = offset;
    record.payload_size = static_cast<uint32_t>(payload.size());
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
  std::vector<uint32_t> intra_, predicted_;
  codec::CodingParams intra_params_;
  codec::BFrameParams b_params_;
  uint64_t done_ = 0;
};

}  // namespace

Status code_faces(CodingJob& job) { return Pipeline(job).run(); }

}  // namespace svc
