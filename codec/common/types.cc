#include "svc/types.h"

namespace svc {

namespace {
constexpr const char* kFaceNames[kFaceCount] = {"px", "nx", "py", "ny", "pz", "nz"};
}

const char* face_name(Face face) noexcept {
  const auto i = static_cast<unsigned>(face);
  return i < kFaceCount ? kFaceNames[i] : "invalid-face";
}

std::optional<Face> face_from_name(std::string_view name) noexcept {
  for (int i = 0; i < kFaceCount; ++i) {
    if (name == kFaceNames[i]) return static_cast<Face>(i);
  }
  return std::nullopt;
}

std::string cell_label(const CellIndex& cell) {
  return "cell (" + std::to_string(cell.x) + "," + std::to_string(cell.y) + "," + std::to_string(cell.z) + ")";
}

std::string face_label(const CellIndex& cell, Face face) { return cell_label(cell) + " face " + face_name(face); }

}  // namespace svc
