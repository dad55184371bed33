// SPDX-License-Identifier: BSD-2-Clause
#include "cli/commands.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <random>
#include <string>

#include "cli/cli_util.h"
#include "cli/quality_report.h"
#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/output_paths.h"
#include "command_line/staged_folder.h"
#include "common/parallel.h"
#include "database/database.h"
#include "scene/scene.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc::cli {

using command_line::check_output;
using command_line::OutputKind;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

json quality_json(const QualityReport& q) {
  return {{"faces", q.faces}, {"psnr_y", q.psnr_y()}, {"psnr_rgb", q.psnr_rgb()}, {"ssim", q.ssim()}};
}

json syntax_bytes_json(const std::array<double, kSyntaxElementCount>& bytes) {
  json j = json::object();
  const std::vector<std::string> names = syntax_element_names();
  for (size_t e = 0; e < kSyntaxElementCount; ++e) j[names[e]] = bytes[e];
  return j;
}

// PSNR-Y of a squared error over `pixels` luma samples; none without samples or error.
std::optional<double> screened_psnr(uint64_t sse, uint64_t pixels) {
  if (pixels == 0 || sse == 0) return std::nullopt;
  return 10.0 * std::log10(255.0 * 255.0 * static_cast<double>(pixels) / static_cast<double>(sse));
}

json screened_psnr_json(uint64_t sse, uint64_t pixels) {
  const std::optional<double> psnr = screened_psnr(sse, pixels);
  return psnr ? json(*psnr) : json(nullptr);
}

json prediction_json(const PredictionSummary& p) {
  return {{"macroblocks_leaving_face", p.mb_leaving_face},
          {"macroblocks_warped", p.mb_warp},
          {"screened_psnr_y",
           {{"intra", screened_psnr_json(p.screened_sse[0], p.screened_pixels[0])},
            {"inter", screened_psnr_json(p.screened_sse[1], p.screened_pixels[1])}}}};
}

json summary_json(const EncodeSummary& s, const std::filesystem::path& db, const std::filesystem::path& out) {
  json j;
  j["command"] = "encode";
  j["input"] = db.string();
  j["output"] = out.string();
  j["cells"] = s.cells;
  j["faces"] = s.faces;
  j["raw_bytes"] = s.raw_bytes;
  j["file_bytes"] = s.file_bytes;
  j["compression_ratio"] = s.file_bytes ? static_cast<double>(s.raw_bytes) / s.file_bytes : 0.0;
  j["qindex"] = s.qindex;
  j["b_qindex"] = s.b_qindex;
  j["seconds"] = s.seconds;
  j["face_types"] = {{"intra", face_type_stats_json(s.intra)}, {"predicted", face_type_stats_json(s.predicted)}};
  j["syntax_bytes"] = {{"intra", syntax_bytes_json(s.intra_syntax_bytes)},
                       {"predicted", syntax_bytes_json(s.predicted_syntax_bytes)}};
  j["prediction"] = prediction_json(s.prediction);
  return j;
}

// -v: where a face type's bytes go, by syntax element (estimated).
void print_syntax_bytes(const char* name, const FaceTypeStats& stats,
                        const std::array<double, kSyntaxElementCount>& bytes) {
  if (stats.faces == 0) return;
  double total = 0;
  for (double b : bytes) total += b;
  if (total <= 0) return;
  const std::vector<std::string> names = syntax_element_names();
  std::printf("  %-9s syntax:", name);
  for (size_t e = 0; e < kSyntaxElementCount; ++e) {
    std::printf("%s %s %s (%.1f%%)", e ? "," : "", names[e].c_str(),
                human_bytes(static_cast<uint64_t>(bytes[e] + 0.5)).c_str(), 100.0 * bytes[e] / total);
  }
  std::printf("\n");
}

// -v: how close the references came to the B-faces, where intra won and elsewhere.
void print_prediction(const EncodeSummary& s) {
  const PredictionSummary& p = s.prediction;
  if (s.predicted.faces == 0 || p.screened_pixels[0] + p.screened_pixels[1] == 0) return;
  auto text = [&](size_t k) {
    const std::optional<double> psnr = screened_psnr(p.screened_sse[k], p.screened_pixels[k]);
    char buffer[32] = "none";
    if (psnr) std::snprintf(buffer, sizeof buffer, "%.2f dB", *psnr);
    return std::string(buffer);
  };
  std::printf(
      "  B-faces   closest inter prediction PSNR-Y %s where coded intra, %s elsewhere; %llu macroblocks "
      "warped\n",
      text(0).c_str(), text(1).c_str(), static_cast<unsigned long long>(p.mb_warp));
}

void print_summary(const EncodeSummary& s, const std::filesystem::path& out, bool verbose) {
  std::printf("encoded %llu cells, %llu faces into %s\n", static_cast<unsigned long long>(s.cells),
              static_cast<unsigned long long>(s.faces), out.string().c_str());
  std::printf("  size      %s (raw RGB %s), compression %.1f:1, %.3f bits/pixel\n",
              human_bytes(s.file_bytes).c_str(), human_bytes(s.raw_bytes).c_str(),
              s.file_bytes ? static_cast<double>(s.raw_bytes) / s.file_bytes : 0.0,
              s.raw_bytes ? 8.0 * s.file_bytes / (s.raw_bytes / 3.0) : 0.0);
  print_face_type_stats("I-faces", s.intra);
  print_face_type_stats("B-faces", s.predicted);
  if (verbose) {
    print_syntax_bytes("I-faces", s.intra, s.intra_syntax_bytes);
    print_syntax_bytes("B-faces", s.predicted, s.predicted_syntax_bytes);
    print_prediction(s);
  }
  const std::string b_faces = s.b_qindex >= 0 ? " (B-faces " + std::to_string(s.b_qindex) + ")" : "";
  std::printf("  quantizer index %d%s, %.2f s (%.1f faces/s)\n", s.qindex, b_faces.c_str(), s.seconds,
              s.seconds > 0 ? s.faces / s.seconds : 0.0);
}

void print_quality(const QualityReport& q) {
  std::printf("  quality   PSNR-Y %.2f dB, PSNR-RGB %.2f dB, SSIM %.4f over %llu faces\n", q.psnr_y(), q.psnr_rgb(),
              q.ssim(), static_cast<unsigned long long>(q.faces));
}

// An .svc file (or any other file) given where a database folder belongs.
Status check_database_argument(const std::filesystem::path& db) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(db, ec) || db.extension() == ".json") return Status::Ok();
  char magic[4] = {};
  std::ifstream(db, std::ios::binary).read(magic, sizeof magic);
  if (db.extension() == ".svc" || std::string(magic, 4) == "\x89SVC") {
    return Status(ErrorCode::kInvalidArgument, db.string() +
                                                   " is an .svc file; encode expects a database folder "
                                                   "(manifest.json and images). `svc decode` turns an .svc file "
                                                   "into one");
  }
  return Status(ErrorCode::kInvalidArgument,
                db.string() + " is a file; encode expects a database folder (manifest.json and images)");
}

// Decodes what was just written and compares it with the database.
Result<QualityReport> measure_encoded(const EncodeOptions& options) {
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest,
                       load_manifest(options.db_dir, ManifestOptions{options.settings.allow_outside_paths}));
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(options.output));
  ProgressBar bar("measuring", options.verbosity.show_progress());
  return measure_database(*reader, manifest, options.settings.threads, &bar);
}

// -v: the settings in effect, before the work starts.
void print_settings(const EncodeOptions& options) {
  const EncoderSettings& s = options.settings;
  const bool explicit_index = s.qindex >= 0;
  const int qindex = explicit_index ? s.qindex : qindex_for_quality(s.quality);
  const std::string tools_off = comma_list(disabled_coding_tools(s.tools));
  const char* layout = s.intra_only                       ? " (intra only)"
                       : s.layout == CubeLayout::kRegular ? ", regular layout"
                                                          : ", visibility layout";
  std::fprintf(stderr,
               "svc: encoding %s: %s%d (quantizer index %d), I-cube spacing %d,%d,%d%s, motion from %s, %d "
               "threads%s%s\n",
               options.db_dir.string().c_str(), explicit_index ? "qindex " : "quality ",
               explicit_index ? s.qindex : s.quality, qindex, s.i_spacing[0], s.i_spacing[1], s.i_spacing[2],
               layout, s.motion == MotionSearch::kLogarithmic ? "log search" : "depth",
               resolve_thread_count(s.threads), tools_off.empty() ? "" : ", tools off: ", tools_off.c_str());
}

}  // namespace

int encode_command(const EncodeOptions& options) {
  Status status = check_database_argument(options.db_dir);
  if (status.ok()) status = check_output(options.output, OutputKind::kFile, options.overwrite, {options.db_dir});
  if (!status.ok()) return report_error(status);
  if (options.verbosity.verbose) print_settings(options);
  const bool shard = options.shard_count > 0;
  ProgressBar bar(shard
                      ? "encoding part " + std::to_string(options.shard) + "/" + std::to_string(options.shard_count)
                      : std::string("encoding"),
                  options.verbosity.show_progress());
  const EncodeProgress progress = [&](uint64_t done, uint64_t total) {
    bar.update(done, total);
    return keep_going();
  };
  auto summary = shard ? encode_shard(options.db_dir, options.output, options.settings, options.shard,
                                      options.shard_count, progress)
                       : encode_database(options.db_dir, options.output, options.settings, progress);
  bar.finish();
  if (!summary.ok()) return report_error(summary.status());
  json result = summary_json(*summary, options.db_dir, options.output);
  std::optional<QualityReport> quality;
  if (options.psnr) {
    auto measured = measure_encoded(options);
    if (!measured.ok() && command_line::interrupted()) {
      std::fprintf(stderr, "svc: stopped by %s while measuring; %s is complete\n",
                   command_line::interrupting_signal_name(), options.output.string().c_str());
      return command_line::interrupted_exit_code();
    }
    if (!measured.ok()) {
      std::fprintf(stderr, "svc: %s was written; measuring its quality failed:\n", options.output.string().c_str());
      return report_error(measured.status());
    }
    quality = *measured;
    result["quality"] = quality_json(*quality);
  }
  if (options.verbosity.json) {
    print_json(result);
  } else if (options.verbosity.show_summary()) {
    print_summary(*summary, options.output, options.verbosity.verbose);
    if (quality) print_quality(*quality);
  }
  return 0;
}

int merge_command(const MergeOptions& options) {
  const Status writable = check_output(options.output, OutputKind::kFile, options.overwrite, options.parts);
  if (!writable.ok()) return report_error(writable);
  auto summary = merge_shards(options.parts, options.output);
  if (!summary.ok()) return report_error(summary.status());
  if (options.verbosity.json) {
    print_json({{"command", "merge"},
                {"output", options.output.string()},
                {"parts", summary->parts},
                {"cells", summary->cells},
                {"faces", summary->faces},
                {"file_bytes", summary->file_bytes},
                {"seconds", summary->seconds}});
  } else if (options.verbosity.show_summary()) {
    std::printf("merged %llu parts into %s: %llu cells, %llu faces, %s, %.2f s\n",
                static_cast<unsigned long long>(summary->parts), options.output.string().c_str(),
                static_cast<unsigned long long>(summary->cells), static_cast<unsigned long long>(summary->faces),
                human_bytes(summary->file_bytes).c_str(), summary->seconds);
  }
  return 0;
}

int add_command(const AddOptions& options) {
  ProgressBar bar("adding", options.verbosity.show_progress());
  auto summary =
      add_to_database(options.input, options.db_dir, options.settings, [&](uint64_t done, uint64_t total) {
        bar.update(done, total);
        return keep_going();
      });
  bar.finish();
  if (!summary.ok()) return report_error(summary.status());
  const AddSummary& s = *summary;
  if (options.verbosity.json) {
    print_json({{"command", "add"},
                {"input", options.db_dir.string()},
                {"output", options.input.string()},
                {"cells_before", s.cells_before},
                {"cells_added", s.cells_added},
                {"cells_present", s.cells_present},
                {"intra_cells_added", s.intra_cells_added},
                {"predicted_cells_added", s.predicted_cells_added},
                {"faces_added", s.faces_added},
                {"bytes_appended", s.bytes_appended},
                {"file_bytes", s.file_bytes},
                {"generation", s.generation},
                {"grid", {{"dims", s.grid_dims}}},
                {"seconds", s.seconds}});
  } else if (options.verbosity.show_summary()) {
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

int verify_command(const VerifyOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto reader = Reader::open(options.input);
  if (!reader.ok()) {
    // A file too damaged to open (truncated, its index unreadable) is a verify result
    // too: --json still prints one, with the reason as its problem.
    if (options.verbosity.json) {
      print_json({{"command", "verify"},
                  {"input", options.input.string()},
                  {"ok", false},
                  {"cells", 0},
                  {"faces", 0},
                  {"problems", json::array({reader.status().message()})},
                  {"seconds", seconds_since(start)}});
    }
    return report_error(reader.status());
  }
  if (options.verbosity.verbose) {
    std::fprintf(stderr, "svc: verifying %zu faces of %s on %d threads\n", (*reader)->cells().size() * kFaceCount,
                 options.input.string().c_str(), resolve_thread_count(options.threads));
  }
  ProgressBar bar("verifying", options.verbosity.show_progress());
  std::vector<std::string> problems;
  VerifySettings settings;
  settings.threads = options.threads;
  settings.problems = &problems;
  settings.progress = [&](uint64_t done, uint64_t total) {
    bar.update(done, total);
    return keep_going();
  };
  const Status status = (*reader)->verify(settings);
  bar.finish();
  if (status.code() == ErrorCode::kCancelled) return report_error(status);
  const size_t cells = (*reader)->cells().size();
  if (options.verbosity.json) {
    print_json({{"command", "verify"},
                {"input", options.input.string()},
                {"ok", status.ok()},
                {"cells", cells},
                {"faces", cells * kFaceCount},
                {"problems", problems},
                {"seconds", seconds_since(start)}});
  }
  if (!status.ok()) {
    std::fprintf(stderr, "svc: %s is damaged:\n%s\n", options.input.string().c_str(), status.message().c_str());
    return command_line::kExitCorrupt;
  }
  if (options.verbosity.show_summary()) {
    std::printf("%s: ok (%zu cells, %zu faces, every chunk's CRC-32 and every face decode checked, %.2f s)\n",
                options.input.string().c_str(), cells, cells * kFaceCount, seconds_since(start));
  }
  return 0;
}

namespace {

// What svc demo measures on a few random cells of the file it encoded.
struct DemoSample {
  QualityReport quality;
  double open_seconds = 0;
  double decode_seconds = 0;
  json cells = json::array();
};

Result<DemoSample> decode_random_cells(const std::filesystem::path& db, const std::filesystem::path& file,
                                       bool print) {
  DemoSample sample;
  auto t0 = std::chrono::steady_clock::now();
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file));
  sample.open_seconds = seconds_since(t0);
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db));
  std::mt19937 rng(12345);
  const auto& cells = reader->cells();
  const int count = std::min<int>(5, static_cast<int>(cells.size()));
  if (print) std::printf("  decoding %d random cells:\n", count);
  for (int k = 0; k < count; ++k) {
    const CellEntry& cell = cells[rng() % cells.size()];
    const auto start = std::chrono::steady_clock::now();
    SVC_RETURN_IF_ERROR(reader->decode_cube(cell.index).status());
    const double seconds = seconds_since(start);
    sample.decode_seconds += seconds;
    SVC_ASSIGN_OR_RETURN(QualityReport measured, measure_cell(*reader, manifest, *find_cell(manifest, cell.index)));
    sample.quality.add(measured);
    const bool intra = cell.faces[0].type == FaceType::kIntra;
    sample.cells.push_back({{"cell", {cell.index.x, cell.index.y, cell.index.z}},
                            {"type", intra ? "intra" : "predicted"},
                            {"decode_seconds", seconds},
                            {"psnr_y", measured.psnr_y()}});
    if (print) {
      std::printf("    %s %s-cube: 6 faces in %.2f ms, PSNR-Y %.2f dB\n", cell_label(cell.index).c_str(),
                  intra ? "I" : "B", seconds * 1e3, measured.psnr_y());
    }
  }
  return sample;
}

void print_demo_sample(const DemoSample& sample, const EncodeSummary& summary) {
  const QualityReport& q = sample.quality;
  std::printf("  open       %.2f ms\n", sample.open_seconds * 1e3);
  std::printf("  decode     %.2f ms per face on average (%llu faces)\n",
              q.faces ? sample.decode_seconds * 1e3 / q.faces : 0.0, static_cast<unsigned long long>(q.faces));
  std::printf("  quality    PSNR-RGB %.2f dB, PSNR-Y %.2f dB, SSIM %.4f over the decoded faces\n", q.psnr_rgb(),
              q.psnr_y(), q.ssim());
  std::printf("  result     %s for %s raw: %.1f:1\n", human_bytes(summary.file_bytes).c_str(),
              human_bytes(summary.raw_bytes).c_str(),
              summary.file_bytes ? static_cast<double>(summary.raw_bytes) / summary.file_bytes : 0.0);
}

// Where the demo writes: the --keep folder, staged beside it and moved there when
// complete, or a temporary folder that is always removed.
struct DemoFolder {
  std::unique_ptr<command_line::StagedFolder> kept;
  std::filesystem::path temporary;
  ~DemoFolder() {
    std::error_code ec;
    if (!temporary.empty()) std::filesystem::remove_all(temporary, ec);
  }
  std::filesystem::path path() const { return kept ? kept->path() : temporary; }
};

Status open_demo_folder(const DemoOptions& options, DemoFolder* folder) {
  if (!options.keep_dir.empty()) {
    SVC_RETURN_IF_ERROR(check_output(options.keep_dir, OutputKind::kFolder, options.overwrite, {}));
    SVC_ASSIGN_OR_RETURN(folder->kept, command_line::StagedFolder::create(options.keep_dir));
    return Status::Ok();
  }
  const auto path = std::filesystem::temp_directory_path() / ("svc-demo-" + std::to_string(std::random_device{}()));
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) return Status(ErrorCode::kIoError, "cannot create " + path.string() + ": " + ec.message());
  folder->temporary = path;
  return Status::Ok();
}

}  // namespace

int demo_command(const DemoOptions& options) {
  namespace fs = std::filesystem;
  const Verbosity& verbosity = options.verbosity;
  DemoFolder folder;
  if (Status status = open_demo_folder(options, &folder); !status.ok()) return report_error(status);
  const fs::path shown = options.keep_dir.empty() ? folder.path() : options.keep_dir;

  samples::SceneOptions scene;
  scene.kind = options.kind;
  scene.grid = options.grid;
  scene.face_size = options.face_size;
  // Rendering in parallel gives the same bytes; use every core.
  scene.threads = std::min(resolve_thread_count(0), 256);
  const fs::path db = folder.path() / "scene";
  const fs::path out = folder.path() / "scene.svc";
  if (verbosity.show_summary()) {
    std::printf("svc demo: %s scene, %d x %d x %d cells of %dx%d faces, in %s\n",
                samples::scene_kind_name(scene.kind), scene.grid[0], scene.grid[1], scene.grid[2], scene.face_size,
                scene.face_size, shown.string().c_str());
  }
  auto t0 = std::chrono::steady_clock::now();
  {
    ProgressBar bar("generating", verbosity.show_progress());
    Status status = samples::generate_scene(scene, db, [&](int done, int total) {
      bar.update(done, total);
      return keep_going();
    });
    if (!status.ok()) return report_error(status);
  }
  const double generate_seconds = seconds_since(t0);
  if (verbosity.show_summary()) {
    std::printf("  generated  %d faces in %.2f s\n", scene.grid[0] * scene.grid[1] * scene.grid[2] * kFaceCount,
                generate_seconds);
  }

  ProgressBar bar("encoding", verbosity.show_progress());
  auto summary = encode_database(db, out, options.settings, [&](uint64_t done, uint64_t total) {
    bar.update(done, total);
    return keep_going();
  });
  bar.finish();
  if (!summary.ok()) return report_error(summary.status());
  if (verbosity.show_summary()) print_summary(*summary, shown / "scene.svc", verbosity.verbose);

  auto sample = decode_random_cells(db, out, verbosity.show_summary());
  if (!sample.ok()) return report_error(sample.status());
  if (folder.kept) {
    if (Status status = folder.kept->commit(); !status.ok()) return report_error(status);
  }
  if (verbosity.json) {
    json result = summary_json(*summary, shown / "scene", shown / "scene.svc");
    result["command"] = "demo";
    if (!folder.kept) result["input"] = result["output"] = nullptr;  // removed on exit
    result["kind"] = samples::scene_kind_name(scene.kind);
    result["generate_seconds"] = generate_seconds;
    result["open_seconds"] = sample->open_seconds;
    result["decoded_cells"] = sample->cells;
    result["quality"] = quality_json(sample->quality);
    print_json(result);
  } else if (verbosity.show_summary()) {
    print_demo_sample(*sample, *summary);
    if (folder.kept) {
      std::printf("  kept       %s and %s\n", (shown / "scene").string().c_str(),
                  (shown / "scene.svc").string().c_str());
    }
  }
  return 0;
}

}  // namespace svc::cli
