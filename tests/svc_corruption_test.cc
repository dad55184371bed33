// SPDX-License-Identifier: BSD-2-Clause
// Damage sweeps over a tiny database (2x1x2 cells of 16-pixel faces, I- and B-faces):
// the file truncated at every length, and one byte changed at every offset. For each
// damaged copy: opening either fails with an error or verify() reports the damage;
// every face either decodes to exactly the intact file's pixels or fails with an error
// naming it; every face whose chunk (and references' chunks) is intact still decodes.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "container/container.h"
#include "fuzz/fuzz_entry.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

ReaderSettings sweep_settings() {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  return settings;
}

class Corruption : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-corruption");
    samples::SceneOptions options;
    options.grid = {2, 1, 2};
    options.face_size = 16;
    ASSERT_TRUE(samples::generate_scene(options, dir_->path() / "db").ok());
    EncoderSettings settings;
    settings.threads = 1;
    // With depth, so that the sweeps cover depth chunks and index version 5 too.
    settings.depth = true;
    settings.depth_max_error = 2;
    const fs::path file = dir_->path() / "tiny.svc";
    ASSERT_TRUE(encode_database(dir_->path() / "db", file, settings).ok());
    bytes_ = new std::vector<uint8_t>(testing::read_file_data(file));
    auto read = ReadOnlyFile::open(file);
    ASSERT_TRUE(read.ok());
    auto opened = open_container(**read, ReaderLimits{});
    ASSERT_TRUE(opened.ok());
    index_ = new ContainerIndex(opened->index);
    auto reader = Reader::open(file, sweep_settings());
    ASSERT_TRUE(reader.ok());
    originals_ = new std::vector<ImageYCbCr420>();
    original_depths_ = new std::vector<std::vector<float>>();
    for (const FrameRecord& frame : index_->frames) {
      auto image = (*reader)->decode_face_ycbcr(index_->cells[frame.cell].index, frame.face);
      ASSERT_TRUE(image.ok());
      originals_->push_back(*image);
      auto depth = (*reader)->decode_face_depth(index_->cells[frame.cell].index, frame.face);
      ASSERT_TRUE(depth.ok());
      original_depths_->push_back(*depth);
    }
  }
  static void TearDownTestSuite() {
    delete originals_;
    delete original_depths_;
    delete index_;
    delete bytes_;
    delete dir_;
  }

  // The frame whose chunk holds byte `offset`, if any.
  static std::optional<uint32_t> frame_at(uint64_t offset) {
    for (uint32_t f = 0; f < index_->frames.size(); ++f) {
      const FrameRecord& frame = index_->frames[f];
      if (offset >= frame.chunk_offset && offset < frame.chunk_offset + chunk_bytes(frame)) return f;
    }
    return std::nullopt;
  }

  struct Outcome {
    bool opened = false;
    bool verify_reported = false;
    int faces_ok = 0;
    int faces_failed = 0;
  };

  // Opens a damaged copy and decodes every face of the intact index's cells.
  // `damaged_frame`: the frame whose chunk was hit (faces depending on it may fail; all
  // others must decode).
  static Outcome check_copy(const std::vector<uint8_t>& copy, std::optional<uint32_t> damaged_frame,
                            const std::string& what) {
    Outcome outcome;
    fuzz::MemoryFile memory(copy);
    auto reader = Reader::open(memory.path(), sweep_settings());
    if (!reader.ok()) {
      EXPECT_FALSE(reader.status().message().empty()) << what;
      EXPECT_NE(reader.status().code(), ErrorCode::kOk) << what;
      return outcome;
    }
    outcome.opened = true;
    const Status verified = (*reader)->verify();
    outcome.verify_reported = !verified.ok();
    for (uint32_t f = 0; f < index_->frames.size(); ++f) {
      const FrameRecord& frame = index_->frames[f];
      const CellIndex& cell = index_->cells[frame.cell].index;
      auto image = (*reader)->decode_face_ycbcr(cell, frame.face);
      bool depends_on_damage = damaged_frame && *damaged_frame == f;
      for (uint32_t ref : frame_dependencies(frame)) depends_on_damage |= damaged_frame && *damaged_frame == ref;
      if (image.ok()) {
        ++outcome.faces_ok;
        const ImageYCbCr420& original = (*originals_)[f];
        EXPECT_TRUE(image->y == original.y && image->cb == original.cb && image->cr == original.cr)
            << what << ": frame " << f << " decoded to other pixels";
      } else {
        ++outcome.faces_failed;
        EXPECT_TRUE(depends_on_damage) << what << ": intact frame " << f << " failed: " << image.status().message();
        expect_located(image.status());
      }
      auto depth = (*reader)->decode_face_depth(cell, frame.face);
      bool depth_depends_on_damage = damaged_frame && *damaged_frame == f;
      for (uint32_t ref : depth_dependencies(frame))
        depth_depends_on_damage |= damaged_frame && *damaged_frame == ref;
      if (depth.ok()) {
        EXPECT_TRUE(*depth == (*original_depths_)[f]) << what << ": frame " << f << " decoded to other depth";
      } else {
        ++outcome.faces_failed;
        EXPECT_TRUE(depth_depends_on_damage)
            << what << ": intact frame " << f << "'s depth failed: " << depth.status().message();
        expect_located(depth.status());
      }
    }
    return outcome;
  }

  // The error names the cell, the face and a byte offset.
  static void expect_located(const Status& status) {
    EXPECT_NE(status.message().find("cell ("), std::string::npos) << status.message();
    EXPECT_NE(status.message().find("byte offset"), std::string::npos) << status.message();
  }

  static testing::TempDir* dir_;
  static std::vector<uint8_t>* bytes_;
  static ContainerIndex* index_;
  static std::vector<ImageYCbCr420>* originals_;
  static std::vector<std::vector<float>>* original_depths_;
};
testing::TempDir* Corruption::dir_ = nullptr;
std::vector<uint8_t>* Corruption::bytes_ = nullptr;
ContainerIndex* Corruption::index_ = nullptr;
std::vector<ImageYCbCr420>* Corruption::originals_ = nullptr;
std::vector<std::vector<float>>* Corruption::original_depths_ = nullptr;

TEST_F(Corruption, IntactFileVerifies) {
  ASSERT_GT(index_->frames.size(), 0u);
  bool has_predicted = false;
  for (const FrameRecord& frame : index_->frames) has_predicted |= frame.type == FaceType::kPredicted;
  EXPECT_TRUE(has_predicted);
  const Outcome outcome = check_copy(*bytes_, std::nullopt, "intact");
  EXPECT_TRUE(outcome.opened);
  EXPECT_FALSE(outcome.verify_reported);
  EXPECT_EQ(outcome.faces_ok, static_cast<int>(index_->frames.size()));
}

TEST_F(Corruption, TruncationAtEveryLength) {
  int refused = 0, reported = 0;
  for (size_t length = 0; length < bytes_->size(); ++length) {
    const std::vector<uint8_t> copy(bytes_->begin(), bytes_->begin() + static_cast<std::ptrdiff_t>(length));
    const std::string what = "truncated to " + std::to_string(length) + " bytes";
    // The index is the last chunk, so every truncation loses it; faces it listed may
    // still be whole, but the file no longer says where they are.
    const Outcome outcome = check_copy(copy, frame_at(length), what);
    if (!outcome.opened) {
      ++refused;
    } else {
      EXPECT_TRUE(outcome.verify_reported) << what;
      ++reported;
    }
  }
  EXPECT_EQ(refused + reported, static_cast<int>(bytes_->size()));
  std::printf("truncation sweep: %zu lengths, %d refused at open, %d opened and reported by verify\n",
              bytes_->size(), refused, reported);
}

TEST_F(Corruption, OneByteChangedAtEveryOffset) {
  int refused = 0, reported = 0, faces_lost = 0;
  for (size_t offset = 0; offset < bytes_->size(); ++offset) {
    std::vector<uint8_t> copy = *bytes_;
    // A different single-bit flip at each offset, and every 7th offset a whole byte.
    copy[offset] ^= offset % 7 == 0 ? 0xFF : static_cast<uint8_t>(1u << (offset % 8));
    const std::string what = "byte " + std::to_string(offset) + " changed";
    const Outcome outcome = check_copy(copy, frame_at(offset), what);
    if (!outcome.opened) {
      ++refused;
      // Only the prelude and the index make a file unreadable as a whole.
      EXPECT_FALSE(frame_at(offset).has_value()) << what << " made the whole file unreadable";
      continue;
    }
    ++reported;
    EXPECT_TRUE(outcome.verify_reported) << what << " went unnoticed by verify";
    faces_lost += outcome.faces_failed;
    // A hit face chunk costs that face and the B-faces predicted from it, nothing more.
    if (const auto frame = frame_at(offset)) EXPECT_GE(outcome.faces_failed, 1) << what;
  }
  EXPECT_EQ(refused + reported, static_cast<int>(bytes_->size()));
  std::printf(
      "corruption sweep: %zu offsets, %d refused at open (prelude/index), %d opened and reported by "
      "verify, %d face decodes failed in all\n",
      bytes_->size(), refused, reported, faces_lost);
}

}  // namespace
}  // namespace svc
