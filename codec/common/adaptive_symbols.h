// SPDX-License-Identifier: BSD-2-Clause
// The adaptive distribution of a syntax element of 2 to 16 values, coded as one symbol
// (docs/codec.md 2.3) by the range decoder (codec/decoder/range_decoder.h) and encoder
// (codec/encoder/range_encoder.h), in the manner of AV1's multi-symbol coder.
// Threading: AdaptiveSymbols is plain data.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "codec/common/adaptive_bit.h"

namespace svc::codec {

inline constexpr int kMaxSymbols = 16;

// cumulative[k - 1] (k = 1 .. count - 1) is the probability, in 1/32768 units, that the
// symbol is below k: non-decreasing, at most 32767. Entries from count - 1 on are unused.
struct AdaptiveSymbols {
  // From this many symbols on, the adaptation rate stays at its slowest.
  static constexpr uint8_t kSettled = 32;

  alignas(32) std::array<uint16_t, kMaxSymbols> cumulative{};
  uint8_t count = 2;
  uint8_t seen = 0;  // symbols coded so far, saturating at kSettled

  AdaptiveSymbols() : AdaptiveSymbols(2) {}
  // `symbols` equiprobable values (2..16).
  explicit AdaptiveSymbols(int symbols) : count(static_cast<uint8_t>(symbols)) {
    for (int k = 1; k < symbols; ++k) {
      cumulative[static_cast<size_t>(k - 1)] = static_cast<uint16_t>((kProbabilityOne * k + symbols / 2) / symbols);
    }
  }

  // Starts at trained cumulative probabilities (count - 1 of them); adapts from there
  // as fast as a fresh distribution.
  void prime(std::span<const uint16_t> trained) {
    for (size_t k = 0; k + 1 < count && k < trained.size(); ++k) cumulative[k] = trained[k];
  }

  // Moves the distribution towards `symbol` by 2^-rate of the way, the rate growing
  // from 4 (3 values or fewer) or 5 to 6 or 7 as symbols are seen.
  void update(int symbol) {
    const int rate = 3 + (seen > 15) + (seen > 31) + (count > 3 ? 2 : 1);
    seen = static_cast<uint8_t>(seen + (seen < kSettled));
    for (int k = 1; k < count; ++k) {
      uint16_t& c = cumulative[static_cast<size_t>(k - 1)];
      if (k <= symbol) {
        c = static_cast<uint16_t>(c - (c >> rate));
      } else {
        c = static_cast<uint16_t>(c + ((kProbabilityOne - 1 - c) >> rate));
      }
    }
  }

  // Probability of `symbol` in 1/32768 units (for the encoder's estimates).
  uint32_t probability(int symbol) const {
    const uint32_t below = symbol == 0 ? 0 : cumulative[static_cast<size_t>(symbol - 1)];
    const uint32_t upto = symbol + 1 == count ? kProbabilityOne : cumulative[static_cast<size_t>(symbol)];
    return upto - below;
  }
};

// The lower end of symbol k's interval in a range of `range` (k = 1 .. count - 1):
// (range >> 15) * cumulative[k - 1] + k, so that every symbol keeps a non-empty interval
// whatever the adaptation did. Symbol 0 starts at 0, and the last one ends at range.
inline uint32_t symbol_bound(uint32_t range, const AdaptiveSymbols& symbols, int k) {
  return (range >> kProbabilityBits) * symbols.cumulative[static_cast<size_t>(k - 1)] + static_cast<uint32_t>(k);
}

// Calls f on a distribution, or on every distribution of a (nested) array in index order.
template <class F>
void for_each_bit(AdaptiveSymbols& symbols, F&& f) {
  f(symbols);
}
template <class F>
void for_each_bit(const AdaptiveSymbols& symbols, F&& f) {
  f(symbols);
}

// An array of `N` distributions of `symbols` values each.
template <size_t N>
std::array<AdaptiveSymbols, N> symbol_array(int symbols) {
  std::array<AdaptiveSymbols, N> out;
  out.fill(AdaptiveSymbols(symbols));
  return out;
}

}  // namespace svc::codec
