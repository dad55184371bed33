// SPDX-License-Identifier: BSD-2-Clause
#include "reader/pixel_buffer.h"

#include <string>

#include "codec/common/color.h"

namespace svc::reader_internal {

namespace {

const char* format_name(PixelFormat format) {
  switch (format) {
    case PixelFormat::kRGBA8: return "RGBA8";
    case PixelFormat::kBGRA8: return "BGRA8";
    case PixelFormat::kRGB8: return "RGB8";
    case PixelFormat::kYCbCr420: return "YCbCr 4:2:0";
  }
  return "unknown";
}

}  // namespace

Status check_pixel_buffer(const PixelBuffer& buffer, int width, int height) {
  const auto format_value = static_cast<int>(buffer.format);
  if (format_value > static_cast<int>(PixelFormat::kYCbCr420)) {
    return Status(ErrorCode::kInvalidArgument,
                  "pixel buffer: unknown pixel format " + std::to_string(format_value));
  }
  if (buffer.rows != RowOrder::kTopDown && buffer.rows != RowOrder::kBottomUp) {
    return Status(ErrorCode::kInvalidArgument,
                  "pixel buffer: unknown row order " + std::to_string(static_cast<int>(buffer.rows)));
  }
  const std::string face = std::to_string(width) + "x" + std::to_string(height) + " " + format_name(buffer.format);
  for (int p = 0; p < 3; ++p) {
    const size_t row_bytes = pixel_row_bytes(buffer.format, width, p),
                 rows = pixel_plane_rows(buffer.format, height, p);
    if (row_bytes == 0 || rows == 0) continue;
    const auto plane = static_cast<size_t>(p);
    const size_t stride = buffer.strides[plane];
    if (stride < row_bytes) {
      return Status(ErrorCode::kInvalidArgument,
                    "pixel buffer: plane " + std::to_string(p) + "'s stride " + std::to_string(stride) +
                        " is below the " + std::to_string(row_bytes) + " bytes of a row of a " + face + " face");
    }
    // (rows - 1) * stride + row_bytes, without overflow.
    const size_t available = buffer.planes[plane].size();
    if (buffer.planes[plane].data() == nullptr || available < row_bytes ||
        (available - row_bytes) / stride < rows - 1) {
      return Status(ErrorCode::kInvalidArgument,
                    "pixel buffer: plane " + std::to_string(p) + " holds " + std::to_string(available) +
                        " bytes, a " + face + " face needs " + std::to_string(rows) + " rows of " +
                        std::to_string(row_bytes) + " bytes " + std::to_string(stride) + " bytes apart");
    }
  }
  return Status::Ok();
}

void write_pixels(const ImageYCbCr420& image, const PixelBuffer& buffer) {
  codec::ycbcr420_to_pixels(image, buffer.format, buffer.rows,
                            {buffer.planes[0].data(), buffer.planes[1].data(), buffer.planes[2].data()},
                            buffer.strides);
}

}  // namespace svc::reader_internal
