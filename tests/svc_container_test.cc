// The .svc index: serialization round trip and validation of damaged fields.
#include <gtest/gtest.h>

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
  index.coding.quant_scale = 5;
  index.coding.i_spacing = {3, 1, 3};
  const CellIndex cells[] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}};
  for (const CellIndex& c : cells) {
    CellRecord record;
    record.index = c;
    record.position = {c.x * 0.5, 1.5, c.z * 0.25};
    record.cameras[2].world_to_camera[12] = 3.25;
    record.cameras[4].frustum.far_plane = 77;
    index.cells.push_back(record);
  }
  for (uint32_t f = 0; f < index.cells.size() * kFaceCount; ++f) {
    FrameRecord frame;
    frame.cell = f / kFaceCount;
    frame.face = static_cast<Face>(f % kFaceCount);
    frame.kind = frame.cell == 0 ? FrameKind::kIntra : FrameKind::kPredicted;
    if (frame.kind == FrameKind::kPredicted) frame.references = {f % kFaceCount};
    frame.chunk_offset = kPreludeSize + 100 * f;
    frame.payload_size = 50;
    index.frames.push_back(frame);
  }
  return index;
}

constexpr uint64_t kFileSize = 1 << 20;

TEST(ContainerIndex, RoundTripsEveryField) {
  const ContainerIndex index = sample_index();
  const std::vector<uint8_t> bytes = serialize_index(index);
  auto parsed = parse_index(bytes, 1000, kFileSize, ReaderLimits{});
  ASSERT_TRUE(parsed.ok()) << parsed.status().to_string();
  EXPECT_EQ(parsed->face_width, 64u);
  EXPECT_EQ(parsed->face_height, 48u);
  EXPECT_EQ(parsed->grid.dims, index.grid.dims);
  EXPECT_EQ(parsed->grid.spacing, index.grid.spacing);
  EXPECT_EQ(parsed->coding.quant_scale, 5u);
  EXPECT_EQ(parsed->coding.i_spacing, index.coding.i_spacing);
  ASSERT_EQ(parsed->cells.size(), 3u);
  EXPECT_EQ(parsed->cells[2].index, (CellIndex{1, 0, 1}));
  EXPECT_EQ(parsed->cells[1].cameras[2].world_to_camera[12], 3.25);
  EXPECT_EQ(parsed->cells[1].cameras[4].frustum.far_plane, 77);
  ASSERT_EQ(parsed->frames.size(), 18u);
  EXPECT_EQ(parsed->frames[7].kind, FrameKind::kPredicted);
  EXPECT_EQ(parsed->frames[7].references, std::vector<uint32_t>{1});
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
  EXPECT_NE(parsed.status().message().find("cell (1,0,1) face nx"), std::string::npos)
      << parsed.status().message();
}

TEST(ContainerIndex, RejectsOffsetsOutsideTheFile) {
  ContainerIndex index = sample_index();
  index.frames[4].chunk_offset = kFileSize - 10;
  auto parsed = parse_index(serialize_index(index), 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("cell (0,0,0) face pz"), std::string::npos)
      << parsed.status().message();
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
  const size_t cell_count_at = 4 + 8 + 12 + 48 + 4 + 8 + 12;
  forged[cell_count_at + 0] = 0xff;
  forged[cell_count_at + 1] = 0xff;
  forged[cell_count_at + 2] = 0x3f;
  parsed = parse_index(forged, 0, kFileSize, ReaderLimits{});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.status().message().find("does not fit"), std::string::npos) << parsed.status().message();
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

}  // namespace
}  // namespace svc
