// SPDX-License-Identifier: BSD-2-Clause
// Every face of every cell of an .svc file in every pixel format and row order, in one
// fixed order, hashed: the same bytes give the same digest on every platform and
// through every way of opening the file.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "support/sha256.h"
#include "svc/svc.h"

namespace svc::testing {

// Decodes one face of the cell at grid index `cell` into `out`; an svc_status.
using FaceDecoder = std::function<svc_status(const int32_t cell[3], svc_face face, const svc_image& out)>;

struct WalkResult {
  std::string digest;               // SHA-256 of every decoded byte and every error code
  uint64_t faces = 0;               // decodes that succeeded
  std::vector<std::string> errors;  // "cell x,y,z face F: status", once per face
};

// Decodes the faces of `cells` (grid indices) through `decode`, each into a buffer whose
// rows are a few bytes longer than the face's, so that strides are exercised too.
WalkResult walk_faces(const std::vector<std::array<int32_t, 3>>& cells, int32_t width, int32_t height,
                      const FaceDecoder& decode);

}  // namespace svc::testing
