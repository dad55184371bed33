// SPDX-License-Identifier: BSD-2-Clause
// Little-endian serialization with bounds checking, for container headers and index.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "svc/status.h"

namespace svc {

// The standard CRC-32 (ISO-HDLC, the value zlib's crc32() gives); `crc` continues the
// CRC of the bytes before these.
uint32_t crc32_of(std::span<const uint8_t> bytes, uint32_t crc = 0);

class ByteWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(v); }
  void u16(uint16_t v) { put(v, 2); }
  void u32(uint32_t v) { put(v, 4); }
  void u64(uint64_t v) { put(v, 8); }
  void i32(int32_t v) { put(static_cast<uint32_t>(v), 4); }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    put(bits, 8);
  }
  void raw(std::span<const uint8_t> data) { bytes_.insert(bytes_.end(), data.begin(), data.end()); }
  size_t size() const { return bytes_.size(); }
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  void put(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  std::vector<uint8_t> bytes_;
};

// Reads fields from a byte span. A read past the end sets a sticky failure and yields
// zero, so a parser can read a record and check ok() once; `fail_message()` names the
// field offset where the data ran out.
class ByteReader {
 public:
  ByteReader(std::span<const uint8_t> data, uint64_t base_offset = 0) : data_(data), base_offset_(base_offset) {}

  uint8_t u8() { return static_cast<uint8_t>(get(1)); }
  uint16_t u16() { return static_cast<uint16_t>(get(2)); }
  uint32_t u32() { return static_cast<uint32_t>(get(4)); }
  uint64_t u64() { return get(8); }
  int32_t i32() { return static_cast<int32_t>(static_cast<uint32_t>(get(4))); }
  double f64() {
    const uint64_t bits = get(8);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  bool skip(size_t n) {
    if (!ok_ || remaining() < n) return fail(n);
    pos_ += n;
    return true;
  }

  bool ok() const { return ok_; }
  size_t position() const { return pos_; }
  size_t remaining() const { return data_.size() - pos_; }
  // File offset of the next byte (base_offset + position).
  uint64_t file_offset() const { return base_offset_ + pos_; }
  uint64_t failed_at() const { return failed_at_; }

 private:
  uint64_t get(int n) {
    if (!ok_ || remaining() < static_cast<size_t>(n)) {
      fail(n);
      return 0;
    }
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(data_[pos_ + i]) << (8 * i);
    pos_ += n;
    return v;
  }
  bool fail(size_t) {
    if (ok_) failed_at_ = base_offset_ + pos_;
    ok_ = false;
    return false;
  }

  std::span<const uint8_t> data_;
  uint64_t base_offset_ = 0;
  size_t pos_ = 0;
  bool ok_ = true;
  uint64_t failed_at_ = 0;
};

}  // namespace svc
