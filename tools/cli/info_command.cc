// SPDX-License-Identifier: BSD-2-Clause
// svc info: what an .svc file holds: grid, coding settings, bytes by face type and by cell.
#include <charconv>
#include <cstdio>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "svc/reader.h"

namespace svc::cli {

namespace {

// "x,y,z", each the shortest text that reads back as the same double.
std::string triple_text(const std::array<double, 3>& v) {
  std::string out;
  for (int i = 0; i < 3; ++i) {
    char buf[32];
    const auto result = std::to_chars(buf, buf + sizeof buf, v[i]);
    if (i) out += ",";
    out.append(buf, result.ptr);
  }
  return out;
}

// A file encoded with --qindex records no quality (0): only its index is shown.
std::string coding_scale_text(const FileInfo& info) {
  const std::string scale = "quantizer index " + std::to_string(info.qindex);
  if (info.quality <= 0) return scale;
  return "quality " + std::to_string(info.quality) + ", " + scale;
}

const char* face_type_name(FaceType type) { return type == FaceType::kIntra ? "intra" : "predicted"; }

uint64_t cell_bytes(const CellEntry& cell) {
  uint64_t bytes = 0;
  for (const FaceEntry& face : cell.faces) bytes += face.coded_bytes;
  return bytes;
}

json info_json(const std::filesystem::path& input, const FileInfo& info, const std::vector<CellEntry>& cells,
               uint64_t raw) {
  json j;
  j["command"] = "info";
  j["input"] = input.string();
  j["format_version"] = std::to_string(info.format_major) + "." + std::to_string(info.format_minor);
  j["file_bytes"] = info.file_bytes;
  j["raw_bytes"] = raw;
  j["compression_ratio"] = info.file_bytes ? static_cast<double>(raw) / info.file_bytes : 0.0;
  j["grid"] = {{"dims", info.grid_dims}, {"origin", info.grid_origin}, {"spacing", info.grid_spacing}};
  j["face_size"] = {info.face_width, info.face_height};
  j["cells"] = cells.size();
  j["faces"] = cells.size() * kFaceCount;
  // A file encoded with an explicit quantizer scale has no quality.
  j["coding"] = {{"quality", info.quality > 0 ? json(info.quality) : json(nullptr)},
                 {"qindex", info.qindex},
                 {"i_spacing", info.i_spacing},
                 {"motion", info.motion}};
  j["depth"] = info.has_depth ? json{{"max_error", info.depth_max_error}, {"bytes", info.depth_bytes}}
                              : json(nullptr);
  j["face_types"] = {{"intra", face_type_stats_json(info.face_type_stats[0])},
                     {"predicted", face_type_stats_json(info.face_type_stats[1])}};
  json per_cell = json::array();
  for (const CellEntry& cell : cells) {
    json faces = json::object();
    for (Face face : kAllFaces) faces[face_name(face)] = cell.faces[static_cast<int>(face)].coded_bytes;
    per_cell.push_back({{"index", {cell.index.x, cell.index.y, cell.index.z}},
                        {"type", face_type_name(cell.faces[0].type)},
                        {"bytes", cell_bytes(cell)},
                        {"face_bytes", faces}});
  }
  j["per_cell"] = per_cell;
  return j;
}

// One row per cell: index, frame type, bytes of each face and of the cube.
void print_cell_table(const std::vector<CellEntry>& cells) {
  std::printf("  %-12s %-4s %8s %8s %8s %8s %8s %8s %9s\n", "cell", "type", "px", "nx", "py", "ny", "pz", "nz",
              "bytes");
  for (const CellEntry& cell : cells) {
    std::printf("  %-12s %-4s", cell_label(cell.index).substr(5).c_str(),
                cell.faces[0].type == FaceType::kIntra ? "I" : "B");
    for (const FaceEntry& face : cell.faces) std::printf(" %8u", static_cast<unsigned>(face.coded_bytes));
    std::printf(" %9llu\n", static_cast<unsigned long long>(cell_bytes(cell)));
  }
}

}  // namespace

int info_command(const InfoOptions& options) {
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  const FileInfo& info = (*reader)->info();
  const auto& cells = (*reader)->cells();
  uint64_t coded = 0;
  for (const CellEntry& cell : cells) coded += cell_bytes(cell);
  const uint64_t raw = uint64_t{3} * info.face_width * info.face_height * cells.size() * kFaceCount;
  if (options.verbosity.json) {
    print_json(info_json(options.input, info, cells, raw));
    return 0;
  }
  if (options.verbosity.quiet) return 0;
  std::printf("%s: svc format %u.%u, %s\n", options.input.string().c_str(), info.format_major, info.format_minor,
              human_bytes(info.file_bytes).c_str());
  std::printf("  grid      %d x %d x %d cells (%zu present), origin %s, spacing %s, up axis %c\n",
              info.grid_dims[0], info.grid_dims[1], info.grid_dims[2], cells.size(),
              triple_text(info.grid_origin).c_str(), triple_text(info.grid_spacing).c_str(), info.up_axis);
  std::printf("  faces     %d x %d pixels, %zu faces, raw RGB %s, compression %.1f:1\n", info.face_width,
              info.face_height, cells.size() * kFaceCount, human_bytes(raw).c_str(),
              info.file_bytes ? static_cast<double>(raw) / info.file_bytes : 0.0);
  std::printf("  coding    %s, I-cube spacing %d,%d,%d, motion from %s\n", coding_scale_text(info).c_str(),
              info.i_spacing[0], info.i_spacing[1], info.i_spacing[2], info.motion.c_str());
  if (info.has_depth) {
    std::printf("  depth     %s (%.1f%% of the file), maximum error %d (inverse-depth codes)\n",
                human_bytes(info.depth_bytes).c_str(),
                info.file_bytes ? 100.0 * static_cast<double>(info.depth_bytes) / info.file_bytes : 0.0,
                info.depth_max_error);
  }
  print_face_type_stats("I-faces", info.face_type_stats[0]);
  print_face_type_stats("B-faces", info.face_type_stats[1]);
  std::printf("  per cell  %.0f bytes on average\n",
              cells.empty() ? 0.0 : static_cast<double>(coded) / cells.size());
  print_cell_table(cells);
  return 0;
}

}  // namespace svc::cli
