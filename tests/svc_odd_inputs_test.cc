// SPDX-License-Identifier: BSD-2-Clause
// Encoding odd but valid databases, and bad ones: every case decodes (or fails) cleanly.
#include <gtest/gtest.h>

#include <algorithm>

#include <array>
#include <fstream>
#include <limits>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/metrics.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

fs::path make_scene(const fs::path& dir, std::array<int, 3> grid, bool sparse = false,
                    samples::SceneKind kind = samples::SceneKind::kHall) {
  samples::SceneOptions options;
  options.kind = kind;
  options.grid = grid;
  options.face_size = 48;
  options.sparse = sparse;
  const fs::path db = dir / "db";
  EXPECT_TRUE(samples::generate_scene(options, db).ok());
  return db;
}

// The source color image of one face of a manifest cell entry.
ImageRGB8 read_source_face(const fs::path& db, const nlohmann::json& cell, Face face) {
  auto in =
      OIIO::ImageInput::open((db / cell.at("faces").at(face_name(face)).at("color").get<std::string>()).string());
  ImageRGB8 image;
  if (!in) return image;
  image.width = in->spec().width;
  image.height = in->spec().height;
  image.pixels.resize(size_t(image.width) * image.height * 3);
  in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, image.pixels.data());
  return image;
}

// Encodes with the default spatial layout and checks every face decodes close to its
// source; returns the reader.
std::unique_ptr<Reader> encode_and_check(const fs::path& db, const fs::path& out, double min_psnr_y = 30.0) {
  auto summary = encode_database(db, out, EncoderSettings{});
  EXPECT_TRUE(summary.ok()) << summary.status().to_string();
  if (!summary.ok()) return nullptr;
  auto reader = Reader::open(out);
  EXPECT_TRUE(reader.ok()) << reader.status().to_string();
  if (!reader.ok()) return nullptr;
  EXPECT_TRUE((*reader)->verify().ok());
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(db / "manifest.json"));
  for (const auto& cell : manifest.at("cells")) {
    const auto idx = cell.at("index").get<std::array<int, 3>>();
    for (Face face : kAllFaces) {
      const ImageRGB8 original = read_source_face(db, cell, face);
      auto decoded = (*reader)->decode_face(CellIndex{idx[0], idx[1], idx[2]}, face);
      EXPECT_TRUE(decoded.ok()) << decoded.status().to_string();
      if (decoded.ok()) EXPECT_GE(luma_squared_error(original, *decoded)->psnr(), min_psnr_y);
    }
  }
  return std::move(reader).value();
}

// Rewrites every depth image of the database with `value` in every pixel (or in the
// left half only when `half` is set).
void overwrite_depth(const fs::path& db, float value, bool half) {
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(db / "manifest.json"));
  const int w = manifest.at("face_size")[0], h = manifest.at("face_size")[1];
  for (const auto& cell : manifest.at("cells")) {
    for (Face face : kAllFaces) {
      const fs::path path = db / cell.at("faces").at(face_name(face)).at("depth").get<std::string>();
      std::vector<float> depth(size_t(w) * h);
      {
        auto in = OIIO::ImageInput::open(path.string());
        ASSERT_TRUE(in);
        ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, depth.data()));
      }
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < (half ? w / 2 : w); ++x) depth[size_t(y) * w + x] = value;
      }
      auto out = OIIO::ImageOutput::create(path.string());
      OIIO::ImageSpec spec(w, h, 1, OIIO::TypeDesc::FLOAT);
      spec.channelnames = {"Z"};
      ASSERT_TRUE(out->open(path.string(), spec));
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, depth.data()));
      out->close();
    }
  }
}

TEST(OddInputs, SingleCell) {
  testing::TempDir dir;
  auto reader = encode_and_check(make_scene(dir.path(), {1, 1, 1}), dir.path() / "one.svc");
  ASSERT_TRUE(reader);
  ASSERT_EQ(reader->cells().size(), 1u);
  EXPECT_EQ(reader->cells()[0].faces[0].type, FaceType::kIntra);
}

TEST(OddInputs, SingleRow) {
  testing::TempDir dir;
  auto reader = encode_and_check(make_scene(dir.path(), {7, 1, 1}), dir.path() / "row.svc");
  ASSERT_TRUE(reader);
  int predicted = 0;
  for (const CellEntry& cell : reader->cells()) {
    if (cell.faces[0].type == FaceType::kPredicted) {
      ++predicted;
      // One or two reference faces, each with the adjacent faces of its cube whose border
      // the face reads (at most four).
      const auto& dependencies = cell.faces[0].references;
      const auto references = std::count_if(dependencies.begin(), dependencies.end(),
                                            [](const auto& dependency) { return dependency.second == Face::kPX; });
      EXPECT_TRUE(references == 1 || references == 2) << references;
      EXPECT_LE(dependencies.size(), static_cast<size_t>(5 * references));
    }
  }
  EXPECT_GT(predicted, 0);
}

TEST(OddInputs, CellsMissingFromTheGrid) {
  testing::TempDir dir;
  const fs::path db = make_scene(dir.path(), {9, 1, 9}, /*sparse=*/true);
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(db / "manifest.json"));
  ASSERT_LT(manifest.at("cells").size(), 81u);
  auto reader = encode_and_check(db, dir.path() / "sparse.svc");
  ASSERT_TRUE(reader);
  EXPECT_EQ(reader->cells().size(), manifest.at("cells").size());
  // Every reference of every B-face is an I-face of a present cell.
  for (const CellEntry& cell : reader->cells()) {
    for (const FaceEntry& face : cell.faces) {
      for (const auto& [ref_cell, ref_face] : face.references) {
        ASSERT_LT(ref_cell, reader->cells().size());
        EXPECT_EQ(reader->cells()[ref_cell].faces[static_cast<int>(ref_face)].type, FaceType::kIntra);
      }
    }
  }
}

TEST(OddInputs, FacesWhosePixelsAreAllBackground) {
  testing::TempDir dir;
  const fs::path db = make_scene(dir.path(), {3, 1, 3});
  overwrite_depth(db, std::numeric_limits<float>::infinity(), /*half=*/false);
  EXPECT_TRUE(encode_and_check(db, dir.path() / "sky.svc", 25.0));
}

TEST(OddInputs, DepthWithNanAndInfinity) {
  testing::TempDir dir;
  const fs::path db = make_scene(dir.path(), {3, 1, 3}, false, samples::SceneKind::kHouse);
  overwrite_depth(db, std::numeric_limits<float>::quiet_NaN(), /*half=*/true);
  EXPECT_TRUE(encode_and_check(db, dir.path() / "nan.svc", 25.0));
  overwrite_depth(db, -std::numeric_limits<float>::infinity(), /*half=*/true);
  EXPECT_TRUE(encode_and_check(db, dir.path() / "neginf.svc", 25.0));
}

TEST(OddInputs, MissingImageIsNamedAndNothingIsWritten) {
  testing::TempDir dir;
  const fs::path db = make_scene(dir.path(), {2, 1, 2});
  fs::remove(db / "cells" / "1_0_1" / "nz.png");
  const fs::path out = dir.path() / "never.svc";
  auto summary = encode_database(db, out, EncoderSettings{});
  ASSERT_FALSE(summary.ok());
  const std::string message = summary.status().message();
  EXPECT_NE(message.find("(1,0,1)"), std::string::npos) << message;
  EXPECT_NE(message.find("nz"), std::string::npos) << message;
  EXPECT_NE(message.find("nz.png"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(out));
}

TEST(OddInputs, WrongImageSizeIsNamedAndNothingIsWritten) {
  testing::TempDir dir;
  const fs::path db = make_scene(dir.path(), {2, 1, 2});
  const fs::path victim = db / "cells" / "0_0_1" / "py.png";
  {
    auto out = OIIO::ImageOutput::create(victim.string());
    OIIO::ImageSpec spec(20, 20, 3, OIIO::TypeDesc::UINT8);
    std::vector<uint8_t> pixels(20 * 20 * 3, 128);
    ASSERT_TRUE(out->open(victim.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    out->close();
  }
  const fs::path out = dir.path() / "never.svc";
  auto summary = encode_database(db, out, EncoderSettings{});
  ASSERT_FALSE(summary.ok());
  EXPECT_NE(summary.status().message().find("py"), std::string::npos) << summary.status().message();
  EXPECT_NE(summary.status().message().find("(0,0,1)"), std::string::npos) << summary.status().message();
  EXPECT_FALSE(fs::exists(out));
}

// Every quality step changes the output: a strictly smaller file as -q falls, and a
// PSNR-Y that falls with it.
TEST(OddInputs, EveryQualityGivesADistinctSmallerFile) {
  testing::TempDir dir("svc-odd-quality");
  const fs::path db = make_scene(dir.path(), {2, 1, 1});
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(db / "manifest.json"));
  uint64_t previous_bytes = 0;
  std::array<uint64_t, 101> bytes_by_quality{};
  std::string previous_contents;
  double previous_psnr = 0, first_psnr = 0;
  for (int quality = 1; quality <= 100; ++quality) {
    EncoderSettings settings;
    settings.quality = quality;
    const fs::path out = dir.path() / "q.svc";
    fs::remove(out);
    auto summary = encode_database(db, out, settings);
    ASSERT_TRUE(summary.ok()) << summary.status().to_string();
    auto reader = Reader::open(out);
    ASSERT_TRUE(reader.ok());
    SquaredError total;
    for (const auto& cell : manifest.at("cells")) {
      const auto idx = cell.at("index").get<std::array<int, 3>>();
      for (Face face : kAllFaces) {
        const ImageRGB8 original = read_source_face(db, cell, face);
        auto decoded = (*reader)->decode_face(CellIndex{idx[0], idx[1], idx[2]}, face);
        ASSERT_TRUE(decoded.ok());
        total.add(*luma_squared_error(original, *decoded));
      }
    }
    // Rate-distortion decisions (modes, filters, vectors) may give back a few bytes at
    // one step (measured: 7 of 823 between quality 1 and 2, where the vectors of a
    // 48-pixel face cost a tenth of its bytes), never the trend: three steps up is
    // always larger.
    EXPECT_GT(summary->file_bytes, previous_bytes * 98 / 100) << "quality " << quality;
    if (quality > 3) EXPECT_GT(summary->file_bytes, bytes_by_quality[quality - 3]) << "quality " << quality;
    const std::string contents = testing::read_file_bytes(out);
    EXPECT_NE(contents, previous_contents) << "quality " << quality;
    // On these 12 faces of 48x48 the PSNR-Y measured on RGB wanders by up to 0.6 dB at
    // one step near the top, where the step is finer than the color conversion's
    // rounding (measured: 53.20 dB at quality 96, 52.59 at 97); the trend must hold.
    EXPECT_GT(total.psnr(), previous_psnr - 1.0) << "quality " << quality;
    if (quality == 1) first_psnr = total.psnr();
    previous_bytes = summary->file_bytes;
    bytes_by_quality[quality] = summary->file_bytes;
    previous_contents = contents;
    previous_psnr = total.psnr();
  }
  EXPECT_GT(previous_psnr, first_psnr + 20);  // quality 100 against 1
}

TEST(OddInputs, QualitySpreadsEvenlyOverTheQuantizerIndex) {
  EXPECT_EQ(qindex_for_quality(100), 0);
  EXPECT_EQ(qindex_for_quality(75), 64);
  EXPECT_EQ(qindex_for_quality(50), 129);
  EXPECT_EQ(qindex_for_quality(1), 255);
  for (int q = 2; q <= 100; ++q) {
    const int step = qindex_for_quality(q - 1) - qindex_for_quality(q);
    EXPECT_TRUE(step == 2 || step == 3) << q;
  }
}

}  // namespace
}  // namespace svc
