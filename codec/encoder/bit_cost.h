// SPDX-License-Identifier: BSD-2-Clause
// The encoder's bit estimates: -log2 of a context's current probability of a bit, as a
// table read, so that rate-distortion decisions price syntax without coding it.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

#include "codec/common/adaptive_bit.h"

namespace svc::codec {

// -log2 of a probability in steps of 8/32768, built once; inline so the per-bit cost
// of the encoder's estimates is a table read, not a call.
std::array<float, 4097> make_cost_table();
// A namespace-scope table, not a function's static: no guard check on every bit.
inline const std::array<float, 4097> kCostTable = make_cost_table();

inline float bit_cost(const AdaptiveBit& model, int bit) {
  uint32_t p = model.probability_of_zero();
  if (bit) p = kProbabilityOne - p;
  return kCostTable[std::min<uint32_t>(p >> 3, 4096)];
}

inline float exp_golomb_bits(uint32_t value) { return static_cast<float>(2 * (std::bit_width(value + 1) - 1) + 1); }

}  // namespace svc::codec
