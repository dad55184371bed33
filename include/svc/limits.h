// SPDX-License-Identifier: BSD-2-Clause
// Caps on what an .svc file may make the reader allocate. Every field read from a file
// is checked against these, in 64-bit arithmetic, before it sizes an allocation; a file
// above a cap is refused with kLimitExceeded naming the field and its byte offset. The
// defaults suit any database the encoder makes; a caller handling untrusted files lowers
// them through ReaderSettings::limits (docs/format.md, "Validation and caps").
#pragma once

#include <cstdint>

namespace svc {

struct ReaderLimits {
  uint32_t max_face_dimension = 16384;      // width or height of a face, pixels
  uint64_t max_face_pixels = 64ull << 20;   // width * height
  uint64_t max_cells = 1u << 22;            // cells in the index
  uint64_t max_index_bytes = 1ull << 30;    // size of the index chunk
  uint64_t max_frame_bytes = 256ull << 20;  // one coded face
  int32_t max_grid_dimension = 1 << 20;     // cells along one axis
};

}  // namespace svc
