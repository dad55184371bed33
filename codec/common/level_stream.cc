// SPDX-License-Identifier: BSD-2-Clause
#include "codec/common/level_stream.h"

#include <bit>
#include <cstdlib>

namespace svc::codec {

namespace {

constexpr uint32_t kMaxRun = 255;         // a 16x16 block's last scan index
constexpr uint32_t kMaxMagnitude = 4095;  // the quantizer's largest level
// Longest Exp-Golomb prefix a writer produces: magnitude - 1 = 4094 takes 11 zeros.
constexpr int kMaxPrefix = 11;

}  // namespace

void LevelStreamWriter::bits(uint64_t value, int count) {
  held_ = (held_ << count) | value;
  held_count_ += count;
  while (held_count_ >= 8) {
    held_count_ -= 8;
    bytes_->push_back(static_cast<uint8_t>(held_ >> held_count_));
  }
}

// The run and the magnitude each as Exp-Golomb order 0 (v: bit_width(v + 1) - 1 zeros,
// then v + 1 in bit_width(v + 1) bits, that is v + 1 in 2 bit_width(v + 1) - 1 bits),
// then the sign: 41 bits at most, written at once.
void LevelStreamWriter::level(int previous_scan, int scan_index, int level) {
  const auto run_code = static_cast<uint64_t>(scan_index - previous_scan);
  const auto magnitude_code = static_cast<uint64_t>(std::abs(level));
  const int run_bits = 2 * std::bit_width(run_code) - 1;
  const int magnitude_bits = 2 * std::bit_width(magnitude_code) - 1;
  bits((((run_code << magnitude_bits) | magnitude_code) << 1) | (level < 0 ? 1u : 0u),
       run_bits + magnitude_bits + 1);
}

void LevelStreamWriter::flush() {
  if (held_count_ > 0) bits(0, 8 - held_count_);
}

// Eight bytes at a time while they are all inside the stream: the bits beyond buffered_
// are then the stream's next bits, which a later refill ORs in again unchanged.
void LevelStreamReader::refill() {
  if (buffered_ > 56) return;
  if (size_ - next_byte_ >= 8) {
    uint64_t word = 0;
    for (int i = 0; i < 8; ++i) word = (word << 8) | bytes_[next_byte_ + static_cast<size_t>(i)];
    buffer_ |= word >> buffered_;
    const int whole_bytes = (64 - buffered_) >> 3;
    next_byte_ += static_cast<size_t>(whole_bytes);
    buffered_ += 8 * whole_bytes;
    return;
  }
  while (buffered_ <= 56 && next_byte_ < size_) {
    buffer_ |= static_cast<uint64_t>(bytes_[next_byte_++]) << (56 - buffered_);
    buffered_ += 8;
  }
}

// Past the end the buffer holds zeros; buffered_ may then go negative, harmlessly.
void LevelStreamReader::consume(int count) {
  buffer_ <<= count;
  buffered_ -= count;
  bits_read_ += static_cast<size_t>(count);
}

uint32_t LevelStreamReader::bits(int count) {
  refill();
  const auto value = static_cast<uint32_t>(buffer_ >> (64 - count));
  consume(count);
  return value;
}

namespace {

// An Exp-Golomb code at the top of `buffer`: its value minus one, or false for a prefix
// longer than any writer's. *used is the code's length.
inline bool exp_golomb_at(uint64_t buffer, uint32_t* value, int* used) {
  const int zeros = std::countl_zero(buffer);
  if (zeros > kMaxPrefix) return false;
  *used = 2 * zeros + 1;
  *value = static_cast<uint32_t>(buffer >> (64 - *used)) - 1;
  return true;
}

}  // namespace

// One refill covers a whole level, so both codes and the sign are cut from the buffer
// as it stands. A code that fails consumes the codes before it, as reading them one
// by one would (the caller reports bytes_read() even then).
bool LevelStreamReader::level(int previous_scan, int* scan_index, int* level) {
  refill();  // two prefixes of at most 11 zeros and their 12-bit values, and the sign
  uint32_t run = 0, magnitude = 0;
  int run_bits = 0, magnitude_bits = 0;
  const bool valid = exp_golomb_at(buffer_, &run, &run_bits) && run <= kMaxRun &&
                     exp_golomb_at(buffer_ << run_bits, &magnitude, &magnitude_bits) &&
                     magnitude + 1 <= kMaxMagnitude;
  if (!valid) {
    consume(run_bits + magnitude_bits);  // what was read before the failing check
    return false;
  }
  const bool negative = ((buffer_ << (run_bits + magnitude_bits)) >> 63) != 0;
  consume(run_bits + magnitude_bits + 1);
  *scan_index = previous_scan + 1 + static_cast<int>(run);
  *level = negative ? -static_cast<int>(magnitude + 1) : static_cast<int>(magnitude + 1);
  return true;
}

}  // namespace svc::codec
