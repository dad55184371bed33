// SPDX-License-Identifier: BSD-2-Clause
// The levels of the semi-decoded form (CoefficientFrame, docs/runtime.md) packed as
// Exp-Golomb codes: a block with levels starts with its transform type in two bits
// (codec/transform_type.h), then per non-zero level, in increasing scan order within its block, the
// run of zeros before it, its magnitude minus one and its sign. A photographic I-face's
// levels take about 5 bits each instead of 16, which keeps a cached I-face within a
// quarter of its RGB bytes, while reading stays a few shifts per level (no contexts, no
// arithmetic decoding). Each block's levels are written as one stream of whole bytes.
// Writers and readers are single-threaded objects; a stream is
// immutable once written and may be read from several threads through separate readers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/common/transform_size.h"

namespace svc::codec {

inline constexpr int kTransformTypeBits = 2;

// Appends bits to a byte vector, most significant bit of each byte first.
class LevelStreamWriter {
 public:
  explicit LevelStreamWriter(std::vector<uint8_t>* bytes) : bytes_(bytes) {}
  ~LevelStreamWriter() { flush(); }
  LevelStreamWriter(const LevelStreamWriter&) = delete;
  LevelStreamWriter& operator=(const LevelStreamWriter&) = delete;

  // One level at `scan_index` (0..area-1), following the block's previous level at
  // `previous_scan` (-1 for a block's first). `level` is non-zero, |level| <= 4095.
  void level(int previous_scan, int scan_index, int level);
  // A block's transform type, 0..3, before its first level.
  void transform_type(int type) { bits(static_cast<uint32_t>(type), kTransformTypeBits); }
  // Writes out the bits still held (zero-padded to a byte); the destructor calls it.
  void flush();

 private:
  // At most 57 bits at once (held_count_ stays below 8 between calls).
  void bits(uint64_t value, int count);

  std::vector<uint8_t>* bytes_;
  uint64_t held_ = 0;  // pending bits, right-aligned
  int held_count_ = 0;
};

// Reads what LevelStreamWriter wrote. Past the end it reads zeros, and an Exp-Golomb
// prefix longer than any value written ends the stream: a damaged stream gives wrong
// levels, never a read outside `bytes`.
class LevelStreamReader {
 public:
  LevelStreamReader(const uint8_t* bytes, size_t size) : bytes_(bytes), size_(size) {}

  // Bytes the levels read so far occupy (a writer's stream is padded to whole bytes).
  size_t bytes_read() const { return (bits_read_ + 7) / 8; }

  // The next level of a block whose previous level was at `previous_scan`: sets
  // *scan_index and *level. Returns false at the end of the stream or when the code
  // is not one a writer produces (a run past 255, a magnitude above 4095).
  bool level(int previous_scan, int* scan_index, int* level);
  // A block's transform type, 0..3, before its first level (past the end: 0, DCT_DCT).
  int transform_type() { return static_cast<int>(bits(kTransformTypeBits)); }

 private:
  uint32_t bits(int count);
  // Fills the buffer to at least 57 bits, or to the stream's end (zeros follow it).
  void refill();
  // Consumes `count` buffered bits (the caller has refilled for them; a level takes at
  // most 47).
  void consume(int count);

  const uint8_t* bytes_;
  size_t size_;
  size_t next_byte_ = 0;
  uint64_t buffer_ = 0;  // left-aligned unread bits
  int buffered_ = 0;
  size_t bits_read_ = 0;
};

}  // namespace svc::codec
