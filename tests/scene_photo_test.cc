// SPDX-License-Identifier: BSD-2-Clause
// Photographic scenes: images from a folder the test writes reach the surfaces of their
// material class, the output stays deterministic, and bad folders are named in errors.

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "scene/scene_photo.h"
#include "support/test_support.h"

namespace svc::samples {
namespace {

namespace fs = std::filesystem;

struct Rgb {
  uint8_t r, g, b;
};

// A 64 x 64 image of 32-pixel blocks alternating between two colors; with an alpha
// value, the blocks of `b` get that alpha and `a` stays opaque.
void write_blocks(const fs::path& path, Rgb a, Rgb b, int alpha_b = -1) {
  constexpr int kSize = 64;
  const int channels = alpha_b >= 0 ? 4 : 3;
  std::vector<uint8_t> pixels(kSize * kSize * channels);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool second = ((x / 32) + (y / 32)) % 2;
      const Rgb c = second ? b : a;
      uint8_t* p = &pixels[(y * kSize + x) * channels];
      p[0] = c.r;
      p[1] = c.g;
      p[2] = c.b;
      if (channels == 4) p[3] = static_cast<uint8_t>(second ? alpha_b : 255);
    }
  }
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(kSize, kSize, channels, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  ASSERT_TRUE(out->close());
}

constexpr Rgb kRed{220, 30, 30}, kBlue{30, 30, 220}, kYellow{220, 220, 30}, kGrey{40, 40, 40};

// Brick in red and blue, floor tiles in yellow and grey, concrete green, a sky; the
// other classes fall back to any of them.
void write_texture_folder(const fs::path& dir) {
  fs::create_directories(dir / "set" / "skies");
  write_blocks(dir / "set" / "red_blue_brick.png", kRed, kBlue);
  write_blocks(dir / "set" / "floor_tile.png", kYellow, kGrey);
  write_blocks(dir / "set" / "concrete.png", {60, 160, 60}, {50, 140, 50});
  write_blocks(dir / "set" / "skies" / "clouds.png", {200, 210, 230}, {120, 150, 210});
}

// Pixels of `face` whose depth is within 1 cm of `depth`: a known plane.
std::vector<Rgb> pixels_at_depth(const SceneFace& face, double depth) {
  std::vector<Rgb> out;
  for (size_t i = 0; i < face.depth.size(); ++i) {
    if (std::abs(face.depth[i] - depth) < 0.01) {
      const uint8_t* p = &face.color.pixels[i * 3];
      out.push_back({p[0], p[1], p[2]});
    }
  }
  return out;
}

template <typename Pred>
int count_if(const std::vector<Rgb>& pixels, Pred pred) {
  int n = 0;
  for (const Rgb& p : pixels) n += pred(p) ? 1 : 0;
  return n;
}

bool reddish(const Rgb& p) { return p.r > 2 * p.b && p.r > 2 * p.g; }
bool bluish(const Rgb& p) { return p.b > 2 * p.r && p.b > 2 * p.g; }
bool yellowish(const Rgb& p) { return p.r > 2 * p.b && p.g > 2 * p.b; }

// A hall of 3 x 1 x 3 cells: the cell at x = 0 stands 4 m from the solid brick -x wall,
// 1.6 m above the tiled floor.
SceneOptions small_hall(const fs::path& textures) {
  SceneOptions options;
  options.grid = {3, 1, 3};
  options.face_size = 48;
  options.textures = textures;
  return options;
}

TEST(ScenePhoto, WallAndFloorShowTheImagesOfTheirClass) {
  testing::TempDir dir("svc-photo-tex");
  write_texture_folder(dir.path());
  const CellIndex cell{0, 0, 1};

  auto photo_wall = render_scene_face(small_hall(dir.path()), cell, Face::kNX);
  auto plain_wall = render_scene_face(small_hall({}), cell, Face::kNX);
  ASSERT_TRUE(photo_wall.ok()) << photo_wall.status().to_string();
  ASSERT_TRUE(plain_wall.ok());
  const auto wall = pixels_at_depth(*photo_wall, 4.0);
  ASSERT_GT(wall.size(), 200u);
  // Both block colors of the brick image, in about equal shares.
  EXPECT_GT(count_if(wall, reddish), static_cast<int>(wall.size() / 4));
  EXPECT_GT(count_if(wall, bluish), static_cast<int>(wall.size() / 4));
  // The procedural brick has no blue at all.
  const auto plain = pixels_at_depth(*plain_wall, 4.0);
  ASSERT_GT(plain.size(), 200u);
  EXPECT_EQ(count_if(plain, bluish), 0);

  auto photo_floor = render_scene_face(small_hall(dir.path()), cell, Face::kNY);
  ASSERT_TRUE(photo_floor.ok());
  const auto floor = pixels_at_depth(*photo_floor, 1.6);
  ASSERT_GT(floor.size(), 500u);
  EXPECT_GT(count_if(floor, yellowish), static_cast<int>(floor.size() / 4));
  EXPECT_EQ(count_if(floor, bluish), 0);  // not the brick image
}

// Red and blue texels alternating one by one: any pixel covering several texels must
// show their mix, never one of them alone.
void write_fine_checker(const fs::path& path) {
  constexpr int kSize = 256;
  std::vector<uint8_t> pixels(kSize * kSize * 3);
  for (int i = 0; i < kSize * kSize; ++i) {
    const Rgb c = (i % kSize + i / kSize) % 2 ? kBlue : kRed;
    pixels[i * 3] = c.r;
    pixels[i * 3 + 1] = c.g;
    pixels[i * 3 + 2] = c.b;
  }
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(kSize, kSize, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  ASSERT_TRUE(out->close());
}

TEST(ScenePhoto, TexelsFinerThanPixelsAreFilteredNotAliased) {
  testing::TempDir dir("svc-photo-fine");
  write_fine_checker(dir.path() / "floor_checker.png");
  auto face = render_scene_face(small_hall(dir.path()), CellIndex{0, 0, 1}, Face::kNY);
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  // The floor 1.6 m below: a pixel spans several of the 6 mm texels.
  const auto floor = pixels_at_depth(*face, 1.6);
  ASSERT_GT(floor.size(), 500u);
  EXPECT_EQ(count_if(floor, reddish), 0);
  EXPECT_EQ(count_if(floor, bluish), 0);
  EXPECT_EQ(count_if(floor, [](const Rgb& p) { return p.r > 20 && p.b > 20; }), static_cast<int>(floor.size()));
}

TEST(ScenePhoto, CutOutImagesAreNotUsedForSolidSurfaces) {
  testing::TempDir dir("svc-photo-cut");
  // The only brick candidate is a grate whose blue half is transparent: the brick walls
  // take another image instead.
  write_blocks(dir.path() / "brick_grate.png", kRed, kBlue, 0);
  write_blocks(dir.path() / "concrete.png", kYellow, kGrey);
  auto face = render_scene_face(small_hall(dir.path()), CellIndex{0, 0, 1}, Face::kNX);
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  const auto wall = pixels_at_depth(*face, 4.0);
  ASSERT_GT(wall.size(), 200u);
  EXPECT_EQ(count_if(wall, bluish), 0);
  EXPECT_EQ(count_if(wall, reddish), 0);
  EXPECT_GT(count_if(wall, yellowish), static_cast<int>(wall.size() / 4));

  // An opaque alpha channel is no obstacle.
  write_blocks(dir.path() / "brick_grate.png", kRed, kBlue, 255);
  face = render_scene_face(small_hall(dir.path()), CellIndex{0, 0, 1}, Face::kNX);
  ASSERT_TRUE(face.ok()) << face.status().to_string();
  EXPECT_GT(count_if(pixels_at_depth(*face, 4.0), bluish), static_cast<int>(wall.size() / 4));
}

TEST(ScenePhoto, SameOptionsAndFolderGiveSameBytesWhateverTheThreadCount) {
  testing::TempDir tex("svc-photo-tex"), first("svc-photo-a"), second("svc-photo-b");
  write_texture_folder(tex.path());
  for (SceneKind kind : {SceneKind::kHall, SceneKind::kHouse}) {
    SceneOptions options = small_hall(tex.path());
    options.kind = kind;
    options.grid = {2, 1, 2};
    options.face_size = 24;
    ASSERT_TRUE(generate_scene(options, first.path()).ok());
    options.threads = 3;
    ASSERT_TRUE(generate_scene(options, second.path()).ok());
    EXPECT_EQ(testing::expect_identical_trees(first.path(), second.path()), 1 + 4 * 6 * 2);

    // The manifest names the images used, relative to the folder.
    const auto manifest = nlohmann::json::parse(testing::read_file_bytes(first.path() / "manifest.json"));
    const auto names = manifest.at("generator").at("textures").get<std::vector<std::string>>();
    EXPECT_FALSE(names.empty());
    for (const std::string& name : names) EXPECT_TRUE(fs::exists(tex.path() / name)) << name;
    EXPECT_NE(std::find(names.begin(), names.end(), "set/skies/clouds.png"), names.end());
  }
}

TEST(ScenePhoto, MissingOrEmptyFolderIsAnErrorNamingIt) {
  testing::TempDir dir("svc-photo-bad");
  const fs::path out = dir.path() / "out";
  SceneOptions options = small_hall(dir.path() / "no-such-folder");
  Status s = generate_scene(options, out);
  EXPECT_EQ(s.code(), ErrorCode::kNotFound);
  EXPECT_NE(s.message().find("no-such-folder"), std::string::npos) << s.message();
  EXPECT_FALSE(fs::exists(out));

  fs::create_directories(dir.path() / "empty");
  std::ofstream(dir.path() / "empty" / "notes.txt") << "no images here";
  options.textures = dir.path() / "empty";
  s = generate_scene(options, out);
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("empty"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("no images"), std::string::npos) << s.message();
  EXPECT_FALSE(fs::exists(out));

  // Image names, but nothing that decodes.
  fs::create_directories(dir.path() / "broken");
  std::ofstream(dir.path() / "broken" / "brick.jpg") << "not a jpeg";
  options.textures = dir.path() / "broken";
  auto face = render_scene_face(options, CellIndex{0, 0, 0}, Face::kPX);
  ASSERT_FALSE(face.ok());
  EXPECT_NE(face.status().message().find("broken"), std::string::npos) << face.status().message();
  EXPECT_NE(face.status().message().find("no usable image"), std::string::npos);
}

TEST(ScenePhoto, CandidatesFollowTheClassWordsAndSkipLightMaps) {
  const std::vector<std::string> files = {"a/brick1.jpg", "a/brick1_lm.jpg", "a/brick2.tga", "b/oak_wood.jpg",
                                          "b/sky_glow.png"};
  const auto bricks = detail::texture_candidates(files, detail::TextureClass::kBrick, 1);
  EXPECT_EQ(std::set<std::string>(bricks.begin(), bricks.end()),
            (std::set<std::string>{"a/brick1.jpg", "a/brick2.tga"}));
  // No sky image left once the glow layer is skipped: every usable file is a candidate.
  const auto sky = detail::texture_candidates(files, detail::TextureClass::kSky, 1);
  EXPECT_EQ(sky.size(), 3u);
  // The order depends on the seed but not on the order files were listed in.
  std::vector<std::string> reversed(files.rbegin(), files.rend());
  EXPECT_EQ(detail::texture_candidates(reversed, detail::TextureClass::kSky, 1), sky);
}

// The OpenArena set, where the package is installed: a few of its folders extracted.
TEST(ScenePhoto, OpenArenaTexturesReachTheWalls) {
  const fs::path archive = "/usr/share/games/openarena/baseoa/pak4-textures.pk3";
  if (!fs::exists(archive)) GTEST_SKIP() << "openarena-081-textures is not installed";
  if (std::system("command -v unzip >/dev/null") != 0) GTEST_SKIP() << "unzip is not installed";
  testing::TempDir dir("svc-photo-oa");
  const std::string command = "unzip -q " + archive.string() +
                              " 'textures/oquartz/*' 'textures/skies/*' 'textures/base_floor/*' -d " +
                              dir.path().string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  const CellIndex cell{0, 0, 1};
  auto photo = render_scene_face(small_hall(dir.path()), cell, Face::kNX);
  auto plain = render_scene_face(small_hall({}), cell, Face::kNX);
  ASSERT_TRUE(photo.ok()) << photo.status().to_string();
  ASSERT_TRUE(plain.ok());
  const auto a = pixels_at_depth(*photo, 4.0), b = pixels_at_depth(*plain, 4.0);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 200u);
  double difference = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    difference += std::abs(a[i].r - b[i].r) + std::abs(a[i].g - b[i].g) + std::abs(a[i].b - b[i].b);
  }
  EXPECT_GT(difference / (3.0 * a.size()), 4.0) << "the wall looks procedural";
}

}  // namespace
}  // namespace svc::samples

namespace svc::samples {
namespace {

// Normal, specular, gloss and height maps shipped beside the colour images are no
// candidates for any surface.
TEST(ScenePhoto, SurfaceMapsBesideColourImagesAreSkipped) {
  const std::vector<std::string> files = {"w/wall01.png",    "w/wall01_nm.png", "w/wall01_SM.png",
                                          "w/wall01_gm.jpg", "w/wall01_hm.tga", "w/wall_smooth.png"};
  const auto walls = detail::texture_candidates(files, detail::TextureClass::kWall, 1);
  EXPECT_EQ(std::set<std::string>(walls.begin(), walls.end()),
            (std::set<std::string>{"w/wall01.png", "w/wall_smooth.png"}));
}

// Hidden folders (an interrupted extraction's staging folder, a desktop's metadata) are
// no part of the set, so they cannot change which images a scene takes.
TEST(ScenePhoto, HiddenEntriesAreNotListed) {
  testing::TempDir dir("svc-photo-hidden");
  write_texture_folder(dir.path());
  const auto before = detail::list_texture_files(dir.path());
  ASSERT_TRUE(before.ok());
  fs::create_directories(dir.path() / ".textures-staging" / "set");
  write_blocks(dir.path() / ".textures-staging" / "set" / "brick.png", kRed, kRed);
  write_blocks(dir.path() / "set" / ".hidden_brick.png", kBlue, kBlue);
  const auto after = detail::list_texture_files(dir.path());
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(*after, *before);
}

// A folder with no image named for the sky keeps the procedural sky instead of putting a
// wall or floor image over it.
TEST(ScenePhoto, FolderWithoutSkyImagesKeepsTheProceduralSky) {
  testing::TempDir dir("svc-photo-nosky");
  write_texture_folder(dir.path());
  fs::remove_all(dir.path() / "set" / "skies");
  const CellIndex cell{1, 0, 1};
  auto photo = render_scene_face(small_hall(dir.path()), cell, Face::kPY);
  auto plain = render_scene_face(small_hall({}), cell, Face::kPY);
  ASSERT_TRUE(photo.ok()) << photo.status().to_string();
  ASSERT_TRUE(plain.ok());
  int sky = 0;
  for (size_t i = 0; i < photo->depth.size(); ++i) {
    if (!std::isinf(photo->depth[i])) continue;
    ++sky;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(photo->color.pixels[i * 3 + c], plain->color.pixels[i * 3 + c]) << i;
  }
  EXPECT_GT(sky, 0) << "the skylights show no sky";
}

}  // namespace
}  // namespace svc::samples
