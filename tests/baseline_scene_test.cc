// SPDX-License-Identifier: BSD-2-Clause
// The baseline on the procedural sample scene: the six-face database in row-major and
// Hilbert order and MPEG-2 intra-only, with random access checked against sequential
// decoding, and the scene's PNG files read back through libavcodec.
#include <gtest/gtest.h>

#include <iostream>

#include "baseline/baseline.h"
#include "samples/scene/scene.h"
#include "support/test_support.h"

namespace svc::baseline {
namespace {

samples::SceneOptions small_scene() {
  samples::SceneOptions options;
  options.kind = samples::SceneKind::kHall;
  options.grid = {6, 1, 4};
  options.face_size = 64;
  return options;
}

DatabaseFrames scene_frames(const samples::SceneOptions& options) {
  DatabaseFrames frames;
  frames.dims = options.grid;
  for (int z = 0; z < options.grid[2]; ++z)
    for (int x = 0; x < options.grid[0]; ++x) frames.cells.push_back({x, 0, z});
  frames.width = options.face_size;
  frames.height = options.face_size;
  frames.load = [options](CellIndex cell, Face face) -> Result<ImageRGB8> {
    SVC_ASSIGN_OR_RETURN(samples::SceneFace rendered, samples::render_scene_face(options, cell, face));
    return std::move(rendered.color);
  };
  return frames;
}

struct DatabaseNumbers {
  uint64_t bytes = 0;
  Quality quality;
  int max_frames_decoded = 0;
};

// Decodes every (cell, face) by random access, checks it against the sequential decode of
// its face sequence bit for bit, and measures quality against the source.
DatabaseNumbers check_database(const EncodedDatabase& database, const DatabaseFrames& input) {
  DatabaseNumbers numbers;
  numbers.bytes = database.total_bytes();
  std::vector<ImageRGB8> sources, decoded;
  for (Face face : kAllFaces) {
    auto sequential = decode_all(database.faces[static_cast<int>(face)]);
    EXPECT_TRUE(sequential.ok()) << sequential.status().to_string();
    if (!sequential.ok()) return numbers;
    for (const CellIndex& cell : input.cells) {
      auto random = decode_cell_face(database, cell, face);
      EXPECT_TRUE(random.ok()) << random.status().to_string();
      if (!random.ok()) return numbers;
      const int frame = database.layout.frame_of(cell);
      EXPECT_EQ(random->image.pixels, (*sequential)[frame].pixels) << face_name(face) << " frame " << frame;
      numbers.max_frames_decoded = std::max(numbers.max_frames_decoded, random->frames_decoded);
      sources.push_back(input.load(cell, face).value());
      decoded.push_back(std::move(random->image));
    }
  }
  numbers.quality = compare_sequences(sources, decoded).value();
  return numbers;
}

TEST(BaselineSceneTest, SixFaceDatabaseInRowMajorHilbertAndIntraOnly) {
  quiet_ffmpeg_logging();
  const samples::SceneOptions options = small_scene();
  const DatabaseFrames input = scene_frames(options);

  EncodeSettings settings;
  settings.quantizer = 4;
  auto row_major = encode_database(input, CellOrder::kRowMajor, settings);
  ASSERT_TRUE(row_major.ok()) << row_major.status().to_string();
  auto hilbert = encode_database(input, CellOrder::kHilbert, settings);
  ASSERT_TRUE(hilbert.ok()) << hilbert.status().to_string();
  auto intra = encode_database(input, CellOrder::kRowMajor, mpeg2_intra_only_settings(4));
  ASSERT_TRUE(intra.ok()) << intra.status().to_string();

  const DatabaseNumbers a = check_database(*row_major, input);
  const DatabaseNumbers b = check_database(*hilbert, input);
  const DatabaseNumbers c = check_database(*intra, input);
  const uint64_t raw = static_cast<uint64_t>(input.cells.size()) * 6 * 64 * 64 * 3;
  for (const auto& [name, n] :
       {std::pair{"row-major IBBPBB", a}, std::pair{"hilbert IBBPBB", b}, std::pair{"intra-only", c}}) {
    std::cout << "hall 6x1x4, 64px faces, mpeg2 qscale 4, " << name << ": " << n.bytes << " bytes ("
              << static_cast<double>(raw) / n.bytes << ":1), PSNR-RGB " << n.quality.psnr_rgb << " dB, PSNR-Y "
              << n.quality.psnr_y << " dB, worst access " << n.max_frames_decoded << " frames\n";
  }
  EXPECT_EQ(c.max_frames_decoded, 1);
  EXPECT_LE(a.max_frames_decoded, 5);  // I P P B with the next GOP's I at most
  EXPECT_GT(a.quality.psnr_y, 30.0);
  EXPECT_GT(b.quality.psnr_y, 30.0);
  // Prediction pays: both inter orders are smaller than intra-only at the same qscale.
  EXPECT_LT(a.bytes, c.bytes);
  EXPECT_LT(b.bytes, c.bytes);
}

TEST(BaselineSceneTest, ScenePngFilesReadBackAsRendered) {
  samples::SceneOptions options = small_scene();
  options.grid = {2, 1, 1};
  options.face_size = 32;
  testing::TempDir dir("svc-baseline-scene");
  ASSERT_TRUE(samples::generate_scene(options, dir.path()).ok());
  for (Face face : {Face::kPX, Face::kNY}) {
    auto from_file = read_png(dir.path() / "cells" / "1_0_0" / (std::string(face_name(face)) + ".png"));
    ASSERT_TRUE(from_file.ok()) << from_file.status().to_string();
    auto rendered = samples::render_scene_face(options, {1, 0, 0}, face);
    ASSERT_TRUE(rendered.ok());
    EXPECT_EQ(from_file->pixels, rendered->color.pixels);
  }
}

}  // namespace
}  // namespace svc::baseline
