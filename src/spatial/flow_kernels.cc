// SPDX-License-Identifier: BSD-2-Clause
// The plain flow kernels and the table that picks a variant per CPU.
#include "spatial/flow_kernels.h"

#include "codec/common/dsp/dsp.h"
#include "spatial/flow_kernels_init.h"

namespace svc {
namespace {

void flow_row_c(const FlowRow& row, const float* depth, float* dx, float* dy, uint8_t* valid) {
  for (int i = 0; i < row.count; ++i) flow_pixel(row, i, depth[i], &dx[i], &dy[i], &valid[i]);
}

void quarter_pel_keys_c(const float* dx, const float* dy, const uint8_t* valid, size_t count, int limit,
                        int32_t no_key, int32_t* keys) {
  for (size_t i = 0; i < count; ++i) keys[i] = quarter_pel_key(dx[i], dy[i], valid[i], limit, no_key);
}

unsigned run_ends_16_c(const int32_t* row) {
  unsigned ends = 0x8000u;
  for (int i = 0; i + 1 < 16; ++i) ends |= static_cast<unsigned>(row[i] != row[i + 1]) << i;
  return ends;
}

}  // namespace

FlowKernels make_flow_kernels(unsigned cpu_flags) {
  FlowKernels kernels{flow_row_c, quarter_pel_keys_c, run_ends_16_c};
#if defined(__x86_64__) || defined(__i386__)
  if (cpu_flags & codec::dsp::kCpuSse2) init_flow_sse2(&kernels);
#else
  (void)cpu_flags;
#endif
  return kernels;
}

const FlowKernels& get_flow_kernels() {
  static const FlowKernels kernels = make_flow_kernels(codec::dsp::active_cpu_flags());  // once, thread-safe
  return kernels;
}

}  // namespace svc
