// SPDX-License-Identifier: BSD-2-Clause
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

size_t pixel_row_bytes(PixelFormat format, int width, int plane) noexcept {
  if (width <= 0 || plane < 0 || plane > 2) return 0;
  const auto w = static_cast<size_t>(width);
  switch (format) {
    case PixelFormat::kRGBA8:
    case PixelFormat::kBGRA8: return plane == 0 ? 4 * w : 0;
    case PixelFormat::kRGB8: return plane == 0 ? 3 * w : 0;
    case PixelFormat::kYCbCr420: return plane == 0 ? w : (w + 1) / 2;
  }
  return 0;
}

size_t pixel_plane_rows(PixelFormat format, int height, int plane) noexcept {
  if (height <= 0 || plane < 0 || plane > 2) return 0;
  const auto h = static_cast<size_t>(height);
  if (format == PixelFormat::kYCbCr420) return plane == 0 ? h : (h + 1) / 2;
  const bool packed = format == PixelFormat::kRGBA8 || format == PixelFormat::kBGRA8 ||
                      format == PixelFormat::kRGB8;
  return packed && plane == 0 ? h : 0;
}

}  // namespace svc
