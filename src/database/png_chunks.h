// SPDX-License-Identifier: BSD-2-Clause
// A PNG file's chunk structure, checked before the image library reads it: libpng
// prints its own lines on stderr when it meets a truncated or damaged file, so such a
// file is caught here and reported by svc alone.
#pragma once

#include <filesystem>
#include <string>

#include "svc/status.h"

namespace svc {

// Ok for a file that is not a PNG (no PNG signature). For a PNG: every chunk fits in the
// file and matches its CRC-32, and IEND is reached. Errors are kBadInput, prefixed with
// `what` and naming the byte offset and chunk at fault.
Status check_png_chunks(const std::filesystem::path& path, const std::string& what);

}  // namespace svc
