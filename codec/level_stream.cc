#include "codec/level_stream.h"

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

void LevelStreamReader::refill() {
  while (buffered_ <= 56 && next_byte_ < size_) {
    buffer_ |= static_cast<uint64_t>(bytes_[next_byte_++]) << (56 - buffered_);
    buffered_ += 8;
  }
}

// Past the end the buffer holds zeros; buffered_ may then go negative, harmlessly.
uint32_t LevelStreamReader::take(int count) {
  const auto value = static_cast<uint32_t>(buffer_ >> (64 - count));
  buffer_ <<= count;
  buffered_ -= count;
  bits_read_ += static_cast<size_t>(count);
  return value;
}

uint32_t LevelStreamReader::bits(int count) {
  refill();
  return take(count);
}

bool LevelStreamReader::take_exp_golomb(uint32_t* value) {
  const int zeros = std::countl_zero(buffer_);
  if (zeros > kMaxPrefix) return false;
  buffer_ <<= zeros;
  buffered_ -= zeros;
  bits_read_ += static_cast<size_t>(zeros);
  *value = take(zeros + 1) - 1;
  return true;
}

bool LevelStreamReader::level(int previous_scan, int* scan_index, int* level) {
  refill();  // two prefixes of at most 11 zeros and their 12-bit values, and the sign
  uint32_t run = 0, magnitude = 0;
  if (!take_exp_golomb(&run) || run > kMaxRun || !take_exp_golomb(&magnitude) || magnitude + 1 > kMaxMagnitude) {
    return false;
  }
  const bool negative = take(1) != 0;
  *scan_index = previous_scan + 1 + static_cast<int>(run);
  *level = negative ? -static_cast<int>(magnitude + 1) : static_cast<int>(magnitude + 1);
  return true;
}

}  // namespace svc::codec
