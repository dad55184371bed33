// SPDX-License-Identifier: BSD-2-Clause
// Adaptive binary range encoder (LZMA-style carry-less encoder with cache byte) that
// every entropy-coded syntax element is written with; codec/decoder/range_decoder.h
// reads what it writes. Exact arithmetic is specified in docs/codec.md.
// Threading: an encoder object is single-threaded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/common/adaptive_bit.h"
#include "codec/encoder/bit_cost.h"
#include "codec/encoder/syntax_account.h"

namespace svc::codec {

class RangeEncoder {
 public:
  // Appends to `out` (not owned; must outlive the encoder until finish()).
  explicit RangeEncoder(std::vector<uint8_t>* out) : out_(out), start_(out->size()) {}

  // Optional (null by default; not owned): each bin coded from now on adds its cost to
  // account->bits[account->current] (syntax_account.h). Changes no output byte.
  void set_account(SyntaxBits* account) { account_ = account; }
  SyntaxBits* account() const { return account_; }

  void encode(AdaptiveBit& model, int bit) {
    if (account_ != nullptr) [[unlikely]]
      account_->add(account_->current, bit_cost(model, bit));
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
    if (account_ != nullptr) [[unlikely]]
      account_->add(account_->current, 1);
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
  SyntaxBits* account_ = nullptr;
  size_t start_;  // out_'s size before this stream's first byte
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  bool first_byte_ = true;
};

}  // namespace svc::codec
