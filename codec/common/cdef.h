// SPDX-License-Identifier: BSD-2-Clause
// Constrained directional enhancement (docs/codec.md, section 5.8.2), in the manner of
// AV1's CDEF (sections 7.15.2, 7.15.3): after deblocking, each 8x8 luma block (and its 4x4
// chroma blocks) is smoothed along its dominant direction (primary taps) and lightly
// across it (secondary taps), every tap limited by a constraint that spares edges. The
// frame header lists a few strength presets; every 64x64 filter unit picks one or none.
// Bit-exact integer arithmetic; the pixel work is in the dsp table.
//
// Threading: every function is reentrant; filter different frames on different threads.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/common/adaptive_bit.h"
#include "codec/common/dsp/dsp.h"
#include "codec/common/loop_filter.h"
#include "codec/common/thread_buffers.h"

namespace svc::codec {

inline constexpr int kCdefUnitSize = 64;  // luma samples per filter unit side
inline constexpr int kCdefMaxPresets = 4;

struct CdefStrength {
  uint8_t primary = 0;         // 0..15
  uint8_t secondary_code = 0;  // 0..3: secondary strength 0, 1, 2, 4
};

// The filter of one frame: its presets and, per 64x64 unit in raster order, 0 (off) or
// the 1-based preset number.
struct CdefParams {
  std::vector<CdefStrength> presets;  // 1..kCdefMaxPresets when the filter is on
  std::vector<uint8_t> unit_presets;
  size_t memory_bytes() const { return presets.capacity() * sizeof(CdefStrength) + unit_presets.capacity(); }
};

// Filter units along a padded luma side of `samples` samples: ceil(samples / 64).
int cdef_units(int samples);

// The filter's syntax (section 5.8.2) at the end of a frame's range-coded data is read by
// codec/decoder/cdef_syntax.h and written by codec/encoder/cdef_search.h.

// Filters the macroblock-padded planes of a 4:2:0 frame in place (luma multiple of 16 on
// each side, chroma half). `skip` is empty or holds one entry per luma 8x8 block, row-
// major; a non-zero entry leaves the block (and its chroma) unfiltered. Parameters, skip
// map or planes of the wrong size leave the frame unfiltered.
void cdef_frame(const CdefParams& params, int qindex, std::span<const uint8_t> skip,
                const std::array<PlaneView, 3>& planes);

// The pieces of the filter and its syntax that the filter, the syntax reader and writer
// and the encoder's search share (internal to codec/).
namespace cdef {

inline constexpr int kBorder = 2;  // samples read beyond a block on each side

// Contexts of the unit syntax, fresh for every frame.
struct CdefContexts {
  AdaptiveBit unit_on[3];                        // by left + above units on
  AdaptiveBit preset_more[kCdefMaxPresets - 1];  // truncated unary, per position
};

inline int unit_on_context(const std::vector<uint8_t>& units, int units_x, int ux, int uy) {
  const size_t index = static_cast<size_t>(uy) * units_x + ux;
  return (ux > 0 && units[index - 1] != 0) + (uy > 0 && units[index - units_x] != 0);
}

inline int damping_of(int qindex) { return 3 + (std::clamp(qindex, 0, 255) >> 6); }
inline int secondary_of(int code) { return code == 3 ? 4 : code; }

// Primary strength scaled by the block's directional contrast (none on flat blocks).
inline int adjusted_primary(int primary, int32_t variance) {
  if (variance == 0) return 0;
  const int scale = (variance >> 6) != 0
                        ? std::min(static_cast<int>(std::bit_width(static_cast<uint32_t>(variance >> 6))) - 1, 12)
                        : 0;
  return (primary * (4 + scale) + 8) >> 4;
}

inline bool planes_fit(const std::array<PlaneView, 3>& planes) {
  const int w = planes[0].width, h = planes[0].height;
  if (planes[0].data == nullptr || w <= 0 || h <= 0 || w % 16 != 0 || h % 16 != 0 || planes[0].stride < w) {
    return false;
  }
  for (int p = 1; p < 3; ++p) {
    if (planes[p].data == nullptr || planes[p].width != w / 2 || planes[p].height != h / 2 ||
        planes[p].stride < w / 2) {
      return false;
    }
  }
  return true;
}

// The planes widened to 16 bits inside a kBorder frame of kCdefUnavailable, so that
// every block's taps read in place, at the plane's edge as well. Each sample is written
// once per frame. The buffers are the calling thread's, kept from frame to frame: a
// fresh allocation of this size costs page faults on every frame.
class WidenedPlanes {
 public:
  explicit WidenedPlanes(const std::array<PlaneView, 3>& planes)
      : thread_(thread_buffers<std::array<std::vector<uint16_t>, 3>>()) {
    for (int p = 0; p < 3; ++p) widen(planes[p], p);
    thread_.share.set(capacity_bytes(thread_.buffers[0]) + capacity_bytes(thread_.buffers[1]) +
                      capacity_bytes(thread_.buffers[2]));
  }
  WidenedPlanes(const WidenedPlanes&) = delete;
  WidenedPlanes& operator=(const WidenedPlanes&) = delete;
  const uint16_t* at(int p, int x, int y) const { return thread_.buffers[p].data() + index(p, x, y); }
  int stride(int p) const { return strides_[p]; }

 private:
  void widen(const PlaneView& plane, int p) {
    const int stride = plane.width + 2 * kBorder, rows = plane.height + 2 * kBorder;
    strides_[p] = stride;
    std::vector<uint16_t>& buffer = thread_.buffers[p];
    if (buffer.size() < static_cast<size_t>(stride) * rows) buffer.resize(static_cast<size_t>(stride) * rows);
    uint16_t* data = buffer.data();
    std::fill_n(data, static_cast<size_t>(stride) * kBorder, dsp::kCdefUnavailable);
    std::fill_n(data + static_cast<size_t>(stride) * (rows - kBorder), static_cast<size_t>(stride) * kBorder,
                dsp::kCdefUnavailable);
    for (int y = 0; y < plane.height; ++y) {
      uint16_t* row = data + index(p, 0, y);
      std::fill_n(row - kBorder, kBorder, dsp::kCdefUnavailable);
      std::copy_n(plane.data + static_cast<ptrdiff_t>(y) * plane.stride, plane.width, row);
      std::fill_n(row + plane.width, kBorder, dsp::kCdefUnavailable);
    }
  }
  size_t index(int p, int x, int y) const {
    return static_cast<size_t>(y + kBorder) * static_cast<size_t>(strides_[p]) + static_cast<size_t>(x + kBorder);
  }

  // One set per thread (codec/common/thread_buffers.h); a thread holds one WidenedPlanes
  // at a time.
  ThreadBuffers<std::array<std::vector<uint16_t>, 3>>& thread_;
  std::array<int, 3> strides_{};
};

}  // namespace cdef

}  // namespace svc::codec
