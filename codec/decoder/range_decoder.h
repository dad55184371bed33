// SPDX-License-Identifier: BSD-2-Clause
// Adaptive binary range decoder (the LZMA-style coder of docs/codec.md) that every
// entropy-coded syntax element is read with.
//
// Safety: the decoder never reads outside its span; reads past the end yield zero bytes
// and are counted (overrun()), so garbage or truncated input decodes to some values
// without undefined behaviour and the caller can report truncation.
// Threading: a decoder object is single-threaded.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "codec/common/adaptive_bit.h"

namespace svc::codec {

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
