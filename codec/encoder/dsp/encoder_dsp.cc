// SPDX-License-Identifier: BSD-2-Clause
// Builds the encoder's kernel table by the shared table's rules (codec/common/dsp/dsp.cc):
// plain references first, then each x86 or NEON variant whose CPU features are present,
// so the most capable variant of each kernel wins.
#include "codec/encoder/dsp/encoder_dsp.h"

#include "codec/encoder/dsp/encoder_dsp_init.h"

namespace svc::codec::dsp {

EncoderDspTable make_encoder_dsp_table([[maybe_unused]] unsigned cpu_flags) {
  EncoderDspTable table{};
  init_forward_transform_c(&table);
  init_forward_transform_4_16_c(&table);
  init_forward_transform_types_c(&table);
  init_quantize_c(&table);
  init_sad_c(&table);
  init_satd_c(&table);
#if defined(__x86_64__) || defined(__i386__)
  if (cpu_flags & kCpuSse2) {
    init_sad_sse2(&table);
    init_forward_transform_sse2(&table);
  }
  if ((cpu_flags & (kCpuSse2 | kCpuSse41)) == (kCpuSse2 | kCpuSse41)) {
    init_satd_sse41(&table);
    init_forward_transform_4_16_sse41(&table);
    init_forward_transform_types_sse41(&table);
    init_quantize_sse41(&table);
  }
  if ((cpu_flags & (kCpuSse2 | kCpuSse41 | kCpuAvx2)) == (kCpuSse2 | kCpuSse41 | kCpuAvx2)) {
    init_forward_transform_4_16_avx2(&table);
    init_satd_avx2(&table);
  }
#elif defined(__aarch64__)
  // The float kernels have no NEON variant (docs/kernels.md).
  if (cpu_flags & kCpuNeon) {
    init_sad_neon(&table);
    init_satd_neon(&table);
  }
#endif
  return table;
}

const EncoderDspTable& build_process_encoder_dsp_table() {
  static const EncoderDspTable table = make_encoder_dsp_table(active_cpu_flags());  // once, thread-safe
  return table;
}

}  // namespace svc::codec::dsp
