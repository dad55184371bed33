// SPDX-License-Identifier: BSD-2-Clause
// Decoding into the caller's buffers (every pixel format, both row orders, strides with
// padding) and reading from any byte source (memory, the embedder's own reads).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <fstream>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/byte_source.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

constexpr uint8_t kPadding = 0xA5;
constexpr int kFaceSize = 40;

// A 3x1x2 scene encoded once; every test reads it.
class ReaderBuffers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-reader-buffers");
    samples::SceneOptions options;
    options.grid = {3, 1, 2};
    options.face_size = kFaceSize;
    ASSERT_TRUE(samples::generate_scene(options, dir_->path() / "db").ok());
    EncoderSettings encoder;
    encoder.threads = 1;
    auto summary = encode_database(dir_->path() / "db", file(), encoder);
    ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path file() { return dir_->path() / "scene.svc"; }
  static std::unique_ptr<Reader> open_reader() {
    auto reader = Reader::open(file());
    EXPECT_TRUE(reader.ok()) << reader.status().to_string();
    return reader.ok() ? std::move(*reader) : nullptr;
  }

  static testing::TempDir* dir_;
};
testing::TempDir* ReaderBuffers::dir_ = nullptr;

// A packed buffer of `format` with `padding` bytes after each row, filled with kPadding.
struct PackedBuffer {
  std::vector<uint8_t> bytes;
  PixelBuffer view;
  PackedBuffer(PixelFormat format, RowOrder rows, size_t padding) {
    const size_t stride = pixel_row_bytes(format, kFaceSize, 0) + padding;
    bytes.assign(stride * kFaceSize - padding, kPadding);  // the last row needs no padding
    view.format = format;
    view.rows = rows;
    view.planes[0] = bytes;
    view.strides[0] = stride;
  }
};

// The pixel at (x, y) of `rgb` as `format` lays it out.
std::vector<uint8_t> expected_pixel(const ImageRGB8& rgb, int x, int y, PixelFormat format) {
  const uint8_t* p = rgb.pixels.data() + (static_cast<size_t>(y) * rgb.width + x) * 3;
  if (format == PixelFormat::kRGB8) return {p[0], p[1], p[2]};
  if (format == PixelFormat::kRGBA8) return {p[0], p[1], p[2], 255};
  return {p[2], p[1], p[0], 255};
}

void expect_packed(const PackedBuffer& buffer, const ImageRGB8& rgb, const std::string& what) {
  const PixelBuffer& view = buffer.view;
  const size_t pixel = pixel_row_bytes(view.format, 1, 0), row_bytes = pixel * kFaceSize;
  for (int y = 0; y < kFaceSize; ++y) {
    const int stored = view.rows == RowOrder::kTopDown ? y : kFaceSize - 1 - y;
    const uint8_t* row = buffer.bytes.data() + static_cast<size_t>(stored) * view.strides[0];
    for (int x = 0; x < kFaceSize; ++x) {
      const std::vector<uint8_t> actual(row + x * pixel, row + (x + 1) * pixel);
      ASSERT_EQ(actual, expected_pixel(rgb, x, y, view.format)) << what << " pixel (" << x << ", " << y << ")";
    }
    if (stored == kFaceSize - 1) continue;  // the last row in memory has no padding
    for (size_t b = row_bytes; b < view.strides[0]; ++b) {
      ASSERT_EQ(buffer.bytes[static_cast<size_t>(stored) * view.strides[0] + b], kPadding)
          << what << ": row " << stored << "'s padding written";
    }
  }
}

TEST_F(ReaderBuffers, EveryPackedFormatAndRowOrderHoldsTheRgbDecode) {
  auto reader = open_reader();
  ASSERT_NE(reader, nullptr);
  for (const CellEntry& cell : reader->cells()) {
    for (Face face : kAllFaces) {
      auto rgb = reader->decode_face(cell.index, face);
      ASSERT_TRUE(rgb.ok()) << rgb.status().to_string();
      for (PixelFormat format : {PixelFormat::kRGBA8, PixelFormat::kBGRA8, PixelFormat::kRGB8}) {
        for (RowOrder rows : {RowOrder::kTopDown, RowOrder::kBottomUp}) {
          PackedBuffer buffer(format, rows, 13);
          const std::string what = face_label(cell.index, face) + " format " +
                                   std::to_string(static_cast<int>(format)) + " rows " +
                                   std::to_string(static_cast<int>(rows));
          const Status status = reader->decode_face_into(cell.index, face, buffer.view);
          ASSERT_TRUE(status.ok()) << what << ": " << status.to_string();
          expect_packed(buffer, *rgb, what);
        }
      }
    }
  }
}

TEST_F(ReaderBuffers, YCbCrPlanesHoldTheDecodedPlanesInEitherRowOrder) {
  auto reader = open_reader();
  ASSERT_NE(reader, nullptr);
  const CellIndex cell = reader->cells().back().index;
  auto planes = reader->decode_face_ycbcr(cell, Face::kPZ);
  ASSERT_TRUE(planes.ok()) << planes.status().to_string();
  const int chroma = (kFaceSize + 1) / 2;
  for (RowOrder rows : {RowOrder::kTopDown, RowOrder::kBottomUp}) {
    std::vector<uint8_t> y(64 * kFaceSize, kPadding), cb(32 * chroma, kPadding), cr(32 * chroma, kPadding);
    PixelBuffer buffer;
    buffer.format = PixelFormat::kYCbCr420;
    buffer.rows = rows;
    buffer.planes = {std::span<uint8_t>(y), std::span<uint8_t>(cb), std::span<uint8_t>(cr)};
    buffer.strides = {64, 32, 32};
    ASSERT_TRUE(reader->decode_face_into(cell, Face::kPZ, buffer).ok());
    auto check = [&](const std::vector<uint8_t>& got, const std::vector<uint8_t>& want, int size, size_t stride) {
      for (int r = 0; r < size; ++r) {
        const int stored = rows == RowOrder::kTopDown ? r : size - 1 - r;
        for (int x = 0; x < static_cast<int>(stride); ++x) {
          const uint8_t expected = x < size ? want[static_cast<size_t>(r) * size + x] : kPadding;
          ASSERT_EQ(got[static_cast<size_t>(stored) * stride + x], expected) << "row " << r << " column " << x;
        }
      }
    };
    check(y, planes->y, kFaceSize, 64);
    check(cb, planes->cb, chroma, 32);
    check(cr, planes->cr, chroma, 32);
  }
}

TEST_F(ReaderBuffers, CubeIntoSixBuffersHoldsTheCube) {
  auto reader = open_reader();
  ASSERT_NE(reader, nullptr);
  const CellIndex cell = reader->cells().front().index;
  auto cube = reader->decode_cube(cell);
  ASSERT_TRUE(cube.ok()) << cube.status().to_string();
  std::vector<PackedBuffer> buffers;
  std::array<PixelBuffer, kFaceCount> views;
  for (int f = 0; f < kFaceCount; ++f) buffers.emplace_back(PixelFormat::kBGRA8, RowOrder::kBottomUp, 4);
  for (int f = 0; f < kFaceCount; ++f) views[static_cast<size_t>(f)] = buffers[static_cast<size_t>(f)].view;
  ASSERT_TRUE(reader->decode_cube_into(cell, views).ok());
  for (int f = 0; f < kFaceCount; ++f) {
    expect_packed(buffers[static_cast<size_t>(f)], (*cube)[static_cast<size_t>(f)], "face " + std::to_string(f));
  }
}

TEST_F(ReaderBuffers, ABufferTooSmallIsRefusedAndLeftUntouched) {
  auto reader = open_reader();
  ASSERT_NE(reader, nullptr);
  const CellIndex cell = reader->cells().front().index;
  PackedBuffer buffer(PixelFormat::kRGBA8, RowOrder::kTopDown, 0);
  buffer.bytes.pop_back();
  buffer.view.planes[0] = buffer.bytes;
  Status status = reader->decode_face_into(cell, Face::kPX, buffer.view);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("plane 0 holds 6399 bytes"), std::string::npos) << status.message();
  EXPECT_EQ(std::count(buffer.bytes.begin(), buffer.bytes.end(), kPadding),
            static_cast<std::ptrdiff_t>(buffer.bytes.size()));

  PackedBuffer narrow(PixelFormat::kRGB8, RowOrder::kTopDown, 0);
  narrow.view.strides[0] = 3 * kFaceSize - 1;
  status = reader->decode_face_into(cell, Face::kPX, narrow.view);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("stride 119 is below the 120 bytes"), std::string::npos) << status.message();

  PixelBuffer planes_missing;
  planes_missing.format = PixelFormat::kYCbCr420;
  std::vector<uint8_t> y(kFaceSize * kFaceSize);
  planes_missing.planes[0] = y;
  planes_missing.strides = {kFaceSize, kFaceSize / 2, kFaceSize / 2};
  status = reader->decode_face_into(cell, Face::kPX, planes_missing);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("plane 1"), std::string::npos) << status.message();

  PixelBuffer unknown = buffer.view;
  unknown.format = static_cast<PixelFormat>(9);
  EXPECT_EQ(reader->decode_face_into(cell, Face::kPX, unknown).code(), ErrorCode::kInvalidArgument);

  // A cube with one buffer too small writes none of the six.
  std::vector<PackedBuffer> buffers;
  std::array<PixelBuffer, kFaceCount> views;
  for (int f = 0; f < kFaceCount; ++f) buffers.emplace_back(PixelFormat::kRGBA8, RowOrder::kTopDown, 0);
  buffers[3].bytes.resize(100);
  for (int f = 0; f < kFaceCount; ++f) {
    views[static_cast<size_t>(f)] = buffers[static_cast<size_t>(f)].view;
    views[static_cast<size_t>(f)].planes[0] = buffers[static_cast<size_t>(f)].bytes;
  }
  status = reader->decode_cube_into(cell, views);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("face ny"), std::string::npos) << status.message();
  for (const PackedBuffer& untouched : buffers) {
    EXPECT_EQ(std::count(untouched.bytes.begin(), untouched.bytes.end(), kPadding),
              static_cast<std::ptrdiff_t>(untouched.bytes.size()));
  }
}

TEST_F(ReaderBuffers, AMemorySourceDecodesAsTheFile) {
  auto from_file = open_reader();
  ASSERT_NE(from_file, nullptr);
  const std::vector<uint8_t> bytes = testing::read_file_data(file());
  auto from_memory = Reader::open(memory_source(bytes, "scene in memory"));
  ASSERT_TRUE(from_memory.ok()) << from_memory.status().to_string();
  EXPECT_EQ((*from_memory)->info().file_bytes, bytes.size());
  ASSERT_EQ((*from_memory)->cells().size(), from_file->cells().size());
  for (const CellEntry& cell : from_file->cells()) {
    for (Face face : kAllFaces) {
      auto a = from_file->decode_face(cell.index, face);
      auto b = (*from_memory)->decode_face(cell.index, face);
      ASSERT_TRUE(a.ok() && b.ok());
      ASSERT_EQ(a->pixels, b->pixels) << face_label(cell.index, face);
    }
  }
  // A block cut short is refused at open with the source's name, never read past.
  const std::span<const uint8_t> cut(bytes.data(), bytes.size() / 2);
  auto truncated = Reader::open(memory_source(cut, "half a scene"));
  ASSERT_FALSE(truncated.ok());
  EXPECT_NE(truncated.status().message().find("half a scene"), std::string::npos) << truncated.status().message();
  EXPECT_EQ(Reader::open(std::unique_ptr<ByteSource>()).status().code(), ErrorCode::kInvalidArgument);
}

// The embedder's own reads, which can be told to fail.
class FailingSource final : public ByteSource {
 public:
  explicit FailingSource(std::vector<uint8_t> bytes) : bytes_(std::move(bytes)) {}
  uint64_t size() const override { return bytes_.size(); }
  const std::string& name() const override { return name_; }
  Status read_at(uint64_t offset, std::span<uint8_t> out) const override {
    reads.fetch_add(1);
    if (failing.load()) return Status(ErrorCode::kIoError, "the archive is locked");
    std::copy_n(bytes_.data() + offset, out.size(), out.data());
    return Status::Ok();
  }
  mutable std::atomic<int> reads{0};
  std::atomic<bool> failing{false};

 private:
  std::vector<uint8_t> bytes_;
  std::string name_ = "package.pak:scene";
};

TEST_F(ReaderBuffers, TheEmbeddersReadErrorsComeBackNamedAndAreNotKept) {
  auto source = std::make_unique<FailingSource>(testing::read_file_data(file()));
  FailingSource& reads = *source;
  ReaderSettings settings;
  settings.face_cache_bytes = 0;
  settings.coefficient_cache_bytes = 0;
  settings.reference_cache_bytes = 0;
  settings.prefetch_threads = 0;
  auto reader = Reader::open(std::move(source), settings);
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  const CellIndex cell = (*reader)->cells().front().index;
  reads.failing = true;
  auto failed = (*reader)->decode_face(cell, Face::kNY);
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(failed.status().code(), ErrorCode::kIoError);
  const std::string& message = failed.status().message();
  EXPECT_NE(message.find("package.pak:scene"), std::string::npos) << message;
  EXPECT_NE(message.find("the archive is locked"), std::string::npos) << message;
  EXPECT_NE(message.find("face ny"), std::string::npos) << message;
  reads.failing = false;
  const int before = reads.reads.load();
  auto decoded = (*reader)->decode_face(cell, Face::kNY);
  ASSERT_TRUE(decoded.ok()) << decoded.status().to_string();
  EXPECT_GT(reads.reads.load(), before);
}

}  // namespace
}  // namespace svc
