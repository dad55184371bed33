// Index version 2's frame records and statistics, as svc wrote them before version 3
// (docs/format.md "Index version 2"): the tests keep this writer to renew the committed
// files of that version with the current encoder's faces.
#pragma once

#include <cstdint>
#include <vector>

#include "common/bytes.h"
#include "container/container.h"

namespace svc::testing {

inline void write_varint_v2(ByteWriter& w, uint64_t v) {
  for (; v >= 0x80; v >>= 7) w.u8(static_cast<uint8_t>(v | 0x80));
  w.u8(static_cast<uint8_t>(v));
}

// The index payload's tail from the frame count on: version 2 records (type byte, chunk
// offset as a zigzag difference from the previous chunk's end, payload size, references
// as frame numbers), then the statistics.
inline std::vector<uint8_t> serialize_frames_v2(const ContainerIndex& index) {
  ByteWriter w;
  w.u32(static_cast<uint32_t>(index.frames.size()));
  uint64_t previous_end = kPreludeSize;
  for (const FrameRecord& frame : index.frames) {
    w.u8(static_cast<uint8_t>(static_cast<uint8_t>(frame.type) | frame.references.size() << 2 |
                              (frame.cube_references ? 0x10 : 0) | (frame.bare_chunk ? 0x20 : 0)));
    const auto delta = static_cast<int64_t>(frame.chunk_offset - previous_end);
    write_varint_v2(w, (static_cast<uint64_t>(delta) << 1) ^ static_cast<uint64_t>(delta >> 63));
    write_varint_v2(w, frame.payload_size);
    for (uint32_t ref : frame.references) write_varint_v2(w, ref);
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

}  // namespace svc::testing
