// SPDX-License-Identifier: BSD-2-Clause
#include "reader/pixel_buffer.h"

#include <cstring>
#include <string>

#include "codec/common/color.h"
#include "codec/common/depth.h"

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

Status check_depth_buffer(const DepthBuffer& buffer, int width, int height) {
  if (buffer.format != DepthFormat::kEyeZ32F && buffer.format != DepthFormat::kInverse16) {
    return Status(ErrorCode::kInvalidArgument,
                  "depth buffer: unknown depth format " + std::to_string(static_cast<int>(buffer.format)));
  }
  if (buffer.rows != RowOrder::kTopDown && buffer.rows != RowOrder::kBottomUp) {
    return Status(ErrorCode::kInvalidArgument,
                  "depth buffer: unknown row order " + std::to_string(static_cast<int>(buffer.rows)));
  }
  const size_t row_bytes = static_cast<size_t>(width) * (buffer.format == DepthFormat::kEyeZ32F ? 4 : 2);
  const auto rows = static_cast<size_t>(height);
  if (buffer.stride < row_bytes) {
    return Status(ErrorCode::kInvalidArgument, "depth buffer: stride " + std::to_string(buffer.stride) +
                                                   " is below the " + std::to_string(row_bytes) +
                                                   " bytes of a row of a " + std::to_string(width) + "-pixel face");
  }
  if (buffer.data == nullptr || buffer.size < row_bytes || (buffer.size - row_bytes) / buffer.stride < rows - 1) {
    return Status(ErrorCode::kInvalidArgument,
                  "depth buffer holds " + std::to_string(buffer.size) + " bytes, a " + std::to_string(width) + "x" +
                      std::to_string(height) + " face needs " + std::to_string(rows) + " rows of " +
                      std::to_string(row_bytes) + " bytes " + std::to_string(buffer.stride) + " bytes apart");
  }
  return Status::Ok();
}

void write_depth(const std::vector<uint16_t>& codes, int width, int height, double near_plane,
                 const DepthBuffer& buffer) {
  auto* out = static_cast<uint8_t*>(buffer.data);
  for (int y = 0; y < height; ++y) {
    const int row = buffer.rows == RowOrder::kTopDown ? y : height - 1 - y;
    uint8_t* line = out + static_cast<size_t>(row) * buffer.stride;
    const uint16_t* in = codes.data() + static_cast<size_t>(y) * width;
    if (buffer.format == DepthFormat::kInverse16) {
      std::memcpy(line, in, static_cast<size_t>(width) * sizeof(uint16_t));
      continue;
    }
    for (int x = 0; x < width; ++x) {
      const float z = codec::eye_depth_of_code(in[x], near_plane);
      std::memcpy(line + static_cast<size_t>(x) * sizeof(float), &z, sizeof(float));
    }
  }
}

}  // namespace svc::reader_internal
