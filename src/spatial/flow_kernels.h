// SPDX-License-Identifier: BSD-2-Clause
// The encoder's per-pixel flow kernels behind one table of function pointers, chosen
// once by CPU features as codec/common/dsp/dsp.h does for the codec's kernels (the same
// detected flags and SVC_CPU_MASK): a plain C++ reference, always compiled, and x86
// variants that must match it bit for bit. docs/kernels.md describes the pattern;
// svc-checkkernels compares every variant with its reference.
#pragma once

#include <cstddef>
#include <cstdint>

namespace svc {

// Points closer to the reference camera plane than this (scene units, or direction
// units for background) count as behind it: their projection is meaningless or huge.
constexpr double kMinDepthInFront = 1e-9;

// One row of compute_flow: pixel i's ray in reference camera space is
// z (column_i + row_term) + translation (or column_i + row_term alone for background),
// projected by the reference frustum's p00, p02, p11, p12 into a width x height window.
struct FlowRow {
  const double* column_x;  // per pixel: a_i times the x, y, z of the rotation's first column
  const double* column_y;
  const double* column_z;
  double row_x, row_y, row_z;        // b_j col_y - col_z
  double shift_x, shift_y, shift_z;  // the translation
  double p00, p02, p11, p12;
  double width, height;  // of the face, pixels
  double far_plane;      // depths at or beyond it are background
  int row;               // j
  int count;             // pixels in the row
};

struct FlowKernels {
  // Flow (dx, dy) and validity of `row.count` pixels from their depths; invalid pixels
  // get dx = dy = 0.
  void (*flow_row)(const FlowRow& row, const float* depth, float* dx, float* dy, uint8_t* valid);
  // Quarter-pel keys (y * 65536 + x) of `count` pixels: each component rounded to the
  // nearest quarter pixel, halves away from zero, kept only within +-limit (limit <= 32767)
  // and for valid pixels; `no_key` otherwise.
  void (*quarter_pel_keys)(const float* dx, const float* dy, const uint8_t* valid, size_t count, int limit,
                           int32_t no_key, int32_t* keys);
  // Bit i set where a run of equal keys ends at key i of a row of 16: key i differs from
  // key i + 1, or i is the last.
  unsigned (*run_ends_16)(const int32_t* row);
};

// The table for this machine (codec::dsp::active_cpu_flags()), built once; thread-safe.
const FlowKernels& get_flow_kernels();
// A table using only variants whose features are in `cpu_flags` (0: plain references).
FlowKernels make_flow_kernels(unsigned cpu_flags);

}  // namespace svc
