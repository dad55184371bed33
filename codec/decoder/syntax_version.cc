// SPDX-License-Identifier: BSD-2-Clause
#include "codec/decoder/syntax_version.h"

#include <string>

namespace svc::codec {

Status check_syntax_version(std::string_view payload, int version, int first, int latest) {
  if (version >= first && version <= latest) return Status();
  const std::string reads = first == latest ? std::to_string(first)
                                            : std::to_string(first) + " to " + std::to_string(latest);
  const std::string why = version < first ? " predates format 1.0" : " is newer than this build knows";
  return Status(ErrorCode::kUnsupported, std::string(payload) + ": byte 0: syntax version " +
                                             std::to_string(version) + why + " (this build reads " + reads + ")");
}

}  // namespace svc::codec
