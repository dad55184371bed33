// Constrained directional enhancement (docs/codec.md, section 11.2), in the manner of
// AV1's CDEF (sections 7.15.2, 7.15.3): after deblocking, each 8x8 luma block (and its 4x4
// chroma blocks) is smoothed along its dominant direction (primary taps) and lightly
// across it (secondary taps), every tap limited by a constraint that spares edges. The
// frame header lists a few strength presets; every 64x64 filter unit picks one or none.
// Bit-exact integer arithmetic; the pixel work is in the dsp table.
//
// Threading: every function is reentrant; filter different frames on different threads.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/common/loop_filter.h"
#include "codec/common/range_coder.h"

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

// Writes / reads the filter's syntax (section 11.2) at the end of a frame's range-coded
// data. Every bit pattern reads as valid parameters; truncation shows in the decoder's
// truncated().
// `params` must hold units_x x units_y unit entries, each at most its preset count.
void write_cdef_syntax(RangeEncoder& encoder, const CdefParams& params, int units_x, int units_y);
void read_cdef_syntax(RangeDecoder& decoder, int units_x, int units_y, CdefParams* params);

// Filters the macroblock-padded planes of a 4:2:0 frame in place (luma multiple of 16 on
// each side, chroma half). `skip` is empty or holds one entry per luma 8x8 block, row-
// major; a non-zero entry leaves the block (and its chroma) unfiltered. Parameters, skip
// map or planes of the wrong size leave the frame unfiltered.
void cdef_frame(const CdefParams& params, int qindex, std::span<const uint8_t> skip,
                const std::array<PlaneView, 3>& planes);

// Encoder only: the presets and unit choices that minimise squared error against
// `source` (visible planes, stride = width) plus lambda per estimated bit; no presets
// when the filter does not pay. `planes` is left unchanged. `every_candidate` false: the
// presets come from every other one of the candidate strengths (7 of 14), in half the
// time.
struct CdefSource {
  std::array<const uint8_t*, 3> planes{};
  std::array<int, 3> strides{};
  int width = 0, height = 0;  // visible luma size
};
CdefParams choose_cdef(const std::array<PlaneView, 3>& planes, const CdefSource& source, int qindex,
                       std::span<const uint8_t> skip, double lambda, bool every_candidate = true);

}  // namespace svc::codec
