// SPDX-License-Identifier: BSD-2-Clause
// Plain value types shared by the svc encoder and reader APIs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "svc/export.h"

namespace svc {

// The six faces of a cell's cube map, named by the axis each face looks along.
enum class Face : uint8_t { kPX = 0, kNX = 1, kPY = 2, kNY = 3, kPZ = 4, kNZ = 5 };
inline constexpr int kFaceCount = 6;
inline constexpr std::array<Face, kFaceCount> kAllFaces = {Face::kPX, Face::kNX, Face::kPY,
                                                           Face::kNY, Face::kPZ, Face::kNZ};

// "px", "nx", "py", "ny", "pz", "nz".
SVC_API const char* face_name(Face face) noexcept;
SVC_API std::optional<Face> face_from_name(std::string_view name) noexcept;

// A cell's integer coordinates in the grid (x, y, z); y counts layers when y is up.
struct CellIndex {
  int32_t x = 0, y = 0, z = 0;
  friend bool operator==(const CellIndex&, const CellIndex&) = default;
};

// "cell (x,y,z)", the way every message names a cell.
SVC_API std::string cell_label(const CellIndex& cell);
// "cell (x,y,z) face px".
SVC_API std::string face_label(const CellIndex& cell, Face face);

// How a face is coded: on its own (an I-face, in an I-cube) or predicted from up to
// two reference I-faces (a B-face, in a B-cube). The value is the first byte of every
// coded face and its type in the index.
enum class FaceType : uint8_t { kIntra = 0, kPredicted = 1 };

// Where a B-face's motion comes from.
enum class MotionSearch : uint8_t {
  kDepth = 0,        // candidates from depth and camera reprojection (default)
  kLogarithmic = 1,  // image-space logarithmic search in a 64-pixel window
};

// glFrustum parameters of a face's perspective projection.
struct Frustum {
  double left = -1, right = 1, bottom = -1, top = 1, near_plane = 0.05, far_plane = 100;
};

// The camera of one face: OpenGL view matrix (column-major, as GLM stores it) and frustum.
struct Camera {
  std::array<double, 16> world_to_camera{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  Frustum frustum;
};

// An 8-bit RGB image, tightly packed (3 bytes a pixel, no row padding), row 0 at the top.
struct ImageRGB8 {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  // width * height * 3
};

// An 8-bit YCbCr 4:2:0 image in three planes, each tightly packed, row 0 at the top.
// Chroma planes are ((width+1)/2) x ((height+1)/2). The color conversion is the one
// documented in docs/codec.md (full-range BT.601, as JFIF).
struct ImageYCbCr420 {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> y, cb, cr;
};

// The layouts a face can be decoded into (Reader::decode_face_into): the formats GPUs
// upload and the decoder's own planes.
enum class PixelFormat : uint8_t {
  kRGBA8 = 0,     // 4 bytes a pixel in memory order R, G, B, A; alpha is 255
  kBGRA8 = 1,     // B, G, R, A
  kRGB8 = 2,      // 3 bytes a pixel: R, G, B
  kYCbCr420 = 3,  // planes Y (width x height), Cb and Cr ((width+1)/2 x (height+1)/2),
                  // full-range BT.601 as docs/codec.md defines it, as decoded
};

// Whether a buffer's first row is the image's top (as images are stored) or its bottom
// (as OpenGL's texture uploads take rows).
enum class RowOrder : uint8_t { kTopDown = 0, kBottomUp = 1 };

// A caller's buffer to decode a face into. Packed formats use planes[0] alone; YCbCr
// 4:2:0 uses the three. Rows of plane p start strides[p] bytes apart (at least the row's
// bytes: padding at the end of each row is left untouched), so planes[p] must hold
// (rows - 1) * strides[p] + the row's bytes (pixel_row_bytes, pixel_plane_rows). The
// buffer is the caller's: the decoder writes into it and keeps no reference.
struct PixelBuffer {
  PixelFormat format = PixelFormat::kRGBA8;
  RowOrder rows = RowOrder::kTopDown;
  std::array<std::span<uint8_t>, 3> planes{};
  std::array<size_t, 3> strides{};
};

// How a face's depth is decoded into a caller's buffer (Reader::decode_face_depth_into).
enum class DepthFormat : uint8_t {
  // float: eye-space depth, the distance along the face camera's view axis (positive, in
  // scene units); +infinity where the face saw no geometry.
  kEyeZ32F = 0,
  // uint16_t: the coded inverse depth, round(65535 near / z) with `near` the face
  // camera's near plane, clamped to 1..65535 (docs/codec.md 8.1); 0 without geometry.
  kInverse16 = 1,
};

// A caller's buffer to decode a face's depth into: `size` bytes at `data`, rows `stride`
// bytes apart (at least width * 4 for kEyeZ32F, width * 2 for kInverse16; any
// alignment). The buffer is the caller's: the decoder writes into it and keeps no
// reference.
struct DepthBuffer {
  DepthFormat format = DepthFormat::kEyeZ32F;
  RowOrder rows = RowOrder::kTopDown;
  void* data = nullptr;
  size_t stride = 0;
  size_t size = 0;
};

// The bytes of one row and the number of rows of plane `plane` (0..2) of a width x height
// face in `format`; 0 for a plane the format does not have. Thread-safe.
SVC_API size_t pixel_row_bytes(PixelFormat format, int width, int plane) noexcept;
SVC_API size_t pixel_plane_rows(PixelFormat format, int height, int plane) noexcept;

// Statistics of one frame type (I or B) over a whole encode, kept in the .svc index.
struct FaceTypeStats {
  uint64_t faces = 0;
  uint64_t bytes = 0;
  uint64_t mb_intra = 0;
  uint64_t mb_forward = 0;
  uint64_t mb_backward = 0;
  uint64_t mb_bidirectional = 0;
  uint64_t mb_skipped = 0;         // predicted with no residual
  uint64_t candidate_vectors = 0;  // unique candidates summed over predicted faces' macroblocks
  uint64_t candidate_macroblocks = 0;
};

}  // namespace svc
