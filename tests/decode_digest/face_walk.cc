// SPDX-License-Identifier: BSD-2-Clause
#include "decode_digest/face_walk.h"

#include <array>
#include <set>

namespace svc::testing {

namespace {

constexpr size_t kRowPadding = 3;

constexpr std::array<svc_pixel_format, 4> kFormats = {SVC_PIXEL_RGBA8, SVC_PIXEL_BGRA8, SVC_PIXEL_RGB8,
                                                      SVC_PIXEL_YCBCR420};
constexpr std::array<svc_row_order, 2> kRowOrders = {SVC_ROWS_TOP_DOWN, SVC_ROWS_BOTTOM_UP};

// A buffer for one face, its planes' bytes kept in `storage`.
struct FaceBuffer {
  svc_image image{};
  std::array<std::vector<uint8_t>, 3> storage;
  std::array<size_t, 3> row_bytes{};
  std::array<size_t, 3> rows{};
};

FaceBuffer make_buffer(svc_pixel_format format, svc_row_order order, int32_t width, int32_t height) {
  FaceBuffer b;
  b.image.format = format;
  b.image.rows = order;
  for (int p = 0; p < 3; ++p) {
    b.row_bytes[p] = svc_pixel_row_bytes(format, width, p);
    b.rows[p] = svc_pixel_plane_rows(format, height, p);
    if (b.rows[p] == 0) continue;
    b.image.strides[p] = b.row_bytes[p] + kRowPadding;
    b.storage[p].assign(b.rows[p] * b.image.strides[p], 0xA5);
    b.image.planes[p] = b.storage[p].data();
    b.image.plane_sizes[p] = b.storage[p].size();
  }
  return b;
}

// The rows' bytes without the padding, which the decoder leaves alone.
void hash_pixels(const FaceBuffer& b, Sha256& sha) {
  for (int p = 0; p < 3; ++p) {
    for (size_t r = 0; r < b.rows[p]; ++r) {
      sha.update(std::span<const uint8_t>(b.storage[p].data() + r * b.image.strides[p], b.row_bytes[p]));
    }
  }
}

std::string error_line(const std::array<int32_t, 3>& cell, svc_face face, svc_status status) {
  return "cell " + std::to_string(cell[0]) + "," + std::to_string(cell[1]) + "," + std::to_string(cell[2]) +
         " face " + std::to_string(static_cast<int>(face)) + ": " + svc_status_name(status);
}

}  // namespace

WalkResult walk_faces(const std::vector<std::array<int32_t, 3>>& cells, int32_t width, int32_t height,
                      const FaceDecoder& decode) {
  WalkResult result;
  Sha256 sha;
  std::set<std::string> seen;
  for (const auto& cell : cells) {
    for (int f = 0; f < 6; ++f) {
      const auto face = static_cast<svc_face>(f);
      for (const svc_pixel_format format : kFormats) {
        for (const svc_row_order order : kRowOrders) {
          FaceBuffer buffer = make_buffer(format, order, width, height);
          const svc_status status = decode(cell.data(), face, buffer.image);
          const uint8_t code = static_cast<uint8_t>(status);
          sha.update(std::span<const uint8_t>(&code, 1));
          if (status == SVC_OK) {
            hash_pixels(buffer, sha);
            ++result.faces;
          } else if (seen.insert(error_line(cell, face, status)).second) {
            result.errors.push_back(error_line(cell, face, status));
          }
        }
      }
    }
  }
  result.digest = sha.hex_digest();
  return result;
}

}  // namespace svc::testing
