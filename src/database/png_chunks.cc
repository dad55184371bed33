// SPDX-License-Identifier: BSD-2-Clause
#include "database/png_chunks.h"

#include <array>
#include <fstream>
#include <vector>

#include "common/bytes.h"

namespace svc {

namespace {

constexpr std::array<uint8_t, 8> kSignature = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};

uint32_t big_endian(const uint8_t* p) {
  return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | uint32_t{p[3]};
}

}  // namespace

Status check_png_chunks(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  std::array<uint8_t, 8> signature{};
  in.read(reinterpret_cast<char*>(signature.data()), signature.size());
  if (!in || signature != kSignature) return Status::Ok();
  const auto damaged = [&](uint64_t offset, const std::string& why) {
    return Status(ErrorCode::kBadInput, what + ": damaged PNG: " + why + " at byte " + std::to_string(offset));
  };
  uint64_t offset = signature.size();
  std::vector<uint8_t> chunk;
  for (;;) {
    std::array<uint8_t, 8> header{};
    in.read(reinterpret_cast<char*>(header.data()), header.size());
    if (!in) return damaged(offset, "the file ends before the IEND chunk");
    const uint32_t length = big_endian(header.data());
    const std::string type(header.begin() + 4, header.end());
    if (length > (1u << 31))
      return damaged(offset, "chunk " + type + " claims " + std::to_string(length) + " bytes");
    // Read in pieces so that a length larger than the file allocates nothing big.
    uint32_t crc = crc32_of(std::span<const uint8_t>(header.data() + 4, 4));
    std::array<uint8_t, 65536> buffer;
    for (uint32_t left = length; left > 0;) {
      const uint32_t n = std::min<uint32_t>(left, buffer.size());
      in.read(reinterpret_cast<char*>(buffer.data()), n);
      if (!in) return damaged(offset, "chunk " + type + " runs past the end of the file");
      crc = crc32_of(std::span<const uint8_t>(buffer.data(), n), crc);
      left -= n;
    }
    std::array<uint8_t, 4> stored{};
    in.read(reinterpret_cast<char*>(stored.data()), stored.size());
    if (!in) return damaged(offset, "chunk " + type + " runs past the end of the file");
    if (big_endian(stored.data()) != crc) return damaged(offset, "chunk " + type + " fails its CRC-32 check");
    if (type == "IEND") return Status::Ok();
    offset += uint64_t{12} + length;
  }
}

}  // namespace svc
