// SPDX-License-Identifier: BSD-2-Clause
// Whole-database round trips: generate a sample scene, encode, read back, damage.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>

#include <OpenImageIO/imageio.h>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/metrics.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

// One small scene shared by the tests in this file (generation costs a little).
class RoundTrip : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-roundtrip");
    samples::SceneOptions options;
    options.kind = samples::SceneKind::kHall;
    options.grid = {3, 1, 3};
    options.face_size = 64;
    ASSERT_TRUE(samples::generate_scene(options, db()).ok());
    // The same scene at 32x32 for the tests that encode it many times (tools, speeds).
    options.face_size = 32;
    ASSERT_TRUE(samples::generate_scene(options, small_db()).ok());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path db() { return dir_->path() / "db"; }
  static fs::path small_db() { return dir_->path() / "small-db"; }
  static fs::path out(const std::string& name) { return dir_->path() / name; }

  static ImageRGB8 source_face(const fs::path& database, const CellIndex& c, Face face) {
    const fs::path path = database / "cells" /
                          (std::to_string(c.x) + "_" + std::to_string(c.y) + "_" + std::to_string(c.z)) /
                          (std::string(face_name(face)) + ".png");
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path;
    ImageRGB8 image;
    image.width = in->spec().width;
    image.height = in->spec().height;
    image.pixels.resize(static_cast<size_t>(image.width) * image.height * 3);
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, image.pixels.data()));
    return image;
  }

  // Encodes the scene with `settings` into out(name): the file verifies and decodes to
  // the encoder's quality. `label` names the case in failures.
  static void expect_sound_encode(const EncoderSettings& settings, const std::string& name,
                                  const std::string& label, const fs::path& database = db()) {
    const fs::path file = out(name);
    auto summary = encode_database(database, file, settings);
    ASSERT_TRUE(summary.ok()) << label << ": " << summary.status().to_string();
    auto reader = Reader::open(file);
    ASSERT_TRUE(reader.ok()) << label;
    EXPECT_TRUE((*reader)->verify().ok()) << label;
    EXPECT_GE(database_psnr_y(file, database), 36.0) << label;
  }

  static double database_psnr_y(const fs::path& svc_file, const fs::path& database = db()) {
    auto reader = Reader::open(svc_file);
    EXPECT_TRUE(reader.ok()) << reader.status().to_string();
    SquaredError total;
    for (const CellEntry& cell : (*reader)->cells()) {
      for (Face face : kAllFaces) {
        auto decoded = (*reader)->decode_face(cell.index, face);
        EXPECT_TRUE(decoded.ok()) << decoded.status().to_string();
        total.add(*luma_squared_error(source_face(database, cell.index, face), *decoded));
      }
    }
    return total.psnr();
  }

  static testing::TempDir* dir_;
};
testing::TempDir* RoundTrip::dir_ = nullptr;

EncoderSettings intra_settings(int quality) {
  EncoderSettings settings;
  settings.quality = quality;
  settings.intra_only = true;
  return settings;
}

TEST_F(RoundTrip, EncodesVerifiesAndDecodesEveryFace) {
  const fs::path file = out("default.svc");
  auto summary = encode_database(db(), file, EncoderSettings{});
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_EQ(summary->cells, 9u);
  EXPECT_EQ(summary->faces, 54u);
  EXPECT_EQ(summary->file_bytes, fs::file_size(file));
  EXPECT_LT(summary->file_bytes, summary->raw_bytes / 8);

  auto reader = Reader::open(file);
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  EXPECT_TRUE((*reader)->verify().ok());
  EXPECT_EQ((*reader)->info().face_width, 64);
  EXPECT_EQ((*reader)->cells().size(), 9u);
  EXPECT_GE(database_psnr_y(file), 38.0);
  // The statistics the index records reach the public API as the encoder reported them.
  const auto& stats = (*reader)->info().face_type_stats;
  const FaceTypeStats& intra = stats[static_cast<int>(FaceType::kIntra)];
  const FaceTypeStats& predicted = stats[static_cast<int>(FaceType::kPredicted)];
  EXPECT_EQ(intra.faces, summary->intra.faces);
  EXPECT_EQ(intra.bytes, summary->intra.bytes);
  EXPECT_EQ(predicted.faces, summary->predicted.faces);
  EXPECT_EQ(predicted.mb_skipped, summary->predicted.mb_skipped);
  EXPECT_EQ(predicted.candidate_vectors, summary->predicted.candidate_vectors);
  EXPECT_GT(predicted.faces, 0u);
}

// Every coding tool can be switched off alone or all together; each stream still
// verifies and decodes to the encoder's quality, and the switches reach the coder.
TEST_F(RoundTrip, EveryCodingToolCanBeSwitchedOff) {
  const std::vector<std::string> names = coding_tool_names();
  ASSERT_FALSE(names.empty());
  ASSERT_TRUE(encode_database(small_db(), out("tools-on.svc"), EncoderSettings{}).ok());
  EncoderSettings all_off;
  for (const std::string& name : names) {
    EncoderSettings one_off;
    ASSERT_TRUE(disable_coding_tool(&one_off.tools, name).ok()) << name;
    ASSERT_TRUE(disable_coding_tool(&all_off.tools, name).ok()) << name;
    ASSERT_NO_FATAL_FAILURE(expect_sound_encode(one_off, "tool-off-" + name + ".svc", name, small_db()));
  }
  // All off together too: switches that interact (quantization without its
  // rate-distortion step under a mode search without one) still write what decodes.
  ASSERT_NO_FATAL_FAILURE(expect_sound_encode(all_off, "tools-off.svc", "every tool off", small_db()));
  EXPECT_NE(testing::read_file_data(out("tools-on.svc")), testing::read_file_data(out("tools-off.svc")));

  const Status unknown = disable_coding_tool(&all_off.tools, "no-such-tool");
  EXPECT_EQ(unknown.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(unknown.message().find("no-such-tool"), std::string::npos);
  for (const std::string& name : names) EXPECT_NE(unknown.message().find(name), std::string::npos) << name;
}

// Every cube border width writes what decodes to the encoder's quality, each its own
// bytes (the border is coded in every B-face header); widths outside 1..4 are refused.
TEST_F(RoundTrip, EveryCubeBorderWidthDecodes) {
  std::vector<std::vector<uint8_t>> files;
  for (int units = 1; units <= 4; ++units) {
    EncoderSettings settings;
    settings.cube_border_units = units;
    const std::string name = "border-" + std::to_string(units) + ".svc";
    ASSERT_NO_FATAL_FAILURE(expect_sound_encode(settings, name, name, small_db()));
    files.push_back(testing::read_file_data(out(name)));
  }
  ASSERT_TRUE(encode_database(small_db(), out("border-default.svc"), EncoderSettings{}).ok());
  EXPECT_EQ(files[3], testing::read_file_data(out("border-default.svc")));
  for (size_t i = 0; i + 1 < files.size(); ++i) EXPECT_NE(files[i], files[i + 1]) << i;
  for (int units : {0, 5}) {
    EncoderSettings settings;
    settings.cube_border_units = units;
    auto refused = encode_database(small_db(), out("border-refused.svc"), settings);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.status().code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(refused.status().message().find("cube border of " + std::to_string(units) + " units"),
              std::string::npos);
  }
}

// Switches interact (a search without its rate-distortion step keeps what quantization
// without one gave it): pairs of tools switched off still write a stream that verifies,
// each face decoded and checked against its chunk. The default run takes a fixed sample
// in which every tool is off once beside another (tool i with tool n-1-i); every pair
// runs under the "long" label (SVC_EVERY_TOOL_PAIR=1; docs/runtime.md, Tests).
std::vector<std::pair<size_t, size_t>> tool_pairs(size_t n, bool every_pair) {
  std::vector<std::pair<size_t, size_t>> pairs;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      if (every_pair || j == n - 1 - i || (n % 2 == 1 && i == 0 && j == n / 2)) pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

TEST(ToolPairs, SampleSwitchesEveryToolOffAndEveryPairIsTheLongRun) {
  for (size_t n : {2u, 7u, 16u}) {
    const auto sample = tool_pairs(n, false);
    std::vector<int> off(n, 0);
    for (const auto& [i, j] : sample) ++off[i], ++off[j];
    for (size_t t = 0; t < n; ++t) EXPECT_GE(off[t], 1) << "tool " << t << " of " << n;
    EXPECT_EQ(sample.size(), (n + 1) / 2) << n;
    EXPECT_EQ(tool_pairs(n, true).size(), n * (n - 1) / 2) << n;
  }
}

TEST_F(RoundTrip, PairsOfCodingToolsCanBeSwitchedOff) {
  const std::vector<std::string> names = coding_tool_names();
  const char* every = std::getenv("SVC_EVERY_TOOL_PAIR");
  for (const auto& [i, j] : tool_pairs(names.size(), every != nullptr && std::string(every) == "1")) {
    EncoderSettings settings;
    ASSERT_TRUE(disable_coding_tool(&settings.tools, names[i]).ok());
    ASSERT_TRUE(disable_coding_tool(&settings.tools, names[j]).ok());
    const std::string label = names[i] + " and " + names[j] + " off";
    const fs::path file = out("pair.svc");
    auto summary = encode_database(small_db(), file, settings);
    ASSERT_TRUE(summary.ok()) << label << ": " << summary.status().to_string();
    auto reader = Reader::open(file);
    ASSERT_TRUE(reader.ok()) << label;
    const Status verified = (*reader)->verify();
    EXPECT_TRUE(verified.ok()) << label << ": " << verified.to_string();
  }
}

// Each speed setting switches off its documented tools, and only those, and sets its
// layout; its stream verifies and decodes to the encoder's quality. Settings outside the
// range change nothing and say what is allowed.
TEST_F(RoundTrip, SpeedSettingsSwitchOffTheirTools) {
  EXPECT_TRUE(speed_disabled_tools(0).empty());
  EXPECT_EQ(speed_layout(0), CubeLayout::kVisibility);
  EXPECT_EQ(speed_layout(kMaxEncoderSpeed), CubeLayout::kRegular);
  CodingTools previous;
  for (int speed = 0; speed <= kMaxEncoderSpeed; ++speed) {
    EncoderSettings settings;
    settings.tools.cfl = false;  // a tool already off stays off
    ASSERT_TRUE(apply_encoder_speed(&settings, speed).ok()) << speed;
    CodingTools expected;
    expected.cfl = false;
    for (const std::string& name : speed_disabled_tools(speed))
      ASSERT_TRUE(disable_coding_tool(&expected, name).ok());
    EXPECT_EQ(settings.tools, expected) << speed;
    EXPECT_EQ(settings.layout, speed_layout(speed)) << speed;
    EXPECT_EQ(disabled_coding_tools(settings.tools).size(), speed_disabled_tools(speed).size() + 1) << speed;
    settings.tools.cfl = true;
    if (speed > 0) {
      EXPECT_FALSE(settings.tools == previous) << "speed " << speed << " adds no tool to the one below";
      EXPECT_GT(speed_disabled_tools(speed).size(), speed_disabled_tools(speed - 1).size());
    }
    previous = settings.tools;
    ASSERT_NO_FATAL_FAILURE(expect_sound_encode(settings, "speed-" + std::to_string(speed) + ".svc",
                                                "speed " + std::to_string(speed), small_db()));
    // With a tool switched off besides: levels as quantized under the speed's searches.
    ASSERT_TRUE(disable_coding_tool(&settings.tools, "rdoq").ok());
    ASSERT_NO_FATAL_FAILURE(expect_sound_encode(settings, "speed-" + std::to_string(speed) + "-no-rdoq.svc",
                                                "speed " + std::to_string(speed) + " without rdoq", small_db()));
  }
  EXPECT_NE(testing::read_file_data(out("speed-0.svc")),
            testing::read_file_data(out("speed-" + std::to_string(kMaxEncoderSpeed) + ".svc")));
  for (int speed : {-1, kMaxEncoderSpeed + 1}) {
    EncoderSettings settings;
    settings.layout = CubeLayout::kRegular;
    const Status status = apply_encoder_speed(&settings, speed);
    EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(status.message().find("0.." + std::to_string(kMaxEncoderSpeed)), std::string::npos);
    EXPECT_EQ(settings.tools, CodingTools{});
    EXPECT_EQ(settings.layout, CubeLayout::kRegular);
  }
}

TEST_F(RoundTrip, PsnrRisesWithQuality) {
  double previous = 0;
  for (int quality : {10, 30, 50, 75, 95}) {
    const fs::path file = out("q" + std::to_string(quality) + ".svc");
    auto summary = encode_database(db(), file, intra_settings(quality));
    ASSERT_TRUE(summary.ok()) << summary.status().to_string();
    const double psnr = database_psnr_y(file);
    EXPECT_GT(psnr, previous) << "quality " << quality;
    previous = psnr;
  }
}

TEST_F(RoundTrip, BytesDoNotDependOnThreadCount) {
  EncoderSettings one = EncoderSettings{};
  one.threads = 1;
  EncoderSettings four = one;
  four.threads = 4;
  ASSERT_TRUE(encode_database(db(), out("t1.svc"), one).ok());
  ASSERT_TRUE(encode_database(db(), out("t4.svc"), four).ok());
  EXPECT_EQ(testing::read_file_data(out("t1.svc")), testing::read_file_data(out("t4.svc")));
}

TEST_F(RoundTrip, RandomAccessEqualsSequentialDecode) {
  const fs::path file = out("access.svc");
  ASSERT_TRUE(encode_database(db(), file, EncoderSettings{}).ok());
  auto sequential = Reader::open(file);
  ASSERT_TRUE(sequential.ok());
  std::map<std::pair<int, int>, std::vector<uint8_t>> expected;
  const auto& cells = (*sequential)->cells();
  for (size_t c = 0; c < cells.size(); ++c) {
    for (Face face : kAllFaces) {
      expected[{static_cast<int>(c), static_cast<int>(face)}] =
          (*sequential)->decode_face(cells[c].index, face)->pixels;
    }
  }
  auto random = Reader::open(file);
  ASSERT_TRUE(random.ok());
  for (int k = 0; k < 40; ++k) {
    const size_t c = (k * 7919) % cells.size();
    const Face face = static_cast<Face>((k * 31) % kFaceCount);
    auto image = (*random)->decode_face(cells[c].index, face);
    ASSERT_TRUE(image.ok());
    EXPECT_EQ(image->pixels, (expected[{static_cast<int>(c), static_cast<int>(face)}]));
  }
}

TEST_F(RoundTrip, FindsCellsByIndexAndWorldPosition) {
  const fs::path file = out("lookup.svc");
  ASSERT_TRUE(encode_database(db(), file, EncoderSettings{}).ok());
  auto reader = Reader::open(file);
  ASSERT_TRUE(reader.ok());
  const auto& cells = (*reader)->cells();
  for (size_t c = 0; c < cells.size(); ++c) {
    EXPECT_EQ((*reader)->find_cell(cells[c].index), c);
    const FileInfo& info = (*reader)->info();
    std::array<double, 3> p;
    const int32_t idx[3] = {cells[c].index.x, cells[c].index.y, cells[c].index.z};
    for (int a = 0; a < 3; ++a) p[a] = info.grid_origin[a] + (idx[a] + 0.3) * info.grid_spacing[a];
    EXPECT_EQ((*reader)->find_cell_at(p), c);
  }
  EXPECT_FALSE((*reader)->find_cell(CellIndex{5, 0, 0}).has_value());
  EXPECT_FALSE((*reader)->find_cell_at({1e9, 0, 0}).has_value());
  EXPECT_EQ((*reader)->decode_face(CellIndex{5, 0, 0}, Face::kPX).status().code(), ErrorCode::kNotFound);
}

TEST_F(RoundTrip, FlippedBytesAreReportedAndNeverCrashTheDecoder) {
  const fs::path file = out("flip.svc");
  ASSERT_TRUE(encode_database(small_db(), file, intra_settings(60)).ok());
  const std::vector<uint8_t> original = testing::read_file_data(file);
  auto clean_reader = Reader::open(file);
  ASSERT_TRUE(clean_reader.ok());
  std::vector<std::vector<uint8_t>> clean;
  for (const CellEntry& cell : (*clean_reader)->cells()) {
    for (Face face : kAllFaces) clean.push_back((*clean_reader)->decode_face(cell.index, face)->pixels);
  }

  // A dense sample of offsets over the whole file: header, slots, chunks, index.
  const fs::path damaged = out("damaged.svc");
  for (size_t offset = 0; offset < original.size(); offset += 1 + original.size() / 400) {
    std::vector<uint8_t> bytes = original;
    bytes[offset] ^= 0x5a;
    std::ofstream(damaged, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    auto reader = Reader::open(damaged);
    if (!reader.ok()) {
      EXPECT_EQ(reader.status().code(), ErrorCode::kCorruptData) << "offset " << offset;
      continue;
    }
    EXPECT_FALSE((*reader)->verify().ok()) << "flip at offset " << offset << " not reported";
    size_t k = 0;
    for (const CellEntry& cell : (*reader)->cells()) {
      for (Face face : kAllFaces) {
        auto image = (*reader)->decode_face(cell.index, face);
        if (image.ok()) EXPECT_EQ(image->pixels, clean[k]) << "offset " << offset;
        ++k;
      }
    }
  }
}

TEST_F(RoundTrip, FailedEncodeLeavesNothingAtTheOutputPath) {
  const fs::path file = out("never.svc");
  auto bad_quality = encode_database(db(), file, intra_settings(0));
  EXPECT_EQ(bad_quality.status().code(), ErrorCode::kInvalidArgument);
  auto missing_db = encode_database(out("no-such-db"), file, EncoderSettings{});
  EXPECT_FALSE(missing_db.ok());
  EXPECT_FALSE(fs::exists(file));

  // A cancelled encode keeps an existing file untouched.
  std::ofstream(file) << "previous";
  auto cancelled =
      encode_database(db(), file, EncoderSettings{}, [](uint64_t done, uint64_t) { return done < 10; });
  EXPECT_EQ(cancelled.status().code(), ErrorCode::kCancelled);
  EXPECT_EQ(testing::read_file_data(file), (std::vector<uint8_t>{'p', 'r', 'e', 'v', 'i', 'o', 'u', 's'}));
  for (const auto& entry : fs::directory_iterator(dir_->path())) {
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

}  // namespace
}  // namespace svc
