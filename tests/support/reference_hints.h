// SPDX-License-Identifier: BSD-2-Clause
// encode_b_frame's per-reference hints from candidate lists and warp node fields alone: no
// partition lists, no epipolar lines, search planes built by the encoder.
#pragma once

#include <array>

#include "codec/encoder/bframe_encoder.h"

namespace svc::codec {

inline std::array<ReferenceHints, 2> candidate_hints(const FaceCandidates& candidates0,
                                                     const FaceCandidates& candidates1,
                                                     const WarpField* warp0 = nullptr,
                                                     const WarpField* warp1 = nullptr) {
  return {ReferenceHints{&candidates0, nullptr, warp0, {}}, ReferenceHints{&candidates1, nullptr, warp1, {}}};
}

}  // namespace svc::codec
