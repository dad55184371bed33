// SPDX-License-Identifier: BSD-2-Clause
// SSE4.1 symbol search of the range decoder: the interval bounds
// scale * cumulative[k - 1] + k of four symbols a register (pmulld: the products fit 32
// bits), compared with the code as unsigned numbers, and the bounds at or below it
// counted among the count - 1 that exist (the entries past them are ignored, whatever
// they hold). Most distributions have 3 or 4 symbols, so counts up to 4 take one
// register and counts up to 8 two; only larger counts take all four.
#include <smmintrin.h>

#include <cstdint>

#include "codec/common/dsp/dsp_init.h"

#pragma GCC target("sse4.1")

namespace svc::codec::dsp {
namespace {

// Set bits of a mask below 16, from a table of 16 nibbles: SSE4.1 does not imply the
// popcnt instruction (Penryn has one without the other).
int bit_count4(unsigned mask) { return static_cast<int>((0x4332322132212110ull >> (4 * mask)) & 15); }
int bit_count8(unsigned mask) { return bit_count4(mask & 15) + bit_count4(mask >> 4); }
// The same below 2^16, adding bits in pairs, nibbles, then bytes.
int bit_count16(unsigned mask) {
  mask -= mask >> 1 & 0x5555;
  mask = (mask & 0x3333) + (mask >> 2 & 0x3333);
  mask = (mask + (mask >> 4)) & 0x0F0F;
  return static_cast<int>((mask + (mask >> 8)) & 31);
}

// Bit i set where the bound of symbol first + i lies above the code, for four symbols
// whose entries are the 32-bit lanes of `entries`. Adding 2^31 to both sides flips their
// top bits, so the signed comparison orders them as unsigned numbers: `first` holds
// first + i + 2^31 in lane i and `code` the code + 2^31.
unsigned above_code(__m128i entries, __m128i scale, __m128i first, __m128i code) {
  const __m128i bound = _mm_add_epi32(_mm_mullo_epi32(entries, scale), first);
  return static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(bound, code))));
}

int find_symbol_sse41(const uint16_t* cumulative, int count, uint32_t scale, uint32_t code) {
  const __m128i scales = _mm_set1_epi32(static_cast<int>(scale));
  const __m128i codes = _mm_set1_epi32(static_cast<int>(code ^ 0x80000000u));
  const __m128i first = _mm_setr_epi32(INT32_MIN + 1, INT32_MIN + 2, INT32_MIN + 3, INT32_MIN + 4);
  const __m128i four = _mm_set1_epi32(4);
  const unsigned exists = (1u << (count - 1)) - 1;  // bit k - 1 for the symbols k = 1 .. count - 1
  if (count <= 4) {
    const __m128i entries = _mm_cvtepu16_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(cumulative)));
    return bit_count4(~above_code(entries, scales, first, codes) & exists);
  }
  const __m128i low = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cumulative));
  const __m128i fifth = _mm_add_epi32(first, four);
  unsigned above = above_code(_mm_cvtepu16_epi32(low), scales, first, codes) |
                   above_code(_mm_cvtepu16_epi32(_mm_srli_si128(low, 8)), scales, fifth, codes) << 4;
  if (count <= 8) return bit_count8(~above & exists);
  const __m128i high = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cumulative + 8));
  const __m128i ninth = _mm_add_epi32(fifth, four);
  above |= above_code(_mm_cvtepu16_epi32(high), scales, ninth, codes) << 8 |
           above_code(_mm_cvtepu16_epi32(_mm_srli_si128(high, 8)), scales, _mm_add_epi32(ninth, four), codes) << 12;
  return bit_count16(~above & exists);
}

}  // namespace

void init_entropy_sse41(DspTable* table) { table->find_symbol = find_symbol_sse41; }

}  // namespace svc::codec::dsp
