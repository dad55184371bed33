// SPDX-License-Identifier: BSD-2-Clause
// The .svc index: serialization round trip, validation of damaged fields, and the refusal
// of index versions other than 4 to 6 and of features this build does not know.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "common/bytes.h"
#include "container/container.h"

namespace svc {
namespace {

ContainerIndex sample_index() {
  ContainerIndex index;
  index.face_width = 64;
  index.face_height = 48;
  index.grid.dims = {2, 1, 2};
  index.grid.origin = {-1, 1.5, 2};
  index.grid.spacing = {0.5, 1, 0.25};
  index.coding.quality = 70;
  index.coding.qindex = 5;
  index.coding.i_spacing = {3, 1, 3};
  const CellIndex cells[] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}};
  for (const CellIndex& c : cells) {
    CellRecord record;
    record.index = c;
    record.position = {c.x * 0.5, 1.5, c.z * 0.25};
    CellCameras cameras;
    cameras[2].world_to_camera[12] = 3.25;
    cameras[4].frustum.far_plane = 77;
    index.cells.push_back(record);
    index.cameras.push_back(cameras);
  }
  for (uint32_t f = 0; f < index.cells.size() * kFaceCount; ++f) {
    FrameRecord frame;
    frame.cell = f / kFaceCount;
    frame.face = static_cast<Face>(f % kFaceCount);
    frame.type = frame.cell == 0 ? FaceType::kIntra : FaceType::kPredicted;
    if (frame.type == FaceType::kPredicted) frame.references = {f % kFaceCount};
    frame.chunk_offset = kPreludeSize + 100 * f;
    frame.payload_size = 50;
    index.frames.push_back(frame);
  }
  return index;
}

constexpr uint64_t kFileSize = 1 << 20;
// The rig table follows the 96-byte header.
constexpr size_t kRigCountAt = 4 + 4 + 8 + 12 + 48 + 4 + 8 + 12;
// A rig entry with a square frustum: packed rotation, flags, right, near and far.
constexpr size_t kSquareRigEntryBytes = 3 + 1 + 3 * 8;

TEST(ContainerIndex, RoundTripsEveryField) {
  const ContainerIndex index = sample_index();
  const std::vector<uint8_t> bytes = serialize_index(index);
  auto parsed = parse_index(bytes, 1000, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  EXPECT_EQ(parsed->face_width, 64u);
  EXPECT_EQ(parsed->face_height, 48u);
  EXPECT_EQ(parsed->grid.dims, index.grid.dims);
  EXPECT_EQ(parsed->grid.spacing, index.grid.spacing);
  EXPECT_EQ(parsed->coding.qindex, 5u);
  EXPECT_EQ(parsed->coding.i_spacing, index.coding.i_spacing);
  ASSERT_EQ(parsed->cells.size(), 3u);
  EXPECT_EQ(parsed->cells[2].index, (CellIndex{1, 0, 1}));
  EXPECT_EQ(parsed->cameras[1][2].world_to_camera[12], 3.25);
  EXPECT_EQ(parsed->cameras[1][4].frustum.far_plane, 77);
  ASSERT_EQ(parsed->frames.size(), 18u);
  EXPECT_EQ(parsed->frames[7].type, FaceType::kPredicted);
  EXPECT_EQ(parsed->frames[7].references, FrameReferences{1});
  EXPECT_EQ(parsed->frames[17].chunk_offset, kPreludeSize + 1700);
  EXPECT_EQ(serialize_index(*parsed), bytes);
}

TEST(ContainerIndex, EveryTruncationIsAnErrorNotACrash) {
  const std::vector<uint8_t> bytes = serialize_index(sample_index());
  for (size_t n = 0; n < bytes.size(); ++n) {
    auto parsed = parse_index(std::span(bytes).first(n), 0, kFileSize, ReaderLimits{});
    ASSERT_FALSE(parsed.ok()) << "truncated to " << n;
    EXPECT_EQ(parsed.status().code(), ErrorCode::kCorruptData) << parsed.status().to_string();
  }
}

TEST(ContainerIndex, RejectsReferencesToPredictedFaces) {
  ContainerIndex index = sample_index();
  index.frames[13].references = {7};  // cell 2 face nx -> cell 1 face nx, a B-face
  auto parsed = parse_index(serialize_index(index), 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("cell (1,0,1) face nx"), std::string::npos) << parsed.status().message();
}

TEST(ContainerIndex, RejectsOffsetsOutsideTheFile) {
  ContainerIndex index = sample_index();
  index.frames[4].chunk_offset = kFileSize - 10;
  auto parsed = parse_index(serialize_index(index), 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("cell (0,0,0) face pz"), std::string::npos) << parsed.status().message();
}

TEST(ContainerIndex, EnforcesCallerLimitsBeforeAllocating) {
  const std::vector<uint8_t> bytes = serialize_index(sample_index());
  ReaderLimits small;
  small.max_face_dimension = 32;
  auto parsed = parse_index(bytes, 0, kFileSize, small);
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().code(), ErrorCode::kLimitExceeded);

  // A huge cell count with few bytes behind it must fail without allocating for it.
  std::vector<uint8_t> forged = bytes;
  ASSERT_EQ(bytes[kRigCountAt], 0);  // sample_index's cameras are all explicit
  const size_t cell_count_at = kRigCountAt + 1;
  forged[cell_count_at + 0] = 0xff;
  forged[cell_count_at + 1] = 0xff;
  forged[cell_count_at + 2] = 0x3f;
  parsed = parse_index(forged, 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("does not fit"), std::string::npos) << parsed.status().message();
}

// --- Camera rig, cell and frame records ---

uint64_t bits(double v) { return std::bit_cast<uint64_t>(v); }

void expect_same_camera(const Camera& a, const Camera& b, const std::string& where) {
  for (size_t i = 0; i < a.world_to_camera.size(); ++i) {
    EXPECT_EQ(bits(a.world_to_camera[i]), bits(b.world_to_camera[i])) << where << " matrix element " << i;
  }
  const Frustum& f = a.frustum;
  const Frustum& g = b.frustum;
  EXPECT_EQ(bits(f.left), bits(g.left)) << where;
  EXPECT_EQ(bits(f.right), bits(g.right)) << where;
  EXPECT_EQ(bits(f.bottom), bits(g.bottom)) << where;
  EXPECT_EQ(bits(f.top), bits(g.top)) << where;
  EXPECT_EQ(bits(f.near_plane), bits(g.near_plane)) << where;
  EXPECT_EQ(bits(f.far_plane), bits(g.far_plane)) << where;
}

std::vector<uint64_t> stat_fields(const FaceTypeStats& t) {
  return {t.faces,
          t.bytes,
          t.mb_intra,
          t.mb_forward,
          t.mb_backward,
          t.mb_bidirectional,
          t.mb_skipped,
          t.candidate_vectors,
          t.candidate_macroblocks};
}

// Every field, doubles compared bit for bit.
void expect_same_index(const ContainerIndex& a, const ContainerIndex& b) {
  EXPECT_EQ(a.face_width, b.face_width);
  EXPECT_EQ(a.face_height, b.face_height);
  EXPECT_EQ(a.grid.dims, b.grid.dims);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(bits(a.grid.origin[axis]), bits(b.grid.origin[axis]));
    EXPECT_EQ(bits(a.grid.spacing[axis]), bits(b.grid.spacing[axis]));
  }
  EXPECT_EQ(a.depth_mode, b.depth_mode);
  EXPECT_EQ(a.up_axis, b.up_axis);
  EXPECT_EQ(a.coding.quality, b.coding.quality);
  EXPECT_EQ(a.coding.qindex, b.coding.qindex);
  EXPECT_EQ(a.coding.i_spacing, b.coding.i_spacing);
  EXPECT_EQ(a.coding.motion, b.coding.motion);
  ASSERT_EQ(a.cells.size(), b.cells.size());
  for (size_t i = 0; i < a.cells.size(); ++i) {
    EXPECT_EQ(a.cells[i].index, b.cells[i].index) << "cell " << i;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(bits(a.cells[i].position[axis]), bits(b.cells[i].position[axis])) << "cell " << i;
    }
    for (int f = 0; f < kFaceCount; ++f) {
      expect_same_camera(a.cameras[i][f], b.cameras[i][f],
                         "cell " + std::to_string(i) + " face " + std::to_string(f));
    }
  }
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (size_t i = 0; i < a.frames.size(); ++i) {
    EXPECT_EQ(a.frames[i].cell, b.frames[i].cell) << "frame " << i;
    EXPECT_EQ(a.frames[i].face, b.frames[i].face) << "frame " << i;
    EXPECT_EQ(a.frames[i].type, b.frames[i].type) << "frame " << i;
    EXPECT_EQ(a.frames[i].chunk_offset, b.frames[i].chunk_offset) << "frame " << i;
    EXPECT_EQ(a.frames[i].payload_size, b.frames[i].payload_size) << "frame " << i;
    EXPECT_EQ(a.frames[i].references, b.frames[i].references) << "frame " << i;
    EXPECT_EQ(a.frames[i].cube_references, b.frames[i].cube_references) << "frame " << i;
    for (size_t r = 0; a.frames[i].cube_references && r < a.frames[i].references.size(); ++r) {
      EXPECT_EQ(reference_border_edges(a.frames[i], r), reference_border_edges(b.frames[i], r)) << "frame " << i;
    }
  }
  for (int k = 0; k < 2; ++k) EXPECT_EQ(stat_fields(a.stats[k]), stat_fields(b.stats[k]));
}

// The view matrix glm::lookAt(centre, centre + forward, up) gives for a cube face,
// computed the same way (the scene generator's cameras).
Camera cube_face_camera(const std::array<double, 3>& c, int face, const Frustum& frustum) {
  static constexpr double kForward[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static constexpr double kUp[6][3] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  const double* f = kForward[face];
  const double* up = kUp[face];
  const double s[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]};
  const double u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
  auto dot = [&](const double* v) { return v[0] * c[0] + v[1] * c[1] + v[2] * c[2]; };
  Camera camera;
  std::array<double, 16>& m = camera.world_to_camera;
  for (int j = 0; j < 3; ++j) {
    m[j * 4 + 0] = s[j];
    m[j * 4 + 1] = u[j];
    m[j * 4 + 2] = -f[j];
    m[j * 4 + 3] = 0;
  }
  m[12] = -dot(s);
  m[13] = -dot(u);
  m[14] = dot(f);
  m[15] = 1;
  camera.frustum = frustum;
  return camera;
}

constexpr Frustum kCubeFrustum{-0.05, 0.05, -0.05, 0.05, 0.05, 250};

// A 3x1x3 grid of cube-map cells (centres off every axis), the first cell an I-cube
// and the others B-cubes referencing it; chunks in frame order, back to back.
ContainerIndex rig_index() {
  ContainerIndex index;
  index.face_width = 32;
  index.face_height = 32;
  index.grid.dims = {3, 1, 3};
  index.grid.origin = {-0.75, 1.6, -1.25};
  index.grid.spacing = {0.5, 1, 0.5};
  index.coding.qindex = 11;
  index.coding.i_spacing = {3, 1, 3};
  for (int z = 0; z < 3; ++z) {
    for (int x = 0; x < 3; ++x) {
      CellRecord cell;
      cell.index = {x, 0, z};
      cell.position = {-0.75 + 0.5 * x, 1.6, -1.25 + 0.5 * z};
      CellCameras cameras;
      for (int f = 0; f < kFaceCount; ++f) cameras[f] = cube_face_camera(cell.position, f, kCubeFrustum);
      index.cells.push_back(cell);
      index.cameras.push_back(cameras);
    }
  }
  uint64_t offset = kPreludeSize;
  for (uint32_t n = 0; n < index.cells.size() * kFaceCount; ++n) {
    FrameRecord frame;
    frame.cell = n / kFaceCount;
    frame.face = static_cast<Face>(n % kFaceCount);
    frame.type = frame.cell == 0 ? FaceType::kIntra : FaceType::kPredicted;
    if (frame.type == FaceType::kPredicted) frame.references = {n % kFaceCount};
    frame.chunk_offset = offset;
    frame.payload_size = 40 + n;
    offset += chunk_bytes(frame);
    index.frames.push_back(frame);
  }
  index.stats[0].faces = 6;
  index.stats[1].faces = 48;
  index.stats[1].candidate_vectors = 1234567;
  return index;
}

uint32_t index_version(const std::vector<uint8_t>& bytes) {
  return uint32_t{bytes[0]} | uint32_t{bytes[1]} << 8 | uint32_t{bytes[2]} << 16 | uint32_t{bytes[3]} << 24;
}

TEST(ContainerIndexRecords, CubeCamerasShareSixRigEntries) {
  const ContainerIndex index = rig_index();
  const std::vector<uint8_t> bytes = serialize_index(index);
  EXPECT_EQ(index_version(bytes), 6u);
  EXPECT_EQ(bytes[kRigCountAt], 6);
  // Header, rig table (square frusta), cell records (position gap, flags: the first with one source byte
  // per face, the others on the grid with the first's rig entries), then frame records:
  // type byte (chunks back to back: no offset delta) and payload size (< 128); a B-cube's
  // first face adds its reference, the other five share it. Statistics as
  // varints: 1 byte each but 1,234,567's 3.
  const size_t cell_bytes = (2 + kFaceCount) + 8 * 2;
  const size_t frame_bytes = 6 * 2 + 8 * (3 + 5 * 2);
  const size_t statistics_bytes = 2 * 9 + 2;
  EXPECT_EQ(bytes.size(),
            kRigCountAt + 1 + 6 * kSquareRigEntryBytes + 4 + cell_bytes + 4 + frame_bytes + statistics_bytes);

  auto parsed = parse_index(bytes, 1000, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_EQ(serialize_index(*parsed), bytes);
}

TEST(ContainerIndexRecords, CamerasNoRigEntryReproducesAreStoredExplicitly) {
  ContainerIndex index = rig_index();
  const size_t rig_only_size = serialize_index(index).size();
  // A yawed rig: rotation entries that are not 0 or +-1.
  const double c = std::cos(0.5), s = std::sin(0.5);
  Camera& yawed = index.cameras[1][0];
  const double p[3] = {index.cells[1].position[0], index.cells[1].position[1], index.cells[1].position[2]};
  yawed.world_to_camera = {c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, -(c * p[0] + s * p[2]), -p[1], s * p[0] - c * p[2],
                           1};
  // A translation that is not -R * centre.
  index.cameras[2][3].world_to_camera[13] += 0.125;
  // A frustum that differs from the rig's: a signed permutation still, so a new entry.
  index.cameras[4][5].frustum.far_plane = 500;
  // Bottom row not 0 0 0 1.
  index.cameras[5][2].world_to_camera[3] = 0.25;

  const std::vector<uint8_t> bytes = serialize_index(index);
  EXPECT_EQ(bytes[kRigCountAt], 7);
  // Three explicit cameras (22 doubles each) and one more rig entry; cells 1 to 6 list
  // their sources (6 bytes each) instead of taking the previous cell's: they have an
  // explicit camera or a new rig entry, or follow a cell with an explicit camera.
  EXPECT_EQ(bytes.size(), rig_only_size + 3 * 22 * 8 + kSquareRigEntryBytes + 6 * kFaceCount);
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_EQ(serialize_index(*parsed), bytes);
}

TEST(ContainerIndexRecords, SignOfZeroIsKeptBitForBit) {
  ContainerIndex index = rig_index();
  const size_t rig_only_size = serialize_index(index).size();
  // A centre on the x = 0 and z = 0 planes: every face has two zero translations.
  CellRecord& cell = index.cells[0];
  CellCameras& cameras = index.cameras[0];
  cell.position = {0, 1.6, 0};
  auto set_zero_translations = [&](double zero) {
    int set = 0;
    for (int f = 0; f < kFaceCount; ++f) {
      cameras[f] = cube_face_camera(cell.position, f, kCubeFrustum);
      for (int i = 12; i < 15; ++i) {
        if (cameras[f].world_to_camera[i] == 0) {
          cameras[f].world_to_camera[i] = zero;
          ++set;
        }
      }
    }
    return set;
  };
  // +0: what the rig derives (and what text manifests hold), so no explicit camera; the
  // centre is off the grid (24 bytes).
  ASSERT_EQ(set_zero_translations(0.0), 2 * kFaceCount);
  std::vector<uint8_t> bytes = serialize_index(index);
  EXPECT_EQ(bytes.size(), rig_only_size + 3 * 8);
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);

  // -0: equal as numbers, different bits, so each face is stored explicitly and comes
  // back with its sign.
  ASSERT_EQ(set_zero_translations(-0.0), 2 * kFaceCount);
  bytes = serialize_index(index);
  // The next cell lists its sources, as it follows explicit cameras.
  EXPECT_EQ(bytes.size(), rig_only_size + 3 * 8 + kFaceCount * 22 * 8 + kFaceCount);
  parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_TRUE(std::signbit(parsed->cameras[0][0].world_to_camera[14]));
}

// Cube references: one bit of the type byte; the dependencies it adds are the four
// adjacent faces of each reference cube, which must be I-faces.
TEST(ContainerIndexRecords, CubeReferencesRoundTripAndNeedIntraCubes) {
  ContainerIndex index = rig_index();
  for (FrameRecord& frame : index.frames) frame.cube_references = frame.type == FaceType::kPredicted;
  const std::vector<uint8_t> bytes = serialize_index(index);
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_TRUE(parsed->frames[6 + 4].cube_references);
  EXPECT_FALSE(parsed->frames[4].cube_references);
  // Face pz of cell 1 predicts from pz of cell 0 and needs its px, nx, py, ny.
  EXPECT_EQ(frame_dependencies(parsed->frames[6 + 4]), (std::vector<uint32_t>{4, 0, 1, 2, 3}));
  EXPECT_EQ(frame_dependencies(parsed->frames[4]), std::vector<uint32_t>{});
  index.frames[6 + 4].cube_references = false;
  EXPECT_EQ(frame_dependencies(index.frames[6 + 4]), std::vector<uint32_t>{4});

  // Border edges: pz's left edge shows px, its right nx, its top py, its bottom ny
  // (docs/codec.md 5.7); only the faces across the edges listed are dependencies.
  index.frames[6 + 4].cube_references = true;
  index.frames[6 + 4].border_edges = 0x05;  // left and top
  index.frames[6 + 5].border_edges = 0x00;  // nz reads no border
  parsed = parse_index(serialize_index(index), 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_EQ(frame_dependencies(parsed->frames[6 + 4]), (std::vector<uint32_t>{4, 0, 2}));
  EXPECT_EQ(frame_dependencies(parsed->frames[6 + 5]), std::vector<uint32_t>{5});
  // Depth still depends on the four (docs/codec.md 8.3).
  EXPECT_EQ(depth_dependencies(parsed->frames[6 + 5]), (std::vector<uint32_t>{5, 0, 1, 2, 3}));
  // With one reference, the bits of a second are never written, and refused: the byte is
  // where serializing another value changes the bytes.
  std::vector<uint8_t> forged = serialize_index(index);
  index.frames[6 + 4].border_edges = 0x15;
  EXPECT_EQ(serialize_index(index), forged);
  index.frames[6 + 4].border_edges = 0x06;
  const std::vector<uint8_t> other = serialize_index(index);
  ASSERT_EQ(other.size(), forged.size());
  const auto at =
      static_cast<size_t>(std::mismatch(forged.begin(), forged.end(), other.begin()).first - forged.begin());
  ASSERT_LT(at, forged.size());
  forged[at] = 0x15;
  parsed = parse_index(forged, 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find(
                "cell (1,0,0) face pz has one reference but border edges 21 name a second"),
            std::string::npos)
      << parsed.status().message();
  index.frames[6 + 4].border_edges = kEveryBorderEdge & 0x0F;

  // Cell 1 px becomes an I-face that cell 2 px predicts from, but cell 1 py stays a
  // B-face: cell 2 px cannot have cube references.
  index.frames[6].type = FaceType::kIntra;
  index.frames[6].references.clear();
  index.frames[6].cube_references = false;
  index.frames[12].references = {6};
  index.frames[12].cube_references = true;
  parsed = parse_index(serialize_index(index), 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().code(), ErrorCode::kCorruptData);
  EXPECT_NE(parsed.status().message().find("cell (1,0,0) face py of its reference cube is not an I-face"),
            std::string::npos)
      << parsed.status().message();
}

TEST(ContainerIndexRecords, OutOfOrderChunksAndLargeValuesRoundTrip) {
  ContainerIndex index = rig_index();
  // As after svc add: the first cell's chunks were appended last, far into a large
  // file; one face is big (a multi-byte payload size varint).
  constexpr uint64_t kLargeFile = uint64_t{1} << 40;
  for (uint32_t n = 0; n < kFaceCount; ++n) index.frames[n].chunk_offset = (uint64_t{1} << 36) + 1000 * n;
  index.frames[3].payload_size = 200u << 20;
  index.frames[20].chunk_offset = index.frames[19].chunk_offset;  // two records naming one chunk
  index.frames[20].payload_size = index.frames[19].payload_size;
  const std::vector<uint8_t> bytes = serialize_index(index);
  auto parsed = parse_index(bytes, 0, kLargeFile, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_EQ(serialize_index(*parsed), bytes);

  // The same offsets must still lie inside the file.
  parsed = parse_index(bytes, 0, uint64_t{1} << 36, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("cell (0,0,0) face px"), std::string::npos) << parsed.status().message();
}

// With depth, the index's feature word says so and each frame record carries its depth
// chunk's size; that chunk lies right after the face's own.
TEST(ContainerIndex, DepthSizesRoundTrip) {
  ContainerIndex index = sample_index();
  index.depth = true;
  for (FrameRecord& frame : index.frames) frame.depth_size = 20 + frame.cell;
  const std::vector<uint8_t> bytes = serialize_index(index);
  EXPECT_EQ(index_version(bytes), 6u);
  EXPECT_EQ(bytes[4], 1);  // the feature word: depth
  auto parsed = parse_index(bytes, 1000, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  EXPECT_TRUE(parsed->depth);
  EXPECT_EQ(parsed->frames[17].depth_size, 22u);
  EXPECT_EQ(chunk_bytes(parsed->frames[17]), 50u + 4 + 22 + 4);
  EXPECT_EQ(serialize_index(*parsed), bytes);
  // A frame without depth in a file with depth is refused.
  index.frames[3].depth_size = 0;
  auto refused = parse_index(serialize_index(index), 1000, kFileSize, ReaderLimits{});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("cell (0,0,0) face ny has no depth chunk"), std::string::npos)
      << refused.status().message();
}

// A feature bit this build does not know is refused by name, at the feature word.
TEST(ContainerIndex, UnknownFeaturesAreRefused) {
  std::vector<uint8_t> bytes = serialize_index(sample_index());
  bytes[4] = 0x06;
  auto parsed = parse_index(bytes, 1000, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().code(), ErrorCode::kUnsupported);
  EXPECT_EQ(
      parsed.status().message(),
      "index uses feature bits 1, 2 that this build does not know (it knows bit 0, depth) at byte offset 1004");
  bytes[4] = 0x01;
  bytes[7] = 0x80;
  parsed = parse_index(bytes, 1000, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.status().message(),
            "index uses feature bit 31 that this build does not know (it knows bit 0, depth) at byte offset 1004");
}

// Index versions 1 to 3 came before the current frame syntaxes; they and any other value
// than 4 to 6 are refused, naming the version and its offset.
TEST(ContainerIndex, VersionsOtherThanFourToSixAreRefused) {
  const std::vector<uint8_t> bytes = serialize_index(sample_index());
  ASSERT_EQ(index_version(bytes), 6u);
  for (uint32_t version : {0u, 1u, 2u, 3u, 7u, 0xFFFFFFFFu}) {
    std::vector<uint8_t> forged = bytes;
    for (int b = 0; b < 4; ++b) forged[static_cast<size_t>(b)] = static_cast<uint8_t>(version >> (8 * b));
    auto parsed = parse_index(forged, 1000, kFileSize, ReaderLimits{});
    ASSERT_FALSE(parsed.ok()) << version;
    EXPECT_EQ(parsed.status().code(), ErrorCode::kUnsupported);
    EXPECT_EQ(parsed.status().message(), "index version " + std::to_string(version) +
                                             " is not supported (this build reads 4 to 6) at byte offset 1000");
  }
}

// The corpus keeps files whose index is in versions 1 to 3 (tests/fuzz/corpus/container,
// old-index-v*): the reader refuses each, naming its version.
TEST(ContainerIndex, OlderCorpusFilesAreRefused) {
  namespace fs = std::filesystem;
  int older_files[4] = {};  // by index version
  for (const auto& entry : fs::directory_iterator(fs::path(SVC_SOURCE_DIR) / "tests/fuzz/corpus/container")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("old-index-v", 0) != 0) continue;
    SCOPED_TRACE(entry.path().string());
    const int version = name[std::string("old-index-v").size()] - '0';
    ASSERT_TRUE(version >= 1 && version <= 3);
    ++older_files[version];
    auto file = ReadOnlyFile::open(entry.path());
    ASSERT_TRUE(file.ok());
    auto opened = open_container(**file, ReaderLimits{});
    ASSERT_FALSE(opened.ok());
    EXPECT_EQ(opened.status().code(), ErrorCode::kUnsupported) << opened.status().to_string();
    EXPECT_NE(opened.status().message().find("index version " + std::to_string(version) +
                                             " is not supported (this build reads 4 to 6) at byte offset "),
              std::string::npos)
        << opened.status().message();
  }
  EXPECT_GE(older_files[1], 3);
  EXPECT_GE(older_files[2], 3);
  EXPECT_GE(older_files[3], 3);
}

TEST(ContainerIndexRecords, EveryTruncationIsAnErrorNotACrash) {
  ContainerIndex index = rig_index();
  index.cameras[3][1].world_to_camera[12] += 1;  // one explicit camera too
  index.frames[9].chunk_offset = kPreludeSize;   // a negative offset delta
  const std::vector<uint8_t> bytes = serialize_index(index);
  ASSERT_TRUE(parse_index(bytes, 0, kFileSize, ReaderLimits{}).ok());
  for (size_t n = 0; n < bytes.size(); ++n) {
    auto parsed = parse_index(std::span(bytes).first(n), 500, kFileSize, ReaderLimits{});
    ASSERT_FALSE(parsed.ok()) << "truncated to " << n;
    EXPECT_EQ(parsed.status().code(), ErrorCode::kCorruptData) << parsed.status().to_string();
    EXPECT_NE(parsed.status().message().find("byte offset"), std::string::npos) << parsed.status().message();
  }
}

// A one-cell index of I-faces whose frame records are the 12 bytes before the statistics
// (18 zero varints): {bare chunk, back to back; payload size 50} each.
struct OneCell {
  ContainerIndex index;
  std::vector<uint8_t> bytes;
  size_t frames_at = 0;  // first frame record
};

OneCell one_cell_index() {
  OneCell one;
  one.index = rig_index();
  one.index.cells.resize(1);
  one.index.cameras.resize(1);
  one.index.frames.resize(kFaceCount);
  one.index.stats = {};
  uint64_t offset = kPreludeSize;
  for (FrameRecord& frame : one.index.frames) {
    frame.chunk_offset = offset;
    frame.payload_size = 50;
    offset += chunk_bytes(frame);
  }
  one.bytes = serialize_index(one.index);
  one.frames_at = one.bytes.size() - 2 * 9 - 2 * kFaceCount;
  return one;
}

// Replaces `length` bytes at `at` with `replacement` and parses.
Status parse_edited(std::vector<uint8_t> bytes, size_t at, size_t length, const std::vector<uint8_t>& replacement) {
  bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(at),
              bytes.begin() + static_cast<std::ptrdiff_t>(at + length));
  bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), replacement.begin(), replacement.end());
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  return parsed.ok() ? Status::Ok() : parsed.status();
}

void expect_refused(const Status& status, const std::string& words) {
  ASSERT_FALSE(status.ok()) << "expected an error about " << words;
  EXPECT_EQ(status.code(), ErrorCode::kCorruptData) << status.to_string();
  EXPECT_NE(status.message().find(words), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("byte offset"), std::string::npos) << status.message();
}

TEST(ContainerIndex, BadVarintsAreRefused) {
  const OneCell one = one_cell_index();
  const size_t record = one.frames_at + 2 * 2;  // frame 2: face py
  ASSERT_EQ(one.bytes[record], 0x60);           // an I-face in a bare chunk, back to back
  ASSERT_EQ(one.bytes[record + 1], 50);
  // The same record with its offset delta (0) stored: bit 6 clear.
  std::vector<uint8_t> bytes = one.bytes;
  bytes[record] = 0x20;
  bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(record + 1), 0);
  ASSERT_TRUE(parse_edited(bytes, 0, 0, {}).ok());
  ASSERT_TRUE(parse_edited(bytes, record, 3, {0, 0, 50}).ok());
  // Payload size 50 written in two bytes.
  expect_refused(parse_edited(bytes, record + 2, 1, {0x80 | 50, 0x00}), "redundant trailing zero byte");
  // Eleven bytes.
  expect_refused(parse_edited(bytes, record + 2, 1,
                              {0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 1}),
                 "longer than 10 bytes");
  // 2^64: the tenth byte carries more than one bit.
  expect_refused(parse_edited(bytes, record + 1, 1, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02}),
                 "overflows 64 bits");
  // Payload size 2^32.
  expect_refused(parse_edited(bytes, record + 2, 1, {0x80, 0x80, 0x80, 0x80, 0x10}), "does not fit 32 bits");
  // Offset deltas before the file's start and past its end (zigzag: odd is negative).
  expect_refused(parse_edited(bytes, record + 1, 1, {0xFF, 0xFF, 0x03}), "leads outside the file");
  expect_refused(parse_edited(bytes, record + 1, 1, {0x80, 0x80, 0x80, 0x02}), "leads outside the file");
  // The largest negative delta, whose magnitude has no positive int64.
  expect_refused(parse_edited(bytes, record + 1, 1, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01}),
                 "leads outside the file");
  // Cube references on an I-face; an unknown frame type.
  expect_refused(parse_edited(bytes, record, 1, {0x10}), "cube-references bit");
  expect_refused(parse_edited(bytes, record, 1, {0x02}), "unknown frame type");
  // An I-face with a reference; a B-face reference past the frame count.
  expect_refused(parse_edited(bytes, record, 3, {0x04, 0, 50, 0}), "references, which its type does not allow");
  // References are cells relative to the frame's own (zigzag): 6 is 3 cells on, 1 is the
  // cell before the first.
  expect_refused(parse_edited(bytes, record, 3, {0x05, 0, 50, 6}), "references a cell 3 cells away, outside the 1");
  expect_refused(parse_edited(bytes, record, 3, {0x05, 0, 50, 1}), "references a cell -1 cells away");
  // A reference to itself (a B-face) is not an I-face.
  expect_refused(parse_edited(bytes, record, 3, {0x05, 0, 50, 0}), "not an I-face");
}

TEST(ContainerIndex, BadRigTablesAreRefused) {
  const OneCell one = one_cell_index();
  const std::vector<uint8_t>& bytes = one.bytes;
  ASSERT_EQ(bytes[kRigCountAt], 6);
  const size_t cell_at = kRigCountAt + 1 + 6 * kSquareRigEntryBytes + 4;
  const size_t sources_at = cell_at + 2;  // after the position gap and the flags
  ASSERT_EQ(bytes[cell_at], 0);
  ASSERT_EQ(bytes[cell_at + 1], 1);  // centre on the grid
  for (int f = 0; f < kFaceCount; ++f) ASSERT_EQ(bytes[sources_at + f], f);

  // More entries than the cap, and more than the bytes left.
  expect_refused(parse_edited(bytes, kRigCountAt, 1, {65}), "more than 64");
  expect_refused(parse_edited(bytes, kRigCountAt, 1, {64}), "does not fit");
  // A face naming an entry the table does not have.
  expect_refused(parse_edited(bytes, sources_at + 4, 1, {6}), "cell (0,0,0) face pz names camera rig entry 6 of 6");
  // Three +1s in the first row (not a signed permutation).
  const size_t entry1 = kRigCountAt + 1 + kSquareRigEntryBytes;
  ASSERT_EQ(bytes[entry1 + 3], 1);  // a square frustum: right, near, far follow
  expect_refused(parse_edited(bytes, entry1, 1, {0x2A}), "rig entry 1 has a rotation");
  // An invalid frustum (near plane 0).
  ByteWriter zero;
  zero.f64(0.0);
  expect_refused(parse_edited(bytes, entry1 + 4 + 8, 8, zero.bytes()), "rig entry 1 has an invalid frustum");
  // Bytes past the statistics.
  expect_refused(parse_edited(bytes, bytes.size(), 0, {0}), "unexpected bytes");
}

TEST(ContainerIndex, BadCellRecordsAreRefused) {
  const OneCell one = one_cell_index();
  const std::vector<uint8_t>& bytes = one.bytes;
  const size_t cell_at = kRigCountAt + 1 + 6 * kSquareRigEntryBytes + 4;
  ASSERT_TRUE(parse_edited(bytes, cell_at, 1, {8}).ok());  // the last cell of the 3x1x3 grid
  expect_refused(parse_edited(bytes, cell_at, 1, {9}), "cell record 0 lies past the end of the grid");
  expect_refused(parse_edited(bytes, cell_at, 1, {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01}),
                 "lies past the end of the grid");
  expect_refused(parse_edited(bytes, cell_at + 1, 1, {0x05}), "cell (0,0,0) has reserved flags set");
  // The first record cannot take a previous cell's rig entries.
  expect_refused(parse_edited(bytes, cell_at + 1, 1 + kFaceCount, {0x03}), "previous cell's rig entries");
  // Off the grid: the centre follows the flags.
  ByteWriter centre;
  for (double v : {0.25, 1.5, -3.0}) centre.f64(v);
  std::vector<uint8_t> off_grid = centre.bytes();
  off_grid.insert(off_grid.begin(), 0x00);
  ASSERT_TRUE(parse_edited(bytes, cell_at + 1, 1, off_grid).ok());
  // Clearing the flag makes the sources, the frame count and records read as a centre,
  // and the statistics (zeros) as sources of rig entry 0 and a frame count of 0.
  expect_refused(parse_edited(bytes, cell_at + 1, 1, {0x00}), "frame count 0 is not six per cell");
}

// Version 4 frame records: an I-cube then a B-cube predicted from it, chunks back to
// back, payloads of 50 bytes, no statistics.
TEST(ContainerIndexRecords, FramesShareChunkPositionsAndReferences) {
  ContainerIndex index = rig_index();
  index.cells.resize(2);
  index.cameras.resize(2);
  index.frames.resize(2 * kFaceCount);
  index.stats = {};
  uint64_t offset = kPreludeSize;
  for (FrameRecord& frame : index.frames) {
    frame.chunk_offset = offset;
    frame.payload_size = 50;
    offset += chunk_bytes(frame);
  }
  const std::vector<uint8_t> bytes = serialize_index(index);
  const size_t frames_at = bytes.size() - 2 * 9 - 2 * kFaceCount - (3 + 5 * 2);
  // I-faces: bare chunk, back to back; the B-cube's first face names cell 0 (zigzag -1),
  // the others share it.
  const std::vector<uint8_t> expected = {0x60, 50, 0x60, 50, 0x60, 50, 0x60, 50, 0x60, 50, 0x60, 50, 0x65,
                                         50,   1,  0xE5, 50, 0xE5, 50, 0xE5, 50, 0xE5, 50, 0xE5, 50};
  ASSERT_TRUE(std::equal(expected.begin(), expected.end(), bytes.begin() + static_cast<std::ptrdiff_t>(frames_at)));
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_EQ(parsed->frames[9].references, FrameReferences{3});  // cell 0's face ny

  // An explicit offset delta of 0 in place of bit 6 is the same index.
  ASSERT_TRUE(parse_edited(bytes, frames_at, 1, {0x20, 0}).ok());
  const size_t b_cube = frames_at + 2 * kFaceCount;
  // Sharing references on a cell's first face; sharing them with another count.
  expect_refused(parse_edited(bytes, b_cube, 3, {0xE5, 50}), "but is its cell's first");
  expect_refused(parse_edited(bytes, b_cube + 3, 1, {0xE9}), "counts 2 against its 1");
  // Statistics are varints: one more byte is not part of them.
  expect_refused(parse_edited(bytes, bytes.size(), 0, {0}), "unexpected bytes");
}

// Version 4 rig entries: the rotation packed two bits an entry (negative zeros kept), a
// frustum that is not square stored whole; reserved bits refused.
TEST(ContainerIndexRecords, RigEntriesArePackedAndExact) {
  ContainerIndex index = rig_index();
  for (int f = 0; f < kFaceCount; ++f) {
    Camera& camera = index.cameras[0][f];
    camera.frustum.left *= 2;  // not centred: all six doubles
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        double& v = camera.world_to_camera[j * 4 + i];
        if (v == 0) v = -0.0;  // negative zeros survive bit for bit
      }
    }
  }
  const std::vector<uint8_t> bytes = serialize_index(index);
  EXPECT_EQ(bytes[kRigCountAt], 12);
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_TRUE(std::signbit(parsed->cameras[0][0].world_to_camera[4]));
  EXPECT_EQ(serialize_index(*parsed), bytes);
  // The first entry: rotation bits past the nine entries, then an unknown flag.
  const size_t entry0 = kRigCountAt + 1;
  expect_refused(parse_edited(bytes, entry0 + 2, 1, {static_cast<uint8_t>(bytes[entry0 + 2] | 0x04)}),
                 "rig entry 0 has reserved bits set");
  expect_refused(parse_edited(bytes, entry0 + 3, 1, {0x02}), "rig entry 0 has reserved bits set");
  // A rotation of two +1s in one row.
  expect_refused(parse_edited(bytes, entry0, 1, {0xAA}), "not a signed permutation");
}

TEST(ContainerIndexRecords, SparseGridsAndCentresOffTheGridRoundTrip) {
  ContainerIndex index = rig_index();
  // Cells 1 and 5 missing (gaps in the raster order), cell 3's centre moved off the grid.
  for (size_t c : {5u, 1u}) {
    index.cells.erase(index.cells.begin() + static_cast<std::ptrdiff_t>(c));
    index.cameras.erase(index.cameras.begin() + static_cast<std::ptrdiff_t>(c));
  }
  index.frames.resize(index.cells.size() * kFaceCount);
  for (uint32_t n = 0; n < index.frames.size(); ++n) index.frames[n].cell = n / kFaceCount;
  index.cells[2].position[1] += 0.001;
  for (int f = 0; f < kFaceCount; ++f) {
    index.cameras[2][f] = cube_face_camera(index.cells[2].position, f, kCubeFrustum);
  }
  const std::vector<uint8_t> bytes = serialize_index(index);
  auto parsed = parse_index(bytes, 0, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  expect_same_index(*parsed, index);
  EXPECT_EQ(serialize_index(*parsed), bytes);
}

TEST(ContainerIndex, CountsAreBoundedByTheBytesLeft) {
  const OneCell one = one_cell_index();
  const size_t cell_count_at = kRigCountAt + 1 + 6 * kSquareRigEntryBytes;
  // Cells need at least 2 bytes each (the one record here takes 8), and six frames per
  // cell at least 2 bytes each.
  const size_t frames_count_at = one.frames_at - 4;
  std::vector<uint8_t> forged = one.bytes;
  forged.resize(frames_count_at);  // drop frames and statistics: the one cell record stays
  forged[cell_count_at] = 5;
  expect_refused(parse_edited(forged, 0, 0, {}), "cell count 5 does not fit");
  forged = one.bytes;
  forged.resize(frames_count_at + 4 + 2 * kFaceCount - 1);
  expect_refused(parse_edited(forged, 0, 0, {}), "frame count 6 does not fit");
}

TEST(ContainerChunk, CarriesTagSizeAndCrc) {
  const std::vector<uint8_t> payload = {1, 2, 3, 4, 5};
  const std::vector<uint8_t> chunk = make_chunk(kFaceChunkTag, payload);
  ASSERT_EQ(chunk.size(), payload.size() + kChunkOverhead);
  EXPECT_EQ(chunk[0], 'F');
  EXPECT_EQ(chunk[3], 'E');
  EXPECT_EQ(chunk[4], 5);
  const uint32_t crc = crc32_of(std::span(chunk).first(chunk.size() - 4));
  EXPECT_EQ(chunk[chunk.size() - 4], crc & 0xff);
  EXPECT_EQ(chunk[chunk.size() - 1], crc >> 24);
}

// The container's CRC-32 is zlib's crc32(): values from zlib, at every alignment and
// split, since the fast path takes eight bytes at a time.
TEST(ContainerChunk, CrcIsZlibsCrc32) {
  const std::string check = "123456789";
  EXPECT_EQ(crc32_of(std::span(reinterpret_cast<const uint8_t*>(check.data()), check.size())), 0xCBF43926u);
  EXPECT_EQ(crc32_of({}), 0u);
  std::vector<uint8_t> all(256);
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint8_t>(i);
  EXPECT_EQ(crc32_of(all), 0x29058C73u);
  std::vector<uint8_t> long_run(100003);
  for (size_t i = 0; i < long_run.size(); ++i) long_run[i] = static_cast<uint8_t>(i * 7 + 3);
  EXPECT_EQ(crc32_of(long_run), 0xCD676DABu);
  const std::span<const uint8_t> bytes(long_run);
  for (size_t split = 0; split < 20; ++split) {
    EXPECT_EQ(crc32_of(bytes.subspan(split), crc32_of(bytes.first(split))), 0xCD676DABu) << split;
  }
}

}  // namespace
}  // namespace svc
