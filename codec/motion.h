// Motion vectors and per-macroblock candidate lists shared by the motion sources
// (depth reprojection in src/spatial, image search in codec) and the B-frame coder.
#pragma once

#include <cstdint>
#include <vector>

namespace svc::codec {

inline constexpr int kMacroblockSize = 16;

// A luma displacement in half-pixel units: the prediction for pixel (x, y) of the
// current face is taken at (x + x/2, y + y/2) in the reference face.
struct MotionVector {
  int16_t x = 0;
  int16_t y = 0;
  friend bool operator==(const MotionVector&, const MotionVector&) = default;
};

// Candidate vectors of one macroblock towards one reference, distinct, in the order
// the motion source ranks them (most pixels first).
using CandidateList = std::vector<MotionVector>;

// Candidates for every macroblock of a face (row-major macroblock order) for one
// reference. Faces are padded to whole macroblocks: ceil(w/16) x ceil(h/16) entries.
using FaceCandidates = std::vector<CandidateList>;

}  // namespace svc::codec
