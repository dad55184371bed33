// SPDX-License-Identifier: BSD-2-Clause
// The index chunk's payload: serialize_index and parse_index (docs/format.md, "The index").
#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <string>

#include "codec/common/cube_padding.h"
#include "common/bytes.h"
#include "container/container.h"

namespace svc {

namespace {

// Read: version 4 (no depth), 5 (depth in every frame record), 6 (features, border
// edges); written: 6.
constexpr uint32_t kIndexVersionWithoutDepth = 4;
constexpr uint32_t kIndexVersionWithDepth = 5;
constexpr uint32_t kIndexVersion = 6;

// "bit 3" or "bits 1, 2": the feature bits of `features`, for errors.
std::string feature_bit_names(uint32_t features) {
  std::string names;
  int count = 0;
  for (int bit = 0; bit < 32; ++bit) {
    if (features & (1u << bit)) names += (count++ ? ", " : "") + std::to_string(bit);
  }
  return (count == 1 ? "bit " : "bits ") + names;
}
// Version 6's feature word: the optional parts a file uses.
constexpr uint32_t kFeatureDepth = 0x1;
constexpr uint32_t kKnownFeatures = kFeatureDepth;
// Smallest record sizes, used to bound counts against the bytes left before allocating.
constexpr uint64_t kFrameRecordMinBytes = 1 + 1;  // type byte, payload size
constexpr uint64_t kCellRecordMinBytes = 1 + 1;   // raster gap, flags
// Cell record flags.
constexpr uint8_t kCentreOnGridBit = 0x01;
constexpr uint8_t kPreviousSourcesBit = 0x02;
constexpr uint8_t kCellFlagsReservedMask = 0xFC;
// Camera rig table.
constexpr uint8_t kExplicitCameraMarker = 255;
constexpr size_t kMaxRigEntries = 64;
// A rig entry: the rotation's nine entries two bits each (+0, -0, +1, -1) in 3 bytes, a
// flags byte (bit 0: the frustum is square and centred, right = top = -left = -bottom,
// and only right, near and far follow), then the frustum's doubles.
constexpr uint64_t kRigEntryMinBytes = 3 + 1 + 3 * 8;
constexpr uint8_t kSquareFrustumBit = 0x01;
// Frame record type byte: bits 0-1 frame type, bits 2-3 reference count, bit 4 cube
// references, bit 5 bare chunk; bit 6, the chunk follows the previous record's (no offset
// delta); bit 7, the references name the cells the previous record's do (no references).
constexpr uint8_t kFaceTypeMask = 0x03;
constexpr int kRefCountShift = 2;
constexpr uint8_t kRefCountMask = 0x03;
constexpr uint8_t kCubeReferencesBit = 0x10;
constexpr uint8_t kBareChunkBit = 0x20;
constexpr uint8_t kBackToBackBit = 0x40;
constexpr uint8_t kSameReferencesBit = 0x80;
constexpr int kMaxVarintBytes = 10;

std::string at_offset(uint64_t offset) { return " at byte offset " + std::to_string(offset); }

bool cell_less(const CellIndex& a, const CellIndex& b) {
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.x < b.x;
}

void write_frustum(ByteWriter& w, const Frustum& f) {
  for (double v : {f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane}) w.f64(v);
}

Frustum read_frustum(ByteReader& r) {
  Frustum f;
  for (double* v : {&f.left, &f.right, &f.bottom, &f.top, &f.near_plane, &f.far_plane}) *v = r.f64();
  return f;
}

void write_camera(ByteWriter& w, const Camera& camera) {
  for (double v : camera.world_to_camera) w.f64(v);
  write_frustum(w, camera.frustum);
}

Camera read_camera(ByteReader& r) {
  Camera camera;
  for (double& v : camera.world_to_camera) v = r.f64();
  camera.frustum = read_frustum(r);
  return camera;
}

bool frustum_is_valid(const Frustum& f) {
  for (double v : {f.left, f.right, f.bottom, f.top, f.near_plane, f.far_plane}) {
    if (!std::isfinite(v)) return false;
  }
  return f.right > f.left && f.top > f.bottom && f.near_plane > 0 && f.far_plane > f.near_plane;
}

bool camera_is_valid(const Camera& camera) {
  for (double v : camera.world_to_camera) {
    if (!std::isfinite(v)) return false;
  }
  return frustum_is_valid(camera.frustum);
}

// --- Camera rig ---------------------------------------------------------

// A face orientation shared by many cells: the rotation part of world_to_camera
// (row-major 3x3) and the frustum. The translation is derived from the cell centre.
struct RigEntry {
  std::array<double, 9> rotation{};
  Frustum frustum;
};

uint64_t bits_of(double v) { return std::bit_cast<uint64_t>(v); }

bool same_bits(const Frustum& a, const Frustum& b) {
  return bits_of(a.left) == bits_of(b.left) && bits_of(a.right) == bits_of(b.right) &&
         bits_of(a.bottom) == bits_of(b.bottom) && bits_of(a.top) == bits_of(b.top) &&
         bits_of(a.near_plane) == bits_of(b.near_plane) && bits_of(a.far_plane) == bits_of(b.far_plane);
}

bool same_bits(const Camera& a, const Camera& b) {
  for (size_t i = 0; i < a.world_to_camera.size(); ++i) {
    if (bits_of(a.world_to_camera[i]) != bits_of(b.world_to_camera[i])) return false;
  }
  return same_bits(a.frustum, b.frustum);
}

bool same_bits(const RigEntry& a, const RigEntry& b) {
  for (size_t i = 0; i < a.rotation.size(); ++i) {
    if (bits_of(a.rotation[i]) != bits_of(b.rotation[i])) return false;
  }
  return same_bits(a.frustum, b.frustum);
}

// Row i, column j of the upper-left 3x3 of a column-major 4x4 matrix is element j*4+i.
std::array<double, 9> rotation_of(const Camera& camera) {
  std::array<double, 9> rotation{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rotation[i * 3 + j] = camera.world_to_camera[j * 4 + i];
  }
  return rotation;
}

// Every entry 0, +1 or -1 with one non-zero per row and column. Then each product
// R_ij * c_j is exact and each row sum has at most one non-zero term, so the derived
// translation is exact and bit-identical whatever the evaluation order (or fused
// multiply-add) a compiler picks.
bool is_signed_permutation(const std::array<double, 9>& rotation) {
  std::array<int, 3> row_nonzero{}, column_nonzero{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double v = rotation[i * 3 + j];
      if (v == 0) continue;
      if (v != 1 && v != -1) return false;
      ++row_nonzero[i];
      ++column_nonzero[j];
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (row_nonzero[k] != 1 || column_nonzero[k] != 1) return false;
  }
  return true;
}

// world_to_camera = [R | -R c; 0 0 0 1], the layout glm::lookAt produces. The row sum
// is exact (one non-zero term), and subtracting it from +0 rather than negating makes a
// zero translation +0 whatever the signs of the zero terms: view matrices read back
// from text manifests carry +0 there.
Camera camera_from_rig(const RigEntry& entry, const std::array<double, 3>& centre) {
  Camera camera;
  std::array<double, 16>& m = camera.world_to_camera;
  m.fill(0.0);
  const std::array<double, 9>& r = entry.rotation;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[j * 4 + i] = r[i * 3 + j];
    m[12 + i] = 0.0 - ((r[i * 3 + 0] * centre[0] + r[i * 3 + 1] * centre[1]) + r[i * 3 + 2] * centre[2]);
  }
  m[15] = 1.0;
  camera.frustum = entry.frustum;
  return camera;
}

// The rig entry that reproduces `camera` bit for bit at `centre`, if its rotation is a
// signed permutation.
std::optional<RigEntry> rig_entry_for(const Camera& camera, const std::array<double, 3>& centre) {
  RigEntry entry{rotation_of(camera), camera.frustum};
  if (!is_signed_permutation(entry.rotation)) return std::nullopt;
  if (!same_bits(camera_from_rig(entry, centre), camera)) return std::nullopt;
  return entry;
}

// The entry of `rig` that reproduces `camera` at `centre` bit for bit, as its position
// in the table, or kExplicitCameraMarker when none does.
uint8_t rig_source(const Camera& camera, const std::array<double, 3>& centre, const std::vector<RigEntry>& rig) {
  const std::optional<RigEntry> entry = rig_entry_for(camera, centre);
  if (!entry) return kExplicitCameraMarker;
  const auto found = std::find_if(rig.begin(), rig.end(), [&](const RigEntry& e) { return same_bits(e, *entry); });
  return found == rig.end() ? kExplicitCameraMarker : static_cast<uint8_t>(found - rig.begin());
}

// A signed-permutation entry as a rig entry codes it: 0 for +0, 1 for -0, 2 for +1, 3 for -1.
uint32_t rotation_entry_code(double v) { return (v != 0 ? 2u : 0u) | (std::signbit(v) ? 1u : 0u); }
double rotation_entry_value(uint32_t code) {
  const double magnitude = code & 2 ? 1.0 : 0.0;
  return code & 1 ? -magnitude : magnitude;
}

bool is_square(const Frustum& f) {
  const double w = f.right;
  return bits_of(f.left) == bits_of(-w) && bits_of(f.bottom) == bits_of(-w) && bits_of(f.top) == bits_of(w);
}

// A rig entry (kRigEntryMinBytes); the rotation must be a signed permutation.
void write_rig_entry(ByteWriter& w, const RigEntry& entry) {
  uint32_t packed = 0;
  for (int k = 0; k < 9; ++k) packed |= rotation_entry_code(entry.rotation[static_cast<size_t>(k)]) << (2 * k);
  for (int b = 0; b < 3; ++b) w.u8(static_cast<uint8_t>(packed >> (8 * b)));
  const bool square = is_square(entry.frustum);
  w.u8(square ? kSquareFrustumBit : 0);
  if (!square) {
    write_frustum(w, entry.frustum);
    return;
  }
  for (double v : {entry.frustum.right, entry.frustum.near_plane, entry.frustum.far_plane}) w.f64(v);
}

// Reads what write_rig_entry wrote; the caller checks r.ok() and the entry's values.
// Returns false for reserved flag bits or rotation bits.
bool read_rig_entry(ByteReader& r, RigEntry& entry) {
  uint32_t packed = 0;
  for (int b = 0; b < 3; ++b) packed |= uint32_t{r.u8()} << (8 * b);
  const uint8_t flags = r.u8();
  for (int k = 0; k < 9; ++k) entry.rotation[static_cast<size_t>(k)] = rotation_entry_value(packed >> (2 * k) & 3);
  if (!(flags & kSquareFrustumBit)) {
    entry.frustum = read_frustum(r);
  } else {
    const double w = r.f64(), near = r.f64(), far = r.f64();
    entry.frustum = {-w, w, -w, w, near, far};
  }
  return (packed >> 18) == 0 && (flags & ~kSquareFrustumBit) == 0;
}

// Adds the entry that reproduces `camera` when the table has none yet and has room:
// first-use order makes the table a function of the cells alone.
void add_rig_entry(const Camera& camera, const std::array<double, 3>& centre, std::vector<RigEntry>& rig) {
  const std::optional<RigEntry> entry = rig_entry_for(camera, centre);
  if (!entry || rig.size() >= kMaxRigEntries) return;
  if (std::none_of(rig.begin(), rig.end(), [&](const RigEntry& e) { return same_bits(e, *entry); })) {
    rig.push_back(*entry);
  }
}

// --- Varints ------------------------------------------------------------

void write_varint(ByteWriter& w, uint64_t v) {
  while (v >= 0x80) {
    w.u8(static_cast<uint8_t>(v | 0x80));
    v >>= 7;
  }
  w.u8(static_cast<uint8_t>(v));
}

uint64_t zigzag_encode(int64_t v) { return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63); }
int64_t zigzag_decode(uint64_t v) { return static_cast<int64_t>(v >> 1) ^ -static_cast<int64_t>(v & 1); }

// --- Cell records ----------------------------------------------

// A cell's position in (y, z, x) order over the whole grid: the order of the records.
uint64_t raster_of(const CellIndex& c, const GridSpec& grid) {
  return (uint64_t(c.y) * uint64_t(grid.dims[2]) + uint64_t(c.z)) * uint64_t(grid.dims[0]) + uint64_t(c.x);
}

CellIndex cell_at_raster(uint64_t raster, const GridSpec& grid) {
  const uint64_t dx = uint64_t(grid.dims[0]), dz = uint64_t(grid.dims[2]);
  return CellIndex{static_cast<int32_t>(raster % dx), static_cast<int32_t>(raster / dx / dz),
                   static_cast<int32_t>(raster / dx % dz)};
}

// origin + index * spacing per axis, as one correctly rounded fused multiply-add: the
// same bits on every machine.
std::array<double, 3> grid_centre(const CellIndex& c, const GridSpec& grid) {
  const std::array<int32_t, 3> index{c.x, c.y, c.z};
  std::array<double, 3> centre{};
  for (int axis = 0; axis < 3; ++axis) {
    centre[axis] = std::fma(static_cast<double>(index[axis]), grid.spacing[axis], grid.origin[axis]);
  }
  return centre;
}

bool same_bits(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return bits_of(a[0]) == bits_of(b[0]) && bits_of(a[1]) == bits_of(b[1]) && bits_of(a[2]) == bits_of(b[2]);
}

// Unsigned LEB128: at most 10 bytes, no bits beyond 64, no redundant trailing zero
// byte (one encoding per value). `what` names the field for errors.
Result<uint64_t> read_varint(ByteReader& r, const std::string& what) {
  const uint64_t start = r.file_offset();
  uint64_t value = 0;
  for (int i = 0; i < kMaxVarintBytes; ++i) {
    const uint8_t byte = r.u8();
    if (!r.ok()) return corrupt_at(what + " is truncated", r.failed_at());
    const uint64_t bits = byte & 0x7F;
    if (i == kMaxVarintBytes - 1 && bits > 1) return corrupt_at(what + " overflows 64 bits", start);
    value |= bits << (7 * i);
    if ((byte & 0x80) == 0) {
      if (i > 0 && byte == 0) return corrupt_at(what + " has a redundant trailing zero byte", start);
      return value;
    }
  }
  return corrupt_at(what + " is longer than 10 bytes", start);
}

// --- Shared parsing ------------------------------------------------------------------

Status parse_header(ByteReader& r, const ReaderLimits& limits, ContainerIndex& index) {
  const uint64_t size_at = r.file_offset();
  index.face_width = r.u32();
  index.face_height = r.u32();
  for (int32_t& d : index.grid.dims) d = r.i32();
  for (double& v : index.grid.origin) v = r.f64();
  for (double& v : index.grid.spacing) v = r.f64();
  const uint8_t depth_mode = r.u8();
  const uint8_t up_axis = r.u8();
  const uint8_t motion = r.u8();
  const uint8_t reserved = r.u8();
  index.coding.quality = r.u32();
  index.coding.qindex = r.u32();
  for (int32_t& s : index.coding.i_spacing) s = r.i32();
  if (!r.ok()) return corrupt_at("index header is truncated", r.failed_at());

  if (index.face_width == 0 || index.face_height == 0 || index.face_width > limits.max_face_dimension ||
      index.face_height > limits.max_face_dimension ||
      uint64_t{index.face_width} * index.face_height > limits.max_face_pixels) {
    return Status(ErrorCode::kLimitExceeded, "face size " + std::to_string(index.face_width) + "x" +
                                                 std::to_string(index.face_height) +
                                                 " is zero or above the reader's limits" + at_offset(size_at));
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (index.grid.dims[axis] <= 0) {
      return corrupt_at("grid dimension " + std::to_string(index.grid.dims[axis]) + " on axis " +
                            std::to_string(axis) + " is not positive",
                        size_at + 8 + 4 * axis);
    }
    if (index.grid.dims[axis] > limits.max_grid_dimension) {
      return Status(ErrorCode::kLimitExceeded,
                    "grid dimension " + std::to_string(index.grid.dims[axis]) + " on axis " + std::to_string(axis) +
                        " is above the reader's limit" + at_offset(size_at + 8 + 4 * axis));
    }
    if (!std::isfinite(index.grid.origin[axis]) || !std::isfinite(index.grid.spacing[axis]) ||
        index.grid.spacing[axis] <= 0) {
      return corrupt_at("grid origin or spacing is not finite and positive", size_at + 20);
    }
    if (index.coding.i_spacing[axis] <= 0) {
      return corrupt_at("I-cube spacing is not positive", size_at);
    }
  }
  if (depth_mode > 1 || up_axis > 2 || motion > 1) {
    return corrupt_at("depth mode, up axis or motion source has an unknown value", size_at + 68);
  }
  // Index version 5 keeps the depth's maximum error there; version 4 a reserved 0.
  if (!index.depth && reserved != 0) return corrupt_at("reserved index byte is not 0", size_at + 71);
  index.depth_max_error = reserved;
  index.depth_mode = static_cast<DepthMode>(depth_mode);
  index.up_axis = static_cast<UpAxis>(up_axis);
  index.coding.motion = static_cast<MotionSearch>(motion);
  return Status::Ok();
}

Result<std::vector<RigEntry>> parse_rig_table(ByteReader& r) {
  const uint64_t count_at = r.file_offset();
  const uint64_t count = r.u8();
  if (!r.ok()) return corrupt_at("index is truncated before the camera rig table", r.failed_at());
  if (count > kMaxRigEntries) {
    return corrupt_at("camera rig table has " + std::to_string(count) + " entries, more than " +
                          std::to_string(kMaxRigEntries),
                      count_at);
  }
  if (count * kRigEntryMinBytes > r.remaining()) {
    return corrupt_at("camera rig table of " + std::to_string(count) + " entries does not fit in the index",
                      count_at);
  }
  std::vector<RigEntry> rig(count);
  for (uint64_t k = 0; k < count; ++k) {
    const uint64_t entry_at = r.file_offset();
    const bool reserved_clear = read_rig_entry(r, rig[k]);
    if (!r.ok()) return corrupt_at("camera rig entry " + std::to_string(k) + " is truncated", entry_at);
    if (!reserved_clear) {
      return corrupt_at("camera rig entry " + std::to_string(k) + " has reserved bits set", entry_at);
    }
    if (!is_signed_permutation(rig[k].rotation)) {
      return corrupt_at("camera rig entry " + std::to_string(k) +
                            " has a rotation that is not a signed permutation",
                        entry_at);
    }
    if (!frustum_is_valid(rig[k].frustum)) {
      return corrupt_at("camera rig entry " + std::to_string(k) + " has an invalid frustum", entry_at + 4);
    }
  }
  return rig;
}

// Checks once a cell record is read whole.
Status check_cell(const ContainerIndex& index, uint64_t i, uint64_t record_at) {
  const CellRecord& cell = index.cells[i];
  const CellIndex& c = cell.index;
  if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= index.grid.dims[0] || c.y >= index.grid.dims[1] ||
      c.z >= index.grid.dims[2]) {
    return corrupt_at(cell_label(c) + " lies outside the grid", record_at);
  }
  if (i > 0 && !cell_less(index.cells[i - 1].index, c)) {
    return corrupt_at(cell_label(c) + " is out of order or repeated in the index", record_at);
  }
  for (double v : cell.position) {
    if (!std::isfinite(v)) return corrupt_at(cell_label(c) + " has a non-finite position", record_at);
  }
  for (int f = 0; f < kFaceCount; ++f) {
    if (!camera_is_valid(index.cameras[i][f])) {
      return corrupt_at(face_label(c, static_cast<Face>(f)) + " has an invalid camera", record_at);
    }
  }
  return Status::Ok();
}

// The six face cameras, each from a rig entry at the cell's centre or
// explicit; sets each face's source (kExplicitCameraMarker for an explicit one).
Status read_face_cameras(ByteReader& r, const std::vector<RigEntry>& rig, const CellRecord& cell,
                         CellCameras& cameras, std::array<uint8_t, kFaceCount>& sources) {
  for (int f = 0; f < kFaceCount; ++f) {
    const uint64_t source_at = r.file_offset();
    sources[f] = r.u8();
    if (!r.ok()) return Status::Ok();  // the caller reports the truncation
    if (sources[f] == kExplicitCameraMarker) {
      cameras[f] = read_camera(r);
    } else if (sources[f] < rig.size()) {
      // A non-finite centre makes a non-finite camera; check_cell names the centre first.
      cameras[f] = camera_from_rig(rig[sources[f]], cell.position);
    } else {
      return corrupt_at(face_label(cell.index, static_cast<Face>(f)) + " names camera rig entry " +
                            std::to_string(sources[f]) + " of " + std::to_string(rig.size()),
                        source_at);
    }
  }
  return Status::Ok();
}

bool all_from_rig(const std::array<uint8_t, kFaceCount>& sources) {
  return std::none_of(sources.begin(), sources.end(), [](uint8_t s) { return s == kExplicitCameraMarker; });
}

// A cell record after the one that ended at raster position `next_raster`
// (whose face sources were `previous`, none on the first record).
Status read_cell(ByteReader& r, const std::vector<RigEntry>& rig, uint64_t i, uint64_t& next_raster,
                 std::optional<std::array<uint8_t, kFaceCount>>& previous, ContainerIndex& index) {
  const uint64_t record_at = r.file_offset();
  const GridSpec& grid = index.grid;
  const uint64_t cells_in_grid = uint64_t(grid.dims[0]) * uint64_t(grid.dims[1]) * uint64_t(grid.dims[2]);
  SVC_ASSIGN_OR_RETURN(const uint64_t gap, read_varint(r, "cell record " + std::to_string(i) + " position"));
  if (gap >= cells_in_grid - next_raster) {
    return corrupt_at("cell record " + std::to_string(i) + " lies past the end of the grid", record_at);
  }
  const uint64_t raster = next_raster + gap;
  next_raster = raster + 1;
  CellRecord& cell = index.cells[i];
  cell.index = cell_at_raster(raster, grid);
  const uint64_t flags_at = r.file_offset();
  const uint8_t flags = r.u8();
  if (!r.ok()) return corrupt_at("cell record " + std::to_string(i) + " is truncated", record_at);
  if (flags & kCellFlagsReservedMask) {
    return corrupt_at(cell_label(cell.index) + " has reserved flags set", flags_at);
  }
  if (flags & kCentreOnGridBit) {
    cell.position = grid_centre(cell.index, grid);
  } else {
    for (double& v : cell.position) v = r.f64();
  }
  std::array<uint8_t, kFaceCount> sources{};
  if (flags & kPreviousSourcesBit) {
    if (!previous || !all_from_rig(*previous)) {
      return corrupt_at(cell_label(cell.index) + " takes the previous cell's rig entries, which it has not",
                        flags_at);
    }
    sources = *previous;
    for (int f = 0; f < kFaceCount; ++f) index.cameras[i][f] = camera_from_rig(rig[sources[f]], cell.position);
  } else {
    SVC_RETURN_IF_ERROR(read_face_cameras(r, rig, cell, index.cameras[i], sources));
  }
  previous = sources;
  if (!r.ok()) return corrupt_at("cell record " + std::to_string(i) + " is truncated", record_at);
  return check_cell(index, i, record_at);
}

Status parse_cells(ByteReader& r, const std::vector<RigEntry>& rig, const ReaderLimits& limits,
                   ContainerIndex& index) {
  const uint64_t cells_at = r.file_offset();
  const uint64_t cell_count = r.u32();
  if (!r.ok()) return corrupt_at("index is truncated before the cell count", r.failed_at());
  if (cell_count == 0 || cell_count > limits.max_cells) {
    return Status(ErrorCode::kLimitExceeded, "cell count " + std::to_string(cell_count) +
                                                 " is zero or above the reader's limit" + at_offset(cells_at));
  }
  if (cell_count * kCellRecordMinBytes > r.remaining()) {
    return corrupt_at("cell count " + std::to_string(cell_count) + " does not fit in the index", cells_at);
  }
  index.cells.resize(cell_count);
  index.cameras.resize(cell_count);
  uint64_t next_raster = 0;
  std::optional<std::array<uint8_t, kFaceCount>> previous;
  for (uint64_t i = 0; i < cell_count; ++i) {
    SVC_RETURN_IF_ERROR(read_cell(r, rig, i, next_raster, previous, index));
  }
  return Status::Ok();
}

// Checks once a frame record's fixed fields are read.
Status check_frame(const FrameRecord& frame, uint8_t kind, uint64_t ref_count, const std::string& what,
                   uint64_t record_at, uint64_t file_size, const ReaderLimits& limits) {
  if (kind > 1) return corrupt_at(what + " has an unknown frame type " + std::to_string(kind), record_at);
  if (frame.payload_size > limits.max_frame_bytes) {
    return Status(ErrorCode::kLimitExceeded, what + " is " + std::to_string(frame.payload_size) +
                                                 " bytes, above the reader's limit" + at_offset(record_at));
  }
  if (frame.chunk_offset < kPreludeSize || frame.chunk_offset > file_size ||
      chunk_bytes(frame) > file_size - frame.chunk_offset) {
    return corrupt_at(what + " points at bytes " + std::to_string(frame.chunk_offset) + " outside the file",
                      record_at);
  }
  if ((static_cast<FaceType>(kind) == FaceType::kIntra) != (ref_count == 0) || ref_count > 2) {
    return corrupt_at(what + " has " + std::to_string(ref_count) + " references, which its type does not allow",
                      record_at);
  }
  return Status::Ok();
}

std::string frame_name(const ContainerIndex& index, uint64_t i) {
  return face_label(index.cells[i / kFaceCount].index, static_cast<Face>(i % kFaceCount));
}

// Type byte bit 7: frame i references the cells frame i - 1 of the same cell does.
Status copy_previous_references(ContainerIndex& index, uint64_t i, uint64_t ref_count, const std::string& what,
                                uint64_t record_at) {
  if (i % kFaceCount == 0) {
    return corrupt_at(what + " shares the references of a previous face, but is its cell's first", record_at);
  }
  const FrameRecord& previous = index.frames[i - 1];
  if (previous.references.size() != ref_count) {
    return corrupt_at(what + " shares the previous face's references, but counts " + std::to_string(ref_count) +
                          " against its " + std::to_string(previous.references.size()),
                      record_at);
  }
  FrameReferences references;
  for (uint32_t ref : previous.references) references.push_back(ref + 1);  // the same cell, the next face
  index.frames[i].references = references;
  return Status::Ok();
}

// Frame i's `ref_count` references as listed in its record: the referenced cell's ordinal
// less this frame's, zigzag-signed (the face is the frame's own).
Status read_listed_references(ByteReader& r, ContainerIndex& index, uint64_t i, uint64_t ref_count,
                              const std::string& what, uint64_t record_at) {
  const uint64_t frame_count = index.frames.size();
  FrameRecord& frame = index.frames[i];
  frame.references.resize(ref_count);
  for (uint32_t& ref : frame.references) {
    SVC_ASSIGN_OR_RETURN(const uint64_t value, read_varint(r, what + " reference"));
    const int64_t cell_delta = zigzag_decode(value);
    const uint64_t cell_count = frame_count / kFaceCount;
    if (cell_delta < -static_cast<int64_t>(frame.cell) ||
        cell_delta >= static_cast<int64_t>(cell_count - frame.cell)) {
      return corrupt_at(what + " references a cell " + std::to_string(cell_delta) + " cells away, outside the " +
                            std::to_string(cell_count),
                        record_at);
    }
    ref = static_cast<uint32_t>((frame.cell + cell_delta) * kFaceCount + i % kFaceCount);
  }
  return Status::Ok();
}

// Index version 5: the size of the depth chunk after the face's own, which must be bare.
Status read_depth_size(ByteReader& r, FrameRecord& frame, const std::string& what, uint64_t record_at,
                       const ReaderLimits& limits) {
  SVC_ASSIGN_OR_RETURN(const uint64_t depth_size, read_varint(r, what + " depth size"));
  if (depth_size == 0 || !frame.bare_chunk) {
    return corrupt_at(what + " has no depth chunk, or a face chunk that is not bare", record_at);
  }
  if (depth_size > limits.max_frame_bytes) {
    return Status(ErrorCode::kLimitExceeded, what + " depth is " + std::to_string(depth_size) +
                                                 " bytes, above the reader's limit" + at_offset(record_at));
  }
  frame.depth_size = static_cast<uint32_t>(depth_size);
  return Status::Ok();
}

// Varint records (docs/format.md "Frame record").
// Version 6: which border edges of each reference a B-face with cube references reads.
Status read_border_edges(ByteReader& r, FrameRecord& frame, uint64_t ref_count, const std::string& what,
                         uint64_t record_at) {
  frame.border_edges = r.u8();
  if (!r.ok()) return corrupt_at(what + " record is truncated before its border edges", record_at);
  if (ref_count < 2 && (frame.border_edges & 0xF0) != 0) {
    return corrupt_at(what + " has one reference but border edges " + std::to_string(frame.border_edges) +
                          " name a second",
                      record_at);
  }
  return Status::Ok();
}

Status parse_frames(ByteReader& r, uint64_t file_size, const ReaderLimits& limits, bool with_border_edges,
                    ContainerIndex& index) {
  const uint64_t frame_count = index.frames.size();
  uint64_t previous_end = kPreludeSize;  // where the previous frame's chunk ends
  for (uint64_t i = 0; i < frame_count; ++i) {
    const uint64_t record_at = r.file_offset();
    FrameRecord& frame = index.frames[i];
    frame.cell = static_cast<uint32_t>(i / kFaceCount);
    frame.face = static_cast<Face>(i % kFaceCount);
    const std::string what = frame_name(index, i);
    const uint8_t head = r.u8();
    if (!r.ok()) return corrupt_at("frame record " + std::to_string(i) + " is truncated", record_at);
    const bool back_to_back = (head & kBackToBackBit) != 0;
    const bool same_references = (head & kSameReferencesBit) != 0;
    const uint8_t kind = head & kFaceTypeMask;
    const uint8_t ref_count = (head >> kRefCountShift) & kRefCountMask;
    frame.cube_references = (head & kCubeReferencesBit) != 0;
    frame.bare_chunk = (head & kBareChunkBit) != 0;
    if (frame.cube_references && static_cast<FaceType>(kind) != FaceType::kPredicted) {
      return corrupt_at(what + " is not a B-face but has the cube-references bit set", record_at);
    }

    uint64_t zigzag = 0;
    if (!back_to_back) {
      SVC_ASSIGN_OR_RETURN(zigzag, read_varint(r, what + " chunk offset"));
    }
    const int64_t delta = zigzag_decode(zigzag);
    // previous_end <= file_size here, so these bounds keep the sum inside [0, file_size].
    const uint64_t magnitude = delta < 0 ? uint64_t{0} - static_cast<uint64_t>(delta)
                                         : static_cast<uint64_t>(delta);
    if ((delta < 0 && magnitude > previous_end) || (delta >= 0 && magnitude > file_size - previous_end)) {
      return corrupt_at(what + " chunk offset delta " + std::to_string(delta) + " leads outside the file",
                        record_at);
    }
    frame.chunk_offset = delta < 0 ? previous_end - magnitude : previous_end + magnitude;

    SVC_ASSIGN_OR_RETURN(const uint64_t payload_size, read_varint(r, what + " payload size"));
    if (payload_size > UINT32_MAX) {
      return corrupt_at(what + " payload size " + std::to_string(payload_size) + " does not fit 32 bits",
                        record_at);
    }
    frame.payload_size = static_cast<uint32_t>(payload_size);
    if (index.depth) SVC_RETURN_IF_ERROR(read_depth_size(r, frame, what, record_at, limits));
    SVC_RETURN_IF_ERROR(check_frame(frame, kind, ref_count, what, record_at, file_size, limits));
    frame.type = static_cast<FaceType>(kind);
    SVC_RETURN_IF_ERROR(same_references ? copy_previous_references(index, i, ref_count, what, record_at)
                                        : read_listed_references(r, index, i, ref_count, what, record_at));
    if (with_border_edges && frame.cube_references) {
      SVC_RETURN_IF_ERROR(read_border_edges(r, frame, ref_count, what, record_at));
    }
    previous_end = frame.chunk_offset + chunk_bytes(frame);
  }
  return Status::Ok();
}

// Whether `references` (of a frame) name the cells `previous` (of the frame before it,
// the same cell's previous face) name, in the same order.
bool same_reference_cells(const FrameReferences& references, const FrameReferences& previous) {
  if (references.size() != previous.size()) return false;
  for (size_t k = 0; k < references.size(); ++k) {
    if (references[k] / kFaceCount != previous[k] / kFaceCount) return false;
  }
  return true;
}

}  // namespace

std::vector<uint8_t> serialize_index(const ContainerIndex& index) {
  // Reading from the index's own cells cannot fail.
  return serialize_index(index, [&](size_t c) -> Result<CellCameras> { return index.cameras[c]; }).value();
}

Result<std::vector<uint8_t>> serialize_index(const ContainerIndex& index, const CameraReader& read_cameras) {
  ByteWriter w;
  w.u32(kIndexVersion);
  w.u32(index.depth ? kFeatureDepth : 0);
  w.u32(index.face_width);
  w.u32(index.face_height);
  for (int32_t d : index.grid.dims) w.i32(d);
  for (double v : index.grid.origin) w.f64(v);
  for (double v : index.grid.spacing) w.f64(v);
  w.u8(static_cast<uint8_t>(index.depth_mode));
  w.u8(static_cast<uint8_t>(index.up_axis));
  w.u8(static_cast<uint8_t>(index.coding.motion));
  w.u8(index.depth ? static_cast<uint8_t>(index.depth_max_error) : uint8_t{0});
  w.u32(index.coding.quality);
  w.u32(index.coding.qindex);
  for (int32_t s : index.coding.i_spacing) w.i32(s);

  // Rig entries in first-use order; a face whose camera no entry reproduces bit for bit
  // (or once the table is full) is stored explicitly. The cells are read twice, first
  // for the table, then for the records, so that none of them needs to be held.
  std::vector<RigEntry> rig;
  for (size_t c = 0; c < index.cells.size(); ++c) {
    SVC_ASSIGN_OR_RETURN(const CellCameras cameras, read_cameras(c));
    for (const Camera& camera : cameras) add_rig_entry(camera, index.cells[c].position, rig);
  }
  w.u8(static_cast<uint8_t>(rig.size()));
  for (const RigEntry& entry : rig) write_rig_entry(w, entry);

  // Cell records: the position in (y, z, x) order as the gap from the previous
  // record, a centre on the grid and the previous cell's rig entries as flags.
  w.u32(static_cast<uint32_t>(index.cells.size()));
  uint64_t next_raster = 0;
  std::optional<std::array<uint8_t, kFaceCount>> previous;
  for (size_t c = 0; c < index.cells.size(); ++c) {
    const CellRecord& cell = index.cells[c];
    SVC_ASSIGN_OR_RETURN(const CellCameras cameras, read_cameras(c));
    const uint64_t raster = raster_of(cell.index, index.grid);
    write_varint(w, raster - next_raster);
    next_raster = raster + 1;
    std::array<uint8_t, kFaceCount> sources{};
    for (int f = 0; f < kFaceCount; ++f) sources[f] = rig_source(cameras[f], cell.position, rig);
    const bool on_grid = same_bits(cell.position, grid_centre(cell.index, index.grid));
    const bool as_previous = previous && all_from_rig(*previous) && sources == *previous;
    w.u8(static_cast<uint8_t>((on_grid ? kCentreOnGridBit : 0) | (as_previous ? kPreviousSourcesBit : 0)));
    if (!on_grid) {
      for (double v : cell.position) w.f64(v);
    }
    if (!as_previous) {
      for (int f = 0; f < kFaceCount; ++f) {
        w.u8(sources[f]);
        if (sources[f] == kExplicitCameraMarker) write_camera(w, cameras[f]);
      }
    }
    previous = sources;
  }

  w.u32(static_cast<uint32_t>(index.frames.size()));
  uint64_t previous_end = kPreludeSize;
  for (size_t n = 0; n < index.frames.size(); ++n) {
    const FrameRecord& frame = index.frames[n];
    const auto cell = static_cast<int64_t>(n / kFaceCount);
    const bool back_to_back = frame.chunk_offset == previous_end;
    const bool same_references = n % kFaceCount != 0 && !frame.references.empty() &&
                                 same_reference_cells(frame.references, index.frames[n - 1].references);
    w.u8(static_cast<uint8_t>((static_cast<uint8_t>(frame.type) & kFaceTypeMask) |
                              (frame.references.size() & kRefCountMask) << kRefCountShift |
                              (frame.cube_references ? kCubeReferencesBit : 0) |
                              (frame.bare_chunk ? kBareChunkBit : 0) | (back_to_back ? kBackToBackBit : 0) |
                              (same_references ? kSameReferencesBit : 0)));
    // Two's complement difference: chunks appended by `svc add` lie before earlier ones.
    if (!back_to_back) write_varint(w, zigzag_encode(static_cast<int64_t>(frame.chunk_offset - previous_end)));
    write_varint(w, frame.payload_size);
    if (index.depth) write_varint(w, frame.depth_size);
    // References of the same face (the only ones parse_index accepts): the cell suffices.
    if (!same_references) {
      for (uint32_t ref : frame.references) {
        write_varint(w, zigzag_encode(static_cast<int64_t>(ref / kFaceCount) - cell));
      }
    }
    // A second reference's bits only with a second reference: one encoding per value.
    if (frame.cube_references) w.u8(frame.references.size() < 2 ? frame.border_edges & 0x0F : frame.border_edges);
    previous_end = frame.chunk_offset + chunk_bytes(frame);
  }
  for (const FaceTypeStats& t : index.stats) {
    for (uint64_t v : {t.faces, t.bytes, t.mb_intra, t.mb_forward, t.mb_backward, t.mb_bidirectional, t.mb_skipped,
                       t.candidate_vectors, t.candidate_macroblocks}) {
      write_varint(w, v);
    }
  }
  return w.take();
}

Result<ContainerIndex> parse_index(std::span<const uint8_t> payload, uint64_t payload_offset, uint64_t file_size,
                                   const ReaderLimits& limits) {
  ByteReader r(payload, payload_offset);
  ContainerIndex index;
  const uint64_t version_at = r.file_offset();
  const uint32_t version = r.u32();
  if (!r.ok()) return corrupt_at("index is truncated", r.failed_at());
  if (version < kIndexVersionWithoutDepth || version > kIndexVersion) {
    return Status(ErrorCode::kUnsupported, "index version " + std::to_string(version) +
                                               " is not supported (this build reads 4 to 6)" +
                                               at_offset(version_at));
  }
  uint32_t features = version == kIndexVersionWithDepth ? kFeatureDepth : 0;
  if (version == kIndexVersion) {
    const uint64_t features_at = r.file_offset();
    features = r.u32();
    if (!r.ok()) return corrupt_at("index is truncated", r.failed_at());
    if ((features & ~kKnownFeatures) != 0) {
      return Status(ErrorCode::kUnsupported, "index uses feature " + feature_bit_names(features & ~kKnownFeatures) +
                                                 " that this build does not know (it knows bit 0, depth)" +
                                                 at_offset(features_at));
    }
  }
  index.depth = (features & kFeatureDepth) != 0;
  SVC_RETURN_IF_ERROR(parse_header(r, limits, index));
  SVC_ASSIGN_OR_RETURN(const std::vector<RigEntry> rig, parse_rig_table(r));
  SVC_RETURN_IF_ERROR(parse_cells(r, rig, limits, index));

  const uint64_t frames_at = r.file_offset();
  const uint64_t frame_count = r.u32();
  if (!r.ok()) return corrupt_at("index is truncated before the frame count", r.failed_at());
  if (frame_count != index.cells.size() * kFaceCount) {
    return corrupt_at("frame count " + std::to_string(frame_count) + " is not six per cell", frames_at);
  }
  if (frame_count * kFrameRecordMinBytes > r.remaining()) {
    return corrupt_at("frame count " + std::to_string(frame_count) + " does not fit in the index", frames_at);
  }
  index.frames.resize(frame_count);
  SVC_RETURN_IF_ERROR(parse_frames(r, file_size, limits, version == kIndexVersion, index));
  // References must name existing intra frames of the same face, and cube references
  // I-faces of the same cells: then no cycle and no chain can exist, and any face
  // decodes from at most the faces of two I-cubes.
  for (uint64_t i = 0; i < frame_count; ++i) {
    const FrameRecord& frame = index.frames[i];
    for (uint32_t ref : frame.references) {
      if (ref >= frame_count || index.frames[ref].type != FaceType::kIntra ||
          index.frames[ref].face != frame.face) {
        return corrupt_at(face_label(index.cells[frame.cell].index, frame.face) + " references frame " +
                              std::to_string(ref) + ", which is not an I-face of the same face",
                          frames_at);
      }
    }
    for (uint32_t dependency : index.depth ? depth_dependencies(frame) : frame_dependencies(frame)) {
      if (index.frames[dependency].type != FaceType::kIntra) {
        return corrupt_at(face_label(index.cells[frame.cell].index, frame.face) +
                              " depends on its reference cubes, but " + frame_name(index, dependency) +
                              " of its reference cube is not an I-face",
                          frames_at);
      }
    }
  }
  for (FaceTypeStats& t : index.stats) {
    for (uint64_t* v : {&t.faces, &t.bytes, &t.mb_intra, &t.mb_forward, &t.mb_backward, &t.mb_bidirectional,
                        &t.mb_skipped, &t.candidate_vectors, &t.candidate_macroblocks}) {
      SVC_ASSIGN_OR_RETURN(*v, read_varint(r, "encoder statistics"));
    }
  }
  if (!r.ok()) return corrupt_at("encoder statistics are truncated", r.failed_at());
  if (r.remaining() != 0) {
    return corrupt_at(std::to_string(r.remaining()) + " unexpected bytes after the index records", r.file_offset());
  }
  return index;
}

namespace {

std::vector<uint32_t> dependencies(const FrameRecord& frame, bool cube_references, bool every_edge) {
  std::vector<uint32_t> out(frame.references.begin(), frame.references.end());
  if (!cube_references) return out;
  for (size_t r = 0; r < frame.references.size(); ++r) {
    const uint32_t cube = frame.references[r] - frame.references[r] % kFaceCount;
    const uint8_t edges = every_edge ? codec::kAllFaceEdges : reference_border_edges(frame, r);
    for (Face g : codec::adjacent_faces(frame.face)) {
      if (codec::border_edges_show(frame.face, edges, g)) out.push_back(cube + static_cast<uint32_t>(g));
    }
  }
  return out;
}

}  // namespace

std::vector<uint32_t> frame_dependencies(const FrameRecord& frame) {
  return dependencies(frame, frame.cube_references, false);
}

std::vector<uint32_t> depth_dependencies(const FrameRecord& frame) { return dependencies(frame, true, true); }

}  // namespace svc
