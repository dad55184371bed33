// SPDX-License-Identifier: BSD-2-Clause
#include "codec/encoder/search_planes.h"

#include <algorithm>

#include "codec/common/motion_compensation.h"
#include "codec/encoder/dsp/encoder_dsp.h"

namespace svc::codec {

SearchPlanes::SearchPlanes(const ImageYCbCr420& reference, int margin)
    : width_(reference.width), height_(reference.height), margin_(margin) {
  constexpr int kTile = 16;
  const int tiles_x = (width_ + 2 * margin_ + kTile - 1) / kTile,
            tiles_y = (height_ + 2 * margin_ + kTile - 1) / kTile;
  stride_ = tiles_x * kTile;
  for (int phase = 0; phase < 4; ++phase) {
    std::vector<uint8_t>& plane = phases_[static_cast<size_t>(phase)];
    plane.resize(static_cast<size_t>(stride_) * tiles_y * kTile);
    int16_t intermediate[kTile * kTile];
    for (int ty = 0; ty < tiles_y; ++ty) {
      for (int tx = 0; tx < tiles_x; ++tx) {
        predict_block(reference.y.data(), width_, height_, PlaneKind::kLuma, kTile * tx - margin_,
                      kTile * ty - margin_, kTile, kTile, 2 * (phase & 1), 2 * (phase >> 1), intermediate, kTile);
        for (int y = 0; y < kTile; ++y) {
          round_prediction(intermediate + kTile * y, kTile,
                           plane.data() + static_cast<size_t>(kTile * ty + y) * stride_ + kTile * tx);
        }
      }
    }
  }
}

uint64_t SearchPlanes::bytes() const {
  uint64_t total = sizeof(*this);
  for (const std::vector<uint8_t>& plane : phases_) total += plane.capacity();
  return total;
}

const uint8_t* SearchPlanes::at(int hx, int hy, int width, int height) const {
  const int x = (hx >> 1) + margin_, y = (hy >> 1) + margin_;
  // Rows are stride_ long but only width_ + 2 margin_ samples of them are filtered.
  if (x < 0 || y < 0 || x + width > width_ + 2 * margin_ || y + height > height_ + 2 * margin_) return nullptr;
  return phases_[static_cast<size_t>(2 * (hy & 1) + (hx & 1))].data() + static_cast<size_t>(y) * stride_ + x;
}

int SearchPlanes::sad(const uint8_t* source, int source_stride, int x, int y, int width, int height,
                      MotionVector vector) const {
  const int qx = 4 * x + vector.x, qy = 4 * y + vector.y;
  // Half-pel coordinates of the two samples averaged: equal at whole and half positions;
  // across, down or diagonally apart at quarter positions.
  const int ax = (qx - (qx & 1)) >> 1, bx = (qx + (qx & 1)) >> 1;
  const int ay = (qy - (qy & 1)) >> 1, by = (qy + (qy & 1)) >> 1;
  const uint8_t* a = at(ax, ay, width, height);
  const uint8_t* b = at(bx, by, width, height);
  if (a == nullptr || b == nullptr) return -1;
  return dsp::get_encoder_dsp().sad_average(source, source_stride, a, b, stride_, width, height);
}

}  // namespace svc::codec
