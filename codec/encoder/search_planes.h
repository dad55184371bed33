// SPDX-License-Identifier: BSD-2-Clause
// Encoder only: a reference face's luma at the four half-pel phases (whole, half across,
// half down, half both), filtered once with the regular 8-tap filter and edge-extended
// by a margin, so that the motion search prices a candidate vector with one SAD instead
// of an interpolation. Quarter-pel positions are approximated by the rounded-up average
// of the two nearest half-pel samples (as H.264 defines them); the search only ranks
// vectors, and the chosen one is then predicted exactly (motion_compensation.h).
//
// Immutable once built; thread-safe to read. Holds its own copies of the samples.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "codec/common/motion.h"
#include "svc/types.h"

namespace svc::codec {

class SearchPlanes {
 public:
  // `margin` samples of edge extension beyond each side of the reference's luma plane.
  SearchPlanes(const ImageYCbCr420& reference, int margin);

  // SAD of the width x height source block (width 8 or 16, height 1..16) against the
  // reference block whose top-left sample is (x, y) in reference luma coordinates,
  // displaced by the quarter-pel `vector`; -1 when the block leaves the planes.
  int sad(const uint8_t* source, int source_stride, int x, int y, int width, int height, MotionVector vector) const;

  // The reference's luma size and the margin the planes were built with.
  int width() const { return width_; }
  int height() const { return height_; }
  int margin() const { return margin_; }
  // Bytes held, for callers that cache planes.
  uint64_t bytes() const;

 private:
  // The sample at half-pel coordinates (hx, hy) (2 per luma sample), or null when a
  // block of this size starting there leaves the planes.
  const uint8_t* at(int hx, int hy, int width, int height) const;

  int width_ = 0, height_ = 0, margin_ = 0, stride_ = 0;
  std::array<std::vector<uint8_t>, 4> phases_;  // [2 * (hy & 1) + (hx & 1)]
};

}  // namespace svc::codec
