// SPDX-License-Identifier: BSD-2-Clause
// The sample-scene generator writes svc-input databases that are deterministic, follow
// docs/input-format.md, and whose color, depth and cameras agree geometrically.

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "scene/scene.h"
#include "support/test_support.h"

namespace svc::samples {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFaces[6] = {"px", "nx", "py", "ny", "pz", "nz"};

nlohmann::json read_manifest(const fs::path& dir) {
  return nlohmann::json::parse(testing::read_file_bytes(dir / "manifest.json"));
}

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<std::string> channel_names;
  OIIO::TypeDesc format;
  std::vector<float> pixels;
};

Image read_image(const fs::path& path) {
  Image image;
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) {
    ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
    return image;
  }
  const OIIO::ImageSpec& spec = in->spec();
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.channel_names = spec.channelnames;
  image.format = spec.format;
  image.pixels.resize(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) << path;
  in->close();
  return image;
}

glm::dmat4 view_matrix(const nlohmann::json& face) {
  std::vector<double> values = face.at("world_to_camera").get<std::vector<double>>();
  EXPECT_EQ(values.size(), 16u);
  values.resize(16);
  return glm::make_mat4(values.data());
}

// A generated database shared by the tests of one kind.
class SceneDatabase {
 public:
  SceneDatabase(SceneKind kind, std::array<int, 3> grid, int face_size) {
    options_.kind = kind;
    options_.grid = grid;
    options_.face_size = face_size;
    status_ = generate_scene(options_, dir_.path());
  }
  const Status& status() const { return status_; }
  const fs::path& path() const { return dir_.path(); }
  const SceneOptions& options() const { return options_; }

 private:
  testing::TempDir dir_{"svc-scene-db"};
  SceneOptions options_;
  Status status_;
};

TEST(SceneGenerate, SameOptionsGiveSameBytesWhateverTheThreadCount) {
  testing::TempDir first("svc-scene-a"), second("svc-scene-b");
  SceneOptions options;
  options.grid = {2, 1, 2};
  options.face_size = 32;
  options.seed = 7;
  int progress_calls = 0, last_done = 0, last_total = 0;
  ASSERT_TRUE(generate_scene(options, first.path(), [&](int done, int total) {
                ++progress_calls;
                last_done = done;
                last_total = total;
                return true;
              }).ok());
  EXPECT_EQ(progress_calls, 4);
  EXPECT_EQ(last_done, 4);
  EXPECT_EQ(last_total, 4);
  options.threads = 3;
  ASSERT_TRUE(generate_scene(options, second.path()).ok());

  EXPECT_EQ(testing::expect_identical_trees(first.path(), second.path()), 1 + 4 * 6 * 2);
}

TEST(SceneGenerate, SeedChangesTheScene) {
  SceneOptions options;
  options.grid = {1, 1, 1};
  options.face_size = 32;
  auto a = render_scene_face(options, CellIndex{0, 0, 0}, Face::kNY);
  options.seed = 2;
  auto b = render_scene_face(options, CellIndex{0, 0, 0}, Face::kNY);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_NE(a->color.pixels, b->color.pixels);
}

TEST(SceneGenerate, ManifestFollowsTheInputFormat) {
  SceneDatabase db(SceneKind::kHall, {3, 2, 2}, 16);
  ASSERT_TRUE(db.status().ok()) << db.status().to_string();
  const nlohmann::json m = read_manifest(db.path());
  EXPECT_EQ(m.at("format"), "svc-input");
  EXPECT_EQ(m.at("version"), 1);
  EXPECT_EQ(m.at("grid").at("dims"), nlohmann::json({3, 2, 2}));
  const auto origin = m.at("grid").at("origin").get<std::vector<double>>();
  const auto spacing = m.at("grid").at("spacing").get<std::vector<double>>();
  ASSERT_EQ(origin.size(), 3u);
  ASSERT_EQ(spacing.size(), 3u);
  EXPECT_DOUBLE_EQ(origin[1], 1.6);  // lowest layer at eye height
  EXPECT_EQ(m.at("face_size"), nlohmann::json({16, 16}));
  EXPECT_EQ(m.at("projection").at("fov_y_degrees"), 90.0);
  EXPECT_GT(m.at("projection").at("far").get<double>(), m.at("projection").at("near").get<double>());
  EXPECT_EQ(m.at("depth"), "eye_z");
  EXPECT_EQ(m.at("up_axis"), "y");

  const auto& cells = m.at("cells");
  ASSERT_EQ(cells.size(), 12u);
  std::map<std::vector<int>, int> seen;
  for (const auto& cell : cells) {
    const auto index = cell.at("index").get<std::vector<int>>();
    const auto position = cell.at("position").get<std::vector<double>>();
    ASSERT_EQ(index.size(), 3u);
    ++seen[index];
    for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(position[a], origin[a] + index[a] * spacing[a]);
    for (const char* name : kFaces) {
      const auto& face = cell.at("faces").at(name);
      EXPECT_TRUE(fs::exists(db.path() / face.at("color").get<std::string>()));
      EXPECT_TRUE(fs::exists(db.path() / face.at("depth").get<std::string>()));
      // The camera sits at the cell position: the view matrix maps it to the origin.
      const glm::dmat4 view = view_matrix(face);
      const glm::dvec4 eye = view * glm::dvec4(position[0], position[1], position[2], 1.0);
      EXPECT_NEAR(glm::length(glm::dvec3(eye)), 0.0, 1e-9) << name;
    }
  }
  EXPECT_EQ(seen.size(), 12u);
}

TEST(SceneGenerate, FaceCamerasFollowTheOrientationTable) {
  const double forward[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const double up[6][3] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  SceneOptions options;
  options.grid = {1, 1, 1};
  options.face_size = 4;
  for (int f = 0; f < 6; ++f) {
    auto face = render_scene_face(options, CellIndex{0, 0, 0}, static_cast<Face>(f));
    ASSERT_TRUE(face.ok()) << face.status().to_string();
    const glm::dmat4 view = glm::make_mat4(face->world_to_camera.data());
    // Camera -z is the viewing direction and +y the up vector (rows of the rotation).
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(-view[a][2], forward[f][a], 1e-12) << kFaces[f];
      EXPECT_NEAR(view[a][1], up[f][a], 1e-12) << kFaces[f];
    }
  }
}

TEST(SceneGenerate, ImagesHaveTheFaceSizeAndChannels) {
  SceneDatabase db(SceneKind::kHouse, {2, 1, 1}, 24);
  ASSERT_TRUE(db.status().ok()) << db.status().to_string();
  const nlohmann::json m = read_manifest(db.path());
  const auto& face = m.at("cells").at(0).at("faces").at("pz");
  const Image color = read_image(db.path() / face.at("color").get<std::string>());
  EXPECT_EQ(color.width, 24);
  EXPECT_EQ(color.height, 24);
  EXPECT_EQ(color.channels, 3);
  EXPECT_EQ(color.format, OIIO::TypeDesc::UINT8);
  const Image depth = read_image(db.path() / face.at("depth").get<std::string>());
  EXPECT_EQ(depth.width, 24);
  EXPECT_EQ(depth.height, 24);
  ASSERT_EQ(depth.channels, 1);
  EXPECT_EQ(depth.channel_names.at(0), "Z");
  EXPECT_EQ(depth.format, OIIO::TypeDesc::FLOAT);

  // What is on disk is what render_scene_face gives.
  auto rendered = render_scene_face(db.options(), CellIndex{0, 0, 0}, Face::kPZ);
  ASSERT_TRUE(rendered.ok());
  for (size_t i = 0; i < rendered->depth.size(); ++i) {
    ASSERT_EQ(depth.pixels[i], rendered->depth[i]) << i;
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(std::lround(color.pixels[i * 3 + c] * 255.0f), rendered->color.pixels[i * 3 + c]);
    }
  }
}

// Pixels of a face in one cell, lifted to world points by their depth and projected into
// the same face of a neighbouring cell, land on pixels of about the expected depth.
void expect_depth_reprojects(SceneKind kind) {
  SceneDatabase db(kind, {2, 1, 2}, 32);
  ASSERT_TRUE(db.status().ok()) << db.status().to_string();
  const nlohmann::json m = read_manifest(db.path());
  const int size = 32;
  int finite = 0, sky = 0;
  for (const auto& cell : m.at("cells")) {
    for (const char* name : kFaces) {
      const Image depth = read_image(db.path() / cell.at("faces").at(name).at("depth").get<std::string>());
      for (float z : depth.pixels) (std::isfinite(z) ? finite : sky)++;
    }
  }
  EXPECT_GT(finite, 0);
  EXPECT_GT(sky, 0) << "no sky visible anywhere in the " << scene_kind_name(kind);

  int checked = 0, agreed = 0;
  const auto& cells = m.at("cells");
  for (size_t a = 0; a < cells.size(); ++a) {
    for (size_t b = 0; b < cells.size(); ++b) {
      if (a == b) continue;
      for (const char* name : kFaces) {
        const auto& face_a = cells[a].at("faces").at(name);
        const auto& face_b = cells[b].at("faces").at(name);
        const Image depth_a = read_image(db.path() / face_a.at("depth").get<std::string>());
        const Image depth_b = read_image(db.path() / face_b.at("depth").get<std::string>());
        const glm::dmat4 camera_to_world_a = glm::inverse(view_matrix(face_a));
        const glm::dmat4 view_b = view_matrix(face_b);
        for (int j = 0; j < size; ++j) {
          for (int i = 0; i < size; ++i) {
            const double z = depth_a.pixels[j * size + i];
            if (!std::isfinite(z)) continue;
            const double x_ndc = (i + 0.5) / size * 2 - 1, y_ndc = 1 - (j + 0.5) / size * 2;
            const glm::dvec4 world = camera_to_world_a * glm::dvec4(x_ndc * z, y_ndc * z, -z, 1);
            const glm::dvec4 in_b = view_b * world;
            const double z_b = -in_b.z;
            if (z_b < 0.1) continue;
            const double xb = in_b.x / z_b, yb = in_b.y / z_b;
            // Keep away from the border so the target pixel exists.
            if (std::abs(xb) > 0.9 || std::abs(yb) > 0.9) continue;
            const int ib = static_cast<int>((xb + 1) / 2 * size);
            const int jb = static_cast<int>((1 - yb) / 2 * size);
            const double found = depth_b.pixels[jb * size + ib];
            ++checked;
            if (std::isfinite(found) && std::abs(found - z_b) < 0.03 + 0.05 * z_b) ++agreed;
          }
        }
      }
    }
  }
  ASSERT_GT(checked, 1000);
  // Occlusion and parallax at depth edges account for the rest.
  EXPECT_GT(static_cast<double>(agreed) / checked, 0.85)
      << agreed << " of " << checked << " reprojected pixels agree";
}

TEST(SceneGenerate, HallDepthReprojectsIntoNeighbouringCells) { expect_depth_reprojects(SceneKind::kHall); }

TEST(SceneGenerate, HouseDepthReprojectsIntoNeighbouringCells) { expect_depth_reprojects(SceneKind::kHouse); }

TEST(SceneGenerate, StreetDepthReprojectsIntoNeighbouringCells) { expect_depth_reprojects(SceneKind::kStreet); }

TEST(SceneGenerate, ColonnadeDepthReprojectsIntoNeighbouringCells) {
  expect_depth_reprojects(SceneKind::kColonnade);
}

TEST(SceneGenerate, PlazaDepthReprojectsIntoNeighbouringCells) { expect_depth_reprojects(SceneKind::kPlaza); }

TEST(SceneGenerate, SparseGridLeavesOutCellsInsideGeometry) {
  SceneOptions options;
  options.kind = SceneKind::kHall;
  options.grid = {9, 1, 9};
  options.face_size = 4;
  options.sparse = true;
  auto cells = describe_scene_cells(options);
  ASSERT_TRUE(cells.ok());
  int solid = 0;
  for (const auto& c : *cells) solid += c.inside_solid ? 1 : 0;
  EXPECT_GT(solid, 0) << "storage racks stand on some cell centres";

  testing::TempDir dir("svc-scene-sparse");
  ASSERT_TRUE(generate_scene(options, dir.path()).ok());
  const nlohmann::json m = read_manifest(dir.path());
  EXPECT_EQ(static_cast<int>(m.at("cells").size()), 81 - solid);
  for (const auto& cell : m.at("cells")) {
    const auto index = cell.at("index").get<std::vector<int>>();
    const auto& info = (*cells)[index[2] * 9 + index[0]];
    EXPECT_FALSE(info.inside_solid);
  }
  EXPECT_EQ(m.at("grid").at("dims"), nlohmann::json({9, 1, 9}));
}

TEST(SceneGenerate, HouseNeighboursLieInDifferentRoomsBehindWalls) {
  SceneOptions options;
  options.kind = SceneKind::kHouse;
  options.grid = {9, 1, 9};
  options.face_size = 16;
  auto cells = describe_scene_cells(options);
  ASSERT_TRUE(cells.ok());
  std::map<int, int> rooms;
  for (const auto& c : *cells) {
    EXPECT_GE(c.room, 0);
    ++rooms[c.room];
  }
  EXPECT_GE(rooms.size(), 4u);
  // Pairs of x-neighbours in different rooms; from the left one, looking +x, the centre
  // of the view is a wall closer than the neighbour unless a doorway is there.
  int pairs = 0, walls_seen = 0;
  for (int z = 0; z < 9; ++z) {
    for (int x = 0; x + 1 < 9; ++x) {
      if ((*cells)[z * 9 + x].room == (*cells)[z * 9 + x + 1].room) continue;
      ++pairs;
      auto face = render_scene_face(options, CellIndex{x, 0, z}, Face::kPX);
      ASSERT_TRUE(face.ok());
      if (face->depth[8 * 16 + 8] < options.spacing[0]) ++walls_seen;
    }
  }
  EXPECT_GT(pairs, 0);
  EXPECT_GT(walls_seen, 0);
}

TEST(SceneGenerate, AnyGridShapeWorks) {
  for (SceneKind kind : {SceneKind::kHall, SceneKind::kHouse}) {
    for (std::array<int, 3> grid : {std::array<int, 3>{1, 1, 1}, std::array<int, 3>{5, 1, 1},
                                    std::array<int, 3>{1, 1, 5}, std::array<int, 3>{2, 2, 2}}) {
      SceneOptions options;
      options.kind = kind;
      options.grid = grid;
      options.face_size = 8;
      testing::TempDir dir("svc-scene-shape");
      const Status status = generate_scene(options, dir.path());
      ASSERT_TRUE(status.ok()) << status.to_string();
      const nlohmann::json m = read_manifest(dir.path());
      EXPECT_EQ(static_cast<int>(m.at("cells").size()), grid[0] * grid[1] * grid[2]);
      // Cameras see the inside of the building: most of each face is finite depth.
      auto down = render_scene_face(options, CellIndex{0, grid[1] - 1, 0}, Face::kNY);
      ASSERT_TRUE(down.ok());
      for (float z : down->depth) EXPECT_TRUE(std::isfinite(z) && z > 0.5f && z < 5.0f);
    }
  }
}

// An eye at a cell's centre sees exactly what that cell sees: the scene is the one the
// grid describes, not one built around a grid of one cell (which differs).
TEST(SceneGenerate, EyeWritesOneCellOfTheGridsScene) {
  SceneOptions options;
  options.kind = SceneKind::kHouse;
  options.grid = {3, 1, 3};
  options.face_size = 16;
  auto cells = describe_scene_cells(options);
  ASSERT_TRUE(cells.ok());
  const std::array<double, 3> centre = (*cells)[4].position;  // cell (1, 0, 1)
  options.eye = centre;
  testing::TempDir dir("svc-scene-eye");
  ASSERT_TRUE(generate_scene(options, dir.path()).ok());
  const nlohmann::json m = read_manifest(dir.path());
  EXPECT_EQ(m.at("grid").at("dims"), nlohmann::json({1, 1, 1}));
  EXPECT_EQ(m.at("grid").at("origin"), nlohmann::json(centre));
  ASSERT_EQ(m.at("cells").size(), 1u);
  EXPECT_EQ(m.at("cells")[0].at("position"), nlohmann::json(centre));
  options.eye.reset();
  for (int f = 0; f < kFaceCount; ++f) {
    auto expected = render_scene_face(options, CellIndex{1, 0, 1}, static_cast<Face>(f));
    ASSERT_TRUE(expected.ok());
    const Image color =
        read_image(dir.path() / m.at("cells")[0].at("faces").at(kFaces[f]).at("color").get<std::string>());
    std::vector<uint8_t> written;
    for (float v : color.pixels) written.push_back(static_cast<uint8_t>(std::lround(v * 255)));
    EXPECT_EQ(written, expected->color.pixels) << kFaces[f];
  }
  // A grid of one cell at that point is another scene.
  options.grid = {1, 1, 1};
  options.origin = centre;
  auto alone = render_scene_face(options, CellIndex{0, 0, 0}, Face::kPX);
  options.grid = {3, 1, 3};
  options.origin.reset();
  auto in_grid = render_scene_face(options, CellIndex{1, 0, 1}, Face::kPX);
  ASSERT_TRUE(alone.ok() && in_grid.ok());
  EXPECT_NE(alone->color.pixels, in_grid->color.pixels);

  options.eye = std::array<double, 3>{0, NAN, 0};
  const Status bad = validate_scene_options(options);
  EXPECT_EQ(bad.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(bad.message().find("eye y"), std::string::npos) << bad.message();
}

TEST(SceneGenerate, RejectsBadOptionsNamingTheField) {
  testing::TempDir dir("svc-scene-bad");
  SceneOptions options;
  options.grid = {0, 1, 1};
  Status s = generate_scene(options, dir.path());
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("grid x"), std::string::npos) << s.message();
  EXPECT_FALSE(fs::exists(dir.path() / "manifest.json"));

  options = SceneOptions{};
  options.spacing = {0.5, -1.0, 0.5};
  s = validate_scene_options(options);
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("spacing y"), std::string::npos) << s.message();

  options = SceneOptions{};
  options.face_size = 2;
  EXPECT_EQ(validate_scene_options(options).code(), ErrorCode::kInvalidArgument);

  options = SceneOptions{};
  auto face = render_scene_face(options, CellIndex{9, 0, 0}, Face::kPX);
  EXPECT_FALSE(face.ok());
  EXPECT_EQ(face.status().code(), ErrorCode::kInvalidArgument);
}

TEST(SceneGenerate, UnwritableOutputIsAnIoErrorNamingThePath) {
  testing::TempDir dir("svc-scene-io");
  const fs::path blocker = dir.path() / "file";
  std::ofstream(blocker) << "x";
  SceneOptions options;
  options.grid = {1, 1, 1};
  options.face_size = 4;
  const Status s = generate_scene(options, blocker / "db");
  EXPECT_EQ(s.code(), ErrorCode::kIoError);
  EXPECT_NE(s.message().find("file"), std::string::npos) << s.message();
}

TEST(SceneGenerate, KindNamesRoundTrip) {
  SceneKind kind;
  ASSERT_TRUE(parse_scene_kind("house", &kind));
  EXPECT_EQ(kind, SceneKind::kHouse);
  EXPECT_STREQ(scene_kind_name(kind), "house");
  ASSERT_TRUE(parse_scene_kind("hall", &kind));
  EXPECT_STREQ(scene_kind_name(kind), "hall");
  EXPECT_FALSE(parse_scene_kind("castle", &kind));
}

}  // namespace
}  // namespace svc::samples
