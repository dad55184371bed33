#include "cli/commands.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.h"
#include "command_line/command_line.h"
#include "command_line/output_paths.h"
#include "common/file_io.h"
#include "common/parallel.h"
#include "scene/scene.h"
#include "svc/encoder.h"
#include "svc/metrics.h"
#include "svc/reader.h"

namespace svc::cli {

using command_line::check_output;
using command_line::OutputKind;

namespace {

using json = nlohmann::ordered_json;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

json frame_stats_json(const FaceTypeStats& s) {
  json j;
  j["faces"] = s.faces;
  j["bytes"] = s.bytes;
  j["macroblocks"] = {{"intra", s.mb_intra},
                      {"forward", s.mb_forward},
                      {"backward", s.mb_backward},
                      {"bidirectional", s.mb_bidirectional},
                      {"skipped", s.mb_skipped}};
  j["mean_unique_candidates_per_macroblock"] =
      s.candidate_macroblocks ? static_cast<double>(s.candidate_vectors) / s.candidate_macroblocks : 0.0;
  return j;
}

json summary_json(const EncodeSummary& s, const std::filesystem::path& out) {
  json j;
  j["output"] = out.string();
  j["cells"] = s.cells;
  j["faces"] = s.faces;
  j["raw_bytes"] = s.raw_bytes;
  j["file_bytes"] = s.file_bytes;
  j["compression_ratio"] = s.file_bytes ? static_cast<double>(s.raw_bytes) / s.file_bytes : 0.0;
  j["qindex"] = s.qindex;
  j["seconds"] = s.seconds;
  j["intra"] = frame_stats_json(s.intra);
  j["predicted"] = frame_stats_json(s.predicted);
  return j;
}

void print_frame_stats(const char* name, const FaceTypeStats& s) {
  if (s.faces == 0) return;
  std::printf("  %-9s %6llu faces  %10s", name, static_cast<unsigned long long>(s.faces),
              human_bytes(s.bytes).c_str());
  const uint64_t mbs = s.mb_intra + s.mb_forward + s.mb_backward + s.mb_bidirectional + s.mb_skipped;
  if (mbs > 0 && (s.mb_forward + s.mb_backward + s.mb_bidirectional + s.mb_skipped) > 0) {
    std::printf("  macroblocks: intra %llu, forward %llu, backward %llu, bidirectional %llu, skipped %llu",
                static_cast<unsigned long long>(s.mb_intra), static_cast<unsigned long long>(s.mb_forward),
                static_cast<unsigned long long>(s.mb_backward), static_cast<unsigned long long>(s.mb_bidirectional),
                static_cast<unsigned long long>(s.mb_skipped));
    if (s.candidate_macroblocks) {
      std::printf("; %.2f unique candidates/macroblock",
                  static_cast<double>(s.candidate_vectors) / s.candidate_macroblocks);
    }
  }
  std::printf("\n");
}

void print_summary(const EncodeSummary& s, const std::filesystem::path& out) {
  std::printf("encoded %llu cells, %llu faces into %s\n", static_cast<unsigned long long>(s.cells),
              static_cast<unsigned long long>(s.faces), out.string().c_str());
  std::printf("  size      %s (raw RGB %s), compression %.1f:1, %.3f bits/pixel\n",
              human_bytes(s.file_bytes).c_str(), human_bytes(s.raw_bytes).c_str(),
              s.file_bytes ? static_cast<double>(s.raw_bytes) / s.file_bytes : 0.0,
              s.raw_bytes ? 8.0 * s.file_bytes / (s.raw_bytes / 3.0) : 0.0);
  print_frame_stats("I-faces", s.intra);
  print_frame_stats("B-faces", s.predicted);
  std::printf("  quantiser index %d, %.2f s (%.1f faces/s)\n", s.qindex, s.seconds,
              s.seconds > 0 ? s.faces / s.seconds : 0.0);
}

// A file encoded with --qindex records no quality (0): only its index is shown.
std::string coding_scale_text(const FileInfo& info) {
  const std::string scale = "quantiser index " + std::to_string(info.qindex);
  if (info.quality <= 0) return scale;
  return "quality " + std::to_string(info.quality) + ", " + scale;
}

json camera_json(const Camera& camera) {
  json m = json::array();
  for (double v : camera.world_to_camera) m.push_back(v);
  return m;
}

// A depth image in which every pixel is background: the .svc file keeps no depth.
Status write_unknown_depth(const std::filesystem::path& path, int width, int height) {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + path.string());
  OIIO::ImageSpec spec(width, height, 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"Z"};
  spec.attribute("compression", "zip");
  std::vector<float> depth(static_cast<size_t>(width) * height, std::numeric_limits<float>::infinity());
  if (!out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, depth.data()) || !out->close()) {
    return Status(ErrorCode::kIoError, "cannot write " + path.string() + ": " + out->geterror());
  }
  return Status::Ok();
}

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

}  // namespace

Result<EncodeSummary> run_encode(const std::filesystem::path& db, const std::filesystem::path& out,
                                 const EncoderSettings& settings, bool show_progress) {
  ProgressBar bar("encoding", show_progress);
  auto result = encode_database(db, out, settings, [&](uint64_t done, uint64_t total) {
    bar.update(done, total);
    return true;
  });
  bar.finish();
  return result;
}

int add_command(const AddOptions& options) {
  ProgressBar bar("adding", !options.quiet);
  AddSettings settings;
  settings.threads = options.threads;
  auto summary = add_to_database(options.input, options.db_dir, settings, [&](uint64_t done, uint64_t total) {
    bar.update(done, total);
    return true;
  });
  bar.finish();
  if (!summary.ok()) return report_error(summary.status());
  if (!options.quiet) {
    const AddSummary& s = *summary;
    std::printf("added %llu cells (%llu I-cubes, %llu B-cubes), %llu faces to %s; %llu cells were already there\n",
                static_cast<unsigned long long>(s.cells_added),
                static_cast<unsigned long long>(s.intra_cells_added),
                static_cast<unsigned long long>(s.predicted_cells_added),
                static_cast<unsigned long long>(s.faces_added), options.input.string().c_str(),
                static_cast<unsigned long long>(s.cells_present));
    std::printf("  %llu cells, grid %dx%dx%d, %s (%s appended), commit generation %llu, %.2f s\n",
                static_cast<unsigned long long>(s.cells_before + s.cells_added), s.grid_dims[0], s.grid_dims[1],
                s.grid_dims[2], human_bytes(s.file_bytes).c_str(), human_bytes(s.bytes_appended).c_str(),
                static_cast<unsigned long long>(s.generation), s.seconds);
  }
  return 0;
}

int encode_command(const EncodeOptions& options) {
  const Status writable = check_output(options.output, OutputKind::kFile, options.overwrite, {options.db_dir});
  if (!writable.ok()) return report_error(writable);
  auto summary = run_encode(options.db_dir, options.output, options.settings, !options.quiet && !options.json);
  if (!summary.ok()) return report_error(summary.status());
  if (options.json) {
    std::printf("%s\n", summary_json(*summary, options.output).dump(2).c_str());
  } else if (!options.quiet) {
    print_summary(*summary, options.output);
  }
  return 0;
}

int decode_command(const DecodeOptions& options) {
  const Status writable = check_output(options.output, OutputKind::kFolder, options.overwrite, {options.input});
  if (!writable.ok()) return report_error(writable);
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  const FileInfo& info = (*reader)->info();
  const auto& cells = (*reader)->cells();

  std::vector<size_t> selected;
  if (options.cell) {
    auto ordinal = (*reader)->find_cell(*options.cell);
    if (!ordinal) {
      return report_error(
          Status(ErrorCode::kNotFound, options.input.string() + " has no " + cell_label(*options.cell)));
    }
    selected.push_back(*ordinal);
  } else {
    for (size_t i = 0; i < cells.size(); ++i) selected.push_back(i);
  }
  std::vector<Face> faces(kAllFaces.begin(), kAllFaces.end());
  if (options.face) faces = {*options.face};

  std::error_code ec;
  std::filesystem::create_directories(options.output / "cells", ec);
  if (ec) {
    return report_error(
        Status(ErrorCode::kIoError, "cannot create " + options.output.string() + ": " + ec.message()));
  }
  const std::string depth_name = "depth-unknown.exr";
  Status status = write_unknown_depth(options.output / depth_name, info.face_width, info.face_height);
  if (!status.ok()) return report_error(status);

  json manifest;
  manifest["format"] = "svc-input";
  manifest["version"] = 1;
  manifest["grid"] = {{"dims", info.grid_dims}, {"origin", info.grid_origin}, {"spacing", info.grid_spacing}};
  manifest["face_size"] = {info.face_width, info.face_height};
  manifest["depth"] = "eye_z";
  manifest["up_axis"] = std::string(1, info.up_axis);
  manifest["decoded_from"] = options.input.filename().string();
  json cell_list = json::array();
  ProgressBar bar("decoding", !options.quiet);
  uint64_t done = 0;
  const uint64_t total = selected.size() * faces.size();
  int failures = 0;
  for (size_t ordinal : selected) {
    const CellEntry& cell = cells[ordinal];
    json faces_json = json::object();
    const std::string dir = "cells/" + std::to_string(cell.index.x) + "_" + std::to_string(cell.index.y) + "_" +
                            std::to_string(cell.index.z);
    std::filesystem::create_directories(options.output / dir, ec);
    for (Face face : faces) {
      auto image = (*reader)->decode_face(cell.index, face);
      bar.update(++done, total);
      if (!image.ok()) {
        bar.finish();
        std::fprintf(stderr, "svc: %s\n", image.status().to_string().c_str());
        ++failures;
        continue;
      }
      const std::string color = dir + "/" + face_name(face) + ".png";
      status = write_png(options.output / color, *image);
      if (!status.ok()) return report_error(status);
      const Camera& camera = cell.cameras[static_cast<int>(face)];
      const Frustum& f = camera.frustum;
      faces_json[face_name(face)] = {{"color", color},
                                     {"depth", depth_name},
                                     {"world_to_camera", camera_json(camera)},
                                     {"projection",
                                      {{"left", f.left},
                                       {"right", f.right},
                                       {"bottom", f.bottom},
                                       {"top", f.top},
                                       {"near", f.near_plane},
                                       {"far", f.far_plane}}}};
    }
    if (faces_json.size() == kFaceCount) {
      cell_list.push_back({{"index", {cell.index.x, cell.index.y, cell.index.z}},
                           {"position", cell.position},
                           {"faces", faces_json}});
    }
  }
  bar.finish();
  manifest["cells"] = cell_list;
  std::ofstream(options.output / "manifest.json") << manifest.dump(2) << "\n";
  if (!options.quiet) {
    std::printf("decoded %llu faces of %zu cells into %s\n", static_cast<unsigned long long>(done - failures),
                selected.size(), options.output.string().c_str());
    if (faces.size() != kFaceCount) {
      std::printf("  (one face per cell: manifest.json lists only complete cells)\n");
    }
  }
  return failures == 0 ? 0 : 3;
}

int info_command(const InfoOptions& options) {
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  const FileInfo& info = (*reader)->info();
  const auto& cells = (*reader)->cells();
  uint64_t bytes_by_type[2] = {0, 0};
  json per_cell = json::array();
  for (const CellEntry& cell : cells) {
    uint64_t cell_bytes = 0;
    for (const FaceEntry& face : cell.faces) {
      const int t = face.type == FaceType::kIntra ? 0 : 1;
      bytes_by_type[t] += face.coded_bytes;
      cell_bytes += face.coded_bytes;
    }
    per_cell.push_back({{"index", {cell.index.x, cell.index.y, cell.index.z}},
                        {"type", cell.faces[0].type == FaceType::kIntra ? "I" : "B"},
                        {"bytes", cell_bytes}});
  }
  const uint64_t raw = uint64_t{3} * info.face_width * info.face_height * cells.size() * kFaceCount;
  const std::array<FaceTypeStats, 2>& stats = info.face_type_stats;
  if (options.json) {
    json j;
    j["file"] = options.input.string();
    j["format_version"] = std::to_string(info.format_major) + "." + std::to_string(info.format_minor);
    j["file_bytes"] = info.file_bytes;
    j["raw_bytes"] = raw;
    j["compression_ratio"] = info.file_bytes ? static_cast<double>(raw) / info.file_bytes : 0.0;
    j["grid"] = {{"dims", info.grid_dims}, {"origin", info.grid_origin}, {"spacing", info.grid_spacing}};
    j["face_size"] = {info.face_width, info.face_height};
    j["cells"] = cells.size();
    // A file encoded with an explicit quantiser index has no quality.
    j["coding"] = {{"quality", info.quality > 0 ? json(info.quality) : json(nullptr)},
                   {"qindex", info.qindex},
                   {"i_spacing", info.i_spacing},
                   {"motion", info.motion}};
    j["frame_types"] = {{"I", frame_stats_json(stats[0])}, {"B", frame_stats_json(stats[1])}};
    j["per_cell"] = per_cell;
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
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
  print_frame_stats("I-faces", stats[0]);
  print_frame_stats("B-faces", stats[1]);
  std::printf("  per cell  %.0f bytes on average\n",
              cells.empty() ? 0.0 : static_cast<double>(bytes_by_type[0] + bytes_by_type[1]) / cells.size());
  return 0;
}

int verify_command(const VerifyOptions& options) {
  auto reader = Reader::open(options.input);
  if (!reader.ok()) return report_error(reader.status());
  const Status status = (*reader)->verify();
  if (!status.ok()) {
    std::fprintf(stderr, "svc: %s is damaged:\n%s\n", options.input.string().c_str(), status.message().c_str());
    return command_line::kExitCorrupt;
  }
  if (!options.quiet) {
    std::printf("%s: ok (%zu cells, %zu faces, every chunk's CRC-32 and every face decode checked)\n",
                options.input.string().c_str(), (*reader)->cells().size(), (*reader)->cells().size() * kFaceCount);
  }
  return 0;
}

int demo_command(const DemoOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path work = options.keep_dir;
  const bool temporary = work.empty();
  if (!temporary) {
    const Status writable = check_output(work, OutputKind::kFolder, options.overwrite, {});
    if (!writable.ok()) return report_error(writable);
  }
  if (temporary) {
    work = fs::temp_directory_path() / ("svc-demo-" + std::to_string(std::random_device{}()));
  }
  fs::create_directories(work, ec);
  if (ec) return report_error(Status(ErrorCode::kIoError, "cannot create " + work.string() + ": " + ec.message()));
  struct Cleanup {
    fs::path path;
    bool active;
    ~Cleanup() {
      std::error_code e;
      if (active) fs::remove_all(path, e);
    }
  } cleanup{work, temporary};

  samples::SceneOptions scene;
  scene.kind = options.kind;
  // Rendering in parallel gives the same bytes; use every core.
  scene.threads = std::min(resolve_thread_count(0), 256);
  const fs::path db = work / "scene";
  const fs::path out = work / "scene.svc";
  std::printf("svc demo: %s scene, %d x %d x %d cells of %dx%d faces, in %s\n",
              samples::scene_kind_name(scene.kind), scene.grid[0], scene.grid[1], scene.grid[2], scene.face_size,
              scene.face_size, work.string().c_str());

  auto t0 = std::chrono::steady_clock::now();
  {
    ProgressBar bar("generating", true);
    Status status = samples::generate_scene(scene, db, [&](int done, int total) { bar.update(done, total); });
    if (!status.ok()) return report_error(status);
  }
  const double generate_seconds = seconds_since(t0);
  std::printf("  generated  %d faces in %.2f s\n", scene.grid[0] * scene.grid[1] * scene.grid[2] * kFaceCount,
              generate_seconds);

  auto summary = run_encode(db, out, options.settings, true);
  if (!summary.ok()) return report_error(summary.status());
  print_summary(*summary, out);

  t0 = std::chrono::steady_clock::now();
  auto reader = Reader::open(out);
  if (!reader.ok()) return report_error(reader.status());
  const double open_seconds = seconds_since(t0);

  // Decode a few random cells and compare with the source images.
  std::mt19937 rng(12345);
  const auto& cells = (*reader)->cells();
  SquaredError rgb_error, y_error;
  double decode_seconds = 0;
  int decoded_faces = 0;
  const int sample_cells = std::min<int>(5, static_cast<int>(cells.size()));
  std::printf("  decoding %d random cells:\n", sample_cells);
  for (int k = 0; k < sample_cells; ++k) {
    const CellEntry& cell = cells[rng() % cells.size()];
    auto start = std::chrono::steady_clock::now();
    auto cube = (*reader)->decode_cube(cell.index);
    const double seconds = seconds_since(start);
    if (!cube.ok()) return report_error(cube.status());
    decode_seconds += seconds;
    SquaredError cell_y;
    for (Face face : kAllFaces) {
      const fs::path source =
          db / "cells" /
          (std::to_string(cell.index.x) + "_" + std::to_string(cell.index.y) + "_" + std::to_string(cell.index.z)) /
          (std::string(face_name(face)) + ".png");
      auto original = read_rgb(source);
      if (!original.ok()) return report_error(original.status());
      const ImageRGB8& decoded = (*cube)[static_cast<int>(face)];
      auto e_rgb = rgb_squared_error(*original, decoded);
      auto e_y = luma_squared_error(*original, decoded);
      if (!e_rgb.ok()) return report_error(e_rgb.status());
      if (!e_y.ok()) return report_error(e_y.status());
      rgb_error.add(*e_rgb);
      y_error.add(*e_y);
      cell_y.add(*e_y);
      ++decoded_faces;
    }
    std::printf("    %s %s-cube: 6 faces in %.2f ms, PSNR-Y %.2f dB\n", cell_label(cell.index).c_str(),
                cell.faces[0].type == FaceType::kIntra ? "I" : "B", seconds * 1e3, cell_y.psnr());
  }
  std::printf("  open       %.2f ms\n", open_seconds * 1e3);
  std::printf("  decode     %.2f ms per face on average (%d faces)\n",
              decoded_faces ? decode_seconds * 1e3 / decoded_faces : 0.0, decoded_faces);
  std::printf("  quality    PSNR-RGB %.2f dB, PSNR-Y %.2f dB over the decoded faces\n", rgb_error.psnr(),
              y_error.psnr());
  std::printf("  result     %s for %s raw: %.1f:1\n", human_bytes(summary->file_bytes).c_str(),
              human_bytes(summary->raw_bytes).c_str(),
              summary->file_bytes ? static_cast<double>(summary->raw_bytes) / summary->file_bytes : 0.0);
  if (!temporary) std::printf("  kept       %s and %s\n", db.string().c_str(), out.string().c_str());
  return 0;
}

}  // namespace svc::cli
