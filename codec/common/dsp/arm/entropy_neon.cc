// SPDX-License-Identifier: BSD-2-Clause
// NEON symbol search of the range decoder: the interval bounds
// scale * cumulative[k - 1] + k of four symbols a register (a multiply-accumulate: the
// products fit 32 bits), compared with the code as unsigned numbers, and the all-ones
// lanes of the bounds at or below it summed across, among the count - 1 that exist. Most
// distributions have 3 or 4 symbols, so counts up to 4 take one register and counts up
// to 8 two; only 16 take all four.
#include <arm_neon.h>

#include "codec/common/dsp/dsp_init.h"

namespace svc::codec::dsp {
namespace {

// All ones in lane i where symbol first + i exists and its bound is at or below the code;
// `first` holds first + i in lane i, `last` the last symbol, count - 1.
uint32x4_t at_or_below(uint16x4_t entries, uint32_t scale, uint32x4_t first, uint32x4_t last, uint32x4_t code) {
  const uint32x4_t bound = vmlaq_n_u32(first, vmovl_u16(entries), scale);
  return vandq_u32(vcleq_u32(bound, code), vcleq_u32(first, last));
}

int find_symbol_neon(const uint16_t* cumulative, int count, uint32_t scale, uint32_t code) {
  static constexpr uint32_t kFirst[4] = {1, 2, 3, 4};
  const uint32x4_t first = vld1q_u32(kFirst), four = vdupq_n_u32(4);
  const uint32x4_t last = vdupq_n_u32(static_cast<uint32_t>(count - 1)), codes = vdupq_n_u32(code);
  // The lanes are 0 or all ones (-1): their sum is minus the number of symbols below.
  if (count <= 4)
    return -static_cast<int>(vaddvq_u32(at_or_below(vld1_u16(cumulative), scale, first, last, codes)));
  const uint16x8_t low = vld1q_u16(cumulative);
  const uint32x4_t fifth = vaddq_u32(first, four);
  uint32x4_t sum = vaddq_u32(at_or_below(vget_low_u16(low), scale, first, last, codes),
                             at_or_below(vget_high_u16(low), scale, fifth, last, codes));
  if (count > 8) {
    const uint16x8_t high = vld1q_u16(cumulative + 8);
    const uint32x4_t ninth = vaddq_u32(fifth, four);
    sum = vaddq_u32(sum, vaddq_u32(at_or_below(vget_low_u16(high), scale, ninth, last, codes),
                                   at_or_below(vget_high_u16(high), scale, vaddq_u32(ninth, four), last, codes)));
  }
  return -static_cast<int>(vaddvq_u32(sum));
}

}  // namespace

void init_entropy_neon(DspTable* table) { table->find_symbol = find_symbol_neon; }

}  // namespace svc::codec::dsp
