// SPDX-License-Identifier: BSD-2-Clause
// SHA-256 (FIPS 180-4) for pinning bytes in tests: strong enough that a pinned digest
// changes whenever any byte does. Not for security use.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace svc::testing {

class Sha256 {
 public:
  Sha256();
  void update(std::span<const uint8_t> bytes);
  // Finishes the digest and returns it as 64 lowercase hex digits. Call once.
  std::string hex_digest();

 private:
  void compress(const uint8_t* block);

  std::array<uint32_t, 8> state_;
  std::array<uint8_t, 64> block_{};
  size_t block_used_ = 0;
  uint64_t total_bytes_ = 0;
};

// Digest of one buffer, as hex.
std::string sha256_hex(std::span<const uint8_t> bytes);

}  // namespace svc::testing
