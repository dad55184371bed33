// SPDX-License-Identifier: BSD-2-Clause
// Depth stored with --depth: every face's depth decodes within the stated bound through
// the reader, random access stays within the reference cubes, damage stays local.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "codec/common/depth.h"
#include "database/database.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"
#include "svc/svc.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

constexpr int kFaceSize = 48;

class DepthFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-depth");
    samples::SceneOptions options;
    options.kind = samples::SceneKind::kHouse;
    options.grid = {4, 1, 3};
    options.face_size = kFaceSize;
    ASSERT_TRUE(samples::generate_scene(options, db()).ok());
    for (int max_error : {0, 6}) {
      EncoderSettings encoder;
      encoder.threads = 2;
      encoder.quality = 40;
      encoder.depth = true;
      encoder.depth_max_error = max_error;
      auto summary = encode_database(db(), file(max_error), encoder);
      ASSERT_TRUE(summary.ok()) << summary.status().to_string();
    }
    EncoderSettings plain;
    plain.threads = 1;
    plain.quality = 40;
    ASSERT_TRUE(encode_database(db(), dir_->path() / "plain.svc", plain).ok());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path db() { return dir_->path() / "db"; }
  static fs::path file(int max_error) { return dir_->path() / ("depth-" + std::to_string(max_error) + ".svc"); }
  static std::unique_ptr<Reader> open_reader(const fs::path& path, ReaderSettings settings = {}) {
    auto reader = Reader::open(path, settings);
    EXPECT_TRUE(reader.ok()) << reader.status().to_string();
    return reader.ok() ? std::move(*reader) : nullptr;
  }

  static testing::TempDir* dir_;
};
testing::TempDir* DepthFiles::dir_ = nullptr;

std::vector<uint16_t> decode_codes(Reader& reader, const CellIndex& cell, Face face) {
  std::vector<uint16_t> codes(kFaceSize * kFaceSize, 0xDEAD);
  DepthBuffer out;
  out.format = DepthFormat::kInverse16;
  out.data = codes.data();
  out.stride = kFaceSize * 2;
  out.size = codes.size() * 2;
  const Status status = reader.decode_face_depth_into(cell, face, out);
  EXPECT_TRUE(status.ok()) << status.to_string();
  return codes;
}

TEST_F(DepthFiles, EveryFaceDecodesWithinTheBound) {
  auto manifest = load_manifest(db());
  ASSERT_TRUE(manifest.ok());
  for (int max_error : {0, 6}) {
    auto reader = open_reader(file(max_error));
    ASSERT_TRUE(reader->info().has_depth);
    EXPECT_EQ(reader->info().depth_max_error, max_error);
    int worst = 0, geometry = 0, background = 0;
    for (size_t c = 0; c < manifest->cells.size(); ++c) {
      for (Face face : kAllFaces) {
        auto source = load_face(*manifest, c, face);
        ASSERT_TRUE(source.ok());
        const CellEntry& cell = reader->cells()[c];
        const double near_plane = cell.cameras[static_cast<int>(face)].frustum.near_plane;
        const std::vector<uint16_t> codes = decode_codes(*reader, cell.index, face);
        for (size_t i = 0; i < codes.size(); ++i) {
          const uint16_t expected = codec::inverse_depth_code(source->depth[i], near_plane);
          ASSERT_EQ(codes[i] == 0, expected == 0) << face_label(cell.index, face) << " pixel " << i;
          worst = std::max(worst, std::abs(int{codes[i]} - int{expected}));
          (expected == 0 ? background : geometry) += 1;
        }
      }
    }
    EXPECT_LE(worst, max_error);
    if (max_error > 0) EXPECT_GT(worst, 0);  // the bound is used, not just met
    EXPECT_GT(geometry, 0);
    EXPECT_GT(background, 0);
  }
}

TEST_F(DepthFiles, EyeDepthFloatsAndRowOrders) {
  auto reader = open_reader(file(0));
  const CellEntry& cell = reader->cells()[4];
  const std::vector<uint16_t> codes = decode_codes(*reader, cell.index, Face::kPZ);
  auto eye = reader->decode_face_depth(cell.index, Face::kPZ);
  ASSERT_TRUE(eye.ok()) << eye.status().to_string();
  const double near_plane = cell.cameras[static_cast<int>(Face::kPZ)].frustum.near_plane;
  std::vector<float> bottom_up(kFaceSize * kFaceSize + 8, -1.0f);  // rows 4 floats apart beyond the face
  DepthBuffer out;
  out.rows = RowOrder::kBottomUp;
  out.data = bottom_up.data();
  out.stride = (kFaceSize + 0) * 4;
  out.size = bottom_up.size() * 4;
  ASSERT_TRUE(reader->decode_face_depth_into(cell.index, Face::kPZ, out).ok());
  for (int y = 0; y < kFaceSize; ++y) {
    for (int x = 0; x < kFaceSize; ++x) {
      const size_t i = static_cast<size_t>(y) * kFaceSize + x;
      const float z = (*eye)[i];
      EXPECT_EQ(z, codec::eye_depth_of_code(codes[i], near_plane));
      if (codes[i] == 0) EXPECT_TRUE(std::isinf(z));
      EXPECT_EQ(bottom_up[static_cast<size_t>(kFaceSize - 1 - y) * kFaceSize + x], z);
    }
  }
  out.size = kFaceSize * kFaceSize * 4 - 1;
  const Status small = reader->decode_face_depth_into(cell.index, Face::kPZ, out);
  EXPECT_EQ(small.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(small.message().find("depth buffer holds 9215 bytes"), std::string::npos) << small.message();
}

TEST_F(DepthFiles, FilesWithoutDepthSaySo) {
  auto reader = open_reader(dir_->path() / "plain.svc");
  EXPECT_FALSE(reader->info().has_depth);
  auto depth = reader->decode_face_depth(reader->cells()[0].index, Face::kPX);
  EXPECT_EQ(depth.status().code(), ErrorCode::kNotFound);
  EXPECT_NE(depth.status().message().find("holds no depth"), std::string::npos);
}

// A B-face's depth reads its own depth chunk and those of its reference cubes' faces,
// and decodes no color.
TEST_F(DepthFiles, RandomAccessReadsOnlyTheReferenceCubes) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  auto reader = open_reader(file(0), settings);
  int b_faces = 0;
  for (const CellEntry& cell : reader->cells()) {
    for (Face face : kAllFaces) {
      if (cell.faces[static_cast<int>(face)].type != FaceType::kPredicted) continue;
      auto fresh = open_reader(file(0), settings);
      ASSERT_TRUE(fresh->decode_face_depth(cell.index, face).ok());
      const ReaderStats stats = fresh->stats();
      EXPECT_LE(stats.chunks_read, 1u + 2 * 5);
      EXPECT_EQ(stats.intra_faces_parsed, 0u);
      EXPECT_EQ(stats.predicted_faces_decoded, 0u);
      ++b_faces;
    }
  }
  EXPECT_GT(b_faces, 0);
}

TEST_F(DepthFiles, SameBytesOnAnyThreadCount) {
  EncoderSettings encoder;
  encoder.threads = 1;
  encoder.quality = 40;
  encoder.depth = true;
  const fs::path one = dir_->path() / "one-thread.svc";
  ASSERT_TRUE(encode_database(db(), one, encoder).ok());
  std::ifstream a(one, std::ios::binary), b(file(0), std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {}),
      bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(bytes_a, bytes_b);
}

TEST_F(DepthFiles, PrefetchHoldsDepthWithColor) {
  ReaderSettings settings;
  settings.prefetch_threads = 1;
  auto reader = open_reader(file(0), settings);
  ASSERT_TRUE(reader->set_viewer(reader->cells()[5].index).ok());
  ASSERT_TRUE(reader->wait_for_prefetch(std::chrono::seconds(60)));
  const ReaderStats stats = reader->stats();
  EXPECT_GE(stats.depth_cache.entries, 6u);
  const uint64_t misses = stats.depth_cache.misses;
  ASSERT_TRUE(reader->decode_face_depth(reader->cells()[5].index, Face::kNX).ok());
  EXPECT_EQ(reader->stats().depth_cache.misses, misses);
}

// Damage to one depth chunk fails that face's depth (and the depth predicted from it);
// the color of every face still decodes, and verify names the chunk.
TEST_F(DepthFiles, DamagedDepthChunkStaysLocal) {
  auto reader = open_reader(file(0));
  const auto intra = std::find_if(reader->cells().begin(), reader->cells().end(),
                                  [](const CellEntry& c) { return c.faces[0].type == FaceType::kIntra; });
  ASSERT_NE(intra, reader->cells().end());
  const CellEntry& cell = *intra;
  const uint64_t depth_at = cell.faces[0].offset + cell.faces[0].coded_bytes + 4;
  const fs::path damaged = dir_->path() / "damaged.svc";
  fs::copy_file(file(0), damaged, fs::copy_options::overwrite_existing);
  {
    std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(depth_at + 5));
    f.put('\x5A');
  }
  auto broken = open_reader(damaged);
  auto depth = broken->decode_face_depth(cell.index, Face::kPX);
  EXPECT_EQ(depth.status().code(), ErrorCode::kCorruptData);
  EXPECT_NE(depth.status().message().find("byte offset " + std::to_string(depth_at)), std::string::npos)
      << depth.status().message();
  for (const CellEntry& other : broken->cells()) {
    for (Face face : kAllFaces) EXPECT_TRUE(broken->decode_face(other.index, face).ok());
  }
  EXPECT_TRUE(broken->decode_face_depth(cell.index, Face::kNX).ok());
  const Status verified = broken->verify();
  EXPECT_EQ(verified.code(), ErrorCode::kCorruptData);
  EXPECT_NE(verified.message().find(face_label(cell.index, Face::kPX) + " depth"), std::string::npos)
      << verified.message();
}

// Every kind of scene the corpus is made of round-trips its depth within the bound, with
// background exact, and a B-cube's six depths read no more than its two reference cubes'.
TEST(DepthScenes, EverySceneKindRoundTripsWithinTheBound) {
  testing::TempDir dir("svc-depth-kinds");
  for (int k = 0; k < samples::kSceneKinds; ++k) {
    const auto kind = static_cast<samples::SceneKind>(k);
    SCOPED_TRACE(samples::scene_kind_name(kind));
    samples::SceneOptions options;
    options.kind = kind;
    options.grid = {4, 1, 1};
    options.face_size = 32;
    const fs::path db = dir.path() / samples::scene_kind_name(kind);
    ASSERT_TRUE(samples::generate_scene(options, db).ok());
    auto manifest = load_manifest(db);
    ASSERT_TRUE(manifest.ok());
    for (int max_error : {0, 5}) {
      EncoderSettings encoder;
      encoder.threads = 2;
      encoder.depth = true;
      encoder.depth_max_error = max_error;
      const fs::path file = dir.path() / (std::string(samples::scene_kind_name(kind)) + ".svc");
      ASSERT_TRUE(encode_database(db, file, encoder).ok());
      ReaderSettings settings;
      settings.prefetch_threads = 0;
      auto reader = Reader::open(file, settings);
      ASSERT_TRUE(reader.ok());
      int worst = 0;
      for (size_t c = 0; c < manifest->cells.size(); ++c) {
        const CellEntry& cell = (*reader)->cells()[*(*reader)->find_cell(manifest->cells[c].index)];
        const uint64_t chunks_before = (*reader)->stats().chunks_read;
        for (Face face : kAllFaces) {
          auto source = load_face(*manifest, c, face);
          ASSERT_TRUE(source.ok());
          const double near_plane = cell.cameras[static_cast<int>(face)].frustum.near_plane;
          auto depth = (*reader)->decode_face_depth(cell.index, face);
          ASSERT_TRUE(depth.ok()) << depth.status().to_string();
          for (size_t i = 0; i < depth->size(); ++i) {
            const uint16_t got = codec::inverse_depth_code((*depth)[i], near_plane);
            const uint16_t expected = codec::inverse_depth_code(source->depth[i], near_plane);
            ASSERT_EQ(got == 0, expected == 0) << face_label(cell.index, face) << " pixel " << i;
            worst = std::max(worst, std::abs(int{got} - int{expected}));
          }
        }
        EXPECT_LE((*reader)->stats().chunks_read - chunks_before, 18u) << cell_label(cell.index);
      }
      EXPECT_LE(worst, max_error);
    }
  }
}

// The C API gives the C++ reader's depth, in both formats and row orders.
TEST_F(DepthFiles, CApiDecodesTheSameDepth) {
  auto reader = open_reader(file(6));
  svc_reader* c_reader = nullptr;
  ASSERT_EQ(svc_reader_open_file(file(6).string().c_str(), nullptr, &c_reader), SVC_OK) << svc_last_open_error();
  svc_file_info info{};
  ASSERT_EQ(svc_reader_info(c_reader, &info), SVC_OK);
  EXPECT_EQ(info.has_depth, 1);
  EXPECT_EQ(info.depth_max_error, 6);
  EXPECT_EQ(info.depth_bytes, reader->info().depth_bytes);
  for (const CellEntry& cell : reader->cells()) {
    const int32_t index[3] = {cell.index.x, cell.index.y, cell.index.z};
    for (Face face : kAllFaces) {
      std::vector<uint16_t> codes(kFaceSize * kFaceSize);
      svc_depth_image image{SVC_DEPTH_INVERSE_U16, SVC_ROWS_TOP_DOWN, codes.data(), kFaceSize * 2,
                            codes.size() * 2};
      ASSERT_EQ(svc_reader_decode_face_depth(c_reader, index, static_cast<svc_face>(face), &image), SVC_OK)
          << svc_reader_last_error(c_reader);
      EXPECT_EQ(codes, decode_codes(*reader, cell.index, face));
      std::vector<float> eye(kFaceSize * kFaceSize);
      image = {SVC_DEPTH_EYE_Z_F32, SVC_ROWS_BOTTOM_UP, eye.data(), kFaceSize * 4, eye.size() * 4};
      ASSERT_EQ(svc_reader_decode_face_depth(c_reader, index, static_cast<svc_face>(face), &image), SVC_OK);
      auto expected = reader->decode_face_depth(cell.index, face);
      ASSERT_TRUE(expected.ok());
      for (int y = 0; y < kFaceSize; ++y) {
        EXPECT_TRUE(std::equal(expected->begin() + y * kFaceSize, expected->begin() + (y + 1) * kFaceSize,
                               eye.begin() + (kFaceSize - 1 - y) * kFaceSize));
      }
    }
  }
  const int32_t first[3] = {reader->cells()[0].index.x, reader->cells()[0].index.y, reader->cells()[0].index.z};
  std::vector<float> small(10);
  const svc_depth_image too_small{SVC_DEPTH_EYE_Z_F32, SVC_ROWS_TOP_DOWN, small.data(), kFaceSize * 4, 40};
  EXPECT_EQ(svc_reader_decode_face_depth(c_reader, first, SVC_FACE_PX, &too_small), SVC_INVALID_ARGUMENT);
  EXPECT_NE(std::string(svc_reader_last_error(c_reader)).find("depth buffer holds 40 bytes"), std::string::npos);
  svc_reader_destroy(c_reader);
  ASSERT_EQ(svc_reader_open_file((dir_->path() / "plain.svc").string().c_str(), nullptr, &c_reader), SVC_OK);
  std::vector<float> eye(kFaceSize * kFaceSize);
  const svc_depth_image image{SVC_DEPTH_EYE_Z_F32, SVC_ROWS_TOP_DOWN, eye.data(), kFaceSize * 4, eye.size() * 4};
  EXPECT_EQ(svc_reader_decode_face_depth(c_reader, first, SVC_FACE_PX, &image), SVC_NOT_FOUND);
  svc_reader_destroy(c_reader);
}

}  // namespace
}  // namespace svc
