// SPDX-License-Identifier: BSD-2-Clause
// The MD5 of a stream's decoded output, as the conformance suite records it
// (docs/conformance.md): every cell in the reader's order, every face in Face order, its
// Y, Cb and Cr planes row by row; then, in a file with depth, every face's inverse-depth
// codes as little-endian u16, in the same order. Shared by the checker and the generator.
#pragma once

#include <filesystem>
#include <string>

#include "svc/status.h"

namespace svc::conformance {

struct DecodeSettings {
  int threads = 1;        // the reader's decode_threads
  bool prefetch = false;  // prefetch workers running beside the walk (set_viewer per cell)
  // Off: no decoded-face or reference cache, so that every reference I-face is rebuilt
  // from its semi-decoded form in the coefficient cache (another path to the same pixels).
  bool face_caches = true;
};

// 32 lowercase hex digits; the reader's error when any face fails to decode.
Result<std::string> stream_md5(const std::filesystem::path& stream, const DecodeSettings& settings);

}  // namespace svc::conformance
