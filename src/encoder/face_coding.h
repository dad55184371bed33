// SPDX-License-Identifier: BSD-2-Clause
// Coding of one B-face from its references: shared by a full encode and by `svc add`,
// so both code new faces identically.
#pragma once

#include <array>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/encoder/bframe_encoder.h"
#include "database/database.h"
#include "spatial/reprojection.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

struct CodedPredictedFace {
  std::vector<uint8_t> payload;
  codec::BFrameStats stats;
  CandidateStats candidates;           // unique depth candidates before any cap, over references
  std::vector<uint8_t> depth_payload;  // empty without depth
  // Per reference, the cube-border edges its predictions read (codec::BorderEdges).
  std::array<uint8_t, 2> border_edges{};
};

// One reference of a B-face: its reconstructed I-face (as the decoder will see it), the
// camera that took it and, optionally, its search planes (codec::b_frame_search_planes
// of `image`, shared by the B-faces of one reference; null: built for this face).
struct FaceReference {
  const ImageYCbCr420* image = nullptr;
  const Camera* camera = nullptr;
  const codec::SearchPlanes* search = nullptr;
};

// The encoder's guard against writing what no decoder reads: decodes the I-face
// `payload` and compares it with the encoder's `reconstruction` of it (its cost:
// docs/bench.md, "Figures behind code constants"). kInternal naming `what` when the decoder rejects the payload or
// decodes other pixels: a bug in svc, reported instead of written. Thread-safe.
Status check_intra_payload(const std::vector<uint8_t>& payload, const ImageYCbCr420& reconstruction,
                           const std::string& what);

// Codes `data` (color and eye depth of the face taken by `camera`) as a B-face
// predicted from one or two references. Motion comes from depth reprojection
// (candidates and warp nodes) or from logarithmic search. The payload is decoded again
// and must give the encoder's reconstruction (as check_intra_payload). `what` names the
// face in errors. Thread-safe.
Result<CodedPredictedFace> code_predicted_face(const FaceData& data, const Camera& camera,
                                               const std::vector<FaceReference>& references, bool motion_from_depth,
                                               const codec::BFrameParams& params, const std::string& what);

}  // namespace svc
