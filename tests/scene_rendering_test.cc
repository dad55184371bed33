// SPDX-License-Identifier: BSD-2-Clause
// The corpus scene kinds (street, interior, colonnade, plaza) and the rendering settings
// users' renderers differ in: supersampled colour with one-sample depth, exposure and
// anisotropic texture filtering.

#include <cmath>
#include <numeric>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "support/test_support.h"

namespace svc::samples {
namespace {

constexpr SceneKind kCorpusKinds[] = {SceneKind::kStreet, SceneKind::kInterior, SceneKind::kColonnade,
                                      SceneKind::kPlaza};

double mean_of(const std::vector<uint8_t>& bytes) {
  return std::accumulate(bytes.begin(), bytes.end(), 0.0) / static_cast<double>(bytes.size());
}

SceneFace render(const SceneOptions& options, CellIndex cell, Face face) {
  auto rendered = render_scene_face(options, cell, face);
  EXPECT_TRUE(rendered.ok()) << rendered.status().to_string();
  return rendered.ok() ? *rendered : SceneFace{};
}

TEST(SceneKinds, EveryKindNameRoundTripsAndUnknownNamesAreRefused) {
  for (int k = 0; k < kSceneKinds; ++k) {
    SceneKind parsed;
    const SceneKind kind = static_cast<SceneKind>(k);
    ASSERT_TRUE(parse_scene_kind(scene_kind_name(kind), &parsed)) << scene_kind_name(kind);
    EXPECT_EQ(parsed, kind);
    EXPECT_NE(scene_kind_names().find(scene_kind_name(kind)), std::string::npos);
  }
  SceneKind parsed;
  EXPECT_FALSE(parse_scene_kind("castle", &parsed));
  SceneOptions options;
  options.kind = static_cast<SceneKind>(kSceneKinds);
  const Status refused = validate_scene_options(options);
  EXPECT_EQ(refused.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(refused.message().find("scene kind"), std::string::npos) << refused.message();
}

// At every spacing the corpus uses, no camera stands inside geometry, and the faces see
// both near geometry and sky (the plaza and street far more sky than the interior).
TEST(SceneKinds, CamerasStandInTheOpenAndSeeGeometryAndSky) {
  for (SceneKind kind : kCorpusKinds) {
    for (double spacing : {0.5, 2.0}) {
      SceneOptions options;
      options.kind = kind;
      options.grid = {9, 1, 9};
      options.spacing = {spacing, 1.0, spacing};
      options.face_size = 16;
      auto cells = describe_scene_cells(options);
      ASSERT_TRUE(cells.ok()) << cells.status().to_string();
      for (const SceneCellInfo& cell : *cells) {
        EXPECT_FALSE(cell.inside_solid)
            << scene_kind_name(kind) << " spacing " << spacing << " cell " << cell.index.x << "," << cell.index.z;
      }
      int geometry = 0, sky = 0;
      for (Face face : {Face::kPX, Face::kNX, Face::kPY, Face::kPZ, Face::kNZ}) {
        const SceneFace f = render(options, CellIndex{4, 0, 4}, face);
        for (float z : f.depth) (std::isinf(z) ? sky : geometry)++;
      }
      EXPECT_GT(geometry, 0) << scene_kind_name(kind);
      if (kind != SceneKind::kInterior) EXPECT_GT(sky, 0) << scene_kind_name(kind) << " shows no sky";
    }
  }
}

TEST(SceneKinds, SameOptionsGiveSameFacesAndTheSeedChangesThem) {
  for (SceneKind kind : kCorpusKinds) {
    SceneOptions options;
    options.kind = kind;
    options.grid = {3, 1, 3};
    options.face_size = 24;
    const SceneFace a = render(options, CellIndex{1, 0, 1}, Face::kPX);
    const SceneFace b = render(options, CellIndex{1, 0, 1}, Face::kPX);
    EXPECT_EQ(a.color.pixels, b.color.pixels) << scene_kind_name(kind);
    options.seed = 7;
    const SceneFace c = render(options, CellIndex{1, 0, 1}, Face::kPX);
    EXPECT_NE(a.color.pixels, c.color.pixels) << scene_kind_name(kind) << ": the seed changes nothing";
  }
}

// Supersampled colour keeps the depth of the one ray through the pixel centre, and
// changes colour only a little on average (edges and texture detail).
TEST(SceneRendering, SupersamplingAveragesColourAndKeepsOneSampleDepth) {
  SceneOptions options;
  options.kind = SceneKind::kStreet;
  options.grid = {3, 1, 3};
  options.face_size = 48;
  const SceneFace plain = render(options, CellIndex{1, 0, 1}, Face::kPX);
  options.supersample = 2;
  const SceneFace smooth = render(options, CellIndex{1, 0, 1}, Face::kPX);
  EXPECT_EQ(plain.depth, smooth.depth);
  EXPECT_NE(plain.color.pixels, smooth.color.pixels);
  EXPECT_NEAR(mean_of(plain.color.pixels), mean_of(smooth.color.pixels), 4.0);
  // Antialiasing lowers the summed luma steps across geometry edges.
  auto edge_energy = [](const ImageRGB8& image) {
    double sum = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 1; x < image.width; ++x) {
        const size_t i = (static_cast<size_t>(y) * image.width + x) * 3;
        sum += std::pow(std::abs(image.pixels[i + 1] - image.pixels[i - 2]), 2);
      }
    }
    return sum;
  };
  EXPECT_LT(edge_energy(smooth.color), edge_energy(plain.color));
}

TEST(SceneRendering, ExposureBrightensAndFilteringKeepsDepth) {
  SceneOptions options;
  options.kind = SceneKind::kColonnade;
  options.grid = {3, 1, 3};
  options.face_size = 32;
  const SceneFace base = render(options, CellIndex{1, 0, 1}, Face::kNX);
  options.exposure_stops = 1;
  const SceneFace bright = render(options, CellIndex{1, 0, 1}, Face::kNX);
  EXPECT_GT(mean_of(bright.color.pixels), mean_of(base.color.pixels) + 10);
  EXPECT_EQ(bright.depth, base.depth);
  options.exposure_stops = 0;
  options.anisotropic = true;
  const SceneFace sharp = render(options, CellIndex{1, 0, 1}, Face::kNY);  // the floor, seen at grazing angles
  const SceneFace soft = [&] {
    SceneOptions o = options;
    o.anisotropic = false;
    return render(o, CellIndex{1, 0, 1}, Face::kNY);
  }();
  EXPECT_EQ(sharp.depth, soft.depth);
  EXPECT_NE(sharp.color.pixels, soft.color.pixels);
}

TEST(SceneRendering, SettingsAreValidatedAndRecordedInTheManifest) {
  SceneOptions options;
  options.supersample = 5;
  Status s = validate_scene_options(options);
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("supersample"), std::string::npos) << s.message();
  options = SceneOptions{};
  options.exposure_stops = 9;
  s = validate_scene_options(options);
  EXPECT_NE(s.message().find("exposure"), std::string::npos) << s.message();
  options = SceneOptions{};
  options.texture_scale = 0;
  s = validate_scene_options(options);
  EXPECT_NE(s.message().find("texture scale"), std::string::npos) << s.message();

  testing::TempDir dir("svc-scene-settings");
  options = SceneOptions{};
  options.kind = SceneKind::kPlaza;
  options.grid = {2, 1, 2};
  options.face_size = 8;
  options.supersample = 2;
  options.exposure_stops = 0.5;
  options.anisotropic = true;
  ASSERT_TRUE(generate_scene(options, dir.path()).ok());
  const auto manifest = nlohmann::json::parse(testing::read_file_bytes(dir.path() / "manifest.json"));
  const auto& generator = manifest.at("generator");
  EXPECT_EQ(generator.at("kind"), "plaza");
  EXPECT_EQ(generator.at("supersample"), 2);
  EXPECT_EQ(generator.at("exposure_stops"), 0.5);
  EXPECT_EQ(generator.at("anisotropic"), true);
  EXPECT_FALSE(generator.contains("texture_scale"));  // left at its default
}

}  // namespace
}  // namespace svc::samples
