// SPDX-License-Identifier: BSD-2-Clause
// The B-faces' quantizer index chosen per database from trial B-faces
// (docs/encoder.md 5): which faces make the trial, and that every B-face of the file
// carries the index the encode reports.
#include <gtest/gtest.h>

#include <filesystem>

#include "codec/common/bframe.h"
#include "codec/encoder/bframe_encoder.h"
#include "common/file_io.h"
#include "container/container.h"
#include "encoder/coding_pipeline.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

// A row of `types.size()` cells 1 m apart, cell c an I-cube when types[c] is 'I'; each
// B-cube's references are the nearest I-cube on either side.
ContainerIndex index_of(const std::string& types) {
  ContainerIndex index;
  for (size_t c = 0; c < types.size(); ++c) {
    index.cells.push_back({CellIndex{static_cast<int32_t>(c), 0, 0}, {static_cast<double>(c), 0, 0}});
    for (int f = 0; f < kFaceCount; ++f) {
      FrameRecord frame;
      frame.cell = static_cast<uint32_t>(c);
      frame.face = static_cast<Face>(f);
      frame.type = types[c] == 'I' ? FaceType::kIntra : FaceType::kPredicted;
      if (types[c] != 'I') {
        const size_t before = types.rfind('I', c), after = types.find('I', c);
        if (before != std::string::npos) frame.references.push_back(static_cast<uint32_t>(before * kFaceCount + f));
        if (after != std::string::npos) frame.references.push_back(static_cast<uint32_t>(after * kFaceCount + f));
      }
      index.frames.push_back(frame);
    }
  }
  return index;
}

std::vector<uint32_t> faces_of(std::initializer_list<uint32_t> cells) {
  std::vector<uint32_t> frames;
  for (uint32_t cell : cells) {
    for (uint32_t f = 0; f < kFaceCount; ++f) frames.push_back(cell * kFaceCount + f);
  }
  return frames;
}

TEST(BQIndexTrial, TakesWholeBCubesNearAndFarFromTheirReferences) {
  static_assert(kTrialCubes == 3);
  const ContainerIndex index = index_of("IBBBBIBBB");
  // B-cubes by distance to the nearest reference, then cell: 1, 4, 6 (1 m), 2, 3, 7
  // (2 m), 8 (3 m); the trial takes the 2nd, 4th and 6th of the seven.
  EXPECT_EQ(trial_frames(index, faces_of({0, 1, 2, 3, 4, 5, 6, 7, 8})), faces_of({2, 4, 7}));
  // Only cubes whose six faces are all in the list count.
  std::vector<uint32_t> partial = faces_of({0, 1, 3, 5});
  partial.push_back(2 * kFaceCount);
  EXPECT_EQ(trial_frames(index, partial), faces_of({1, 3}));
  EXPECT_EQ(trial_frames(index, faces_of({4})), faces_of({4}));
  EXPECT_TRUE(trial_frames(index, faces_of({0, 5})).empty());
  EXPECT_TRUE(trial_frames(index, {}).empty());
}

TEST(BQIndexTrial, EveryBFaceCarriesTheReportedIndex) {
  testing::TempDir dir("svc-b-qindex");
  samples::SceneOptions options;
  options.grid = {5, 1, 4};
  options.face_size = 32;
  ASSERT_TRUE(samples::generate_scene(options, dir.path() / "db").ok());
  EncoderSettings settings;
  settings.quality = 60;
  settings.threads = 2;
  const fs::path file = dir.path() / "out.svc";
  auto summary = encode_database(dir.path() / "db", file, settings);
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  ASSERT_GT(summary->predicted.faces, 0u);
  EXPECT_GE(summary->b_qindex, summary->qindex + codec::kMinBQIndexOffset);
  EXPECT_LE(summary->b_qindex, codec::suggested_b_qindex(summary->qindex));

  auto opened_file = ReadOnlyFile::open(file);
  ASSERT_TRUE(opened_file.ok()) << opened_file.status().to_string();
  auto container = open_container(**opened_file, ReaderLimits{});
  ASSERT_TRUE(container.ok()) << container.status().to_string();
  int predicted = 0;
  for (const FrameRecord& frame : container->index.frames) {
    auto payload = read_frame_payload(**opened_file, frame, "face");
    ASSERT_TRUE(payload.ok()) << payload.status().to_string();
    ASSERT_GE(payload->size(), 2u);
    const int qindex = (*payload)[1];
    if (frame.type == FaceType::kPredicted) {
      ++predicted;
      EXPECT_EQ(qindex, summary->b_qindex);
    } else {
      EXPECT_EQ(qindex, summary->qindex);
    }
  }
  EXPECT_EQ(static_cast<uint64_t>(predicted), summary->predicted.faces);

  // A fixed offset: every B-face takes it, and the intra faces are as before.
  settings.b_qindex_offset = 7;
  auto fixed = encode_database(dir.path() / "db", dir.path() / "fixed.svc", settings);
  ASSERT_TRUE(fixed.ok()) << fixed.status().to_string();
  EXPECT_EQ(fixed->b_qindex, fixed->qindex + 7);
  EXPECT_EQ(fixed->intra.bytes, summary->intra.bytes);
  settings.b_qindex_offset = 256;
  auto refused = encode_database(dir.path() / "db", dir.path() / "refused.svc", settings);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("B-face quantizer offset 256"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path() / "refused.svc"));
  settings.b_qindex_offset = -1;

  // Intra-only: no B-face, no trial.
  settings.intra_only = true;
  summary = encode_database(dir.path() / "db", dir.path() / "intra.svc", settings);
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_EQ(summary->b_qindex, -1);
}

}  // namespace
}  // namespace svc
