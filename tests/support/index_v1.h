// Index version 1, as svc wrote it before version 2 (fixed-size records): the tests
// keep this writer to check that readers still accept such files.
#pragma once

#include <cstdint>
#include <vector>

#include "common/bytes.h"
#include "container/container.h"

namespace svc::testing {

inline std::vector<uint8_t> serialize_index_v1(const ContainerIndex& index) {
  ByteWriter w;
  w.u32(1);
  w.u32(index.face_width);
  w.u32(index.face_height);
  for (int32_t d : index.grid.dims) w.i32(d);
  for (double v : index.grid.origin) w.f64(v);
  for (double v : index.grid.spacing) w.f64(v);
  w.u8(static_cast<uint8_t>(index.depth_mode));
  w.u8(static_cast<uint8_t>(index.up_axis));
  w.u8(static_cast<uint8_t>(index.coding.motion));
  w.u8(0);
  w.u32(index.coding.quality);
  w.u32(index.coding.qindex);
  for (int32_t s : index.coding.i_spacing) w.i32(s);
  w.u32(static_cast<uint32_t>(index.cells.size()));
  for (size_t c = 0; c < index.cells.size(); ++c) {
    const CellRecord& cell = index.cells[c];
    w.i32(cell.index.x);
    w.i32(cell.index.y);
    w.i32(cell.index.z);
    for (double v : cell.position) w.f64(v);
    for (const Camera& camera : index.cameras[c]) {
      for (double v : camera.world_to_camera) w.f64(v);
      const Frustum& f = camera.frustum;
      for (double v : {f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane}) w.f64(v);
    }
  }
  w.u32(static_cast<uint32_t>(index.frames.size()));
  for (const FrameRecord& frame : index.frames) {
    w.u32(frame.cell);
    w.u8(static_cast<uint8_t>(frame.face));
    w.u8(static_cast<uint8_t>(frame.type));
    w.u8(static_cast<uint8_t>(frame.references.size()));
    w.u8(0);
    w.u64(frame.chunk_offset);
    w.u32(frame.payload_size);
    for (uint32_t ref : frame.references) w.u32(ref);
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
