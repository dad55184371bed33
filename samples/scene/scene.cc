// SPDX-License-Identifier: BSD-2-Clause
#include "scene/scene.h"

#include <array>
#include <cmath>
#include <fstream>
#include <memory>
#include <system_error>
#include <thread>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "common/parallel.h"
#include "scene/scene_layout.h"
#include "scene/scene_photo.h"
#include "scene/scene_render.h"

namespace svc::samples {

namespace {

constexpr const char* kFaceNames[kFaceCount] = {"px", "nx", "py", "ny", "pz", "nz"};

std::string cell_dir_name(const CellIndex& c) {
  return std::to_string(c.x) + "_" + std::to_string(c.y) + "_" + std::to_string(c.z);
}

std::array<double, 16> to_array(const glm::dmat4& m) {
  std::array<double, 16> out{};
  for (int col = 0; col < 4; ++col) {
    for (int row = 0; row < 4; ++row) out[col * 4 + row] = m[col][row] + 0.0;  // no -0
  }
  return out;
}

Status write_color_png(const std::filesystem::path& path, int size, const uint8_t* rgb) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) {
    return Status(ErrorCode::kIoError, "no PNG writer for " + path.string() + ": " + OIIO::geterror());
  }
  // A bare spec: no date or software tags, so that the bytes depend on the pixels alone.
  OIIO::ImageSpec spec(size, size, 3, OIIO::TypeDesc::UINT8);
  // Fast zlib level: textured renders barely compress better at higher levels.
  spec.attribute("png:compressionLevel", 3);
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb) || !out->close()) {
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

Status write_depth_exr(const std::filesystem::path& path, int size, const float* depth) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) {
    return Status(ErrorCode::kIoError, "no OpenEXR writer for " + path.string() + ": " + OIIO::geterror());
  }
  OIIO::ImageSpec spec(size, size, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Z"};
  spec.attribute("compression", "zip");
  // The EXR writer stamps the current time unless given one; an empty stamp keeps the
  // bytes reproducible.
  spec.attribute("DateTime", "");
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, depth) || !out->close()) {
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

std::vector<SceneCellInfo> cell_infos(const SceneOptions& options, const detail::Scene& scene) {
  std::vector<SceneCellInfo> cells;
  cells.reserve(static_cast<size_t>(options.grid[0]) * options.grid[1] * options.grid[2]);
  for (int y = 0; y < options.grid[1]; ++y) {
    for (int z = 0; z < options.grid[2]; ++z) {
      for (int x = 0; x < options.grid[0]; ++x) {
        SceneCellInfo info;
        info.index = CellIndex{x, y, z};
        const detail::Vec3 p = scene.cell_position(x, y, z);
        info.position = {p.x, p.y, p.z};
        info.room = scene.room_at(p.x, p.z);
        info.inside_solid = scene.bvh.inside_any(p);
        cells.push_back(info);
      }
    }
  }
  return cells;
}

// The one cell of a database written with SceneOptions::eye.
std::vector<SceneCellInfo> eye_cell(const std::array<double, 3>& eye, const detail::Scene& scene) {
  SceneCellInfo info;
  info.position = eye;
  info.room = scene.room_at(eye[0], eye[2]);
  info.inside_solid = scene.bvh.inside_any(detail::Vec3(eye[0], eye[1], eye[2]));
  return {info};
}

detail::RenderSettings render_settings(const SceneOptions& options) {
  return {options.supersample, options.exposure_stops, options.anisotropic};
}

// The scene with its photographic textures when the options name a folder.
Result<detail::Scene> build_rendered_scene(const SceneOptions& options) {
  detail::Scene scene = detail::build_scene(options);
  if (!options.textures.empty()) {
    SVC_RETURN_IF_ERROR(
        detail::apply_photo_textures(options.textures, options.seed, options.texture_scale, &scene));
  }
  return scene;
}

}  // namespace

namespace {
constexpr std::array<const char*, kSceneKinds> kSceneKindNames = {"hall",     "house",     "street",
                                                                  "interior", "colonnade", "plaza"};
}  // namespace

const char* scene_kind_name(SceneKind kind) {
  const auto index = static_cast<size_t>(kind);
  return index < kSceneKindNames.size() ? kSceneKindNames[index] : "unknown";
}

bool parse_scene_kind(const std::string& name, SceneKind* out) {
  for (size_t k = 0; k < kSceneKindNames.size(); ++k) {
    if (name == kSceneKindNames[k]) {
      *out = static_cast<SceneKind>(k);
      return true;
    }
  }
  return false;
}

std::string scene_kind_names() {
  std::string out;
  for (const char* name : kSceneKindNames) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

Status validate_scene_options(const SceneOptions& options) {
  if (static_cast<int>(options.kind) >= kSceneKinds) {
    return Status(ErrorCode::kInvalidArgument, "scene kind " + std::to_string(static_cast<int>(options.kind)) +
                                                   " is none of " + scene_kind_names());
  }
  const char* axes[3] = {"x", "y", "z"};
  int64_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    if (options.grid[a] < 1 || options.grid[a] > 1024) {
      return Status(ErrorCode::kInvalidArgument, std::string("grid ") + axes[a] + " = " +
                                                     std::to_string(options.grid[a]) + " is outside 1..1024");
    }
    cells *= options.grid[a];
    if (!std::isfinite(options.spacing[a]) || options.spacing[a] <= 0 || options.spacing[a] > 100) {
      return Status(ErrorCode::kInvalidArgument, std::string("spacing ") + axes[a] + " = " +
                                                     std::to_string(options.spacing[a]) + " is outside (0, 100]");
    }
  }
  for (int a = 0; options.origin && a < 3; ++a) {
    if (!std::isfinite((*options.origin)[a]) || std::abs((*options.origin)[a]) > 1e6) {
      return Status(ErrorCode::kInvalidArgument, std::string("origin ") + axes[a] + " = " +
                                                     std::to_string((*options.origin)[a]) +
                                                     " is outside [-1e6, 1e6]");
    }
  }
  for (int a = 0; options.eye && a < 3; ++a) {
    if (!std::isfinite((*options.eye)[a]) || std::abs((*options.eye)[a]) > 1e6) {
      return Status(ErrorCode::kInvalidArgument, std::string("eye ") + axes[a] + " = " +
                                                     std::to_string((*options.eye)[a]) + " is outside [-1e6, 1e6]");
    }
  }
  if (cells > 1000000) {
    return Status(ErrorCode::kInvalidArgument, "grid has " + std::to_string(cells) + " cells, more than 1000000");
  }
  if (options.face_size < 4 || options.face_size > 8192) {
    return Status(ErrorCode::kInvalidArgument,
                  "face_size " + std::to_string(options.face_size) + " is outside 4..8192");
  }
  if (options.threads < 1 || options.threads > 256) {
    return Status(ErrorCode::kInvalidArgument, "threads " + std::to_string(options.threads) + " is outside 1..256");
  }
  if (options.supersample < 1 || options.supersample > 4) {
    return Status(ErrorCode::kInvalidArgument,
                  "supersample " + std::to_string(options.supersample) + " is outside 1..4");
  }
  if (!std::isfinite(options.exposure_stops) || std::abs(options.exposure_stops) > 4) {
    return Status(ErrorCode::kInvalidArgument,
                  "exposure " + std::to_string(options.exposure_stops) + " stops is outside [-4, 4]");
  }
  if (!std::isfinite(options.texture_scale) || options.texture_scale < 0.1 || options.texture_scale > 10) {
    return Status(ErrorCode::kInvalidArgument,
                  "texture scale " + std::to_string(options.texture_scale) + " is outside [0.1, 10]");
  }
  return Status::Ok();
}

std::array<double, 3> scene_grid_origin(const SceneOptions& options) {
  if (options.origin) return *options.origin;
  // Centred on the vertical axis of the scene, the lowest layer at eye height.
  constexpr double kEyeHeight = 1.6;
  return {-(options.grid[0] - 1) * options.spacing[0] / 2, kEyeHeight,
          -(options.grid[2] - 1) * options.spacing[2] / 2};
}

Result<std::vector<SceneCellInfo>> describe_scene_cells(const SceneOptions& options) {
  SVC_RETURN_IF_ERROR(validate_scene_options(options));
  const detail::Scene scene = detail::build_scene(options);
  return cell_infos(options, scene);
}

Result<SceneFace> render_scene_face(const SceneOptions& options, CellIndex cell, Face face) {
  SVC_RETURN_IF_ERROR(validate_scene_options(options));
  if (cell.x < 0 || cell.x >= options.grid[0] || cell.y < 0 || cell.y >= options.grid[1] || cell.z < 0 ||
      cell.z >= options.grid[2]) {
    return Status(ErrorCode::kInvalidArgument, cell_label(cell) + " is outside the grid");
  }
  const int face_index = static_cast<int>(face);
  if (face_index < 0 || face_index >= kFaceCount) {
    return Status(ErrorCode::kInvalidArgument, "face " + std::to_string(face_index) + " is not 0..5");
  }
  SVC_ASSIGN_OR_RETURN(const detail::Scene scene, build_rendered_scene(options));
  const detail::Vec3 eye = scene.cell_position(cell.x, cell.y, cell.z);
  const glm::dmat4 view = detail::face_view_matrix(eye, face_index);
  SceneFace out;
  const int n = options.face_size;
  out.color.width = n;
  out.color.height = n;
  out.color.pixels.resize(static_cast<size_t>(n) * n * 3);
  out.depth.resize(static_cast<size_t>(n) * n);
  detail::render_face(scene, eye, view, n, render_settings(options), out.color.pixels.data(), out.depth.data());
  out.world_to_camera = to_array(view);
  return out;
}

Status generate_scene(const SceneOptions& options, const std::filesystem::path& out_dir,
                      const SceneProgress& progress) {
  SVC_RETURN_IF_ERROR(validate_scene_options(options));
  SVC_ASSIGN_OR_RETURN(const detail::Scene scene, build_rendered_scene(options));
  std::vector<SceneCellInfo> cells = options.eye ? eye_cell(*options.eye, scene) : cell_infos(options, scene);
  if (options.sparse) {
    std::erase_if(cells, [](const SceneCellInfo& c) { return c.inside_solid; });
    if (cells.empty()) {
      return Status(ErrorCode::kInvalidArgument,
                    "every cell centre lies inside solid geometry; a sparse grid would be empty");
    }
  }

  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    return Status(ErrorCode::kIoError, "cannot create " + out_dir.string() + ": " + ec.message());
  }

  const int n = options.face_size;
  const size_t pixels = static_cast<size_t>(n) * n;
  // Per-face buffers reused across cells.
  std::vector<std::vector<uint8_t>> rgb(kFaceCount, std::vector<uint8_t>(pixels * 3));
  std::vector<std::vector<float>> depth(kFaceCount, std::vector<float>(pixels));

  nlohmann::ordered_json cells_json = nlohmann::ordered_json::array();
  const int total = static_cast<int>(cells.size());
  int done = 0;
  for (const SceneCellInfo& cell : cells) {
    const std::string rel_dir = "cells/" + cell_dir_name(cell.index);
    std::filesystem::create_directories(out_dir / rel_dir, ec);
    if (ec) {
      return Status(ErrorCode::kIoError, "cannot create " + (out_dir / rel_dir).string() + ": " + ec.message());
    }
    const detail::Vec3 eye(cell.position[0], cell.position[1], cell.position[2]);
    glm::dmat4 views[kFaceCount];
    for (int f = 0; f < kFaceCount; ++f) views[f] = detail::face_view_matrix(eye, f);

    // Each face is rendered and written by one worker; files and bytes do not depend on
    // which worker or in which order.
    SVC_RETURN_IF_ERROR(parallel_for(kFaceCount, options.threads, [&](size_t f) {
      detail::render_face(scene, eye, views[f], n, render_settings(options), rgb[f].data(), depth[f].data());
      const std::string stem = rel_dir + "/" + kFaceNames[f];
      Status s = write_color_png(out_dir / (stem + ".png"), n, rgb[f].data());
      if (s.ok()) s = write_depth_exr(out_dir / (stem + ".exr"), n, depth[f].data());
      return s.with_context(face_label(cell.index, static_cast<Face>(f)));
    }));

    nlohmann::ordered_json faces = nlohmann::ordered_json::object();
    for (int f = 0; f < kFaceCount; ++f) {
      const std::string stem = rel_dir + "/" + kFaceNames[f];
      nlohmann::ordered_json face;
      face["color"] = stem + ".png";
      face["depth"] = stem + ".exr";
      face["world_to_camera"] = to_array(views[f]);
      faces[kFaceNames[f]] = std::move(face);
    }
    nlohmann::ordered_json cell_json;
    cell_json["index"] = {cell.index.x, cell.index.y, cell.index.z};
    cell_json["position"] = cell.position;
    cell_json["faces"] = std::move(faces);
    cells_json.push_back(std::move(cell_json));
    ++done;
    if (progress && !progress(done, total)) {
      return Status(ErrorCode::kCancelled, "scene generation cancelled after " + std::to_string(done) + " cells");
    }
  }

  nlohmann::ordered_json manifest;
  manifest["format"] = "svc-input";
  manifest["version"] = 1;
  manifest["generator"] = {{"name", "svc-scene"},
                           {"kind", scene_kind_name(options.kind)},
                           {"seed", options.seed},
                           {"sparse", options.sparse}};
  // Written only when set, so that earlier scenes keep their manifests byte for byte.
  if (options.supersample != 1) manifest["generator"]["supersample"] = options.supersample;
  if (options.exposure_stops != 0) manifest["generator"]["exposure_stops"] = options.exposure_stops;
  if (options.anisotropic) manifest["generator"]["anisotropic"] = true;
  if (options.texture_scale != 1) manifest["generator"]["texture_scale"] = options.texture_scale;
  // The images used, relative to the texture folder: where it lies does not matter.
  if (!scene.texture_names.empty()) manifest["generator"]["textures"] = scene.texture_names;
  if (options.eye) {
    manifest["grid"] = {{"dims", {1, 1, 1}}, {"origin", *options.eye}, {"spacing", options.spacing}};
  } else {
    manifest["grid"] = {{"dims", options.grid},
                        {"origin", scene_grid_origin(options)},
                        {"spacing", options.spacing}};
  }
  manifest["face_size"] = {n, n};
  manifest["projection"] = {{"fov_y_degrees", kSceneFovYDegrees}, {"near", kSceneNear}, {"far", kSceneFar}};
  manifest["depth"] = "eye_z";
  manifest["up_axis"] = "y";
  manifest["cells"] = std::move(cells_json);

  const std::filesystem::path manifest_path = out_dir / "manifest.json";
  std::ofstream file(manifest_path, std::ios::binary | std::ios::trunc);
  file << manifest.dump(2) << '\n';
  file.close();
  if (!file) return Status(ErrorCode::kIoError, "cannot write " + manifest_path.string());
  return Status::Ok();
}

}  // namespace svc::samples
