// SPDX-License-Identifier: BSD-2-Clause
// load_manifest: parsing, validation and error messages of svc-input manifests.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "database/database.h"
#include "support/test_support.h"

namespace svc {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kWidth = 16;
constexpr int kHeight = 12;

void write_rgb_png(const fs::path& path, int width, int height) {
  fs::create_directories(path.parent_path());
  std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * 3, 128);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  ASSERT_TRUE(out->close());
}

void write_depth_exr(const fs::path& path, int width, int height) {
  fs::create_directories(path.parent_path());
  std::vector<float> depth(static_cast<size_t>(width) * height, 3.0f);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Z"};
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, depth.data()));
  ASSERT_TRUE(out->close());
}

// Column-major view matrix: rotation by `degrees` about +y, then translation t.
std::vector<double> view_matrix(double degrees, double tx, double ty, double tz) {
  const double a = degrees * 3.14159265358979323846 / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  // Rows: [c 0 s tx; 0 1 0 ty; -s 0 c tz; 0 0 0 1], listed column by column.
  return {c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, tx, ty, tz, 1};
}

// The full sources of a loaded manifest's cell, read again from the file.
CellSource cell_of(const DatabaseManifest& manifest, size_t ordinal) {
  Result<CellSource> cell = read_cell(manifest, ordinal);
  EXPECT_TRUE(cell.ok()) << cell.status().to_string();
  return cell.ok() ? std::move(cell).value() : CellSource{};
}

json face_entry(const std::string& color, const std::string& depth, double degrees) {
  return json{{"color", color}, {"depth", depth}, {"world_to_camera", view_matrix(degrees, 1, 2, 3)}};
}

json cell_entry(int x, int y, int z) {
  json faces = json::object();
  double degrees = 0;
  for (const Face face : kAllFaces) {
    faces[face_name(face)] = face_entry("cells/color.png", "cells/depth.exr", degrees);
    degrees += 10;
  }
  return json{{"index", {x, y, z}}, {"position", {x * 0.5 - 1.0, 1.5 + y, z * 0.5 + 0.25}}, {"faces", faces}};
}

// A 2x1x2 grid with cell (1,0,1) missing, cells listed out of order.
json valid_manifest() {
  return json{{"format", "svc-input"},
              {"version", 1},
              {"scene", "unit-test"},  // unknown keys are ignored
              {"grid", {{"dims", {2, 1, 2}}, {"origin", {-1.0, 1.5, 0.25}}, {"spacing", {0.5, 1.0, 0.5}}}},
              {"face_size", {kWidth, kHeight}},
              {"projection", {{"fov_y_degrees", 90.0}, {"near", 0.1}, {"far", 50.0}}},
              {"cells", {cell_entry(0, 0, 1), cell_entry(1, 0, 0), cell_entry(0, 0, 0)}}};
}

class ManifestTest : public ::testing::Test {
 protected:
  void SetUp() override {
    write_rgb_png(dir_.path() / "cells" / "color.png", kWidth, kHeight);
    write_depth_exr(dir_.path() / "cells" / "depth.exr", kWidth, kHeight);
  }

  void write_manifest_text(const std::string& text) {
    std::ofstream out(dir_.path() / "manifest.json", std::ios::binary);
    out << text;
  }
  void write_manifest(const json& manifest) { write_manifest_text(manifest.dump(2)); }

  // Writes the valid manifest after `mutate`, expects load_manifest to fail with `code`
  // and a message containing every string in `needles`.
  void expect_error(const std::function<void(json&)>& mutate, ErrorCode code,
                    const std::vector<std::string>& needles) {
    json manifest = valid_manifest();
    mutate(manifest);
    write_manifest(manifest);
    expect_load_error(code, needles);
  }

  void expect_load_error(ErrorCode code, const std::vector<std::string>& needles) {
    const auto result = load_manifest(dir_.path());
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), code) << result.status().to_string();
    for (const std::string& needle : needles) {
      EXPECT_NE(result.status().message().find(needle), std::string::npos)
          << "message lacks \"" << needle << "\": " << result.status().message();
    }
  }

  testing::TempDir dir_{"svc-database-manifest"};
};

TEST_F(ManifestTest, LoadsSparseGridSortedByYThenZThenX) {
  write_manifest(valid_manifest());
  const auto result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  const DatabaseManifest& m = *result;
  EXPECT_EQ(m.root, dir_.path());
  EXPECT_EQ(m.grid.dims, (std::array<int32_t, 3>{2, 1, 2}));
  EXPECT_EQ(m.grid.origin, (std::array<double, 3>{-1.0, 1.5, 0.25}));
  EXPECT_EQ(m.grid.spacing, (std::array<double, 3>{0.5, 1.0, 0.5}));
  EXPECT_EQ(m.face_width, kWidth);
  EXPECT_EQ(m.face_height, kHeight);
  EXPECT_EQ(m.depth_mode, DepthMode::kEyeZ);
  EXPECT_EQ(m.up_axis, UpAxis::kY);
  ASSERT_EQ(m.cells.size(), 3u);
  // z before x: (1,0,0) precedes (0,0,1).
  EXPECT_EQ(m.cells[0].index, (CellIndex{0, 0, 0}));
  EXPECT_EQ(m.cells[1].index, (CellIndex{1, 0, 0}));
  EXPECT_EQ(m.cells[2].index, (CellIndex{0, 0, 1}));
  EXPECT_EQ(m.cells[2].position, (std::array<double, 3>{-1.0, 1.5, 0.75}));

  EXPECT_EQ(find_cell(m, CellIndex{0, 0, 1}), std::optional<size_t>(2));
  EXPECT_EQ(find_cell(m, CellIndex{1, 0, 0}), std::optional<size_t>(1));
  EXPECT_EQ(find_cell(m, CellIndex{1, 0, 1}), std::nullopt);

  const CellSource first = cell_of(m, 0);
  EXPECT_EQ(first.index, (CellIndex{0, 0, 0}));
  const FaceSource& px = first.faces[static_cast<size_t>(Face::kPX)];
  EXPECT_EQ(px.color_path, "cells/color.png");
  EXPECT_EQ(px.depth_path, "cells/depth.exr");
  EXPECT_EQ(resolve_database_path(m, px.color_path), dir_.path() / "cells" / "color.png");
}

TEST_F(ManifestTest, ViewMatricesAreColumnMajor) {
  write_manifest(valid_manifest());
  const auto result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  // Face nx was written with a 10 degree rotation about y and translation (1,2,3).
  const Camera camera = cell_of(*result, 0).faces[static_cast<size_t>(Face::kNX)].camera;
  const auto& m = camera.world_to_camera;
  const auto at = [&](int row, int column) { return m[column * 4 + row]; };
  const double a = 10 * 3.14159265358979323846 / 180.0;
  EXPECT_DOUBLE_EQ(at(0, 0), std::cos(a));
  EXPECT_DOUBLE_EQ(at(0, 2), std::sin(a));
  EXPECT_DOUBLE_EQ(at(2, 0), -std::sin(a));
  EXPECT_DOUBLE_EQ(at(0, 3), 1.0);
  EXPECT_DOUBLE_EQ(at(1, 3), 2.0);
  EXPECT_DOUBLE_EQ(at(2, 3), 3.0);
  EXPECT_DOUBLE_EQ(at(3, 3), 1.0);
  EXPECT_DOUBLE_EQ(m[12], 1.0);  // translation lives in elements 12..14
}

TEST_F(ManifestTest, GlobalPerFaceAndExplicitProjections) {
  json manifest = valid_manifest();
  json& faces = manifest["cells"][2]["faces"];  // cell (0,0,0)
  faces["nx"]["projection"] = {{"fov_y_degrees", 60.0}, {"near", 0.5}, {"far", 20.0}};
  faces["py"]["projection"] = {{"left", -0.2}, {"right", 0.1}, {"bottom", -0.05},
                               {"top", 0.15},  {"near", 0.1},  {"far", 80.0}};
  write_manifest(manifest);
  const auto result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  const CellSource cell = cell_of(*result, 0);
  ASSERT_EQ(cell.index, (CellIndex{0, 0, 0}));

  const Frustum& global = cell.faces[static_cast<size_t>(Face::kPX)].camera.frustum;
  const double aspect = static_cast<double>(kWidth) / kHeight;
  EXPECT_NEAR(global.top, 0.1, 1e-12);  // near * tan(45 degrees)
  EXPECT_NEAR(global.bottom, -0.1, 1e-12);
  EXPECT_NEAR(global.right, 0.1 * aspect, 1e-12);
  EXPECT_NEAR(global.left, -0.1 * aspect, 1e-12);
  EXPECT_DOUBLE_EQ(global.near_plane, 0.1);
  EXPECT_DOUBLE_EQ(global.far_plane, 50.0);

  const Frustum& own = cell.faces[static_cast<size_t>(Face::kNX)].camera.frustum;
  EXPECT_NEAR(own.top, 0.5 * std::tan(30 * 3.14159265358979323846 / 180), 1e-12);
  EXPECT_NEAR(own.right, own.top * aspect, 1e-12);
  EXPECT_DOUBLE_EQ(own.near_plane, 0.5);
  EXPECT_DOUBLE_EQ(own.far_plane, 20.0);

  const Frustum& explicit_frustum = cell.faces[static_cast<size_t>(Face::kPY)].camera.frustum;
  EXPECT_DOUBLE_EQ(explicit_frustum.left, -0.2);
  EXPECT_DOUBLE_EQ(explicit_frustum.right, 0.1);
  EXPECT_DOUBLE_EQ(explicit_frustum.bottom, -0.05);
  EXPECT_DOUBLE_EQ(explicit_frustum.top, 0.15);
  EXPECT_DOUBLE_EQ(explicit_frustum.near_plane, 0.1);
  EXPECT_DOUBLE_EQ(explicit_frustum.far_plane, 80.0);

  // Other cells keep the global projection.
  EXPECT_DOUBLE_EQ(cell_of(*result, 1).faces[static_cast<size_t>(Face::kNX)].camera.frustum.far_plane, 50.0);
}

TEST_F(ManifestTest, PerFaceProjectionsWithoutGlobalProjection) {
  json manifest = valid_manifest();
  manifest.erase("projection");
  for (json& cell : manifest["cells"]) {
    for (auto& [name, face] : cell["faces"].items()) {
      face["projection"] = {{"fov_y_degrees", 90.0}, {"near", 0.2}, {"far", 10.0}};
    }
  }
  write_manifest(manifest);
  const auto result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  EXPECT_NEAR(cell_of(*result, 2).faces[5].camera.frustum.top, 0.2, 1e-12);

  manifest["cells"][0]["faces"].erase("nz");
  manifest["cells"][0]["faces"]["nz"] = face_entry("cells/color.png", "cells/depth.exr", 0);
  write_manifest(manifest);
  expect_load_error(ErrorCode::kBadInput, {"manifest.json", "cell (0,0,1)", "face nz", "projection"});
}

TEST_F(ManifestTest, OptionalSettingsAndAbsolutePaths) {
  json manifest = valid_manifest();
  manifest["depth"] = "radial";
  manifest["up_axis"] = "z";
  const std::string absolute = (dir_.path() / "cells" / "color.png").string();
  manifest["cells"][0]["faces"]["pz"]["color"] = absolute;
  manifest["cells"][0]["faces"]["pz"]["renderer_note"] = "ignored";
  write_manifest(manifest);
  // The manifest file itself may be named instead of its directory.
  const auto result = load_manifest(dir_.path() / "manifest.json");
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  EXPECT_EQ(result->root, dir_.path());
  EXPECT_EQ(result->depth_mode, DepthMode::kRadial);
  EXPECT_EQ(result->up_axis, UpAxis::kZ);
  const FaceSource pz = cell_of(*result, 2).faces[static_cast<size_t>(Face::kPZ)];
  EXPECT_EQ(pz.color_path, absolute);
  EXPECT_EQ(resolve_database_path(*result, pz.color_path), fs::path(absolute));
}

// A manifest from elsewhere must not pull arbitrary files into an .svc file: paths that
// leave the database folder are refused unless the caller allows them.
TEST_F(ManifestTest, PathsOutsideTheDatabaseNeedPermission) {
  const testing::TempDir elsewhere("svc-database-elsewhere");
  write_rgb_png(elsewhere.path() / "secret.png", kWidth, kHeight);
  const std::string absolute = (elsewhere.path() / "secret.png").string();
  const std::string climbing =
      (fs::path("cells") / ".." / ".." / elsewhere.path().filename() / "secret.png").string();
  for (const std::string& outside : {absolute, climbing}) {
    json manifest = valid_manifest();
    manifest["cells"][1]["faces"]["ny"]["color"] = outside;
    write_manifest(manifest);
    expect_load_error(ErrorCode::kBadInput, {"manifest.json", "cell (1,0,0)", "face ny", "color file", outside,
                                             "outside the database folder", "--allow-outside-paths"});
    const auto allowed = load_manifest(dir_.path(), ManifestOptions{.allow_outside_paths = true});
    ASSERT_TRUE(allowed.ok()) << allowed.status().to_string();
    const FaceSource ny = cell_of(*allowed, 1).faces[static_cast<size_t>(Face::kNY)];
    EXPECT_TRUE(fs::equivalent(resolve_database_path(*allowed, ny.color_path), elsewhere.path() / "secret.png"));
  }
  // ".." that stays inside the folder is fine.
  json manifest = valid_manifest();
  manifest["cells"][1]["faces"]["ny"]["depth"] = "cells/../cells/depth.exr";
  write_manifest(manifest);
  EXPECT_TRUE(load_manifest(dir_.path()).ok());
}

// A symbolic link inside the folder that resolves outside it (to a file, or a folder on
// the way) leaves the folder as "../x.png" does; a link that stays inside is fine.
TEST_F(ManifestTest, LinksLeadingOutsideTheDatabaseNeedPermission) {
  const testing::TempDir elsewhere("svc-database-linked");
  write_rgb_png(elsewhere.path() / "secret.png", kWidth, kHeight);
  fs::create_symlink(elsewhere.path() / "secret.png", dir_.path() / "cells" / "linked.png");
  fs::create_directory_symlink(elsewhere.path(), dir_.path() / "linked-folder");
  fs::create_symlink(dir_.path() / "cells" / "color.png", dir_.path() / "cells" / "inside.png");
  for (const std::string& outside : {std::string("cells/linked.png"), std::string("linked-folder/secret.png")}) {
    json manifest = valid_manifest();
    manifest["cells"][1]["faces"]["ny"]["color"] = outside;
    write_manifest(manifest);
    expect_load_error(ErrorCode::kBadInput, {"manifest.json", "cell (1,0,0)", "face ny", "color file", outside,
                                             "outside the database folder", "--allow-outside-paths"});
    EXPECT_TRUE(load_manifest(dir_.path(), ManifestOptions{.allow_outside_paths = true}).ok()) << outside;
  }
  json manifest = valid_manifest();
  manifest["cells"][1]["faces"]["ny"]["color"] = "cells/inside.png";
  write_manifest(manifest);
  EXPECT_TRUE(load_manifest(dir_.path()).ok());
}

TEST_F(ManifestTest, RejectsInvalidJsonWithPosition) {
  write_manifest_text("{\n  \"format\": \"svc-input\",\n  \"version\": 1,\n  \"grid\": [1, 2,\n}");
  expect_load_error(ErrorCode::kBadInput, {"manifest.json", "not valid JSON", "line 5"});
}

TEST_F(ManifestTest, RejectsNumberOverflowWithPosition) {
  std::string text = valid_manifest().dump(2);
  const std::string needle = "\"version\": 1";
  ASSERT_NE(text.find(needle), std::string::npos);
  text.replace(text.find(needle), needle.size(), "\"version\": 1e999");
  write_manifest_text(text);
  expect_load_error(ErrorCode::kBadInput, {"manifest.json", "not valid JSON", "line ", "1e999"});
}

TEST_F(ManifestTest, RejectsMissingDatabaseAndManifest) {
  const auto missing_dir = load_manifest(dir_.path() / "absent");
  ASSERT_FALSE(missing_dir.ok());
  EXPECT_EQ(missing_dir.status().code(), ErrorCode::kNotFound);
  EXPECT_NE(missing_dir.status().message().find("absent"), std::string::npos);
  expect_load_error(ErrorCode::kNotFound, {"manifest.json", "not found"});
}

TEST_F(ManifestTest, RejectsWrongFormatAndVersion) {
  expect_error([](json& m) { m["format"] = "svc-output"; }, ErrorCode::kBadInput,
               {"manifest.json", "format", "svc-output"});
  expect_error([](json& m) { m["version"] = 2; }, ErrorCode::kUnsupported, {"manifest.json", "version 2"});
  expect_error([](json& m) { m["version"] = "1"; }, ErrorCode::kBadInput, {"version", "expected an integer"});
  expect_error([](json& m) { m.erase("format"); }, ErrorCode::kBadInput, {"missing key \"format\""});
}

TEST_F(ManifestTest, RejectsMissingOrBadTopLevelKeys) {
  expect_error([](json& m) { m.erase("grid"); }, ErrorCode::kBadInput, {"missing key \"grid\""});
  expect_error([](json& m) { m["grid"].erase("spacing"); }, ErrorCode::kBadInput,
               {"grid", "missing key \"spacing\""});
  expect_error([](json& m) { m["grid"]["dims"] = {2, 0, 2}; }, ErrorCode::kBadInput, {"grid.dims", "positive"});
  expect_error([](json& m) { m["grid"]["dims"] = {2, 1.5, 2}; }, ErrorCode::kBadInput, {"grid.dims[1]", "integer"});
  expect_error([](json& m) { m["grid"]["dims"] = {4096, 4096, 4096}; }, ErrorCode::kLimitExceeded, {"grid.dims"});
  expect_error([](json& m) { m["face_size"] = {16}; }, ErrorCode::kBadInput, {"face_size", "expected 2 numbers"});
  expect_error([](json& m) { m["face_size"] = {16, -12}; }, ErrorCode::kBadInput, {"face_size", "positive"});
  expect_error([](json& m) { m["projection"]["far"] = 0.05; }, ErrorCode::kBadInput,
               {"projection.far", "greater than near"});
  expect_error([](json& m) { m["projection"]["fov_y_degrees"] = 180; }, ErrorCode::kBadInput,
               {"projection.fov_y_degrees"});
  expect_error([](json& m) { m["depth"] = "z_buffer"; }, ErrorCode::kBadInput, {"depth", "z_buffer"});
  expect_error([](json& m) { m["up_axis"] = "w"; }, ErrorCode::kBadInput, {"up_axis"});
  expect_error([](json& m) { m["cells"] = json::array(); }, ErrorCode::kBadInput, {"cells", "no cells"});
}

TEST_F(ManifestTest, RejectsCellOutsideGridAndDuplicates) {
  expect_error(
      [](json& m) {
        m["cells"][1]["index"] = {2, 0, 0};
      },
      ErrorCode::kBadInput, {"manifest.json", "cells[1]", "(2,0,0)", "outside the grid"});
  expect_error(
      [](json& m) {
        m["cells"][0]["index"] = {0, -1, 0};
      },
      ErrorCode::kBadInput, {"cells[0]", "outside the grid"});
  expect_error([](json& m) { m["cells"].push_back(cell_entry(1, 0, 0)); }, ErrorCode::kBadInput,
               {"manifest.json", "cell (1,0,0)", "listed twice", "cells[3]", "cells[1]"});
}

TEST_F(ManifestTest, RejectsMissingFaceAndFaceKeys) {
  expect_error([](json& m) { m["cells"][0]["faces"].erase("ny"); }, ErrorCode::kBadInput,
               {"manifest.json", "cell (0,0,1)", "missing face \"ny\""});
  expect_error([](json& m) { m["cells"][0]["faces"]["px"].erase("depth"); }, ErrorCode::kBadInput,
               {"manifest.json", "cell (0,0,1)", "face px", "missing key \"depth\""});
  expect_error([](json& m) { m["cells"][2]["faces"]["pz"].erase("world_to_camera"); }, ErrorCode::kBadInput,
               {"cell (0,0,0)", "face pz", "world_to_camera"});
  expect_error([](json& m) { m["cells"][1].erase("position"); }, ErrorCode::kBadInput,
               {"cell (1,0,0)", "missing key \"position\""});
  expect_error([](json& m) { m["cells"][1]["faces"]["nx"]["color"] = 7; }, ErrorCode::kBadInput,
               {"cell (1,0,0)", "face nx", "color", "expected a string"});
}

TEST_F(ManifestTest, RejectsMissingFilesNamingCellFaceAndFile) {
  expect_error([](json& m) { m["cells"][1]["faces"]["py"]["color"] = "cells/absent.png"; }, ErrorCode::kNotFound,
               {"manifest.json", "cell (1,0,0)", "face py", "color", "cells/absent.png"});
  expect_error([](json& m) { m["cells"][0]["faces"]["nz"]["depth"] = "elsewhere/absent.exr"; },
               ErrorCode::kNotFound, {"cell (0,0,1)", "face nz", "depth", "elsewhere/absent.exr", "not found"});
  expect_error([](json& m) { m["cells"][0]["faces"]["nz"]["depth"] = "cells"; }, ErrorCode::kNotFound,
               {"cell (0,0,1)", "face nz", "not a regular file"});
}

// Of two missing files, the one of the first cell in (y, z, x) order is reported, not the
// first one listed: the streamed parse reports what a whole-document parse did.
TEST_F(ManifestTest, ReportsTheMissingFileOfTheFirstCellInCellOrder) {
  expect_error(
      [](json& m) {
        m["cells"][0]["faces"]["px"]["color"] = "cells/listed-first.png";  // cell (0,0,1)
        m["cells"][2]["faces"]["nz"]["color"] = "cells/sorted-first.png";  // cell (0,0,0)
      },
      ErrorCode::kNotFound, {"cell (0,0,0)", "face nz", "cells/sorted-first.png"});
}

// The cells are read as a stream whatever the order of the keys; a repeated "cells" key
// means its last array, as for any repeated key.
TEST_F(ManifestTest, StreamsTheCellsWhereverTheyStandAndKeepsTheLastRepeatedKey) {
  const json manifest = valid_manifest();
  const std::string cells_first = manifest.dump();  // keys sorted: "cells" comes first
  ASSERT_EQ(cells_first.rfind("{\"cells\":", 0), 0u);
  const std::string lone_cell = json::array({cell_entry(1, 0, 1)}).dump();

  write_manifest_text("{\"cells\": " + lone_cell + ", " + cells_first.substr(1));
  auto result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  ASSERT_EQ(result->cells.size(), 3u);
  EXPECT_EQ(find_cell(*result, CellIndex{1, 0, 1}), std::nullopt);

  write_manifest_text(cells_first.substr(0, cells_first.size() - 1) + ", \"cells\": " + lone_cell + "}");
  result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  ASSERT_EQ(result->cells.size(), 1u);
  EXPECT_EQ(result->cells[0].index, (CellIndex{1, 0, 1}));
  EXPECT_EQ(cell_of(*result, 0).faces[static_cast<size_t>(Face::kNY)].color_path, "cells/color.png");
}

TEST_F(ManifestTest, VisitorSeesEveryCellOnceInListedOrder) {
  write_manifest(valid_manifest());
  std::vector<CellIndex> seen;
  const auto result = load_manifest(dir_.path(), {}, [&](const CellSource& cell, size_t listed_at, size_t listed) {
    EXPECT_EQ(listed_at, seen.size());
    EXPECT_EQ(listed, 3u);
    EXPECT_EQ(cell.faces[static_cast<size_t>(Face::kPZ)].depth_path, "cells/depth.exr");
    seen.push_back(cell.index);
    return Status::Ok();
  });
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  EXPECT_EQ(seen, (std::vector<CellIndex>{{0, 0, 1}, {1, 0, 0}, {0, 0, 0}}));

  const auto refused = load_manifest(dir_.path(), {}, [](const CellSource& cell, size_t, size_t) {
    return cell.index == CellIndex{1, 0, 0} ? Status(ErrorCode::kLimitExceeded, "no room for cell (1,0,0)")
                                            : Status::Ok();
  });
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(refused.status().message(), "no room for cell (1,0,0)");
}

// read_cell reads a cell's entry again; a manifest rewritten since it was loaded is
// noticed, not misread.
TEST_F(ManifestTest, ReadCellNoticesAManifestChangedSinceItWasLoaded) {
  write_manifest(valid_manifest());
  const auto result = load_manifest(dir_.path());
  ASSERT_TRUE(result.ok()) << result.status().to_string();
  for (size_t c = 0; c < result->cells.size(); ++c) EXPECT_EQ(cell_of(*result, c).index, result->cells[c].index);
  const auto out_of_range = read_cell(*result, 3);
  ASSERT_FALSE(out_of_range.ok());
  EXPECT_EQ(out_of_range.status().code(), ErrorCode::kInvalidArgument);

  json moved = valid_manifest();
  moved["a_note"] = "a key written before the cells, which moves every entry";
  write_manifest(moved);
  const auto changed = read_cell(*result, 1);
  ASSERT_FALSE(changed.ok());
  EXPECT_EQ(changed.status().code(), ErrorCode::kBadInput);
  for (const std::string needle : {"manifest.json", "cell (1,0,0)", "byte", "changed"}) {
    EXPECT_NE(changed.status().message().find(needle), std::string::npos) << changed.status().message();
  }
}

TEST_F(ManifestTest, RejectsBadViewMatrices) {
  // A number too large for a double cannot be represented; null stands for non-finite
  // values that some writers emit.
  expect_error([](json& m) { m["cells"][0]["faces"]["px"]["world_to_camera"][5] = nullptr; }, ErrorCode::kBadInput,
               {"cell (0,0,1)", "face px", "world_to_camera[5]", "number"});
  expect_error(
      [](json& m) {
        auto matrix = view_matrix(0, 1, 2, 3);
        matrix.pop_back();
        m["cells"][0]["faces"]["nx"]["world_to_camera"] = matrix;
      },
      ErrorCode::kBadInput, {"cell (0,0,1)", "face nx", "expected 16 numbers, got 15"});
  // Row-major by mistake: the translation lands in the last row.
  expect_error(
      [](json& m) {
        m["cells"][2]["faces"]["pz"]["world_to_camera"] =
            std::vector<double>{1, 0, 0, 1, 0, 1, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1};
      },
      ErrorCode::kBadInput, {"cell (0,0,0)", "face pz", "last row"});
  expect_error(
      [](json& m) {
        m["cells"][2]["faces"]["ny"]["world_to_camera"] =
            std::vector<double>{2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
      },
      ErrorCode::kBadInput, {"cell (0,0,0)", "face ny", "orthonormal"});
  expect_error([](json& m) { m["cells"][2]["faces"]["ny"]["world_to_camera"] = std::vector<double>(16, 0.0); },
               ErrorCode::kBadInput, {"cell (0,0,0)", "face ny"});
}

TEST_F(ManifestTest, RejectsBadPerFaceProjection) {
  expect_error(
      [](json& m) {
        m["cells"][1]["faces"]["px"]["projection"] = {{"left", 0.1}, {"right", -0.1}, {"bottom", -0.1},
                                                      {"top", 0.1},  {"near", 0.1},   {"far", 10.0}};
      },
      ErrorCode::kBadInput, {"cell (1,0,0)", "face px", "projection", "right must be greater"});
  expect_error(
      [](json& m) {
        m["cells"][1]["faces"]["px"]["projection"] = {{"left", -0.1}, {"right", 0.1}, {"near", 0.1}, {"far", 10.0}};
      },
      ErrorCode::kBadInput, {"cell (1,0,0)", "face px", "missing key \"bottom\""});
  expect_error(
      [](json& m) {
        m["cells"][1]["faces"]["px"]["projection"] = {{"near", 0.1}, {"far", 1.0}};
      },
      ErrorCode::kBadInput, {"cell (1,0,0)", "face px", "fov_y_degrees"});
}

}  // namespace
}  // namespace svc
