// SPDX-License-Identifier: BSD-2-Clause
// The .svc container (docs/format.md): file header, two commit slots, CRC-protected
// chunks holding coded faces, and an index chunk with grid, cameras, coding settings
// and every face's offset, size, type and references (an adjacency list). This header
// is the reading side (index_coding.cc, chunks.cc); writing a new file is
// output/writer.h, adding to one in place output/updater.h (the full library).
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <vector>

#include "common/file_io.h"
#include "container/grid.h"
#include "svc/limits.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

inline constexpr uint16_t kFormatMajor = 1;
inline constexpr uint16_t kFormatMinor = 0;
inline constexpr uint64_t kFileHeaderSize = 32;
inline constexpr uint64_t kCommitSlotSize = 32;
inline constexpr uint64_t kPreludeSize = kFileHeaderSize + 2 * kCommitSlotSize;  // chunks start here
inline constexpr uint64_t kChunkOverhead = 16;                                   // tag, payload size, CRC-32
inline constexpr uint64_t kBareChunkOverhead = 4;                                // CRC-32 (docs/format.md)

inline constexpr uint32_t chunk_tag(char a, char b, char c, char d) {
  return uint32_t(uint8_t(a)) | uint32_t(uint8_t(b)) << 8 | uint32_t(uint8_t(c)) << 16 | uint32_t(uint8_t(d)) << 24;
}
inline constexpr uint32_t kFaceChunkTag = chunk_tag('F', 'A', 'C', 'E');
inline constexpr uint32_t kIndexChunkTag = chunk_tag('I', 'N', 'D', 'X');

struct CodingRecord {
  uint32_t quality = 0;  // 1..100 as asked, or 0 when qindex was given
  uint32_t qindex = 0;   // the I-faces' quantizer index (B-faces: codec::suggested_b_qindex)
  std::array<int32_t, 3> i_spacing{1, 1, 1};
  MotionSearch motion = MotionSearch::kDepth;
};

struct CellRecord {
  CellIndex index;
  std::array<double, 3> position{0, 0, 0};
};

// A cell's six face cameras, indexed by Face.
using CellCameras = std::array<Camera, kFaceCount>;

// A frame's references: none for an I-face, one or two for a B-face (docs/format.md).
// Held inline, so that an index of any size makes no allocation per frame.
class FrameReferences {
 public:
  static constexpr size_t kCapacity = 2;

  FrameReferences() = default;
  FrameReferences(std::initializer_list<uint32_t> refs) {
    for (uint32_t ref : refs) push_back(ref);
  }

  // A third reference is a caller's error (the placement gives at most two); it is
  // dropped rather than written past the end.
  void push_back(uint32_t ref) {
    assert(size_ < kCapacity);
    if (size_ < kCapacity) refs_[size_++] = ref;
  }
  // n <= kCapacity; new references are 0.
  void resize(size_t n) {
    assert(n <= kCapacity);
    for (size_t i = size_; i < n && i < kCapacity; ++i) refs_[i] = 0;
    size_ = static_cast<uint8_t>(std::min(n, kCapacity));
  }
  void clear() { size_ = 0; }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  uint32_t operator[](size_t i) const { return refs_[i]; }
  uint32_t* begin() { return refs_.data(); }
  uint32_t* end() { return refs_.data() + size_; }
  const uint32_t* begin() const { return refs_.data(); }
  const uint32_t* end() const { return refs_.data() + size_; }
  friend bool operator==(const FrameReferences& a, const FrameReferences& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end());
  }

 private:
  std::array<uint32_t, kCapacity> refs_{};
  uint8_t size_ = 0;
};

// FrameRecord::border_edges of a B-face that may read its references' whole border.
inline constexpr uint8_t kEveryBorderEdge = 0xFF;

// Packed: 40 bytes a frame, the index's cost per face besides its camera.
struct FrameRecord {
  uint64_t chunk_offset = 0;  // file offset of the face's chunk
  uint32_t cell = 0;          // ordinal into ContainerIndex::cells
  uint32_t payload_size = 0;  // coded bytes inside the chunk
  // Coded depth bytes, in a bare chunk right after the face's chunk; 0 in a file without
  // depth (ContainerIndex::depth).
  uint32_t depth_size = 0;
  FrameReferences references;  // ordinals into ContainerIndex::frames
  Face face = Face::kPX;
  FaceType type = FaceType::kIntra;
  // A B-face predicting from padded references (docs/codec.md 5.7): it also depends on
  // the faces adjacent to its face in each reference cube whose border it reads
  // (frame_dependencies).
  bool cube_references = false;
  // With cube_references: the border edges (codec::FaceEdge bits) of reference 0 its
  // predictions read in bits 0-3, of reference 1 in bits 4-7; every edge in files
  // written before index version 6.
  uint8_t border_edges = kEveryBorderEdge;
  // The chunk is bare (payload and CRC-32, make_bare_chunk), as every writer now writes
  // them; a FACE chunk (make_chunk) in files from before.
  bool bare_chunk = true;
};
static_assert(sizeof(FrameRecord) <= 40);

// The four border-edge bits (codec::FaceEdge) of reference r of a frame with cube
// references, and FrameRecord::border_edges from those of each reference.
inline uint8_t reference_border_edges(const FrameRecord& frame, size_t r) {
  return static_cast<uint8_t>(frame.border_edges >> (4 * r) & 0x0F);
}
inline uint8_t pack_border_edges(const std::array<uint8_t, 2>& per_reference) {
  return static_cast<uint8_t>((per_reference[0] & 0x0F) | (per_reference[1] & 0x0F) << 4);
}

// Bytes the face's own chunk takes in the file, payload and framing.
inline uint64_t color_chunk_bytes(const FrameRecord& frame) {
  return uint64_t{frame.payload_size} + (frame.bare_chunk ? kBareChunkOverhead : kChunkOverhead);
}
// Bytes the depth chunk takes (0 without depth); it starts where the face's chunk ends.
inline uint64_t depth_chunk_bytes(const FrameRecord& frame) {
  return frame.depth_size == 0 ? 0 : uint64_t{frame.depth_size} + kBareChunkOverhead;
}
// Bytes the frame takes in the file: its chunk and its depth chunk.
inline uint64_t chunk_bytes(const FrameRecord& frame) {
  return color_chunk_bytes(frame) + depth_chunk_bytes(frame);
}

// Every frame `frame` needs decoded before it can be: its references, then, with cube
// references, for each reference the adjacent faces of its cube across the border edges
// listed (codec/common/cube_padding.h face order). Frames lie cell-major, six per cell,
// so the cube's faces are found by position.
std::vector<uint32_t> frame_dependencies(const FrameRecord& frame);
// The faces whose depth a B-face's depth is predicted from (docs/codec.md 8.3): for
// each reference, its face and the four adjacent faces of its cube, whether or not the
// frame has cube references; frame_dependencies' order. Empty for an I-face.
std::vector<uint32_t> depth_dependencies(const FrameRecord& frame);

struct ContainerIndex {
  uint32_t face_width = 0;
  uint32_t face_height = 0;
  GridSpec grid;
  DepthMode depth_mode = DepthMode::kEyeZ;
  UpAxis up_axis = UpAxis::kY;
  CodingRecord coding;
  // Every face has a depth chunk (FrameRecord::depth_size > 0): index version 5.
  bool depth = false;
  // The bound on every depth code's error (codec/common/depth.h), 0..255; 0 without depth.
  int depth_max_error = 0;
  std::vector<CellRecord> cells;  // sorted by (y, z, x), unique
  // One per cell, as cells. Apart so that an index being built may leave it empty (an
  // encode reads cameras from its manifest, serialize_index through a CameraReader) and
  // a reader may move it out.
  std::vector<CellCameras> cameras;
  std::vector<FrameRecord> frames;     // six per cell, cell-major, face order px..nz
  std::array<FaceTypeStats, 2> stats;  // indexed by FaceType, kept for `svc info`
};

// Writes index version 4, or 5 for an index with depth (docs/format.md, "The index"): face cameras that a rig entry
// reproduces bit for bit are stored as one byte, cell records of a regular grid in two,
// frame records as varints, without the chunk offset of a chunk that follows the
// previous one or the references a B-cube's faces share. Lossless:
// parse_index returns exactly `index` (every double bit for bit). `index` must be one
// that parse_index accepts (at most two references per frame).
std::vector<uint8_t> serialize_index(const ContainerIndex& index);
// The same for an index whose `cameras` are not held (an encode's: they stay in its
// manifest): the cameras of cell c come from read_cameras(c), called twice a cell, in
// order; its first error is returned. The bytes are those serialize_index gives with
// those cameras in `cameras`.
using CameraReader = std::function<Result<CellCameras>(size_t cell)>;
Result<std::vector<uint8_t>> serialize_index(const ContainerIndex& index, const CameraReader& read_cameras);
// Reads index versions 4 and 5 (those serialize_index writes) and refuses any other
// (ErrorCode::kUnsupported, naming the version). Validates every field against `limits` before it sizes
// anything; `file_size` bounds chunk offsets. Errors name the field and its file offset
// (`payload_offset` is the index payload's offset in the file).
Result<ContainerIndex> parse_index(std::span<const uint8_t> payload, uint64_t payload_offset, uint64_t file_size,
                                   const ReaderLimits& limits);

// A chunk as written to the file: tag, payload size, payload, CRC-32 of all before it.
std::vector<uint8_t> make_chunk(uint32_t tag, std::span<const uint8_t> payload);
// A face's bare chunk: the payload and its CRC-32. The index holds its offset and size.
std::vector<uint8_t> make_bare_chunk(std::span<const uint8_t> payload);

std::vector<uint8_t> make_file_header();
std::vector<uint8_t> make_commit_slot(uint64_t generation, uint64_t index_offset, uint64_t index_chunk_size);

// An opened container: where the committed index lies and what it says.
struct OpenedContainer {
  ContainerIndex index;
  uint64_t index_offset = 0;      // of the INDX chunk
  uint64_t index_chunk_size = 0;  // including chunk overhead
  uint64_t generation = 0;
  int slot = 0;  // commit slot in use (0 or 1)
  // Per slot: neither all zero nor valid (CRC fails): an interrupted commit or damage.
  std::array<bool, 2> slot_damaged{false, false};
  // The other slot holds a newer generation whose index failed to read or validate:
  // this index is an older one.
  bool fell_back = false;
};

// Reads the header, the newest valid commit slot and the index it points at.
Result<OpenedContainer> open_container(const ReadOnlyFile& file, const ReaderLimits& limits);

// Reads one face's chunk (bare or FACE, as the record says) and checks its CRC, and a
// FACE chunk's tag and size. Errors name the chunk offset and, through `what`, the face.
Result<std::vector<uint8_t>> read_frame_payload(const ReadOnlyFile& file, const FrameRecord& frame,
                                                const std::string& what);

// Reads one face's depth chunk (bare, right after its face chunk) and checks its CRC;
// kNotFound when the frame has none. Errors name the chunk offset and `what`.
Result<std::vector<uint8_t>> read_frame_depth(const ReadOnlyFile& file, const FrameRecord& frame,
                                              const std::string& what);

// Reads the chunk of `chunk_size` bytes (overhead included) at `offset` and checks its
// tag, size field and CRC-32; returns its payload. Errors name `what` and the offset.
Result<std::vector<uint8_t>> read_chunk(const ReadOnlyFile& file, uint64_t offset, uint64_t chunk_size,
                                        uint32_t expected_tag, const std::string& what);

// kCorruptData: `what` at byte `offset` of the file.
Status corrupt_at(const std::string& what, uint64_t offset);

}  // namespace svc
