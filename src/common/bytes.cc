#include "common/bytes.h"

#include <zlib.h>

namespace svc {

uint32_t crc32_of(std::span<const uint8_t> bytes, uint32_t crc) {
  // zlib's crc32 takes a uInt length; feed large spans in pieces.
  uLong value = crc;
  const uint8_t* p = bytes.data();
  size_t left = bytes.size();
  while (left > 0) {
    const uInt n = left > (1u << 30) ? (1u << 30) : static_cast<uInt>(left);
    value = ::crc32(value, p, n);
    p += n;
    left -= n;
  }
  return static_cast<uint32_t>(value);
}

}  // namespace svc
