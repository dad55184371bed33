// Adaptive binary range coder (LZMA-style carry-less encoder with cache byte) shared by
// every entropy-coded syntax element. Exact arithmetic is specified in docs/codec.md.
//
// Safety: the decoder never reads outside its span; reads past the end yield zero bytes
// and are counted (overrun()), so garbage or truncated input decodes to some values
// without undefined behaviour and the caller can report truncation.
// Threading: encoder/decoder objects are single-threaded; AdaptiveBit is plain data.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

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

class RangeEncoder {
 public:
  // Appends to `out` (not owned; must outlive the encoder until finish()).
  explicit RangeEncoder(std::vector<uint8_t>* out) : out_(out), start_(out->size()) {}

  void encode(AdaptiveBit& model, int bit) {
    const uint32_t bound = (range_ >> kProbabilityBits) * model.probability_of_zero();
    if (bit) {
      low_ += bound;
      range_ -= bound;
    } else {
      range_ = bound;
    }
    model.update(bit);
    normalize();
  }

  // Equiprobable bit, no model.
  void encode_bypass(int bit) {
    range_ >>= 1;
    if (bit) low_ += range_;
    normalize();
  }

  // Writes the final bytes; the encoder must not be used afterwards. The stream ends on
  // the value in [low, low + range) with the most trailing zero bits, and its last
  // kImplicitZeroBytes zero bytes, at most, are left out: the decoder reads them as zeros.
  void finish() {
    for (int bits = 32; bits > 0; --bits) {
      const uint64_t mask = (uint64_t{1} << bits) - 1;
      const uint64_t value = (low_ + mask) & ~mask;
      if (value - low_ < range_) {
        low_ = value;
        break;
      }
    }
    for (int i = 0; i < 5; ++i) shift_low();
    for (size_t i = 0; i < kImplicitZeroBytes && out_->size() > start_ && out_->back() == 0; ++i) out_->pop_back();
  }

 private:
  void normalize() {
    while (range_ < (1u << 24)) {
      range_ <<= 8;
      shift_low();
    }
  }
  void shift_low() {
    if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
      uint8_t byte = cache_;
      do {
        // The very first byte is always 0 and is not stored (the decoder assumes it).
        if (!first_byte_) out_->push_back(static_cast<uint8_t>(byte + carry));
        first_byte_ = false;
        byte = 0xFF;
      } while (--cache_size_ != 0);
      cache_ = static_cast<uint8_t>(low_ >> 24);
    }
    ++cache_size_;
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }

  std::vector<uint8_t>* out_;
  size_t start_;  // out_'s size before this stream's first byte
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  bool first_byte_ = true;
};

class RangeDecoder {
 public:
  // `bytes` must outlive the decoder.
  explicit RangeDecoder(std::span<const uint8_t> bytes) : bytes_(bytes) {
    for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
  }

  int decode(AdaptiveBit& model) {
    const uint32_t bound = (range_ >> kProbabilityBits) * model.probability_of_zero();
    const int bit = code_ >= bound;
    code_ = bit ? code_ - bound : code_;
    range_ = bit ? range_ - bound : bound;
    model.update(bit);
    normalize();
    return bit;
  }

  // Without a branch on the bit: bypass bits (signs above all) are unpredictable.
  int decode_bypass() {
    range_ >>= 1;
    const uint32_t bit = code_ >= range_;
    code_ -= range_ & (0u - bit);
    normalize();
    return static_cast<int>(bit);
  }

  // Bytes requested beyond the end of the input (at most kImplicitZeroBytes for any
  // complete stream).
  size_t overrun() const { return position_ - consumed(); }
  // Whether the decoder has read further past the end than a complete stream can make it.
  bool truncated() const { return overrun() > kImplicitZeroBytes; }
  // Bytes of input consumed so far (including the 4 read at construction).
  size_t consumed() const { return std::min(position_, bytes_.size()); }

 private:
  // position_ counts every byte requested, those past the end too: one counter for both.
  uint8_t next_byte() {
    const uint8_t byte = position_ < bytes_.size() ? bytes_[position_] : uint8_t{0};
    ++position_;
    return byte;
  }
  void normalize() {
    while (range_ < (1u << 24)) {
      range_ <<= 8;
      code_ = (code_ << 8) | next_byte();
    }
  }

  std::span<const uint8_t> bytes_;
  size_t position_ = 0;
  uint32_t code_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
};

}  // namespace svc::codec
