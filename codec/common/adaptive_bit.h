// SPDX-License-Identifier: BSD-2-Clause
// The adaptive probability model of every context-coded bit, shared by the range
// decoder (codec/decoder/range_decoder.h) and encoder (codec/encoder/range_encoder.h).
// Exact arithmetic is specified in docs/codec.md.
// Threading: AdaptiveBit is plain data.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace svc::codec {

inline constexpr int kProbabilityBits = 15;
// A complete stream may end this many bytes before the last byte its decoder reads
// (RangeEncoder::finish leaves out final zero bytes); reading further means truncation.
inline constexpr size_t kImplicitZeroBytes = 4;
inline constexpr uint32_t kProbabilityOne = 1u << kProbabilityBits;

// Probability that the next bit is 0, as the mean of a fast- and a slow-adapting
// estimate (shifts 4 and 6 once settled), each in 1/32768 units.
struct AdaptiveBit {
  // From this many bits on, the shifts stay at 4 and 6 (bit_width(seen + 2) >= 6).
  static constexpr uint8_t kSettled = 62;

  uint16_t fast = kProbabilityOne / 2;
  uint16_t slow = kProbabilityOne / 2;
  uint8_t seen = 0;  // bits coded so far, saturating at kSettled: young contexts adapt faster

  uint32_t probability_of_zero() const { return (uint32_t{fast} + uint32_t{slow}) >> 1; }
  // Starts a fresh context at a trained probability of 0 (1..32767) instead of 1/2; it
  // adapts from there as fast as a fresh one.
  void prime(uint16_t probability) { fast = slow = probability; }
  void update(int bit) {
    const Shifts shifts = kShifts[seen];
    seen = static_cast<uint8_t>(seen + (seen < kSettled));
    // Both branches computed and one kept: the bit is data, so a branch on it mispredicts.
    const auto fast_down = static_cast<uint16_t>(fast - (fast >> shifts.fast));
    const auto fast_up = static_cast<uint16_t>(fast + ((kProbabilityOne - fast) >> shifts.fast));
    const auto slow_down = static_cast<uint16_t>(slow - (slow >> shifts.slow));
    const auto slow_up = static_cast<uint16_t>(slow + ((kProbabilityOne - slow) >> shifts.slow));
    fast = bit ? fast_down : fast_up;
    slow = bit ? slow_down : slow_up;
  }

 private:
  struct Shifts {
    uint8_t fast, slow;
  };
  // Adaptation shifts by bits seen: min(bit_width(seen + 2), 4) and min(..., 6), so that
  // young contexts move faster; settled ones use 4 and 6.
  static constexpr std::array<Shifts, kSettled + 1> kShifts = [] {
    std::array<Shifts, kSettled + 1> table{};
    for (int seen = 0; seen <= kSettled; ++seen) {
      const int warm = seen < kSettled ? std::bit_width(static_cast<unsigned>(seen) + 2u) : 6;
      table[static_cast<size_t>(seen)] = {static_cast<uint8_t>(std::min(warm, 4)),
                                          static_cast<uint8_t>(std::min(warm, 6))};
    }
    return table;
  }();
};

// Calls f(bit) on a context, or on every context of a (nested) array in index order: the
// building block of the context sets' for_each_context.
template <class Bit, class F>
requires std::same_as<std::remove_const_t<Bit>, AdaptiveBit>
void for_each_bit(Bit& bit, F&& f) { f(bit); }
template <class T, size_t N, class F>
void for_each_bit(std::array<T, N>& bits, F&& f) {
  for (T& bit : bits) for_each_bit(bit, f);
}
template <class T, size_t N, class F>
void for_each_bit(const std::array<T, N>& bits, F&& f) {
  for (const T& bit : bits) for_each_bit(bit, f);
}

}  // namespace svc::codec
