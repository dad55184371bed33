// SPDX-License-Identifier: BSD-2-Clause
// The frame payloads' syntax versions a decoder reads: every one from the version format
// 1.0 froze to the newest this build knows (docs/codec.md 1.1). A payload of any other
// version is refused as unsupported, saying whether it predates format 1.0 or comes from
// a newer encoder, so that a user knows which side to update.
#pragma once

#include <string_view>

#include "svc/status.h"

namespace svc::codec {

// kUnsupported naming `payload` ("intra frame", "B-face", "depth"), the byte the version
// is in and the versions this build reads, unless first <= version <= latest.
Status check_syntax_version(std::string_view payload, int version, int first, int latest);

}  // namespace svc::codec
