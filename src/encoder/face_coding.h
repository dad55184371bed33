// Coding of one B-face from its references: shared by a full encode and by `svc add`,
// so both code new faces identically.
#pragma once

#include <array>
#include <memory>
#include <mutex>
#include <vector>

#include "codec/bframe_codec.h"
#include "database/database.h"
#include "spatial/reprojection.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

struct CodedPredictedFace {
  std::vector<uint8_t> payload;
  codec::BFrameStats stats;
  CandidateStats candidates;  // unique depth candidates before any cap, over references
};

// One reference of a B-face: its reconstructed I-face (as the decoder will see it) and
// the camera that took it.
struct FaceReference {
  const ImageYCbCr420* image = nullptr;
  const Camera* camera = nullptr;
};

// Buffers code_predicted_face reuses from face to face: a fresh face-sized flow field per
// face costs more (zero-filling, page faults) than the flow computed into it.
struct PredictedFaceScratch {
  FlowField flow;
};

// The scratch buffers of one encode, shared by its worker threads: a call takes one for
// its duration and puts it back, so there are as many as calls ever ran at once. Freed
// with the pool. Thread-safe.
class PredictedFaceScratchPool {
 public:
  std::unique_ptr<PredictedFaceScratch> take();
  void put_back(std::unique_ptr<PredictedFaceScratch> scratch);

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<PredictedFaceScratch>> free_;
};

// Codes `data` (colour and eye depth of the face taken by `camera`) as a B-face
// predicted from one or two references. Motion comes from depth reprojection
// (candidates and warp nodes) or from logarithmic search. `what` names the face in
// errors. `scratch` (optional) lends reusable buffers; the result does not depend on it.
// Thread-safe.
Result<CodedPredictedFace> code_predicted_face(const FaceData& data, const Camera& camera,
                                               const std::vector<FaceReference>& references, bool motion_from_depth,
                                               const codec::BFrameParams& params, const std::string& what,
                                               PredictedFaceScratchPool* scratch = nullptr);

}  // namespace svc
