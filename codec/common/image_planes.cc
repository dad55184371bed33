// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/image_planes.h"

#include <cstddef>
#include <vector>

namespace svc::codec {
namespace {

// Appends rows instead of resizing first: a resize would zero the whole plane only for
// the copy to overwrite it.
void copy_rows(const uint8_t* plane, int stride, int width, int height, std::vector<uint8_t>* out) {
  out->clear();
  out->reserve(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = plane + static_cast<ptrdiff_t>(y) * stride;
    out->insert(out->end(), row, row + width);
  }
}

}  // namespace

void copy_planes_to_image(const std::array<const uint8_t*, 3>& planes, const std::array<int, 3>& strides, int width,
                          int height, ImageYCbCr420* out) {
  out->width = width;
  out->height = height;
  const int chroma_width = (width + 1) / 2, chroma_height = (height + 1) / 2;
  copy_rows(planes[0], strides[0], width, height, &out->y);
  copy_rows(planes[1], strides[1], chroma_width, chroma_height, &out->cb);
  copy_rows(planes[2], strides[2], chroma_width, chroma_height, &out->cr);
}

}  // namespace svc::codec
