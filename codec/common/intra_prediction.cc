// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/intra_prediction.h"

#include <algorithm>
#include <cstring>

#include "codec/common/transform_size.h"

namespace svc::codec {
void build_intra_edge(const uint8_t* plane, ptrdiff_t stride, int x0, int y0, TransformSize size,
                      const EdgeAvailability& available, uint8_t* edge) {
  const int w = transform_width(size), h = transform_height(size);
  const int corner = w + h, samples = 2 * (w + h) + 1;
  if (!available.left && !available.above) {
    std::memset(edge, 128, static_cast<size_t>(samples));
    return;
  }
  const uint8_t* origin = plane + static_cast<ptrdiff_t>(y0) * stride + x0;
  if (available.left) {
    const int rows = available.below_left ? w + h : h;
    for (int i = 0; i < rows; ++i) edge[corner - 1 - i] = origin[i * stride - 1];
    if (!available.below_left) std::memset(edge, edge[corner - h], static_cast<size_t>(w));
  }
  if (available.above) {
    const int columns = available.above_right ? w + h : w;
    std::memcpy(edge + corner + 1, origin - stride, static_cast<size_t>(columns));
    if (!available.above_right) std::memset(edge + corner + 1 + w, edge[corner + w], static_cast<size_t>(h));
  }
  if (available.left && available.above) {
    edge[corner] = origin[-stride - 1];
  } else if (available.left) {
    std::memset(edge + corner, edge[corner - 1], static_cast<size_t>(w + h + 1));
  } else {
    std::memset(edge, edge[corner + 1], static_cast<size_t>(w + h + 1));
  }
}

IntraPredictor intra_predictor(TransformSize size) { return dsp::get_dsp().intra_predict[size_index(size)]; }

ModeCandidates most_probable_modes(int left_mode, int above_mode) {
  const int left_class = std::min(left_mode, 2);  // planar, DC, angular
  if (left_mode == above_mode) {
    if (left_mode < 2) return {{kPlanarMode, kDcMode, kVerticalMode}, left_class};
    // The mode and its two angular neighbours (wrapping within 2..33).
    return {{left_mode, 2 + (left_mode + 29) % 32, 2 + (left_mode - 2 + 1) % 32}, left_class};
  }
  int third = kVerticalMode;
  if (left_mode != kPlanarMode && above_mode != kPlanarMode) {
    third = kPlanarMode;
  } else if (left_mode != kDcMode && above_mode != kDcMode) {
    third = kDcMode;
  }
  return {{left_mode, above_mode, third}, 3 + left_class};
}

int mode_size_class(TransformSize size) {
  const int area = transform_area(size);
  return area < 64 ? 0 : area == 64 ? 1 : 2;
}

}  // namespace svc::codec
