// SPDX-License-Identifier: BSD-2-Clause
// The packed, semi-decoded form of an intra frame (CoefficientFrame) and its block
// layout.
#include <array>

#include "codec/common/coefficient_contexts.h"
#include "codec/common/intra_frame.h"
#include "codec/common/level_stream.h"

namespace svc::codec {

size_t CoefficientFrame::memory_bytes() const {
  return sizeof(*this) + luma_partitions.capacity() * sizeof(uint16_t) +
         block_counts.capacity() * sizeof(uint16_t) + block_modes.capacity() + levels.capacity() +
         cdef.memory_bytes();
}

namespace {

// Natural position -> scan index, per transform size.
const std::array<uint8_t, kMaxTransformArea>& inverse_scan(TransformSize size) {
  static const auto tables = [] {
    std::array<std::array<uint8_t, kMaxTransformArea>, kTransformSizes> t{};
    for (int s = 0; s < kTransformSizes; ++s) {
      const ScanOrder& order = scan_order(static_cast<TransformSize>(s));
      for (int i = 0; i < order.count; ++i) t[static_cast<size_t>(s)][order.scan[i]] = static_cast<uint8_t>(i);
    }
    return t;
  }();
  return tables[static_cast<size_t>(size)];
}

}  // namespace

void CoefficientFrame::append_levels(const BlockLevel* block_levels, int count, TransformSize size,
                                     TransformType type) {
  if (count <= 0) return;
  const std::array<uint8_t, kMaxTransformArea>& scan_of = inverse_scan(size);
  LevelStreamWriter writer(&levels);
  writer.transform_type(static_cast<int>(type));
  int previous = -1;
  for (int i = 0; i < count; ++i) {
    const int scan = scan_of[block_levels[i].position];
    writer.level(previous, scan, block_levels[i].level);
    previous = scan;
  }
}

int CoefficientFrame::read_levels(size_t* offset, int count, TransformSize size, int* positions, int* values,
                                  TransformType* type) const {
  *type = TransformType::kDctDct;
  if (count <= 0 || *offset >= levels.size()) return 0;
  const ScanOrder& order = scan_order(size);
  LevelStreamReader reader(levels.data() + *offset, levels.size() - *offset);
  *type = static_cast<TransformType>(reader.transform_type());
  int read = 0, previous = -1;
  while (read < count) {
    int scan, value;
    if (!reader.level(previous, &scan, &value) || scan >= order.count) break;
    positions[read] = order.scan[scan];
    values[read++] = value;
    previous = scan;
  }
  *offset += reader.bytes_read();
  return read;
}

BlockLayout block_layout(int width, int height) {
  BlockLayout layout;
  if (width <= 0 || height <= 0) return layout;
  const int mb_x = (width + 15) / 16, mb_y = (height + 15) / 16;
  layout.luma_blocks_x = 2 * mb_x;
  layout.luma_blocks_y = 2 * mb_y;
  layout.chroma_blocks_x = mb_x;
  layout.chroma_blocks_y = mb_y;
  return layout;
}

}  // namespace svc::codec
