// SPDX-License-Identifier: BSD-2-Clause
// Pins the encoder's output: the SHA-256 of each .svc file and of its decoded pixels for
// a small sample database at two settings. Any change to the bitstream, the encoder's
// decisions or the decoder's reconstruction fails here, so such a change is always a
// deliberate one.
//
// After a deliberate bitstream or reconstruction change, update the pins: run
//   build/bin/svc_integration_tests --gtest_filter='PinnedOutput.*'
// and copy the "actual" digests from the failure messages into kPins below, saying in
// the commit message why the output changed. The input pin (kSceneInputSha256) changes
// only when the sample-scene generator renders different pixels; then every output pin
// changes with it.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "support/sha256.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

samples::SceneOptions pinned_scene() {
  samples::SceneOptions options;
  options.kind = samples::SceneKind::kHall;
  options.grid = {3, 1, 3};
  options.face_size = 32;
  options.seed = 1;
  return options;
}

struct PinnedEncode {
  const char* name;
  EncoderSettings settings;
  const char* file_sha256;
  const char* pixels_sha256;
};

EncoderSettings with(int quality, MotionSearch motion) {
  EncoderSettings settings;
  settings.quality = quality;
  settings.motion = motion;
  settings.threads = 2;
  return settings;
}

const char kSceneInputSha256[] = "213b5a32303ab7eff13fd86e08c426a17fd7de8b4433c33078545d8bab443065";
const PinnedEncode kPins[] = {
    {"q75-depth", with(75, MotionSearch::kDepth),
     "8e74b50a7407e0f9cded8410b7f3f0e5b446e6a82fefb1ffadc8e7411d62c8a8",
     "8e7f4d9c89bae88f2032f390592ba825d567ecddcdf290af7fc7165bed1a305c"},
    {"q30-logarithmic", with(30, MotionSearch::kLogarithmic),
     "5b201ba5b04af3e3513ebefff0dd6fe5ae4298c3418aa1b74d02410af13ff92c",
     "bbf60cf8fa516701e4e5b1e543c8f92f9d4ddf45485565ff29e62eb938217bf6"},
};

// Files written before index version 6 (tests/fuzz/corpus/container/index-v*.svc, kept
// as written): every later reader decodes them to these pixels.
struct PinnedOlderFile {
  const char* name;
  const char* pixels_sha256;
};
const PinnedOlderFile kOlderFiles[] = {
    {"index-v4-2x1x2-ib-depth.svc", "87c79131a44974135c5f4d3f5f6747ab85912aeac6a9b409231b4d673f045f59"},
    {"index-v4-3x1x1-ib-log.svc", "253c117ad671ad11758bff40a0fdf54c6da99957e52a9139db7f81a47c56f630"},
    {"index-v5-3x1x1-ib-stored-depth.svc", "334af393ecbce64a6b5eae59ca321f163877185913bf5df4c45ba5fa1740c830"},
};

std::string file_sha256(const fs::path& path) { return testing::sha256_hex(testing::read_file_data(path)); }

// Every face's RGB in the reader's cell order (y, z, x), faces in Face order, each
// preceded by its cell index, face and size so a moved face changes the digest too.
std::string decoded_pixels_sha256(const fs::path& path) {
  auto reader = Reader::open(path);
  EXPECT_TRUE(reader.ok()) << reader.status().to_string();
  if (!reader.ok()) return "";
  testing::Sha256 hash;
  for (const CellEntry& cell : (*reader)->cells()) {
    for (Face face : kAllFaces) {
      auto image = (*reader)->decode_face(cell.index, face);
      EXPECT_TRUE(image.ok()) << image.status().to_string();
      if (!image.ok()) return "";
      const int32_t header[] = {cell.index.x, cell.index.y, cell.index.z, static_cast<int32_t>(face),
                                image->width, image->height};
      hash.update({reinterpret_cast<const uint8_t*>(header), sizeof(header)});
      hash.update(image->pixels);
    }
  }
  return hash.hex_digest();
}

// What the encoder reads, rendered in memory: color, depth and camera of every face.
std::string scene_input_sha256(const samples::SceneOptions& options) {
  testing::Sha256 hash;
  for (int z = 0; z < options.grid[2]; ++z) {
    for (int x = 0; x < options.grid[0]; ++x) {
      for (Face face : kAllFaces) {
        auto rendered = samples::render_scene_face(options, CellIndex{x, 0, z}, face);
        EXPECT_TRUE(rendered.ok()) << rendered.status().to_string();
        if (!rendered.ok()) return "";
        hash.update(rendered->color.pixels);
        hash.update(
            {reinterpret_cast<const uint8_t*>(rendered->depth.data()), rendered->depth.size() * sizeof(float)});
        hash.update({reinterpret_cast<const uint8_t*>(rendered->world_to_camera.data()),
                     rendered->world_to_camera.size() * sizeof(double)});
      }
    }
  }
  return hash.hex_digest();
}

TEST(Sha256, MatchesTheStandardTestVectors) {
  auto text = [](const std::string& s) {
    return testing::sha256_hex({reinterpret_cast<const uint8_t*>(s.data()), s.size()});
  };
  EXPECT_EQ(text(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(text("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(text("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(text(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(PinnedOutput, SceneInputIsUnchanged) {
  EXPECT_EQ(scene_input_sha256(pinned_scene()), kSceneInputSha256)
      << "the sample-scene generator renders different pixels: the output pins below change with it";
}

TEST(PinnedOutput, FilesAndDecodedPixelsAreUnchanged) {
  testing::TempDir dir("svc-pinned");
  ASSERT_TRUE(samples::generate_scene(pinned_scene(), dir.path() / "db").ok());
  for (const PinnedEncode& pin : kPins) {
    const fs::path file = dir.path() / (std::string(pin.name) + ".svc");
    auto summary = encode_database(dir.path() / "db", file, pin.settings);
    ASSERT_TRUE(summary.ok()) << pin.name << ": " << summary.status().to_string();
    EXPECT_GT(summary->predicted.faces, 0u) << pin.name << ": B-cubes should be pinned too";
    EXPECT_EQ(file_sha256(file), pin.file_sha256) << pin.name << ": .svc bytes changed";
    EXPECT_EQ(decoded_pixels_sha256(file), pin.pixels_sha256) << pin.name << ": decoded pixels changed";
  }
}

TEST(PinnedOutput, FilesOfEarlierIndexVersionsDecodeToTheirPixels) {
  for (const PinnedOlderFile& older : kOlderFiles) {
    const fs::path file = fs::path(SVC_SOURCE_DIR) / "tests/fuzz/corpus/container" / older.name;
    EXPECT_EQ(decoded_pixels_sha256(file), older.pixels_sha256) << older.name;
  }
}

}  // namespace
}  // namespace svc
