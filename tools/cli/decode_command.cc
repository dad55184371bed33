// SPDX-License-Identifier: BSD-2-Clause
// svc decode: an .svc file back into an svc-input database (manifest.json, a PNG per
// face, its depth as an EXR when the file keeps depth, cameras copied), written beside
// the destination and moved there when complete.
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>

#include <OpenImageIO/imageio.h>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/command_line.h"
#include "command_line/output_paths.h"
#include "command_line/staged_folder.h"
#include "common/parallel.h"
#include "svc/reader.h"

namespace svc::cli {

namespace {

namespace fs = std::filesystem;

const char* const kDepthName = "depth-unknown.exr";

// A one-channel float EXR of eye-space depth (+infinity without geometry).
Status write_depth_exr(const fs::path& path, int width, int height, const std::vector<float>& depth) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + path.string());
  OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Z"};
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");  // no time stamp: the same file decodes to the same bytes
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, depth.data()) || !out->close()) {
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

// A depth image in which every pixel is background, for a file that keeps no depth.
Status write_unknown_depth(const fs::path& path, int width, int height) {
  return write_depth_exr(path, width, height,
                         std::vector<float>(static_cast<size_t>(width) * height,
                                            std::numeric_limits<float>::infinity()));
}

std::string depth_file(const CellEntry& cell, Face face, bool has_depth) {
  return has_depth ? cell_folder(cell.index) + "/" + face_name(face) + ".exr" : kDepthName;
}

json face_json(const CellEntry& cell, Face face, bool has_depth) {
  const Camera& camera = cell.cameras[static_cast<int>(face)];
  const Frustum& f = camera.frustum;
  return {{"color", cell_folder(cell.index) + "/" + face_name(face) + ".png"},
          {"depth", depth_file(cell, face, has_depth)},
          {"world_to_camera", camera.world_to_camera},
          {"projection",
           {{"left", f.left},
            {"right", f.right},
            {"bottom", f.bottom},
            {"top", f.top},
            {"near", f.near_plane},
            {"far", f.far_plane}}}};
}

struct DecodeResult {
  uint64_t faces = 0;
  std::vector<std::string> damaged;  // one message per face that failed to decode, in order
  std::vector<bool> complete;        // per selected cell: all selected faces decoded
  std::vector<bool> decoded;         // per selected cell and face, cell-major
};

// The manifest of the decoded database. With all six faces selected it lists the cells
// whose faces all decoded, so that svc encode takes it back; with some faces selected
// (--face), each cell with the faces that decoded: a database svc check accepts, of
// faces rather than whole cubes.
json manifest_json(const DecodeOptions& options, const FileInfo& info, const std::vector<const CellEntry*>& cells,
                   const std::vector<Face>& faces, const DecodeResult& result) {
  json manifest;
  manifest["format"] = "svc-input";
  manifest["version"] = 1;
  manifest["grid"] = {{"dims", info.grid_dims}, {"origin", info.grid_origin}, {"spacing", info.grid_spacing}};
  manifest["face_size"] = {info.face_width, info.face_height};
  manifest["depth"] = "eye_z";
  manifest["up_axis"] = std::string(1, info.up_axis);
  manifest["decoded_from"] = options.input.filename().string();
  json list = json::array();
  for (size_t c = 0; c < cells.size(); ++c) {
    if (faces.size() == kFaceCount && !result.complete[c]) continue;
    const CellEntry& cell = *cells[c];
    json faces_json = json::object();
    for (size_t f = 0; f < faces.size(); ++f) {
      if (result.decoded[c * faces.size() + f])
        faces_json[face_name(faces[f])] = face_json(cell, faces[f], info.has_depth);
    }
    if (faces_json.empty()) continue;
    list.push_back({{"index", {cell.index.x, cell.index.y, cell.index.z}},
                    {"position", cell.position},
                    {"faces", faces_json}});
  }
  manifest["cells"] = list;
  return manifest;
}

// Decodes the selected faces into `folder` on options.threads threads. A face that fails
// to decode is recorded and skipped; a failed write or an interrupt stops everything.
Result<DecodeResult> decode_faces(Reader& reader, const DecodeOptions& options,
                                  const std::vector<const CellEntry*>& cells, const std::vector<Face>& faces,
                                  const fs::path& folder) {
  for (const CellEntry* cell : cells) {
    std::error_code ec;
    fs::create_directories(folder / cell_folder(cell->index), ec);
    if (ec) return Status(ErrorCode::kIoError, "cannot create " + (folder / cell_folder(cell->index)).string());
  }
  const size_t total = cells.size() * faces.size();
  std::vector<Status> outcomes(total);
  std::mutex progress_mutex;
  uint64_t done = 0;
  ProgressBar bar("decoding", options.verbosity.show_progress());
  SVC_RETURN_IF_ERROR(parallel_for(total, resolve_thread_count(options.threads), [&](size_t i) -> Status {
    if (!keep_going()) return Status(ErrorCode::kCancelled, "decoding cancelled");
    const CellEntry& cell = *cells[i / faces.size()];
    const Face face = faces[i % faces.size()];
    auto image = reader.decode_face(cell.index, face);
    Result<std::vector<float>> depth = std::vector<float>{};
    if (image.ok() && reader.info().has_depth) depth = reader.decode_face_depth(cell.index, face);
    if (image.ok() && depth.ok()) {
      SVC_RETURN_IF_ERROR(
          write_png(folder / cell_folder(cell.index) / (std::string(face_name(face)) + ".png"), *image));
      if (reader.info().has_depth) {
        SVC_RETURN_IF_ERROR(write_depth_exr(folder / depth_file(cell, face, true), reader.info().face_width,
                                            reader.info().face_height, *depth));
      }
    } else {
      outcomes[i] = image.ok() ? depth.status() : image.status();
    }
    std::lock_guard<std::mutex> lock(progress_mutex);
    bar.update(++done, total);
    return Status::Ok();
  }));
  bar.finish();
  DecodeResult result;
  result.complete.assign(cells.size(), true);
  result.decoded.assign(total, false);
  for (size_t i = 0; i < total; ++i) {
    result.decoded[i] = outcomes[i].ok();
    if (outcomes[i].ok()) {
      ++result.faces;
    } else {
      result.damaged.push_back(outcomes[i].to_string());
      result.complete[i / faces.size()] = false;
    }
  }
  return result;
}

Result<std::vector<const CellEntry*>> selected_cells(Reader& reader, const DecodeOptions& options) {
  std::vector<const CellEntry*> selected;
  const auto& cells = reader.cells();
  if (!options.cell) {
    for (const CellEntry& cell : cells) selected.push_back(&cell);
    return selected;
  }
  const auto ordinal = reader.find_cell(*options.cell);
  if (!ordinal)
    return Status(ErrorCode::kNotFound, options.input.string() + " has no " + cell_label(*options.cell));
  selected.push_back(&cells[*ordinal]);
  return selected;
}

Status write_database(Reader& reader, const DecodeOptions& options, const std::vector<const CellEntry*>& cells,
                      const std::vector<Face>& faces, const fs::path& folder, DecodeResult* result) {
  const FileInfo& info = reader.info();
  if (!info.has_depth)
    SVC_RETURN_IF_ERROR(write_unknown_depth(folder / kDepthName, info.face_width, info.face_height));
  SVC_ASSIGN_OR_RETURN(*result, decode_faces(reader, options, cells, faces, folder));
  std::ofstream manifest(folder / "manifest.json");
  manifest << manifest_json(options, info, cells, faces, *result).dump(2) << "\n";
  manifest.close();
  if (!manifest) return Status(ErrorCode::kIoError, "cannot write " + (folder / "manifest.json").string());
  return Status::Ok();
}

}  // namespace

int decode_command(const DecodeOptions& options) {
  const Status writable = command_line::check_output(options.output, command_line::OutputKind::kFolder,
                                                     options.overwrite, {options.input});
  if (!writable.ok()) return report_error(writable);
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  auto cells = selected_cells(**reader, options);
  if (!cells.ok()) return report_error(cells.status());
  std::vector<Face> faces(kAllFaces.begin(), kAllFaces.end());
  if (options.face) faces = {*options.face};

  const auto start = std::chrono::steady_clock::now();
  if (options.verbosity.verbose) {
    std::fprintf(stderr, "svc: decoding %zu faces of %s on %d threads\n", cells->size() * faces.size(),
                 options.input.string().c_str(), resolve_thread_count(options.threads));
  }
  auto staged = command_line::StagedFolder::create(options.output);
  if (!staged.ok()) return report_error(staged.status());
  DecodeResult result;
  Status status = write_database(**reader, options, *cells, faces, (*staged)->path(), &result);
  if (status.ok()) status = (*staged)->commit();
  if (!status.ok()) return report_error(status);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  for (const std::string& message : result.damaged) std::fprintf(stderr, "svc: %s\n", message.c_str());
  if (options.verbosity.json) {
    print_json({{"command", "decode"},
                {"input", options.input.string()},
                {"output", options.output.string()},
                {"cells", cells->size()},
                {"faces", result.faces},
                {"damaged_faces", result.damaged},
                {"seconds", seconds}});
  } else if (options.verbosity.show_summary()) {
    std::printf("decoded %llu faces of %zu cells into %s in %.2f s\n",
                static_cast<unsigned long long>(result.faces), cells->size(), options.output.string().c_str(),
                seconds);
    if (faces.size() != kFaceCount) {
      std::printf(
          "  (one face per cell: svc check accepts the database, svc encode needs all six faces of a cell)\n");
    }
  }
  return result.damaged.empty() ? command_line::kExitOk : command_line::kExitCorrupt;
}

}  // namespace svc::cli
