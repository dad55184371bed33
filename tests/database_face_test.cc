// SPDX-License-Identifier: BSD-2-Clause
// load_face: color and depth decoding of svc-input faces.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "database/database.h"
#include "support/test_support.h"

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kWidth = 16;
constexpr int kHeight = 12;
constexpr size_t kPixels = static_cast<size_t>(kWidth) * kHeight;
constexpr float kInf = std::numeric_limits<float>::infinity();

// Writes `data` (interleaved, of type `data_type`) as an image stored as `file_type`.
void write_image(const fs::path& path, int width, int height, const std::vector<std::string>& channel_names,
                 OIIO::TypeDesc file_type, OIIO::TypeDesc data_type, const void* data) {
  fs::create_directories(path.parent_path());
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(width, height, static_cast<int>(channel_names.size()), file_type);
  spec.channelnames = channel_names;
  spec.alpha_channel = -1;
  spec.z_channel = -1;
  spec.attribute("oiio:UnassociatedAlpha", 1);  // store color as given, alpha or not
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(data_type, data)) << out->geterror();
  ASSERT_TRUE(out->close());
}

void write_float_exr(const fs::path& path, const std::vector<std::string>& channel_names,
                     const std::vector<float>& data, OIIO::TypeDesc file_type = OIIO::TypeDesc::FLOAT,
                     int width = kWidth, int height = kHeight) {
  write_image(path, width, height, channel_names, file_type, OIIO::TypeDesc::FLOAT, data.data());
}

// Deterministic 8-bit test pattern covering the whole 0..255 range.
std::vector<uint8_t> pattern8(size_t pixels, int channels) {
  std::vector<uint8_t> data(pixels * channels);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<uint8_t>((i * 37 + i / 7) & 0xff);
  return data;
}

std::vector<float> constant(size_t count, float value) { return std::vector<float>(count, value); }

// Reference sRGB encoding, written independently of the library.
uint8_t srgb_reference(double linear) {
  if (std::isnan(linear) || linear <= 0) return 0;
  if (linear >= 1) return 255;
  const double v = linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return static_cast<uint8_t>(std::floor(v * 255 + 0.5));
}

class FaceTest : public ::testing::Test {
 protected:
  // A one-cell database at index (0,0,0) whose six faces all use `color` and `depth`.
  DatabaseManifest make_database(const std::string& color, const std::string& depth,
                                 const json& extra = json::object()) {
    json faces = json::object();
    for (const Face face : kAllFaces) {
      faces[face_name(face)] = {{"color", color},
                                {"depth", depth},
                                {"world_to_camera", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}};
    }
    json manifest = {{"format", "svc-input"},
                     {"version", 1},
                     {"grid", {{"dims", {1, 1, 1}}, {"origin", {0, 0, 0}}, {"spacing", {1, 1, 1}}}},
                     {"face_size", {kWidth, kHeight}},
                     {"projection", {{"fov_y_degrees", 90.0}, {"near", 0.1}, {"far", 50.0}}},
                     {"cells", {{{"index", {0, 0, 0}}, {"position", {0, 0, 0}}, {"faces", faces}}}}};
    manifest.update(extra);
    std::ofstream(dir_.path() / "manifest.json") << manifest.dump(2);
    auto result = load_manifest(dir_.path());
    EXPECT_TRUE(result.ok()) << result.status().to_string();
    return result.ok() ? *result : DatabaseManifest{};
  }

  Result<FaceData> load(const DatabaseManifest& manifest, Face face = Face::kPX) {
    return load_face(manifest, 0, face);
  }

  template <class T>
  void expect_error(const Result<T>& result, ErrorCode code, const std::vector<std::string>& needles) {
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), code) << result.status().to_string();
    for (const std::string& needle : needles) {
      EXPECT_NE(result.status().message().find(needle), std::string::npos)
          << "message lacks \"" << needle << "\": " << result.status().message();
    }
  }

  fs::path at(const std::string& relative) const { return dir_.path() / relative; }

  void write_default_depth() { write_float_exr(at("depth.exr"), {"Z"}, constant(kPixels, 2.5f)); }

  // An 8-bit RGB PNG of the face size holding pattern8; returns its pixels.
  std::vector<uint8_t> write_rgb_png(const std::string& relative) {
    const auto rgb = pattern8(kPixels, 3);
    write_image(at(relative), kWidth, kHeight, {"R", "G", "B"}, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8,
                rgb.data());
    return rgb;
  }

  testing::TempDir dir_{"svc-database-face"};
};

TEST_F(FaceTest, EightBitPngIsLoadedExactly) {
  const auto rgb = write_rgb_png("faces/rgb.png");
  write_default_depth();
  const DatabaseManifest manifest = make_database("faces/rgb.png", "depth.exr");
  const auto face = load(manifest, Face::kNZ);
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  EXPECT_EQ(face->color.width, kWidth);
  EXPECT_EQ(face->color.height, kHeight);
  EXPECT_EQ(face->color.pixels, rgb);
  ASSERT_EQ(face->depth.size(), kPixels);
  for (const float d : face->depth) EXPECT_EQ(d, 2.5f);
}

TEST_F(FaceTest, AlphaIsIgnoredAndGreyIsExpanded) {
  const auto rgba = pattern8(kPixels, 4);
  write_image(at("rgba.png"), kWidth, kHeight, {"R", "G", "B", "A"}, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8,
              rgba.data());
  const auto grey = pattern8(kPixels, 1);
  write_image(at("grey.png"), kWidth, kHeight, {"Y"}, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8, grey.data());
  write_default_depth();

  const auto with_alpha = load(make_database("rgba.png", "depth.exr"));
  ASSERT_TRUE(with_alpha.ok()) << with_alpha.status().to_string();
  for (size_t i = 0; i < kPixels; ++i) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(with_alpha->color.pixels[i * 3 + k], rgba[i * 4 + k]);
  }
  const auto grey_face = load(make_database("grey.png", "depth.exr"));
  ASSERT_TRUE(grey_face.ok()) << grey_face.status().to_string();
  for (size_t i = 0; i < kPixels; ++i) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(grey_face->color.pixels[i * 3 + k], grey[i]);
  }
}

TEST_F(FaceTest, SixteenBitPngIsRoundedToEightBits) {
  std::vector<uint16_t> rgb16(kPixels * 3);
  for (size_t i = 0; i < rgb16.size(); ++i) rgb16[i] = static_cast<uint16_t>((i * 1237 + 5) % 65536);
  rgb16[0] = 0;
  rgb16[1] = 65535;
  rgb16[2] = 128;  // 128 / 257 = 0.498 rounds down
  rgb16[3] = 129;  // 0.502 rounds up
  write_image(at("deep.png"), kWidth, kHeight, {"R", "G", "B"}, OIIO::TypeDesc::UINT16, OIIO::TypeDesc::UINT16,
              rgb16.data());
  write_default_depth();
  const auto face = load(make_database("deep.png", "depth.exr"));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  for (size_t i = 0; i < rgb16.size(); ++i) {
    ASSERT_EQ(face->color.pixels[i], (rgb16[i] * 255 + 32767) / 65535) << "value " << rgb16[i];
  }
  EXPECT_EQ(face->color.pixels[2], 0);
  EXPECT_EQ(face->color.pixels[3], 1);
}

TEST_F(FaceTest, FloatColorIsConvertedToSrgb) {
  std::vector<float> rgb(kPixels * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<float>(i) / (rgb.size() - 1) * 1.2f - 0.1f;
  rgb[0] = 0.5f;
  rgb[1] = 0.0f;
  rgb[2] = 1.0f;
  rgb[3] = 4.0f;
  rgb[4] = -2.0f;
  rgb[5] = std::numeric_limits<float>::quiet_NaN();
  rgb[6] = 0.001f;
  write_float_exr(at("linear.exr"), {"R", "G", "B"}, rgb);
  write_default_depth();
  const auto face = load(make_database("linear.exr", "depth.exr"));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  const auto& px = face->color.pixels;
  EXPECT_EQ(px[0], 188);  // linear 0.5 is sRGB 187.5 -> 188
  EXPECT_EQ(px[1], 0);
  EXPECT_EQ(px[2], 255);
  EXPECT_EQ(px[3], 255);
  EXPECT_EQ(px[4], 0);
  EXPECT_EQ(px[5], 0);
  EXPECT_EQ(px[6], 3);  // linear segment: 0.001 * 12.92 * 255 = 3.29
  for (size_t i = 0; i < rgb.size(); ++i) ASSERT_EQ(px[i], srgb_reference(rgb[i])) << rgb[i];
  for (int v = 0; v <= 1000; ++v) {
    const float linear = v / 1000.0f;
    ASSERT_EQ(linear_to_srgb8(linear), srgb_reference(linear)) << linear;
  }
}

TEST_F(FaceTest, HalfColorAndDepthAreAccepted) {
  std::vector<float> rgbz(kPixels * 4);
  for (size_t i = 0; i < kPixels; ++i) {
    rgbz[i * 4 + 0] = 0.5f;  // exact in half
    rgbz[i * 4 + 1] = 0.25f;
    rgbz[i * 4 + 2] = 1.0f;
    rgbz[i * 4 + 3] = 4.0f;
  }
  write_float_exr(at("half.exr"), {"R", "G", "B", "Z"}, rgbz, OIIO::TypeDesc::HALF);
  const auto face = load(make_database("half.exr", "half.exr"));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  for (size_t i = 0; i < kPixels; ++i) {
    ASSERT_EQ(face->color.pixels[i * 3 + 0], 188);
    ASSERT_EQ(face->color.pixels[i * 3 + 1], srgb_reference(0.25));
    ASSERT_EQ(face->color.pixels[i * 3 + 2], 255);
    ASSERT_EQ(face->depth[i], 4.0f);
  }
}

TEST_F(FaceTest, CombinedRgbzExrServesColorAndDepth) {
  std::vector<float> data(kPixels * 4);
  for (size_t i = 0; i < kPixels; ++i) {
    data[i * 4 + 0] = 1.0f;
    data[i * 4 + 1] = 0.0f;
    data[i * 4 + 2] = 0.5f;
    data[i * 4 + 3] = 1.0f + static_cast<float>(i) * 0.125f;
  }
  write_float_exr(at("beauty.exr"), {"R", "G", "B", "Z"}, data);
  const auto face = load(make_database("beauty.exr", "beauty.exr"));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  for (size_t i = 0; i < kPixels; ++i) {
    ASSERT_EQ(face->color.pixels[i * 3 + 0], 255);
    ASSERT_EQ(face->color.pixels[i * 3 + 1], 0);
    ASSERT_EQ(face->color.pixels[i * 3 + 2], 188);
    ASSERT_EQ(face->depth[i], 1.0f + static_cast<float>(i) * 0.125f);
  }
}

TEST_F(FaceTest, BlenderLayerChannelsServeColorAndDepth) {
  const std::vector<std::string> names = {"ViewLayer.Combined.A", "ViewLayer.Combined.B", "ViewLayer.Combined.G",
                                          "ViewLayer.Combined.R", "ViewLayer.Depth.Z"};
  std::vector<float> data(kPixels * names.size());
  for (size_t i = 0; i < kPixels; ++i) {
    data[i * 5 + 0] = 0.0f;  // A
    data[i * 5 + 1] = 0.5f;  // B
    data[i * 5 + 2] = 0.0f;  // G
    data[i * 5 + 3] = 1.0f;  // R
    data[i * 5 + 4] = 7.0f;  // depth
  }
  write_float_exr(at("render.exr"), names, data);
  const auto face = load(make_database("render.exr", "render.exr"));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  EXPECT_EQ(face->color.pixels[0], 255);
  EXPECT_EQ(face->color.pixels[1], 0);
  EXPECT_EQ(face->color.pixels[2], 188);
  for (const float d : face->depth) ASSERT_EQ(d, 7.0f);
}

TEST_F(FaceTest, DepthChannelIsFoundByName) {
  write_rgb_png("rgb.png");
  struct Case {
    std::vector<std::string> names;
    int depth_channel;  // which channel holds the real depth
  };
  const std::vector<Case> cases = {
      {{"A", "Z"}, 1},                      // Z
      {{"A", "Z", "depth", "Y"}, 1},        // Z wins over the others
      {{"B", "ViewLayer.Depth.Z"}, 1},      // *.Z
      {{"ViewLayer.Depth.Z", "depth"}, 0},  // *.Z wins over depth
      {{"G", "depth", "Y"}, 1},             // depth wins over Y
      {{"R", "Y"}, 1},                      // Y
      {{"distance"}, 0},                    // the only channel
  };
  for (size_t c = 0; c < cases.size(); ++c) {
    const Case& test_case = cases[c];
    const size_t channels = test_case.names.size();
    std::vector<float> data(kPixels * channels, 99.0f);
    for (size_t i = 0; i < kPixels; ++i) data[i * channels + test_case.depth_channel] = 1.0f + 0.125f * i;
    const std::string file = "depth" + std::to_string(c) + ".exr";
    write_float_exr(at(file), test_case.names, data);
    const auto face = load(make_database("rgb.png", file));
    ASSERT_TRUE(face.ok()) << file << ": " << face.status().to_string();
    for (size_t i = 0; i < kPixels; ++i) {
      ASSERT_EQ(face->depth[i], 1.0f + 0.125f * i) << "case " << c << " pixel " << i;
    }
  }
}

TEST_F(FaceTest, DepthFileWithoutUsableChannelIsRejected) {
  write_rgb_png("rgb.png");
  write_float_exr(at("nodepth.exr"), {"U", "V"}, constant(kPixels * 2, 1.0f));
  expect_error(load(make_database("rgb.png", "nodepth.exr"), Face::kPY), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face py", "nodepth.exr", "no depth channel", "U, V"});
  // An 8-bit image cannot carry depth in scene units.
  expect_error(load(make_database("rgb.png", "rgb.png")), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face px", "rgb.png", "depth"});
}

TEST_F(FaceTest, BackgroundDepthBecomesInfinity) {
  write_rgb_png("rgb.png");
  std::vector<float> depth = constant(kPixels, 1.0f);
  depth[0] = kInf;
  depth[1] = std::numeric_limits<float>::quiet_NaN();
  depth[2] = 0.0f;
  depth[3] = -4.0f;
  depth[4] = 50.0f;  // = far
  depth[5] = 1e10f;  // beyond far
  depth[6] = -kInf;
  depth[7] = 49.5f;  // just inside
  depth[8] = 0.01f;  // nearer than the near plane, still geometry
  write_float_exr(at("bg.exr"), {"Z"}, depth);
  const auto face = load(make_database("rgb.png", "bg.exr"));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  for (int i = 0; i <= 6; ++i) EXPECT_EQ(face->depth[i], kInf) << "pixel " << i;
  EXPECT_EQ(face->depth[7], 49.5f);
  EXPECT_EQ(face->depth[8], 0.01f);
  EXPECT_EQ(face->depth[9], 1.0f);
}

TEST_F(FaceTest, RadialDepthIsConvertedToEyeZ) {
  const auto rgb = pattern8(4, 3);
  write_image(at("small.png"), 2, 2, {"R", "G", "B"}, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8, rgb.data());
  // Frustum [-1,1]^2 at near 1: pixel centres look along (+-0.5, +-0.5, -1), |dir| = sqrt(1.5).
  const std::vector<float> radial = {3.0f, 6.0f, std::sqrt(1.5f) * 2.0f, 1e6f};
  write_float_exr(at("radial.exr"), {"Z"}, radial, OIIO::TypeDesc::FLOAT, 2, 2);
  const json extra = {
      {"face_size", {2, 2}},
      {"depth", "radial"},
      {"projection",
       {{"left", -1.0}, {"right", 1.0}, {"bottom", -1.0}, {"top", 1.0}, {"near", 1.0}, {"far", 100.0}}}};
  const auto face = load(make_database("small.png", "radial.exr", extra));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  EXPECT_NEAR(face->depth[0], 3.0 / std::sqrt(1.5), 1e-5);
  EXPECT_NEAR(face->depth[1], 6.0 / std::sqrt(1.5), 1e-5);
  EXPECT_NEAR(face->depth[2], 2.0, 1e-5);
  EXPECT_EQ(face->depth[3], kInf);
}

TEST_F(FaceTest, RadialDepthOfAPlaneIsFlatInEyeZ) {
  // A wall at eye z = 5 seen through an off-centre frustum: radial = 5 * |dir| / near.
  const double left = -0.3, right = 0.1, bottom = -0.05, top = 0.2, near_plane = 0.1;
  std::vector<float> radial(kPixels);
  for (int j = 0; j < kHeight; ++j) {
    for (int i = 0; i < kWidth; ++i) {
      const double x = left + (i + 0.5) / kWidth * (right - left);
      const double y = top - (j + 0.5) / kHeight * (top - bottom);
      radial[j * kWidth + i] =
          static_cast<float>(5.0 * std::sqrt(x * x + y * y + near_plane * near_plane) / near_plane);
    }
  }
  write_float_exr(at("wall.exr"), {"Z"}, radial);
  write_rgb_png("rgb.png");
  const json extra = {
      {"depth", "radial"},
      {"projection",
       {{"left", left}, {"right", right}, {"bottom", bottom}, {"top", top}, {"near", near_plane}, {"far", 100.0}}}};
  const auto face = load(make_database("rgb.png", "wall.exr", extra));
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  for (size_t i = 0; i < kPixels; ++i) ASSERT_NEAR(face->depth[i], 5.0, 1e-5) << "pixel " << i;
}

TEST_F(FaceTest, WrongImageSizeNamesBothSizes) {
  const auto rgb = pattern8(8 * 8, 3);
  write_image(at("faces/small.png"), 8, 8, {"R", "G", "B"}, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8,
              rgb.data());
  write_default_depth();
  expect_error(load(make_database("faces/small.png", "depth.exr"), Face::kNY), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face ny", "color", "faces/small.png", "8x8", "16x12"});
  write_float_exr(at("depth_small.exr"), {"Z"}, constant(64, 1.0f), OIIO::TypeDesc::FLOAT, 8, 8);
  const auto full = pattern8(kPixels, 3);
  write_image(at("rgb.png"), kWidth, kHeight, {"R", "G", "B"}, OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT8,
              full.data());
  expect_error(load(make_database("rgb.png", "depth_small.exr")), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face px", "depth", "depth_small.exr", "8x8", "16x12"});
}

TEST_F(FaceTest, GarbageAndMissingFilesAreReported) {
  {
    std::ofstream garbage(at("garbage.png"), std::ios::binary);
    for (int i = 0; i < 1000; ++i) garbage.put(static_cast<char>((i * 131 + 7) & 0xff));
  }
  {
    // A real PNG signature followed by junk: opened by the PNG reader, then fails.
    std::ofstream truncated(at("truncated.png"), std::ios::binary);
    const unsigned char signature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    truncated.write(reinterpret_cast<const char*>(signature), sizeof signature);
    for (int i = 0; i < 64; ++i) truncated.put(static_cast<char>(i));
  }
  write_default_depth();
  expect_error(load(make_database("garbage.png", "depth.exr"), Face::kPZ), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face pz", "color", "garbage.png"});
  expect_error(load(make_database("truncated.png", "depth.exr")), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face px", "color", "truncated.png"});

  write_rgb_png("rgb.png");
  const DatabaseManifest manifest = make_database("rgb.png", "depth.exr");
  fs::remove(at("depth.exr"));
  expect_error(load(manifest, Face::kNX), ErrorCode::kNotFound, {"cell (0,0,0)", "face nx", "depth", "depth.exr"});
}

TEST_F(FaceTest, DepthAloneEqualsTheFacesDepthAndSkipsTheColor) {
  write_rgb_png("rgb.png");
  std::vector<float> depth = constant(kPixels, 3.0f);
  depth[5] = kInf;
  depth[9] = 7.25f;
  write_float_exr(at("d.exr"), {"Z"}, depth);
  const DatabaseManifest manifest = make_database("rgb.png", "d.exr");
  const auto cell = read_cell(manifest, 0);
  ASSERT_TRUE(cell.ok()) << cell.status().to_string();
  const auto face = load(manifest, Face::kNY);
  const auto alone = load_face_depth(manifest, *cell, Face::kNY);
  ASSERT_TRUE(face.ok() && alone.ok());
  EXPECT_EQ(*alone, face->depth);

  // The color file is not read: damaged, it fails the face but not its depth.
  std::ofstream(at("rgb.png"), std::ios::binary | std::ios::trunc) << "not an image";
  EXPECT_FALSE(load(manifest, Face::kNY).ok());
  const auto still = load_face_depth(manifest, *cell, Face::kNY);
  ASSERT_TRUE(still.ok()) << still.status().to_string();
  EXPECT_EQ(*still, face->depth);

  // A missing depth file is named as for the whole face.
  fs::remove(at("d.exr"));
  const auto missing = load_face_depth(manifest, *cell, Face::kPZ);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), ErrorCode::kNotFound);
  for (const char* needle : {"cell (0,0,0)", "face pz", "depth", "d.exr"}) {
    EXPECT_NE(missing.status().message().find(needle), std::string::npos) << missing.status().message();
  }
}

TEST_F(FaceTest, ColorAloneEqualsTheFacesColorAndSkipsTheDepth) {
  write_rgb_png("rgb.png");
  write_float_exr(at("d.exr"), {"Z"}, constant(kPixels, 3.0f));
  const DatabaseManifest manifest = make_database("rgb.png", "d.exr");
  const auto face = load(manifest, Face::kPY);
  const auto alone = load_face_color(manifest, 0, Face::kPY);
  ASSERT_TRUE(face.ok() && alone.ok());
  EXPECT_EQ(alone->width, face->color.width);
  EXPECT_EQ(alone->height, face->color.height);
  EXPECT_EQ(alone->pixels, face->color.pixels);

  // The depth file is not read: damaged, it fails the face but not its color.
  std::ofstream(at("d.exr"), std::ios::binary | std::ios::trunc) << "not an image";
  EXPECT_FALSE(load(manifest, Face::kPY).ok());
  const auto still = load_face_color(manifest, 0, Face::kPY);
  ASSERT_TRUE(still.ok()) << still.status().to_string();
  EXPECT_EQ(still->pixels, face->color.pixels);

  // A missing color file is named as for the whole face; a bad ordinal is refused.
  fs::remove(at("rgb.png"));
  expect_error(load_face_color(manifest, 0, Face::kNZ), ErrorCode::kNotFound,
               {"cell (0,0,0)", "face nz", "color", "rgb.png"});
  expect_error(load_face_color(manifest, 1, Face::kPX), ErrorCode::kInvalidArgument, {"ordinal 1"});
}

TEST_F(FaceTest, OutOfRangeArgumentsAreRejected) {
  write_rgb_png("rgb.png");
  write_default_depth();
  const DatabaseManifest manifest = make_database("rgb.png", "depth.exr");
  expect_error(load_face(manifest, 1, Face::kPX), ErrorCode::kInvalidArgument, {"ordinal 1"});
  expect_error(load_face(manifest, 0, static_cast<Face>(6)), ErrorCode::kInvalidArgument, {"face"});
}

TEST_F(FaceTest, ConcurrentLoadsAgree) {
  std::vector<float> data(kPixels * 4);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<float>(i % 97) / 50.0f + 0.01f;
  write_float_exr(at("rgbz.exr"), {"R", "G", "B", "Z"}, data);
  const DatabaseManifest manifest = make_database("rgbz.exr", "rgbz.exr");
  const auto expected = load(manifest);
  ASSERT_TRUE(expected.ok()) << expected.status().to_string();
  constexpr int kThreads = 8;
  std::vector<int> matches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int round = 0; round < 4; ++round) {
        const auto face = load_face(manifest, 0, kAllFaces[(t + round) % kFaceCount]);
        if (face.ok() && face->color.pixels == expected->color.pixels &&
            std::equal(face->depth.begin(), face->depth.end(), expected->depth.begin(), expected->depth.end())) {
          ++matches[t];
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(matches[t], 4) << "thread " << t;
}

// configure_image_loading switches OpenImageIO to OpenEXR's core library: every EXR
// the loaders accept decodes to the same values, and damaged ones still fail cleanly.
TEST_F(FaceTest, ConfiguredLoadingReadsTheSameValues) {
  std::vector<float> rgbz(kPixels * 4);
  for (size_t i = 0; i < rgbz.size(); ++i) rgbz[i] = static_cast<float>((i * 29) % 101) / 16.0f + 0.0625f;
  rgbz[7] = kInf;
  write_float_exr(at("float.exr"), {"R", "G", "B", "Z"}, rgbz);
  write_float_exr(at("half.exr"), {"R", "G", "B", "Z"}, rgbz, OIIO::TypeDesc::HALF);
  write_float_exr(at("layer.exr"),
                  {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B", "ViewLayer.Depth.Z"},
                  rgbz);
  {
    // A valid header and its line offsets, then nothing: the pixel data is missing.
    std::ifstream whole(at("float.exr"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(whole)), std::istreambuf_iterator<char>());
    std::ofstream(at("cut.exr"), std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  }
  const std::vector<std::string> names = {"float.exr", "half.exr", "layer.exr"};
  std::vector<FaceData> classic;
  for (const std::string& name : names) {
    const auto face = load(make_database(name, name));
    ASSERT_TRUE(face.ok()) << face.status().to_string();
    classic.push_back(*face);
  }
  int core_before = 0, threads_before = 0;
  OIIO::getattribute("openexr:core", core_before);
  OIIO::getattribute("exr_threads", threads_before);
  configure_image_loading();
  for (size_t n = 0; n < names.size(); ++n) {
    const auto face = load(make_database(names[n], names[n]));
    ASSERT_TRUE(face.ok()) << names[n] << ": " << face.status().to_string();
    EXPECT_EQ(face->color.pixels, classic[n].color.pixels) << names[n];
    EXPECT_TRUE(
        std::equal(face->depth.begin(), face->depth.end(), classic[n].depth.begin(), classic[n].depth.end()))
        << names[n];
  }
  expect_error(load(make_database("cut.exr", "cut.exr")), ErrorCode::kBadInput,
               {"cell (0,0,0)", "face px", "cut.exr"});
  OIIO::attribute("openexr:core", core_before);
  OIIO::attribute("exr_threads", threads_before);
}

}  // namespace
}  // namespace svc
