// SPDX-License-Identifier: BSD-2-Clause
// manifest.json of an svc-input database: syntax, keys, ranges and the files it names.
#include "database/database.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <system_error>
#include <tuple>
#include <utility>

#include "database/json_stream.h"

namespace svc {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string in_quotes(const std::string& text) { return "\"" + text + "\""; }

// ---------------------------------------------------------------------------------------
// Manifest

// Reads the manifest's values, turning every problem into a kBadInput Status that names
// the manifest file and the place in it ("cells[3] (cell (1,0,2)), face px, depth").
class ManifestParser {
 public:
  explicit ManifestParser(std::string manifest_label) : label_(std::move(manifest_label)) {}

  Status error(const std::string& where, const std::string& what, ErrorCode code = ErrorCode::kBadInput) const {
    return Status(code, label_ + ": " + (where.empty() ? "" : where + ": ") + what);
  }

  Result<const json*> required(const json& object, const char* key, const std::string& where) const {
    const auto it = object.find(key);
    if (it == object.end()) return error(where, "missing key " + in_quotes(key));
    return &*it;
  }

  Status expect_object(const json& value, const std::string& where) const {
    if (!value.is_object()) return error(where, "expected an object, got " + std::string(value.type_name()));
    return Status::Ok();
  }

  Result<double> number(const json& value, const std::string& where) const {
    if (!value.is_number()) {
      return error(where, "expected a number, got " + std::string(value.type_name()));
    }
    const double v = value.get<double>();
    if (!std::isfinite(v)) return error(where, "number is not finite");
    return v;
  }

  // JSON has one number type; an integer is any number with an integral value in range.
  Result<int64_t> integer(const json& value, const std::string& where) const {
    if (!value.is_number()) {
      return error(where, "expected an integer, got " + std::string(value.type_name()));
    }
    if (value.is_number_integer()) {
      if (value.is_number_unsigned() &&
          value.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int32_t>::max())) {
        return error(where, "integer out of range");
      }
      const int64_t v = value.get<int64_t>();
      if (v < std::numeric_limits<int32_t>::min() || v > std::numeric_limits<int32_t>::max()) {
        return error(where, "integer out of range");
      }
      return v;
    }
    const double d = value.get<double>();
    if (!std::isfinite(d) || d != std::floor(d)) return error(where, "expected an integer");
    if (d < std::numeric_limits<int32_t>::min() || d > std::numeric_limits<int32_t>::max()) {
      return error(where, "integer out of range");
    }
    return static_cast<int64_t>(d);
  }

  Result<std::string> string(const json& value, const std::string& where) const {
    if (!value.is_string()) {
      return error(where, "expected a string, got " + std::string(value.type_name()));
    }
    return value.get<std::string>();
  }

  template <size_t N>
  Result<std::array<double, N>> numbers(const json& value, const std::string& where) const {
    SVC_RETURN_IF_ERROR(expect_array(value, N, where));
    std::array<double, N> out{};
    for (size_t i = 0; i < N; ++i) {
      SVC_ASSIGN_OR_RETURN(out[i], number(value[i], where + "[" + std::to_string(i) + "]"));
    }
    return out;
  }

  template <size_t N>
  Result<std::array<int64_t, N>> integers(const json& value, const std::string& where) const {
    SVC_RETURN_IF_ERROR(expect_array(value, N, where));
    std::array<int64_t, N> out{};
    for (size_t i = 0; i < N; ++i) {
      SVC_ASSIGN_OR_RETURN(out[i], integer(value[i], where + "[" + std::to_string(i) + "]"));
    }
    return out;
  }

 private:
  Status expect_array(const json& value, size_t size, const std::string& where) const {
    if (!value.is_array()) {
      return error(where, "expected an array of " + std::to_string(size) + " numbers, got " +
                              std::string(value.type_name()));
    }
    if (value.size() != size) {
      return error(where, "expected " + std::to_string(size) + " numbers, got " + std::to_string(value.size()));
    }
    return Status::Ok();
  }

  std::string label_;
};

std::string join(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

// A projection object: either {fov_y_degrees, near, far} or the glFrustum parameters.
Result<Frustum> parse_projection(const ManifestParser& p, const json& value, const std::string& where,
                                 double aspect) {
  SVC_RETURN_IF_ERROR(p.expect_object(value, where));
  const bool symmetric = value.contains("fov_y_degrees");
  const bool explicit_frustum = value.contains("left") || value.contains("right") || value.contains("bottom") ||
                                value.contains("top");
  if (symmetric && explicit_frustum) {
    return p.error(where, "give either fov_y_degrees or left/right/bottom/top, not both");
  }
  if (!symmetric && !explicit_frustum) {
    return p.error(where,
                   "missing key \"fov_y_degrees\" (or an explicit frustum with "
                   "\"left\", \"right\", \"bottom\", \"top\")");
  }
  double near_plane = 0, far_plane = 0;
  {
    SVC_ASSIGN_OR_RETURN(const json* n, p.required(value, "near", where));
    SVC_ASSIGN_OR_RETURN(near_plane, p.number(*n, join(where, "near")));
    SVC_ASSIGN_OR_RETURN(const json* f, p.required(value, "far", where));
    SVC_ASSIGN_OR_RETURN(far_plane, p.number(*f, join(where, "far")));
  }
  if (!(near_plane > 0)) return p.error(join(where, "near"), "must be positive");
  if (!(far_plane > near_plane)) {
    return p.error(join(where, "far"), "must be greater than near");
  }
  if (symmetric) {
    SVC_ASSIGN_OR_RETURN(const double fov, p.number(value["fov_y_degrees"], join(where, "fov_y_degrees")));
    if (!(fov > 0 && fov < 180)) {
      return p.error(join(where, "fov_y_degrees"), "must lie strictly between 0 and 180");
    }
    return symmetric_frustum(fov, aspect, near_plane, far_plane);
  }
  Frustum frustum;
  frustum.near_plane = near_plane;
  frustum.far_plane = far_plane;
  const std::pair<const char*, double*> sides[] = {{"left", &frustum.left},
                                                   {"right", &frustum.right},
                                                   {"bottom", &frustum.bottom},
                                                   {"top", &frustum.top}};
  for (const auto& [key, target] : sides) {
    SVC_ASSIGN_OR_RETURN(const json* v, p.required(value, key, where));
    SVC_ASSIGN_OR_RETURN(*target, p.number(*v, join(where, key)));
  }
  if (!(frustum.right > frustum.left)) return p.error(where, "right must be greater than left");
  if (!(frustum.top > frustum.bottom)) return p.error(where, "top must be greater than bottom");
  return frustum;
}

// An OpenGL view matrix: finite, affine (last row 0 0 0 1), rotation part orthonormal.
Result<std::array<double, 16>> parse_view_matrix(const ManifestParser& p, const json& value,
                                                 const std::string& where) {
  SVC_ASSIGN_OR_RETURN(const auto m, p.numbers<16>(value, where));
  // Column-major: element (row r, column c) is m[c * 4 + r].
  const auto at = [&](int r, int c) { return m[c * 4 + r]; };
  constexpr double kRowTolerance = 1e-6;
  if (std::abs(at(3, 0)) > kRowTolerance || std::abs(at(3, 1)) > kRowTolerance ||
      std::abs(at(3, 2)) > kRowTolerance || std::abs(at(3, 3) - 1) > kRowTolerance) {
    std::ostringstream row;
    row << at(3, 0) << " " << at(3, 1) << " " << at(3, 2) << " " << at(3, 3);
    return p.error(where, "last row is (" + row.str() +
                              "), a view matrix needs (0 0 0 1) (elements 3, 7, 11, 15 of the "
                              "column-major list)");
  }
  constexpr double kOrthoTolerance = 1e-3;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += at(a, k) * at(b, k);
      if (std::abs(dot - (a == b ? 1.0 : 0.0)) > kOrthoTolerance) {
        return p.error(where,
                       "rotation part is not orthonormal (a view matrix must be a rigid "
                       "transform: no scale, shear or singularity)");
      }
    }
  }
  return m;
}

struct ParsedCell {
  CellSource cell;
  size_t listed_at = 0;  // position in the manifest's "cells" array
};

Result<ParsedCell> parse_cell(const ManifestParser& p, const json& value, size_t ordinal, const GridSpec& grid,
                              const std::optional<Frustum>& global_projection, double aspect, bool allow_partial) {
  std::string where = "cells[" + std::to_string(ordinal) + "]";
  SVC_RETURN_IF_ERROR(p.expect_object(value, where));
  ParsedCell parsed;
  parsed.listed_at = ordinal;
  CellSource& cell = parsed.cell;

  SVC_ASSIGN_OR_RETURN(const json* index_json, p.required(value, "index", where));
  SVC_ASSIGN_OR_RETURN(const auto index, p.integers<3>(*index_json, join(where, "index")));
  for (int axis = 0; axis < 3; ++axis) {
    if (index[axis] < 0 || index[axis] >= grid.dims[axis]) {
      return p.error(where, "index (" + std::to_string(index[0]) + "," + std::to_string(index[1]) + "," +
                                std::to_string(index[2]) + ") lies outside the grid dims (" +
                                std::to_string(grid.dims[0]) + "," + std::to_string(grid.dims[1]) + "," +
                                std::to_string(grid.dims[2]) + ")");
    }
  }
  cell.index =
      CellIndex{static_cast<int32_t>(index[0]), static_cast<int32_t>(index[1]), static_cast<int32_t>(index[2])};
  where += " (" + cell_label(cell.index) + ")";

  SVC_ASSIGN_OR_RETURN(const json* position, p.required(value, "position", where));
  SVC_ASSIGN_OR_RETURN(cell.position, p.numbers<3>(*position, join(where, "position")));

  SVC_ASSIGN_OR_RETURN(const json* faces, p.required(value, "faces", where));
  SVC_RETURN_IF_ERROR(p.expect_object(*faces, join(where, "faces")));
  for (const Face face : kAllFaces) {
    const std::string name = face_name(face);
    const std::string face_where = where + ", face " + name;
    const auto it = faces->find(name);
    if (it == faces->end()) {
      if (!allow_partial) return p.error(where, "missing face " + in_quotes(name) + " in \"faces\"");
      cell.listed_faces &= static_cast<uint8_t>(~(1 << static_cast<int>(face)));
      continue;
    }
    const json& face_json = *it;
    SVC_RETURN_IF_ERROR(p.expect_object(face_json, face_where));
    FaceSource& source = cell.faces[static_cast<size_t>(face)];

    SVC_ASSIGN_OR_RETURN(const json* color, p.required(face_json, "color", face_where));
    SVC_ASSIGN_OR_RETURN(source.color_path, p.string(*color, face_where + ", color"));
    SVC_ASSIGN_OR_RETURN(const json* depth, p.required(face_json, "depth", face_where));
    SVC_ASSIGN_OR_RETURN(source.depth_path, p.string(*depth, face_where + ", depth"));
    if (source.color_path.empty()) return p.error(face_where + ", color", "empty file name");
    if (source.depth_path.empty()) return p.error(face_where + ", depth", "empty file name");

    SVC_ASSIGN_OR_RETURN(const json* view, p.required(face_json, "world_to_camera", face_where));
    SVC_ASSIGN_OR_RETURN(source.camera.world_to_camera,
                         parse_view_matrix(p, *view, face_where + ", world_to_camera"));

    const auto projection = face_json.find("projection");
    if (projection != face_json.end()) {
      SVC_ASSIGN_OR_RETURN(source.camera.frustum,
                           parse_projection(p, *projection, face_where + ", projection", aspect));
    } else if (global_projection) {
      source.camera.frustum = *global_projection;
    } else {
      return p.error(face_where,
                     "missing key \"projection\" (and the manifest has no global "
                     "\"projection\")");
    }
  }
  if (cell.listed_faces == 0) return p.error(join(where, "faces"), "lists none of the six faces");
  return parsed;
}

double aspect_of(const DatabaseManifest& manifest) {
  return static_cast<double>(manifest.face_width) / manifest.face_height;
}

// Whether `file` is `folder` or lies under it, comparing whole path elements.
bool lies_within(const fs::path& file, const fs::path& folder) {
  auto f = file.begin();
  for (auto r = folder.begin(); r != folder.end(); ++r, ++f) {
    if (r->empty()) continue;  // a trailing separator
    if (f == file.end() || *f != *r) return false;
  }
  return f != file.end();
}

// Whether a manifest path stays inside the database folder, both as written ("." and
// ".." resolved) and once symbolic links are followed: a link in the folder to a file
// or folder elsewhere leaves it as surely as "../x.png" does.
bool stays_inside_database(const DatabaseManifest& manifest, const std::string& path) {
  std::error_code ec;
  const fs::path file = resolve_database_path(manifest, path);
  if (!lies_within(fs::absolute(file, ec).lexically_normal(), fs::absolute(manifest.root, ec).lexically_normal())) {
    return false;
  }
  const fs::path real_root = fs::weakly_canonical(manifest.root, ec);
  if (ec) return false;
  const fs::path real_file = fs::weakly_canonical(file, ec);
  return !ec && lies_within(real_file, real_root);
}

// Refuses a path that leaves the database folder unless the caller allows it: a manifest
// from elsewhere must not pull arbitrary files of the machine into an .svc file.
Status check_inside_database(const std::string& manifest_label, const DatabaseManifest& manifest,
                             const CellSource& cell, Face face, const char* role, const std::string& path,
                             const ManifestOptions& options) {
  if (options.allow_outside_paths || stays_inside_database(manifest, path)) return Status::Ok();
  return Status(ErrorCode::kBadInput, manifest_label + ": " + cell_label(cell.index) + ", face " + face_name(face) +
                                          ": " + role + " file " + in_quotes(path) +
                                          " lies outside the database folder (allow it with "
                                          "--allow-outside-paths)");
}

// Checks that a file the manifest names exists; errors name cell, face and file.
Status check_file_exists(const std::string& manifest_label, const DatabaseManifest& manifest,
                         const CellSource& cell, Face face, const char* role, const std::string& path) {
  const fs::path resolved = resolve_database_path(manifest, path);
  std::error_code ec;
  const fs::file_status status = fs::status(resolved, ec);
  if (fs::is_regular_file(status)) return Status::Ok();
  const std::string what = fs::exists(status) ? "is not a regular file" : "not found";
  return Status(ErrorCode::kNotFound, manifest_label + ": " + cell_label(cell.index) + ", face " + face_name(face) +
                                          ": " + role + " file " + in_quotes(path) + " (" + resolved.string() +
                                          ") " + what);
}

// Opens manifest.json for a streamed read.
Result<std::ifstream> open_manifest(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) {
    return Status(ErrorCode::kNotFound, path.string() + ": not found");
  }
  if (!fs::is_regular_file(status)) {
    return Status(ErrorCode::kBadInput, path.string() + ": not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(ErrorCode::kIoError, path.string() + ": cannot open for reading");
  return in;
}

Status syntax_error(const std::string& label, std::istream& in, const JsonSyntaxError& error) {
  if (error.has_position) {
    return Status(ErrorCode::kBadInput, label + ": not valid JSON: " + error.message);
  }
  const auto [line, column] = line_and_column(in, error.offset);
  return Status(ErrorCode::kBadInput, label + ": not valid JSON near line " + std::to_string(line) + ", column " +
                                          std::to_string(column) + " (last token " + in_quotes(error.last_token) +
                                          "): " + error.message);
}

// Everything but the cells: format, version, grid, face size, projection, depth, up axis.
Status parse_header(const json& root_json, const ManifestParser& p, DatabaseManifest& manifest) {
  SVC_RETURN_IF_ERROR(p.expect_object(root_json, ""));

  SVC_ASSIGN_OR_RETURN(const json* format, p.required(root_json, "format", ""));
  SVC_ASSIGN_OR_RETURN(const std::string format_name, p.string(*format, "format"));
  if (format_name != "svc-input") {
    return p.error("format", in_quotes(format_name) + " is not \"svc-input\"");
  }
  SVC_ASSIGN_OR_RETURN(const json* version_json, p.required(root_json, "version", ""));
  SVC_ASSIGN_OR_RETURN(const int64_t version, p.integer(*version_json, "version"));
  if (version != 1) {
    return p.error("version",
                   "version " + std::to_string(version) + " is not supported (this reader reads version 1)",
                   ErrorCode::kUnsupported);
  }

  // grid
  SVC_ASSIGN_OR_RETURN(const json* grid, p.required(root_json, "grid", ""));
  SVC_RETURN_IF_ERROR(p.expect_object(*grid, "grid"));
  {
    SVC_ASSIGN_OR_RETURN(const json* dims_json, p.required(*grid, "dims", "grid"));
    SVC_ASSIGN_OR_RETURN(const auto dims, p.integers<3>(*dims_json, "grid.dims"));
    int64_t cell_count = 1;
    for (int axis = 0; axis < 3; ++axis) {
      if (dims[axis] <= 0) return p.error("grid.dims", "dimensions must be positive");
      cell_count *= dims[axis];  // each factor < 2^31 and the product is checked per step
      if (cell_count > kMaxGridCells) {
        return p.error("grid.dims", "grid has more than " + std::to_string(kMaxGridCells) + " cells",
                       ErrorCode::kLimitExceeded);
      }
      manifest.grid.dims[axis] = static_cast<int32_t>(dims[axis]);
    }
    SVC_ASSIGN_OR_RETURN(const json* origin, p.required(*grid, "origin", "grid"));
    SVC_ASSIGN_OR_RETURN(manifest.grid.origin, p.numbers<3>(*origin, "grid.origin"));
    SVC_ASSIGN_OR_RETURN(const json* spacing, p.required(*grid, "spacing", "grid"));
    SVC_ASSIGN_OR_RETURN(manifest.grid.spacing, p.numbers<3>(*spacing, "grid.spacing"));
    for (int axis = 0; axis < 3; ++axis) {
      // Spacing only matters along an axis with more than one cell.
      if (manifest.grid.dims[axis] > 1 && !(manifest.grid.spacing[axis] > 0)) {
        return p.error("grid.spacing",
                       "spacing must be positive along an axis with more than "
                       "one cell");
      }
    }
  }

  // face_size
  {
    SVC_ASSIGN_OR_RETURN(const json* size_json, p.required(root_json, "face_size", ""));
    SVC_ASSIGN_OR_RETURN(const auto size, p.integers<2>(*size_json, "face_size"));
    if (size[0] <= 0 || size[1] <= 0) return p.error("face_size", "width and height must be positive");
    if (size[0] > kMaxFaceSide || size[1] > kMaxFaceSide) {
      return p.error("face_size",
                     "faces larger than " + std::to_string(kMaxFaceSide) + " pixels a side are not accepted",
                     ErrorCode::kLimitExceeded);
    }
    manifest.face_width = static_cast<int>(size[0]);
    manifest.face_height = static_cast<int>(size[1]);
  }
  if (const auto it = root_json.find("projection"); it != root_json.end()) {
    SVC_ASSIGN_OR_RETURN(manifest.projection, parse_projection(p, *it, "projection", aspect_of(manifest)));
  }

  if (const auto it = root_json.find("depth"); it != root_json.end()) {
    SVC_ASSIGN_OR_RETURN(const std::string mode, p.string(*it, "depth"));
    if (mode == "eye_z") {
      manifest.depth_mode = DepthMode::kEyeZ;
    } else if (mode == "radial") {
      manifest.depth_mode = DepthMode::kRadial;
    } else {
      return p.error("depth", in_quotes(mode) + " is neither \"eye_z\" nor \"radial\"");
    }
  }
  if (const auto it = root_json.find("up_axis"); it != root_json.end()) {
    SVC_ASSIGN_OR_RETURN(const std::string axis, p.string(*it, "up_axis"));
    if (axis == "x") {
      manifest.up_axis = UpAxis::kX;
    } else if (axis == "y") {
      manifest.up_axis = UpAxis::kY;
    } else if (axis == "z") {
      manifest.up_axis = UpAxis::kZ;
    } else {
      return p.error("up_axis", in_quotes(axis) + " is not one of \"x\", \"y\", \"z\"");
    }
  }

  return Status::Ok();
}

Result<ParsedCell> parse_cell_safely(const ManifestParser& p, const json& element, size_t ordinal,
                                     const DatabaseManifest& manifest, bool allow_partial) {
  try {
    return parse_cell(p, element, ordinal, manifest.grid, manifest.projection, aspect_of(manifest), allow_partial);
  } catch (const json::exception& e) {
    // The parser checks every type before reading it; this is a safety net.
    return p.error("cells[" + std::to_string(ordinal) + "]", e.what());
  }
}

// The first failing file check of one face: files inside the database folder (unless
// allowed), then present.
Status check_face_files(const std::string& label, const DatabaseManifest& manifest, const CellSource& cell,
                        Face face, const ManifestOptions& options) {
  const FaceSource& source = cell.faces[static_cast<size_t>(face)];
  SVC_RETURN_IF_ERROR(check_inside_database(label, manifest, cell, face, "color", source.color_path, options));
  SVC_RETURN_IF_ERROR(check_inside_database(label, manifest, cell, face, "depth", source.depth_path, options));
  SVC_RETURN_IF_ERROR(check_file_exists(label, manifest, cell, face, "color", source.color_path));
  if (source.depth_path != source.color_path) {
    SVC_RETURN_IF_ERROR(check_file_exists(label, manifest, cell, face, "depth", source.depth_path));
  }
  return Status::Ok();
}

// The failing file checks of a cell's listed faces, face by face: all of them when
// options.file_problems collects them, else the first.
std::vector<FaceFileProblem> check_cell_files(const std::string& label, const DatabaseManifest& manifest,
                                              const CellSource& cell, const ManifestOptions& options) {
  std::vector<FaceFileProblem> problems;
  for (const Face face : kAllFaces) {
    if (!lists_face(cell.listed_faces, face)) continue;
    Status status = check_face_files(label, manifest, cell, face, options);
    if (status.ok()) continue;
    problems.push_back(FaceFileProblem{cell.index, face, std::move(status)});
    if (options.file_problems == nullptr) break;
  }
  return problems;
}

std::tuple<int32_t, int32_t, int32_t> cell_key(const CellIndex& c) { return std::make_tuple(c.y, c.z, c.x); }

// The second pass over the file: every cell parsed and checked as it streams past.
// Errors come in the order a whole-document parse gives them: the first bad entry in the
// list, then a cell listed twice, then the first bad file in cell order.
Status parse_cells(std::istream& in, int cells_array, size_t cells_listed, const ManifestParser& p,
                   const std::string& label, const ManifestOptions& options, const CellVisitor& visit_cell,
                   DatabaseManifest& manifest) {
  Status failed = Status::Ok();
  std::optional<std::pair<std::tuple<int32_t, int32_t, int32_t>, Status>> first_bad_file;
  const JsonElementHandler on_cell = [&](json& element, uint64_t offset, uint64_t size) {
    const size_t ordinal = manifest.cells.size();
    Result<ParsedCell> parsed = parse_cell_safely(p, element, ordinal, manifest, options.allow_partial_cells);
    if (parsed.ok() && visit_cell) {
      Status visited = visit_cell(parsed->cell, ordinal, cells_listed);
      if (!visited.ok()) parsed = std::move(visited);
    }
    if (!parsed.ok()) {
      failed = parsed.status();
      return false;
    }
    const CellSource& cell = parsed->cell;
    manifest.cells.push_back(
        ManifestCell{cell.index, static_cast<uint32_t>(ordinal), cell.position, offset, size, cell.listed_faces});
    const auto key = cell_key(cell.index);
    if (options.file_problems != nullptr) {
      for (FaceFileProblem& problem : check_cell_files(label, manifest, cell, options)) {
        options.file_problems->push_back(std::move(problem));
      }
    } else if (!first_bad_file || key < first_bad_file->first) {
      std::vector<FaceFileProblem> files = check_cell_files(label, manifest, cell, options);
      if (!files.empty()) first_bad_file.emplace(key, std::move(files.front().status));
    }
    return true;
  };
  in.clear();
  in.seekg(0);
  const StreamedJson streamed = stream_json(in, "cells", cells_array, on_cell);
  if (!failed.ok()) return failed;
  if (!streamed.syntax_ok) return syntax_error(label, in, streamed.syntax_error);  // the file changed meanwhile

  std::stable_sort(manifest.cells.begin(), manifest.cells.end(), [](const ManifestCell& a, const ManifestCell& b) {
    return cell_key(a.index) < cell_key(b.index);
  });
  for (size_t i = 1; i < manifest.cells.size(); ++i) {
    if (manifest.cells[i].index == manifest.cells[i - 1].index) {
      const size_t first = std::min(manifest.cells[i - 1].listed_at, manifest.cells[i].listed_at);
      const size_t second = std::max(manifest.cells[i - 1].listed_at, manifest.cells[i].listed_at);
      return p.error("cells[" + std::to_string(second) + "]", cell_label(manifest.cells[i].index) +
                                                                  " is listed twice (also at cells[" +
                                                                  std::to_string(first) + "])");
    }
  }
  if (options.file_problems != nullptr) {
    std::stable_sort(options.file_problems->begin(), options.file_problems->end(),
                     [](const FaceFileProblem& a, const FaceFileProblem& b) {
                       return std::make_pair(cell_key(a.cell), a.face) < std::make_pair(cell_key(b.cell), b.face);
                     });
  }
  if (first_bad_file) return first_bad_file->second;
  return Status::Ok();
}

}  // namespace

Frustum symmetric_frustum(double fov_y_degrees, double aspect, double near_plane, double far_plane) noexcept {
  constexpr double kPi = 3.14159265358979323846;
  Frustum f;
  f.near_plane = near_plane;
  f.far_plane = far_plane;
  f.top = near_plane * std::tan(fov_y_degrees * kPi / 360.0);
  f.bottom = -f.top;
  f.right = f.top * aspect;
  f.left = -f.right;
  return f;
}

std::filesystem::path resolve_database_path(const DatabaseManifest& manifest, const std::string& manifest_path) {
  const fs::path path(manifest_path);
  if (path.is_absolute()) return path;
  return manifest.root / path;
}

std::optional<size_t> find_cell(const DatabaseManifest& manifest, const CellIndex& index) {
  const auto it =
      std::lower_bound(manifest.cells.begin(), manifest.cells.end(), cell_key(index),
                       [&](const ManifestCell& cell, const auto& k) { return cell_key(cell.index) < k; });
  if (it == manifest.cells.end() || !(it->index == index)) return std::nullopt;
  return static_cast<size_t>(it - manifest.cells.begin());
}

Result<DatabaseManifest> load_manifest(const std::filesystem::path& db_dir, const ManifestOptions& options,
                                       const CellVisitor& visit_cell) {
  std::error_code ec;
  const fs::file_status status = fs::status(db_dir, ec);
  if (!fs::exists(status)) {
    return Status(ErrorCode::kNotFound, "database " + db_dir.string() + ": not found");
  }
  DatabaseManifest manifest;
  if (fs::is_directory(status)) {
    manifest.root = db_dir;
    manifest.manifest_file = db_dir / "manifest.json";
  } else {
    manifest.manifest_file = db_dir;
    manifest.root = db_dir.parent_path().empty() ? fs::path(".") : db_dir.parent_path();
  }
  SVC_ASSIGN_OR_RETURN(std::ifstream in, open_manifest(manifest.manifest_file));
  const std::string label = manifest.manifest_file.string();
  const ManifestParser p(label);
  // First pass: the syntax of the whole file (errors with their position, including a
  // number too large for a double, which nlohmann::json reports without one) and the
  // keys other than the cells, which may come after them.
  const StreamedJson outline = stream_json(in, "cells", 0, {});
  if (in.bad()) return Status(ErrorCode::kIoError, label + ": read failed");
  if (!outline.syntax_ok) return syntax_error(label, in, outline.syntax_error);
  try {
    SVC_RETURN_IF_ERROR(parse_header(outline.outline, p, manifest));
    SVC_ASSIGN_OR_RETURN(const json* cells, p.required(outline.outline, "cells", ""));
    if (!cells->is_array()) {
      return p.error("cells", "expected an array, got " + std::string(cells->type_name()));
    }
  } catch (const json::exception& e) {
    // The parser checks every type before reading it; this is a safety net.
    return Status(ErrorCode::kBadInput, label + ": " + e.what());
  }
  if (outline.last_array_size == 0) return p.error("cells", "the database lists no cells");
  manifest.cells.reserve(outline.last_array_size);
  // Second pass: the cells, one at a time; a repeated "cells" key means its last array.
  SVC_RETURN_IF_ERROR(
      parse_cells(in, outline.array_count, outline.last_array_size, p, label, options, visit_cell, manifest));
  if (in.bad()) return Status(ErrorCode::kIoError, label + ": read failed");
  return manifest;
}

Result<CellSource> read_cell(const DatabaseManifest& manifest, size_t cell_ordinal) {
  if (cell_ordinal >= manifest.cells.size()) {
    return Status(ErrorCode::kInvalidArgument, "cell ordinal " + std::to_string(cell_ordinal) +
                                                   " is out of range (" + std::to_string(manifest.cells.size()) +
                                                   " cells)");
  }
  const ManifestCell& entry = manifest.cells[cell_ordinal];
  const std::string label = manifest.manifest_file.string();
  const auto changed = [&] {
    return Status(ErrorCode::kBadInput, label + ": " + cell_label(entry.index) + ": its entry at byte " +
                                            std::to_string(entry.entry_offset) +
                                            " no longer reads as that cell (the file changed since it was read)");
  };
  SVC_ASSIGN_OR_RETURN(std::ifstream in, open_manifest(manifest.manifest_file));
  std::string text(entry.entry_size, '\0');
  in.seekg(static_cast<std::streamoff>(entry.entry_offset));
  if (!in.read(text.data(), static_cast<std::streamsize>(text.size()))) return changed();
  const json element = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (element.is_discarded()) return changed();
  const ManifestParser p(label);
  Result<ParsedCell> parsed = parse_cell_safely(p, element, entry.listed_at, manifest, /*allow_partial=*/true);
  if (!parsed.ok()) return parsed.status();
  if (!(parsed->cell.index == entry.index) || parsed->cell.listed_faces != entry.listed_faces) return changed();
  return std::move(parsed->cell);
}

}  // namespace svc
