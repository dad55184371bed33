// SPDX-License-Identifier: BSD-2-Clause
// Bad input to the encoder: each case fails with an error naming the cause, leaves
// nothing at the output path (nor a temporary file beside it), and the svc tool exits
// with a non-zero status.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

class EncoderInput : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-encoder-input");
    samples::SceneOptions options;
    options.grid = {2, 1, 1};
    options.face_size = 16;
    ASSERT_TRUE(samples::generate_scene(options, pristine()).ok());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path pristine() { return dir_->path() / "pristine"; }

  // A fresh copy of the database to damage.
  fs::path copy(const std::string& name) {
    const fs::path out = dir_->path() / name;
    fs::remove_all(out);
    fs::copy(pristine(), out, fs::copy_options::recursive);
    return out;
  }
  static json manifest_of(const fs::path& db) {
    std::ifstream in(db / "manifest.json");
    return json::parse(in);
  }
  static void write_manifest(const fs::path& db, const json& manifest) {
    std::ofstream(db / "manifest.json") << manifest.dump(1);
  }

  // Encodes and expects failure with `needle` in the message and no output left over.
  void expect_rejected(const fs::path& db, const std::string& needle, EncoderSettings settings = {},
                       fs::path out = {}) {
    if (out.empty()) out = dir_->path() / "out" / "result.svc";
    fs::create_directories(dir_->path() / "out");
    settings.threads = 1;
    auto result = encode_database(db, out, settings);
    ASSERT_FALSE(result.ok()) << "accepted; expected an error about " << needle;
    EXPECT_NE(result.status().message().find(needle), std::string::npos)
        << "'" << result.status().message() << "' does not mention '" << needle << "'";
    EXPECT_FALSE(fs::is_regular_file(out));
    if (fs::is_directory(out.parent_path())) {
      for (const auto& entry : fs::directory_iterator(out.parent_path())) {
        EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
      }
    }
    ++rejected_;
    if (cli_exists()) {
      // The tool: non-zero exit, nothing written.
      const std::string command = cli().string() + " encode --quiet --threads 1 \"" + db.string() + "\" -o \"" +
                                  out.string() + "\"" + cli_settings(settings) + " >/dev/null 2>&1";
      const int status = std::system(command.c_str());
      EXPECT_NE(status, 0) << command;
      EXPECT_FALSE(fs::is_regular_file(out));
    }
  }

  static fs::path cli() { return fs::path(SVC_BINARY_DIR) / "bin" / "svc"; }
  static bool cli_exists() { return fs::exists(cli()); }
  static std::string cli_settings(const EncoderSettings& settings) {
    if (settings.qindex >= 0) return " --qindex " + std::to_string(settings.qindex);
    return " --quality " + std::to_string(settings.quality);
  }

  static int rejected_;
  static testing::TempDir* dir_;
};
testing::TempDir* EncoderInput::dir_ = nullptr;
int EncoderInput::rejected_ = 0;

TEST_F(EncoderInput, PristineDatabaseEncodes) {
  const fs::path out = dir_->path() / "ok.svc";
  auto summary = encode_database(pristine(), out, EncoderSettings{});
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  EXPECT_TRUE(fs::exists(out));
}

TEST_F(EncoderInput, MissingImage) {
  const fs::path db = copy("missing");
  fs::remove(db / "cells" / "1_0_0" / "pz.png");
  expect_rejected(db, "pz.png");
}

TEST_F(EncoderInput, UnreadableImage) {
  const fs::path db = copy("unreadable");
  std::ofstream(db / "cells" / "0_0_0" / "nx.png") << "this is not a PNG file";
  expect_rejected(db, "nx.png");
  const fs::path depth = copy("unreadable-depth");
  std::ofstream(depth / "cells" / "1_0_0" / "py.exr") << "nor an EXR";
  expect_rejected(depth, "py.exr");
}

TEST_F(EncoderInput, WrongImageSize) {
  const fs::path db = copy("wrong-size");
  OIIO::ImageSpec spec(8, 8, 3, OIIO::TypeDesc::UINT8);
  std::vector<uint8_t> pixels(8 * 8 * 3, 100);
  const fs::path png = db / "cells" / "0_0_0" / "px.png";
  auto out = OIIO::ImageOutput::create(png.string());
  ASSERT_TRUE(out && out->open(png.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  out->close();
  expect_rejected(db, "px.png");
}

TEST_F(EncoderInput, InvalidManifests) {
  fs::path db = copy("not-json");
  std::ofstream(db / "manifest.json") << "{ \"format\": \"svc-input\", ";
  expect_rejected(db, "manifest.json");

  db = copy("no-cells-key");
  json manifest = manifest_of(db);
  manifest.erase("cells");
  write_manifest(db, manifest);
  expect_rejected(db, "cells");

  db = copy("no-manifest");
  fs::remove(db / "manifest.json");
  expect_rejected(db, "manifest.json");

  db = copy("cell-outside-grid");
  manifest = manifest_of(db);
  manifest["cells"][1]["index"] = {5, 0, 0};
  write_manifest(db, manifest);
  expect_rejected(db, "(5,0,0)");
}

TEST_F(EncoderInput, NonFiniteNumbersInTheManifest) {
  // JSON has no NaN or infinity literal; an overflowing number reads as infinity.
  const fs::path db = copy("infinite");
  std::ifstream in(db / "manifest.json");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  in.close();
  const json manifest = json::parse(text);
  const std::string origin = "\"origin\":";
  json grid = manifest["grid"];
  grid["origin"] = {0.0, 0.0, 0.0};
  std::string patched = manifest.dump();
  const size_t at = patched.find(origin);
  ASSERT_NE(at, std::string::npos);
  const size_t end = patched.find(']', at);
  patched.replace(at, end - at + 1, origin + "[1e999,0,0]");
  std::ofstream(db / "manifest.json") << patched;
  expect_rejected(db, "finite");
}

TEST_F(EncoderInput, NonFiniteDepthIsBackgroundNotAnError) {
  // docs/input-format.md: depth +inf, NaN, <= 0 or beyond far marks a pixel that saw no
  // geometry. Such pixels are accepted (no motion from depth) and color is coded as usual.
  const fs::path db = copy("nan-depth");
  const fs::path exr = db / "cells" / "0_0_0" / "px.exr";
  OIIO::ImageSpec spec(16, 16, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Z"};
  std::vector<float> depth(16 * 16);
  for (size_t i = 0; i < depth.size(); ++i) {
    depth[i] = i % 3 == 0   ? std::numeric_limits<float>::quiet_NaN()
               : i % 3 == 1 ? std::numeric_limits<float>::infinity()
                            : -std::numeric_limits<float>::infinity();
  }
  auto out = OIIO::ImageOutput::create(exr.string());
  ASSERT_TRUE(out && out->open(exr.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, depth.data()));
  out->close();
  const fs::path file = dir_->path() / "nan-depth.svc";
  auto summary = encode_database(db, file, EncoderSettings{});
  ASSERT_TRUE(summary.ok()) << summary.status().to_string();
  auto reader = Reader::open(file);
  ASSERT_TRUE(reader.ok());
  EXPECT_TRUE((*reader)->verify().ok());
}

TEST_F(EncoderInput, ZeroSizeGrid) {
  fs::path db = copy("zero-grid");
  json manifest = manifest_of(db);
  manifest["grid"]["dims"] = {0, 1, 1};
  write_manifest(db, manifest);
  expect_rejected(db, "dims");

  db = copy("zero-face");
  manifest = manifest_of(db);
  manifest["face_size"] = {0, 16};
  write_manifest(db, manifest);
  expect_rejected(db, "face_size");

  db = copy("no-cells");
  manifest = manifest_of(db);
  manifest["cells"] = json::array();
  write_manifest(db, manifest);
  expect_rejected(db, "cells");
}

TEST_F(EncoderInput, QualityOutOfRange) {
  for (int quality : {0, -5, 101}) {
    EncoderSettings settings;
    settings.quality = quality;
    expect_rejected(pristine(), "quality " + std::to_string(quality), settings);
  }
  EncoderSettings settings;
  settings.qindex = 256;
  expect_rejected(pristine(), "quantizer index 256", settings);
}

TEST_F(EncoderInput, UnwritableOutput) {
  expect_rejected(pristine(), "does not exist", {}, dir_->path() / "no-such-folder" / "x.svc");
  fs::create_directories(dir_->path() / "a-folder.svc");
  expect_rejected(pristine(), "is a folder", {}, dir_->path() / "a-folder.svc");
  // An existing file at the output path is left as it was when the encode fails.
  const fs::path existing = dir_->path() / "existing.svc";
  std::ofstream(existing) << "old contents";
  EncoderSettings settings;
  settings.quality = 0;
  auto result = encode_database(pristine(), existing, settings);
  EXPECT_FALSE(result.ok());
  std::ifstream in(existing);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), {}), "old contents");
}

TEST_F(EncoderInput, AddRejectsBadInputWithoutTouchingTheFile) {
  const fs::path file = dir_->path() / "add-target.svc";
  ASSERT_TRUE(encode_database(pristine(), file, EncoderSettings{}).ok());
  std::ifstream in(file, std::ios::binary);
  const std::vector<char> before((std::istreambuf_iterator<char>(in)), {});
  const fs::path db = copy("add-missing");
  // A new cell whose image is missing: the add fails, the file is as it was.
  json manifest = manifest_of(db);
  manifest["grid"]["dims"] = {3, 1, 1};
  json cell = manifest["cells"][1];
  cell["index"] = {2, 0, 0};
  cell["faces"]["px"]["color"] = "cells/2_0_0/px.png";
  manifest["cells"].push_back(cell);
  write_manifest(db, manifest);
  auto result = add_to_database(file, db);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.status().message().find("2_0_0"), std::string::npos) << result.status().message();
  std::ifstream again(file, std::ios::binary);
  EXPECT_EQ(std::vector<char>((std::istreambuf_iterator<char>(again)), {}), before);
  if (cli_exists()) {
    EXPECT_NE(std::system((cli().string() + " add --quiet \"" + file.string() + "\" \"" + db.string() +
                           "\" >/dev/null 2>&1")
                              .c_str()),
              0);
    EXPECT_NE(std::system(
                  (cli().string() + " add --quiet /no/such.svc \"" + db.string() + "\" >/dev/null 2>&1").c_str()),
              0);
  }
}

}  // namespace
}  // namespace svc
