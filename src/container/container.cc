#include "container/container.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/bytes.h"

namespace svc {

namespace {

constexpr uint8_t kMagic[8] = {0x89, 'S', 'V', 'C', 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint32_t kIndexVersion = 1;
// Fixed bytes per record in the index, used to bound counts before allocating.
constexpr uint64_t kCellRecordBytes = 3 * 4 + 3 * 8 + kFaceCount * (16 + 6) * 8;
constexpr uint64_t kFrameRecordMinBytes = 4 + 1 + 1 + 1 + 1 + 8 + 4;

std::string at_offset(uint64_t offset) { return " at byte offset " + std::to_string(offset); }

Status corrupt(const std::string& what, uint64_t offset) {
  return Status(ErrorCode::kCorruptData, what + at_offset(offset));
}

std::string cell_name(const CellIndex& c) {
  return "cell (" + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z) + ")";
}

bool cell_less(const CellIndex& a, const CellIndex& b) {
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.x < b.x;
}

void write_camera(ByteWriter& w, const Camera& camera) {
  for (double v : camera.world_to_camera) w.f64(v);
  const Frustum& f = camera.frustum;
  for (double v : {f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane}) w.f64(v);
}

Camera read_camera(ByteReader& r) {
  Camera camera;
  for (double& v : camera.world_to_camera) v = r.f64();
  Frustum& f = camera.frustum;
  for (double* v : {&f.left, &f.right, &f.bottom, &f.top, &f.near_plane, &f.far_plane}) *v = r.f64();
  return camera;
}

bool camera_is_valid(const Camera& camera) {
  for (double v : camera.world_to_camera) {
    if (!std::isfinite(v)) return false;
  }
  const Frustum& f = camera.frustum;
  for (double v : {f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane}) {
    if (!std::isfinite(v)) return false;
  }
  return f.right > f.left && f.top > f.bottom && f.near_plane > 0 && f.far_plane > f.near_plane;
}

}  // namespace

std::vector<uint8_t> serialize_index(const ContainerIndex& index) {
  ByteWriter w;
  w.u32(kIndexVersion);
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
  w.u32(index.coding.quant_scale);
  for (int32_t s : index.coding.i_spacing) w.i32(s);
  w.u32(static_cast<uint32_t>(index.cells.size()));
  for (const CellRecord& cell : index.cells) {
    w.i32(cell.index.x);
    w.i32(cell.index.y);
    w.i32(cell.index.z);
    for (double v : cell.position) w.f64(v);
    for (const Camera& camera : cell.cameras) write_camera(w, camera);
  }
  w.u32(static_cast<uint32_t>(index.frames.size()));
  for (const FrameRecord& frame : index.frames) {
    w.u32(frame.cell);
    w.u8(static_cast<uint8_t>(frame.face));
    w.u8(static_cast<uint8_t>(frame.kind));
    w.u8(static_cast<uint8_t>(frame.references.size()));
    w.u8(0);
    w.u64(frame.chunk_offset);
    w.u32(frame.payload_size);
    for (uint32_t ref : frame.references) w.u32(ref);
  }
  for (const FrameTypeRecord& t : index.stats) {
    for (uint64_t v : {t.faces, t.bytes, t.mb_intra, t.mb_forward, t.mb_backward, t.mb_bidirectional, t.mb_skipped,
                       t.candidate_vectors, t.candidate_macroblocks}) {
      w.u64(v);
    }
  }
  return w.take();
}

Result<ContainerIndex> parse_index(std::span<const uint8_t> payload, uint64_t payload_offset,
                                   uint64_t file_size, const ReaderLimits& limits) {
  ByteReader r(payload, payload_offset);
  ContainerIndex index;
  const uint64_t version_at = r.file_offset();
  const uint32_t version = r.u32();
  if (!r.ok()) return corrupt("index is truncated", r.failed_at());
  if (version != kIndexVersion) {
    return Status(ErrorCode::kUnsupported,
                  "index version " + std::to_string(version) + " is not supported" + at_offset(version_at));
  }

  const uint64_t size_at = r.file_offset();
  index.face_width = r.u32();
  index.face_height = r.u32();
  for (int32_t& d : index.grid.dims) d = r.i32();
  for (double& v : index.grid.origin) v = r.f64();
  for (double& v : index.grid.spacing) v = r.f64();
  const uint8_t depth_mode = r.u8();
  const uint8_t up_axis = r.u8();
  const uint8_t motion = r.u8();
  r.u8();
  index.coding.quality = r.u32();
  index.coding.quant_scale = r.u32();
  for (int32_t& s : index.coding.i_spacing) s = r.i32();
  if (!r.ok()) return corrupt("index header is truncated", r.failed_at());

  if (index.face_width == 0 || index.face_height == 0 ||
      index.face_width > limits.max_face_dimension || index.face_height > limits.max_face_dimension ||
      uint64_t{index.face_width} * index.face_height > limits.max_face_pixels) {
    return Status(ErrorCode::kLimitExceeded,
                  "face size " + std::to_string(index.face_width) + "x" +
                      std::to_string(index.face_height) + " is zero or above the reader's limits" +
                      at_offset(size_at));
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (index.grid.dims[axis] <= 0 || index.grid.dims[axis] > limits.max_grid_dimension) {
      return Status(ErrorCode::kCorruptData, "grid dimension " + std::to_string(index.grid.dims[axis]) +
                                                 " on axis " + std::to_string(axis) + " is out of range" +
                                                 at_offset(size_at + 8 + 4 * axis));
    }
    if (!std::isfinite(index.grid.origin[axis]) || !std::isfinite(index.grid.spacing[axis]) ||
        index.grid.spacing[axis] <= 0) {
      return corrupt("grid origin or spacing is not finite and positive", size_at + 20);
    }
    if (index.coding.i_spacing[axis] <= 0) {
      return corrupt("I-cube spacing is not positive", size_at);
    }
  }
  if (depth_mode > 1 || up_axis > 2 || motion > 1) {
    return corrupt("depth mode, up axis or motion source has an unknown value", size_at + 68);
  }
  index.depth_mode = static_cast<DepthMode>(depth_mode);
  index.up_axis = static_cast<UpAxis>(up_axis);
  index.coding.motion = static_cast<MotionSource>(motion);

  const uint64_t cells_at = r.file_offset();
  const uint64_t cell_count = r.u32();
  if (!r.ok()) return corrupt("index is truncated before the cell count", r.failed_at());
  if (cell_count == 0 || cell_count > limits.max_cells) {
    return Status(ErrorCode::kLimitExceeded, "cell count " + std::to_string(cell_count) +
                                                 " is zero or above the reader's limit" + at_offset(cells_at));
  }
  if (cell_count * kCellRecordBytes > r.remaining()) {
    return corrupt("cell count " + std::to_string(cell_count) + " does not fit in the index", cells_at);
  }
  index.cells.resize(cell_count);
  for (uint64_t i = 0; i < cell_count; ++i) {
    const uint64_t record_at = r.file_offset();
    CellRecord& cell = index.cells[i];
    cell.index.x = r.i32();
    cell.index.y = r.i32();
    cell.index.z = r.i32();
    for (double& v : cell.position) v = r.f64();
    for (Camera& camera : cell.cameras) camera = read_camera(r);
    if (!r.ok()) return corrupt("cell record " + std::to_string(i) + " is truncated", record_at);
    const CellIndex& c = cell.index;
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= index.grid.dims[0] || c.y >= index.grid.dims[1] ||
        c.z >= index.grid.dims[2]) {
      return corrupt(cell_name(c) + " lies outside the grid", record_at);
    }
    if (i > 0 && !cell_less(index.cells[i - 1].index, c)) {
      return corrupt(cell_name(c) + " is out of order or repeated in the index", record_at);
    }
    for (double v : cell.position) {
      if (!std::isfinite(v)) return corrupt(cell_name(c) + " has a non-finite position", record_at);
    }
    for (int f = 0; f < kFaceCount; ++f) {
      if (!camera_is_valid(cell.cameras[f])) {
        return corrupt(cell_name(c) + " face " + face_name(static_cast<Face>(f)) + " has an invalid camera",
                       record_at);
      }
    }
  }

  const uint64_t frames_at = r.file_offset();
  const uint64_t frame_count = r.u32();
  if (!r.ok()) return corrupt("index is truncated before the frame count", r.failed_at());
  if (frame_count != cell_count * kFaceCount) {
    return corrupt("frame count " + std::to_string(frame_count) + " is not six per cell", frames_at);
  }
  if (frame_count * kFrameRecordMinBytes > r.remaining()) {
    return corrupt("frame count " + std::to_string(frame_count) + " does not fit in the index", frames_at);
  }
  index.frames.resize(frame_count);
  for (uint64_t i = 0; i < frame_count; ++i) {
    const uint64_t record_at = r.file_offset();
    FrameRecord& frame = index.frames[i];
    frame.cell = r.u32();
    const uint8_t face = r.u8();
    const uint8_t kind = r.u8();
    const uint8_t ref_count = r.u8();
    r.u8();
    frame.chunk_offset = r.u64();
    frame.payload_size = r.u32();
    if (!r.ok()) return corrupt("frame record " + std::to_string(i) + " is truncated", record_at);
    // Frames are stored cell-major in face order, so the position fixes cell and face.
    if (frame.cell != i / kFaceCount || face != i % kFaceCount) {
      return corrupt("frame record " + std::to_string(i) + " names the wrong cell or face", record_at);
    }
    frame.face = static_cast<Face>(face);
    const std::string what = cell_name(index.cells[frame.cell].index) + " face " + face_name(frame.face);
    if (kind > 1) return corrupt(what + " has an unknown frame type " + std::to_string(kind), record_at);
    frame.kind = static_cast<FrameKind>(kind);
    if (frame.payload_size > limits.max_frame_bytes) {
      return Status(ErrorCode::kLimitExceeded,
                    what + " is " + std::to_string(frame.payload_size) + " bytes, above the reader's limit" +
                        at_offset(record_at));
    }
    if (frame.chunk_offset < kPreludeSize || frame.chunk_offset > file_size ||
        uint64_t{frame.payload_size} + kChunkOverhead > file_size - frame.chunk_offset) {
      return corrupt(what + " points at bytes " + std::to_string(frame.chunk_offset) +
                         " outside the file", record_at);
    }
    if ((frame.kind == FrameKind::kIntra) != (ref_count == 0) || ref_count > 2) {
      return corrupt(what + " has " + std::to_string(ref_count) + " references, which its type does not allow",
                     record_at);
    }
    frame.references.resize(ref_count);
    for (uint32_t& ref : frame.references) ref = r.u32();
    if (!r.ok()) return corrupt("frame record " + std::to_string(i) + " is truncated", record_at);
  }
  // References must name existing intra frames of the same face: then no cycle and no
  // chain can exist, and any face decodes from at most two others.
  for (uint64_t i = 0; i < frame_count; ++i) {
    const FrameRecord& frame = index.frames[i];
    for (uint32_t ref : frame.references) {
      if (ref >= frame_count || index.frames[ref].kind != FrameKind::kIntra ||
          index.frames[ref].face != frame.face) {
        return corrupt(cell_name(index.cells[frame.cell].index) + " face " + face_name(frame.face) +
                           " references frame " + std::to_string(ref) + ", which is not an I-face of the same face",
                       frames_at);
      }
    }
  }
  for (FrameTypeRecord& t : index.stats) {
    for (uint64_t* v : {&t.faces, &t.bytes, &t.mb_intra, &t.mb_forward, &t.mb_backward, &t.mb_bidirectional,
                        &t.mb_skipped, &t.candidate_vectors, &t.candidate_macroblocks}) {
      *v = r.u64();
    }
  }
  if (!r.ok()) return corrupt("encoder statistics are truncated", r.failed_at());
  if (r.remaining() != 0) {
    return corrupt(std::to_string(r.remaining()) + " unexpected bytes after the index records", r.file_offset());
  }
  return index;
}

std::vector<uint8_t> make_chunk(uint32_t tag, std::span<const uint8_t> payload) {
  ByteWriter w;
  w.u32(tag);
  w.u64(payload.size());
  w.raw(payload);
  w.u32(crc32_of(w.bytes()));
  return w.take();
}

std::vector<uint8_t> make_file_header() {
  ByteWriter w;
  w.raw(kMagic);
  w.u16(kFormatMajor);
  w.u16(kFormatMinor);
  w.u32(static_cast<uint32_t>(kPreludeSize));
  w.u32(0);  // flags
  w.u32(0);  // reserved
  w.u32(0);  // reserved
  w.u32(crc32_of(w.bytes()));
  return w.take();
}

std::vector<uint8_t> make_commit_slot(uint64_t generation, uint64_t index_offset,
                                      uint64_t index_chunk_size) {
  ByteWriter w;
  w.u64(generation);
  w.u64(index_offset);
  w.u64(index_chunk_size);
  w.u32(0);  // reserved
  w.u32(crc32_of(w.bytes()));
  return w.take();
}

namespace {

struct CommitSlot {
  bool valid = false;
  bool empty = false;
  uint64_t generation = 0, index_offset = 0, index_chunk_size = 0;
};

CommitSlot parse_slot(std::span<const uint8_t> bytes) {
  CommitSlot slot;
  ByteReader r(bytes);
  slot.generation = r.u64();
  slot.index_offset = r.u64();
  slot.index_chunk_size = r.u64();
  r.u32();
  const uint32_t crc = r.u32();
  slot.valid = r.ok() && slot.generation != 0 && crc == crc32_of(bytes.first(kCommitSlotSize - 4));
  slot.empty = std::all_of(bytes.begin(), bytes.end(), [](uint8_t b) { return b == 0; });
  return slot;
}

// Reads and checks a chunk's framing; returns its payload.
Result<std::vector<uint8_t>> read_chunk(const ReadOnlyFile& file, uint64_t offset, uint64_t chunk_size,
                                        uint32_t expected_tag, const std::string& what) {
  if (chunk_size < kChunkOverhead || offset > file.size() || chunk_size > file.size() - offset) {
    return corrupt(what + " chunk of " + std::to_string(chunk_size) + " bytes lies outside the file", offset);
  }
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, file.read_vector(offset, chunk_size));
  ByteReader r(bytes, offset);
  const uint32_t tag = r.u32();
  const uint64_t payload_size = r.u64();
  if (tag != expected_tag) return corrupt(what + " chunk has a wrong tag", offset);
  if (payload_size != chunk_size - kChunkOverhead) {
    return corrupt(what + " chunk's size field does not match the index", offset + 4);
  }
  const std::span<const uint8_t> all(bytes);
  const uint32_t stored_crc = static_cast<uint32_t>(all[chunk_size - 4]) |
                              static_cast<uint32_t>(all[chunk_size - 3]) << 8 |
                              static_cast<uint32_t>(all[chunk_size - 2]) << 16 |
                              static_cast<uint32_t>(all[chunk_size - 1]) << 24;
  if (stored_crc != crc32_of(all.first(chunk_size - 4))) {
    return corrupt(what + " chunk fails its CRC-32 check (" + std::to_string(chunk_size) + " bytes)", offset);
  }
  bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(chunk_size - 4), bytes.end());
  bytes.erase(bytes.begin(), bytes.begin() + 12);
  return bytes;
}

}  // namespace

Result<OpenedContainer> open_container(const ReadOnlyFile& file, const ReaderLimits& limits) {
  const std::string name = file.path().string();
  if (file.size() < kPreludeSize) {
    return Status(ErrorCode::kCorruptData, name + " is too short to be an .svc file (" +
                                               std::to_string(file.size()) + " bytes)");
  }
  std::vector<uint8_t> prelude(kPreludeSize);
  SVC_RETURN_IF_ERROR(file.read_at(0, prelude));
  if (!std::equal(std::begin(kMagic), std::end(kMagic), prelude.begin())) {
    return Status(ErrorCode::kCorruptData, name + " is not an .svc file (bad signature)");
  }
  ByteReader header(std::span<const uint8_t>(prelude).first(kFileHeaderSize));
  header.skip(8);
  const uint16_t major = header.u16();
  const uint16_t minor = header.u16();
  const uint32_t prelude_size = header.u32();
  header.skip(12);
  const uint32_t header_crc = header.u32();
  if (header_crc != crc32_of(std::span<const uint8_t>(prelude).first(kFileHeaderSize - 4))) {
    return Status(ErrorCode::kCorruptData, name + ": file header fails its CRC-32 check at byte offset 0");
  }
  if (major != kFormatMajor) {
    return Status(ErrorCode::kUnsupported, name + ": format version " + std::to_string(major) + "." +
                                               std::to_string(minor) + " is not supported");
  }
  if (prelude_size != kPreludeSize) {
    return Status(ErrorCode::kCorruptData, name + ": header size field is wrong at byte offset 12");
  }

  const std::span<const uint8_t> slots(prelude.data() + kFileHeaderSize, 2 * kCommitSlotSize);
  CommitSlot slot[2] = {parse_slot(slots.first(kCommitSlotSize)), parse_slot(slots.last(kCommitSlotSize))};
  // Try the newest valid slot first; fall back to the other (an interrupted commit).
  int order[2] = {0, 1};
  if (slot[1].valid && (!slot[0].valid || slot[1].generation > slot[0].generation)) std::swap(order[0], order[1]);
  Status first_error;
  for (int k : order) {
    if (!slot[k].valid) continue;
    const CommitSlot& s = slot[k];
    if (s.index_chunk_size > limits.max_index_bytes + kChunkOverhead) {
      first_error = Status(ErrorCode::kLimitExceeded, name + ": index of " + std::to_string(s.index_chunk_size) +
                                                          " bytes is above the reader's limit");
      continue;
    }
    auto payload = read_chunk(file, s.index_offset, s.index_chunk_size, kIndexChunkTag, "index");
    if (!payload.ok()) {
      if (first_error.ok()) first_error = payload.status().with_context(name);
      continue;
    }
    auto index = parse_index(*payload, s.index_offset + 12, file.size(), limits);
    if (!index.ok()) {
      if (first_error.ok()) first_error = index.status().with_context(name + ": index");
      continue;
    }
    OpenedContainer opened;
    opened.index = std::move(index).value();
    opened.index_offset = s.index_offset;
    opened.index_chunk_size = s.index_chunk_size;
    opened.generation = s.generation;
    opened.slot = k;
    opened.fell_back = k != order[0] && slot[order[0]].valid;
    for (int j = 0; j < 2; ++j) opened.slot_damaged[j] = !slot[j].valid && !slot[j].empty;
    return opened;
  }
  if (!first_error.ok()) return first_error;
  return Status(ErrorCode::kCorruptData, name + ": no valid commit slot (bytes 32-95): the file holds no index");
}

Result<std::vector<uint8_t>> read_frame_payload(const ReadOnlyFile& file, const FrameRecord& frame,
                                                const std::string& what) {
  return read_chunk(file, frame.chunk_offset, uint64_t{frame.payload_size} + kChunkOverhead, kFaceChunkTag,
                    what);
}

Result<std::unique_ptr<ContainerWriter>> ContainerWriter::create(const std::filesystem::path& path) {
  SVC_ASSIGN_OR_RETURN(auto out, AtomicOutputFile::create(path));
  const std::vector<uint8_t> header = make_file_header();
  SVC_RETURN_IF_ERROR(out->write(header));
  const std::vector<uint8_t> empty_slots(2 * kCommitSlotSize, 0);
  SVC_RETURN_IF_ERROR(out->write(empty_slots));
  return std::unique_ptr<ContainerWriter>(new ContainerWriter(std::move(out)));
}

Result<uint64_t> ContainerWriter::append_frame(std::span<const uint8_t> payload) {
  const uint64_t offset = out_->position();
  SVC_RETURN_IF_ERROR(out_->write(make_chunk(kFaceChunkTag, payload)));
  return offset;
}

Status ContainerWriter::finish(const ContainerIndex& index) {
  const uint64_t index_offset = out_->position();
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, serialize_index(index));
  SVC_RETURN_IF_ERROR(out_->write(chunk));
  SVC_RETURN_IF_ERROR(out_->write_at(kFileHeaderSize, make_commit_slot(1, index_offset, chunk.size())));
  return out_->commit();
}

namespace {

std::atomic<int64_t> g_kill_after_bytes{-1};

}  // namespace

void set_updater_kill_after_bytes_for_testing(int64_t bytes) { g_kill_after_bytes.store(bytes); }

Result<std::unique_ptr<ContainerUpdater>> ContainerUpdater::open(const std::filesystem::path& path,
                                                                 const ReaderLimits& limits) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    const ErrorCode code = errno == ENOENT ? ErrorCode::kNotFound : ErrorCode::kIoError;
    return Status(code, "cannot open " + path.string() + " for update: " + std::strerror(errno));
  }
  auto fail = [&](Status status) {
    ::close(fd);
    return status;
  };
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    return fail(Status(ErrorCode::kIoError, path.string() + " is being updated by another process"));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    return fail(Status(ErrorCode::kIoError, path.string() + " is not a regular file"));
  }
  // Opened after the lock, so no other updater is mid-commit while the index is read.
  auto file = ReadOnlyFile::open(path);
  if (!file.ok()) return fail(file.status());
  auto opened = open_container(**file, limits);
  if (!opened.ok()) return fail(opened.status());
  if (opened->fell_back) {
    return fail(Status(ErrorCode::kCorruptData,
                       path.string() + ": the newest index is damaged (an older one is in use); run svc verify"));
  }
  // Committed data ends with the last chunk the index refers to; anything after it was
  // appended by an update that never committed.
  uint64_t end = opened->index_offset + opened->index_chunk_size;
  for (const FrameRecord& frame : opened->index.frames) {
    end = std::max(end, frame.chunk_offset + frame.payload_size + kChunkOverhead);
  }
  if (end < (*file)->size() && ::ftruncate(fd, static_cast<off_t>(end)) != 0) {
    return fail(Status(ErrorCode::kIoError, "cannot cut uncommitted bytes off " + path.string() + ": " +
                                                std::strerror(errno)));
  }
  return std::unique_ptr<ContainerUpdater>(
      new ContainerUpdater(fd, std::move(file).value(), std::move(opened).value(), end));
}

ContainerUpdater::~ContainerUpdater() {
  // Uncommitted chunks are unreferenced; cut them off again (best effort).
  if (!committed_once_ && end_ > start_) (void)::ftruncate(fd_, static_cast<off_t>(start_));
  ::close(fd_);  // also releases the lock
}

Status ContainerUpdater::write_at(uint64_t offset, std::span<const uint8_t> data) {
  int64_t budget = g_kill_after_bytes.load();
  if (budget >= 0) {
    if (static_cast<uint64_t>(budget) < data.size()) {
      // A crash in the middle of this write: what reached the file stays, then death.
      (void)::pwrite(fd_, data.data(), static_cast<size_t>(budget), static_cast<off_t>(offset));
      ::raise(SIGKILL);
    }
    g_kill_after_bytes.store(budget - static_cast<int64_t>(data.size()));
  }
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n =
        ::pwrite(fd_, data.data() + done, data.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      return Status(ErrorCode::kIoError, "write to " + file_->path().string() + " at byte offset " +
                                             std::to_string(offset + done) + " failed: " + std::strerror(errno));
    }
    done += static_cast<size_t>(n);
  }
  return Status::Ok();
}

Status ContainerUpdater::sync(const char* what) {
  if (::fsync(fd_) != 0) {
    return Status(ErrorCode::kIoError,
                  "sync of " + file_->path().string() + " " + what + " failed: " + std::strerror(errno));
  }
  return Status::Ok();
}

Result<uint64_t> ContainerUpdater::append_frame(std::span<const uint8_t> payload) {
  if (committed_once_) return Status(ErrorCode::kInternal, "append after commit");
  const uint64_t offset = end_;
  const std::vector<uint8_t> chunk = make_chunk(kFaceChunkTag, payload);
  SVC_RETURN_IF_ERROR(write_at(offset, chunk));
  end_ += chunk.size();
  return offset;
}

Status ContainerUpdater::commit(const ContainerIndex& index) {
  if (committed_once_) return Status(ErrorCode::kInternal, "commit called twice");
  const uint64_t index_offset = end_;
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, serialize_index(index));
  SVC_RETURN_IF_ERROR(write_at(index_offset, chunk));
  end_ += chunk.size();
  // The index and every face chunk must be durable before a slot points at them.
  SVC_RETURN_IF_ERROR(sync("before the commit"));
  const int slot = 1 - committed_.slot;
  const std::vector<uint8_t> record = make_commit_slot(committed_.generation + 1, index_offset, chunk.size());
  SVC_RETURN_IF_ERROR(write_at(kFileHeaderSize + static_cast<uint64_t>(slot) * kCommitSlotSize, record));
  SVC_RETURN_IF_ERROR(sync("after the commit"));
  committed_once_ = true;
  return Status::Ok();
}

}  // namespace svc
