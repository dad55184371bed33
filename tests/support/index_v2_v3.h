// Index versions 2 and 3 as svc wrote them before version 4 (docs/format.md "Index
// version 3" and "Index version 2"): the tests keep these writers to check that readers
// still accept such files and to renew the committed files of those versions.
#pragma once

#include <cstdint>
#include <vector>

#include "common/bytes.h"
#include "container/container.h"

namespace svc::testing {

inline void write_varint_before_v4(ByteWriter& w, uint64_t v) {
  for (; v >= 0x80; v >>= 7) w.u8(static_cast<uint8_t>(v | 0x80));
  w.u8(static_cast<uint8_t>(v));
}

inline uint64_t zigzag(int64_t v) { return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63); }

// The index payload's tail from the frame count on, in `version` 2 or 3: records (type
// byte, chunk offset as a zigzag difference from the previous chunk's end, payload size,
// references: frame numbers in version 2, zigzag cell differences in version 3), then the
// statistics as u64s.
inline std::vector<uint8_t> serialize_frames_v2_v3(const ContainerIndex& index, uint32_t version) {
  ByteWriter w;
  w.u32(static_cast<uint32_t>(index.frames.size()));
  uint64_t previous_end = kPreludeSize;
  for (size_t n = 0; n < index.frames.size(); ++n) {
    const FrameRecord& frame = index.frames[n];
    w.u8(static_cast<uint8_t>(static_cast<uint8_t>(frame.type) | frame.references.size() << 2 |
                              (frame.cube_references ? 0x10 : 0) | (frame.bare_chunk ? 0x20 : 0)));
    write_varint_before_v4(w, zigzag(static_cast<int64_t>(frame.chunk_offset - previous_end)));
    write_varint_before_v4(w, frame.payload_size);
    for (uint32_t ref : frame.references) {
      const int64_t cell_difference = static_cast<int64_t>(ref / kFaceCount) - static_cast<int64_t>(n / kFaceCount);
      write_varint_before_v4(w, version == 2 ? ref : zigzag(cell_difference));
    }
    previous_end = frame.chunk_offset + chunk_bytes(frame);
  }
  for (const FaceTypeStats& t : index.stats) {
    for (uint64_t v : {t.faces, t.bytes, t.mb_intra, t.mb_forward, t.mb_backward, t.mb_bidirectional, t.mb_skipped,
                       t.candidate_vectors, t.candidate_macroblocks}) {
      w.u64(v);
    }
  }
  return w.take();
}

// A version 3 index: version 4's header and cell records (the same bytes), its rig
// entries written out in full (nine rotation doubles, six frustum doubles), then version
// 3's frame records and statistics.
inline std::vector<uint8_t> serialize_index_v3(const ContainerIndex& index) {
  constexpr size_t kRigCountAt = 4 + 8 + 12 + 48 + 4 + 8 + 12;
  // Without frames and statistics the version 4 index ends in a zero frame count and 18
  // one-byte zero statistics.
  ContainerIndex cells_only = index;
  cells_only.frames.clear();
  cells_only.stats = {};
  const std::vector<uint8_t> v4 = serialize_index(cells_only);
  std::vector<uint8_t> bytes(v4.begin(), v4.begin() + kRigCountAt + 1);
  bytes[0] = 3;
  ByteReader r(std::span<const uint8_t>(v4).subspan(kRigCountAt + 1), 0);
  ByteWriter rig;
  for (int k = 0; k < v4[kRigCountAt]; ++k) {
    uint32_t packed = 0;
    for (int b = 0; b < 3; ++b) packed |= uint32_t{r.u8()} << (8 * b);
    for (int e = 0; e < 9; ++e) {
      const uint32_t code = packed >> (2 * e) & 3;
      const double magnitude = code & 2 ? 1.0 : 0.0;
      rig.f64(code & 1 ? -magnitude : magnitude);
    }
    if (r.u8() == 0) {
      for (int v = 0; v < 6; ++v) rig.f64(r.f64());
    } else {
      const double w = r.f64(), near = r.f64(), far = r.f64();
      for (double v : {-w, w, -w, w, near, far}) rig.f64(v);
    }
  }
  bytes.insert(bytes.end(), rig.bytes().begin(), rig.bytes().end());
  const size_t cells_at = v4.size() - r.remaining();
  bytes.insert(bytes.end(), v4.begin() + static_cast<std::ptrdiff_t>(cells_at), v4.end() - 4 - 2 * 9);
  const std::vector<uint8_t> frames = serialize_frames_v2_v3(index, 3);
  bytes.insert(bytes.end(), frames.begin(), frames.end());
  return bytes;
}

}  // namespace svc::testing
