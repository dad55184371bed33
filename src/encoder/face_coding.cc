// SPDX-License-Identifier: BSD-2-Clause
#include "encoder/face_coding.h"

#include "codec/common/intra_frame.h"
#include "codec/common/thread_slot.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/log_search.h"
#include "codec/encoder/rgb_to_ycbcr.h"
#include "spatial/epipolar_lines.h"

namespace svc {

namespace {

// What check_intra_payload reports for a decode that gave `status` and `decoded`.
Status compare_with_reconstruction(const Status& status, const ImageYCbCr420& decoded,
                                   const ImageYCbCr420& reconstruction, const std::string& what) {
  if (!status.ok()) {
    return Status(ErrorCode::kInternal, what + ": the encoder coded a payload its decoder rejects (" +
                                            status.message() + "); this is a bug in svc, nothing was written");
  }
  if (decoded.y != reconstruction.y || decoded.cb != reconstruction.cb || decoded.cr != reconstruction.cr) {
    return Status(ErrorCode::kInternal, what +
                                            ": the coded payload decodes to other pixels than the encoder's "
                                            "reconstruction; this is a bug in svc, nothing was written");
  }
  return Status::Ok();
}

}  // namespace

Status check_intra_payload(const std::vector<uint8_t>& payload, const ImageYCbCr420& reconstruction,
                           const std::string& what) {
  ImageYCbCr420 decoded;
  const Status status = codec::decode_intra_frame(payload, reconstruction.width, reconstruction.height, &decoded);
  return compare_with_reconstruction(status, decoded, reconstruction, what);
}

Result<CodedPredictedFace> code_predicted_face(const FaceData& data, const Camera& camera,
                                               const std::vector<FaceReference>& references, bool motion_from_depth,
                                               const codec::BFrameParams& params, const std::string& what) {
  if (references.empty() || references.size() > 2) {
    return Status(ErrorCode::kInternal, what + ": a B-face needs one or two references");
  }
  const ImageYCbCr420 ycc = codec::rgb_to_ycbcr420(data.color.pixels.data(), data.color.width, data.color.height);
  std::array<codec::FaceCandidates, 2> candidates, block_lists;
  // Depth also gives each reference a warp node field (per-pixel flow, sent compactly).
  std::array<codec::WarpField, 2> warps;
  CodedPredictedFace coded;
  // One field for both references, kept by the thread from face to face: compute_flow
  // reuses its storage, which spares the pages a fresh field would fault in.
  FlowField& flow = codec::thread_object<FlowField>();
  for (size_t r = 0; r < references.size(); ++r) {
    if (motion_from_depth) {
      compute_flow(camera, *references[r].camera, data.color.width, data.color.height, data.depth, &flow);
      candidates[r] = macroblock_candidates(flow);
      if (params.partitions) block_lists[r] = block_candidates(flow);
      warps[r] = warp_nodes(flow);
    } else {
      candidates[r] = codec::log_search_candidates(ycc, *references[r].image);
    }
    coded.candidates += candidate_stats(candidates[r]);
  }
  const ImageYCbCr420* second = references.size() > 1 ? references[1].image : nullptr;
  std::array<codec::ReferenceHints, 2> hints = {
      codec::ReferenceHints{&candidates[0], &block_lists[0], &warps[0], {}},
      codec::ReferenceHints{&candidates[1], &block_lists[1], &warps[1], {}}};
  for (size_t r = 0; r < references.size(); ++r) {
    hints[r].lines = epipolar_lines(camera, *references[r].camera, data.color.width, data.color.height);
    hints[r].search = references[r].search;
  }
  ImageYCbCr420 reconstruction, decoded;
  coded.payload =
      codec::encode_b_frame(ycc, *references[0].image, second, hints, params, &reconstruction, &coded.stats);
  if (coded.payload.empty()) return Status(ErrorCode::kInternal, what + ": B-face coding failed");
  codec::BorderEdges edges;
  const Status status = codec::decode_b_frame(coded.payload, ycc.width, ycc.height, *references[0].image, second,
                                              &decoded, nullptr, nullptr, nullptr, &edges);
  SVC_RETURN_IF_ERROR(compare_with_reconstruction(status, decoded, reconstruction, what));
  coded.border_edges = edges.read;
  return coded;
}

}  // namespace svc
