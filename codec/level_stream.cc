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

void LevelStreamWriter::bits(uint32_t value, int count) {
  held_ = (held_ << count) | value;
  held_count_ += count;
  while (held_count_ >= 8) {
    held_count_ -= 8;
    bytes_->push_back(static_cast<uint8_t>(held_ >> held_count_));
  }
}

// Order 0: n - 1 zeros, then value + 1 in its n = bit_width(value + 1) bits.
void LevelStreamWriter::exp_golomb(uint32_t value) {
  const int n = std::bit_width(value + 1);
  bits(0, n - 1);
  bits(value + 1, n);
}

void LevelStreamWriter::level(int previous_scan, int scan_index, int level) {
  exp_golomb(static_cast<uint32_t>(scan_index - previous_scan - 1));
  exp_golomb(static_cast<uint32_t>(std::abs(level) - 1));
  bits(level < 0 ? 1u : 0u, 1);
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
uint32_t LevelStreamReader::bits(int count) {
  refill();
  const auto value = static_cast<uint32_t>(buffer_ >> (64 - count));
  buffer_ <<= count;
  buffered_ -= count;
  bits_read_ += static_cast<size_t>(count);
  return value;
}

bool LevelStreamReader::exp_golomb(uint32_t* value) {
  refill();
  const int zeros = std::countl_zero(buffer_);
  if (zeros > kMaxPrefix) return false;
  buffer_ <<= zeros;
  buffered_ -= zeros;
  bits_read_ += static_cast<size_t>(zeros);
  *value = bits(zeros + 1) - 1;
  return true;
}

bool LevelStreamReader::level(int previous_scan, int* scan_index, int* level) {
  uint32_t run = 0, magnitude = 0;
  if (!exp_golomb(&run) || run > kMaxRun || !exp_golomb(&magnitude) || magnitude + 1 > kMaxMagnitude) {
    return false;
  }
  const bool negative = bits(1) != 0;
  *scan_index = previous_scan + 1 + static_cast<int>(run);
  *level = negative ? -static_cast<int>(magnitude + 1) : static_cast<int>(magnitude + 1);
  return true;
}

}  // namespace svc::codec
