// SPDX-License-Identifier: BSD-2-Clause
// Image-space motion search: the two-dimensional logarithmic search of J. R. Jain and
// A. K. Jain ("Displacement measurement and its application in interframe image coding",
// IEEE Trans. Communications 29(12), 1981), as the standard alternative to motion vectors
// derived from depth. It produces one candidate vector per macroblock in the same form
// as the depth-based source (FaceCandidates), so encode_b_frame can be fed with either
// and the two compared on the same faces.
//
// Pure and thread-safe; the encoder only (not part of the bitstream).
#pragma once

#include <cstdint>

#include "codec/common/motion.h"
#include "svc/types.h"

namespace svc::codec {

enum class LogSearchPattern : uint8_t {
  // Jain & Jain: the centre and the 4 points +-step along each axis; the centre moves
  // with the same step until it wins, then the step halves; 3x3 at step 1.
  kCross = 0,
  // The variant the dissertation describes (and MPEG software encoders ship as
  // "logarithmic"): the centre and the 8 points at +-step (corners and side midpoints),
  // the step halving after every round: a fixed 8 x log2(window) + 1 points.
  kNinePoint = 1,
};

struct LogSearchParams {
  // The dissertation's Table 7.4 comparison uses the nine-point pattern.
  LogSearchPattern pattern = LogSearchPattern::kNinePoint;
  // Search window: integer displacements within +-window pixels in each direction
  // (32 gives the 64-pixel window of the dissertation's comparison).
  int window = 32;
  // After the integer search, tries the 8 half-pel neighbours of the best vector.
  bool half_pel = true;
};

struct LogSearchStats {
  int64_t sad_evaluations = 0;  // SADs computed, over all macroblocks
};

// Per macroblock of `source` (padded to whole macroblocks by replication), the vector
// towards `reference` (same size) with the least luma SAD found by the search, kCross:
//   step = 2^(floor(log2 window) - 1) (16 for a 32-pixel window); centre = (0, 0);
//   repeat: score the centre and the four points +-step along x and y (inside the
//   window); if the best is the centre, or lies on the window boundary, move there and
//   halve the step, else move there keeping the step; until the step is 1, when the
//   eight neighbours of the centre are scored and the best taken.
// kNinePoint: the same first step; each round scores the 8 points at +-step around the
// centre (inside the window), moves to the best and halves the step, through step 1.
// Ties keep the earlier point (centre first, then row-major offsets).
// Like every image-space search, both can settle in a false minimum on periodic or
// strongly oriented texture (the aperture problem); that is the behaviour compared. Reference samples
// outside the face are edge-extended as in motion compensation. Returns one list of one
// vector (quarter-pel units) per macroblock, row-major; empty for inconsistent images.
FaceCandidates log_search_candidates(const ImageYCbCr420& source, const ImageYCbCr420& reference,
                                     const LogSearchParams& params = {}, LogSearchStats* stats = nullptr);

}  // namespace svc::codec
