// SPDX-License-Identifier: BSD-2-Clause
// Builds the kernel table: plain references first, then each x86 or NEON variant whose
// CPU features are present, so the most capable variant of each kernel wins.
#include "codec/common/dsp/dsp.h"

#include <cstdlib>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {

unsigned detected_cpu_flags() {
  unsigned flags = 0;
#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  if (__builtin_cpu_supports("sse2")) flags |= kCpuSse2;
  if (__builtin_cpu_supports("sse4.1")) flags |= kCpuSse41;
  if (__builtin_cpu_supports("avx2")) flags |= kCpuAvx2;
#elif defined(__aarch64__)
  flags |= kCpuNeon;  // part of the AArch64 base architecture
#endif
  return flags;
}

unsigned active_cpu_flags() {
  static const unsigned flags = [] {
    unsigned result = detected_cpu_flags();
    if (const char* mask = std::getenv("SVC_CPU_MASK"); mask != nullptr && *mask != '\0') {
      char* end = nullptr;
      const unsigned long value = std::strtoul(mask, &end, 0);
      if (end != nullptr && *end == '\0') result &= static_cast<unsigned>(value);  // else ignored: not a number
    }
    return result;
  }();
  return flags;
}

DspTable make_dsp_table(unsigned cpu_flags) {
  DspTable table{};
  init_transform_c(&table);
  init_transform_4_16_c(&table);
  init_transform_types_c(&table);
  init_quant_c(&table);
  init_color_c(&table);
  init_mc_c(&table);
  init_intra_c(&table);
  init_deblock_c(&table);
  init_cdef_c(&table);
  init_cfl_c(&table);
  init_pad_c(&table);
#if defined(__x86_64__) || defined(__i386__)
  if (cpu_flags & kCpuSse2) {
    init_mc_sse2(&table);
    init_transform_sse2(&table);
    init_color_sse2(&table);
  }
  if ((cpu_flags & (kCpuSse2 | kCpuSse41)) == (kCpuSse2 | kCpuSse41)) {
    init_color_sse41(&table);
    init_intra_sse41(&table);
    init_transform_4_16_sse41(&table);
    init_transform_types_sse41(&table);
    init_mc_sse41(&table);
    init_deblock_sse41(&table);
    init_cdef_sse41(&table);
    init_cfl_sse41(&table);
    init_quant_sse41(&table);
  }
  if ((cpu_flags & (kCpuSse2 | kCpuSse41 | kCpuAvx2)) == (kCpuSse2 | kCpuSse41 | kCpuAvx2)) {
    init_mc_avx2(&table);
    init_cdef_avx2(&table);
    init_color_avx2(&table);
    init_pad_avx2(&table);
  }
#elif defined(__aarch64__)
  if (cpu_flags & kCpuNeon) {
    init_transform_neon(&table);
    init_transform_4_16_neon(&table);
    init_transform_types_neon(&table);
    init_quant_neon(&table);
    init_color_neon(&table);
    init_mc_neon(&table);
    init_intra_neon(&table);
    init_deblock_neon(&table);
    init_cdef_neon(&table);
    init_cfl_neon(&table);
  }
#endif
  return table;
}

const DspTable& build_process_dsp_table() {
  static const DspTable table = make_dsp_table(active_cpu_flags());  // initialised once, thread-safe
  return table;
}

}  // namespace svc::codec::dsp
