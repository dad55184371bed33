#include "encoder/face_coding.h"

#include "codec/color.h"
#include "codec/log_search.h"

namespace svc {

std::unique_ptr<PredictedFaceScratch> PredictedFaceScratchPool::take() {
  std::lock_guard lock(mutex_);
  if (free_.empty()) return std::make_unique<PredictedFaceScratch>();
  std::unique_ptr<PredictedFaceScratch> scratch = std::move(free_.back());
  free_.pop_back();
  return scratch;
}

void PredictedFaceScratchPool::put_back(std::unique_ptr<PredictedFaceScratch> scratch) {
  std::lock_guard lock(mutex_);
  free_.push_back(std::move(scratch));
}

Result<CodedPredictedFace> code_predicted_face(const FaceData& data, const Camera& camera,
                                               const std::vector<FaceReference>& references, bool motion_from_depth,
                                               const codec::BFrameParams& params, const std::string& what,
                                               PredictedFaceScratchPool* scratch_pool) {
  if (references.empty() || references.size() > 2) {
    return Status(ErrorCode::kInternal, what + ": a B-face needs one or two references");
  }
  const ImageYCbCr420 ycc = codec::rgb_to_ycbcr420(data.color.pixels.data(), data.color.width, data.color.height);
  std::array<codec::FaceCandidates, 2> candidates;
  // Depth also gives each reference a warp node field (per-pixel flow, sent compactly).
  std::array<codec::WarpField, 2> warps;
  CodedPredictedFace coded;
  std::unique_ptr<PredictedFaceScratch> scratch;
  if (motion_from_depth) scratch = scratch_pool ? scratch_pool->take() : std::make_unique<PredictedFaceScratch>();
  for (size_t r = 0; r < references.size(); ++r) {
    if (motion_from_depth) {
      FlowField& flow = scratch->flow;
      compute_flow(camera, *references[r].camera, data.color.width, data.color.height, data.depth, &flow);
      candidates[r] = macroblock_candidates(flow);
      warps[r] = warp_nodes(flow);
    } else {
      candidates[r] = codec::log_search_candidates(ycc, *references[r].image);
    }
    coded.candidates += candidate_stats(candidates[r]);
  }
  if (scratch_pool != nullptr && scratch != nullptr) scratch_pool->put_back(std::move(scratch));
  const ImageYCbCr420* second = references.size() > 1 ? references[1].image : nullptr;
  coded.payload = codec::encode_b_frame(ycc, *references[0].image, second, candidates[0], candidates[1], &warps[0],
                                        &warps[1], params, nullptr, &coded.stats);
  if (coded.payload.empty()) return Status(ErrorCode::kInternal, what + ": B-frame coding failed");
  return coded;
}

}  // namespace svc
