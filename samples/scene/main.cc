// SPDX-License-Identifier: BSD-2-Clause
// svc-scene: writes a procedural or photographic sample scene as an svc-input database.
//
//   svc-scene OUT_DIR [--kind hall|house] [--grid X,Y,Z] [--spacing S | SX,SY,SZ]
//             [--origin X,Y,Z] [--eye X,Y,Z] [--face-size N] [--seed N] [--textures DIR] [--sparse]
//             [--threads N] [--json] [--quiet] [--progress | --no-progress] [-y]
//
// The database is written into ".OUT_DIR.tmp-PID" beside OUT_DIR and moved into place
// when complete: a failed or interrupted (SIGINT, SIGTERM) run leaves nothing behind.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/output_paths.h"
#include "command_line/progress.h"
#include "command_line/report.h"
#include "command_line/staged_folder.h"
#include "scene/scene.h"

namespace {

// "a,b,c" -> numbers; false on anything else.
template <typename T>
bool parse_list(const std::string& text, std::vector<T>* out) {
  out->clear();
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::stringstream item_stream(item);
    T value;
    if (!(item_stream >> value)) return false;
    item_stream >> std::ws;
    if (!item_stream.eof()) return false;
    out->push_back(value);
  }
  return !out->empty();
}

// Writes the scene into a staging folder beside `out_dir` and moves it into place.
svc::Status write_scene(const svc::samples::SceneOptions& options, const std::string& out_dir,
                        const svc::command_line::Verbosity& verbosity, int* cells_written) {
  SVC_ASSIGN_OR_RETURN(auto staged, svc::command_line::StagedFolder::create(out_dir));
  svc::command_line::ProgressBar bar("generating", verbosity.show_progress());
  const svc::Status status = svc::samples::generate_scene(options, staged->path(), [&](int done, int total) {
    *cells_written = done;
    bar.update(done, total);
    return !svc::command_line::interrupted();
  });
  bar.finish();
  SVC_RETURN_IF_ERROR(status);
  return staged->commit();
}

void print_result(const svc::samples::SceneOptions& options, const std::string& out_dir, int cells, double seconds,
                  const svc::command_line::Verbosity& verbosity) {
  if (verbosity.json) {
    const nlohmann::ordered_json result = {{"command", "svc-scene"},
                                           {"output", out_dir},
                                           {"kind", svc::samples::scene_kind_name(options.kind)},
                                           {"photographic", !options.textures.empty()},
                                           {"grid",
                                            {{"dims", options.grid},
                                             {"origin", svc::samples::scene_grid_origin(options)},
                                             {"spacing", options.spacing}}},
                                           {"face_size", {options.face_size, options.face_size}},
                                           {"cells", cells},
                                           {"faces", cells * svc::kFaceCount},
                                           {"seconds", seconds}};
    std::printf("%s\n", result.dump(2).c_str());
  } else if (verbosity.show_summary()) {
    std::printf("svc-scene: wrote %s%s scene, %d cells (%d faces of %dx%d) to %s in %.1f s\n",
                options.textures.empty() ? "" : "photographic ", svc::samples::scene_kind_name(options.kind), cells,
                cells * svc::kFaceCount, options.face_size, options.face_size, out_dir.c_str(), seconds);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Write a procedural (or, with --textures, photographic) architectural scene as an\nsvc-input database."};
  std::string out_dir, kind = "hall", grid = "9,1,9", spacing = "0.5,1.0,0.5", origin;
  svc::samples::SceneOptions options;
  svc::command_line::Verbosity verbosity;
  app.add_option("OUT_DIR", out_dir, "Output directory (created if missing)")->required();
  std::vector<std::string> kinds;
  for (int k = 0; k < svc::samples::kSceneKinds; ++k)
    kinds.push_back(svc::samples::scene_kind_name(static_cast<svc::samples::SceneKind>(k)));
  app.add_option("--kind", kind, "Scene: " + svc::samples::scene_kind_names())
      ->capture_default_str()
      ->check(CLI::IsMember(kinds));
  app.add_option("--grid", grid, "Cells along x,y,z (y counts layers)")->capture_default_str();
  app.add_option("--spacing", spacing, "Cell spacing in metres: S or SX,SY,SZ")->capture_default_str();
  app.add_option("--origin", origin,
                 "Centre of cell (0,0,0), X,Y,Z in metres (default: the grid centred, lowest layer at eye height); "
                 "a second database with the first one's origin and a larger grid extends it (svc add)");
  std::string eye;
  app.add_option("--eye", eye,
                 "Write one cell, its cameras at X,Y,Z of the scene the grid, spacing and origin describe (a 1x1x1 "
                 "database: the view between cells, as a ground truth)");
  app.add_option("--face-size", options.face_size, "Square face size in pixels")->capture_default_str();
  app.add_option("--seed", options.seed, "Layout and texture variation")->capture_default_str();
  int threads = 0;
  app.add_option("--threads", threads, "Faces rendered at once, 0: all cores (the output does not depend on it)")
      ->check(svc::command_line::integer_in(0, 256))
      ->capture_default_str();
  app.add_option("--textures", options.textures,
                 "Photographic variant: map the images of this folder (jpg, tga, png, ...) "
                 "onto walls, floors, furniture and sky, chosen by file name (brick, "
                 "concrete, wood, metal, tile, wall, ceil, grass, sky); "
                 "scripts/fetch-textures.sh extracts a set");
  app.add_flag("--sparse", options.sparse, "Leave out cells whose centre is inside geometry");
  app.add_option("--supersample", options.supersample,
                 "N x N colour samples per pixel (antialiased edges); depth stays one sample per pixel")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  app.add_option("--exposure", options.exposure_stops,
                 "Exposure in stops above the default (daylight renders: about +1)")
      ->check(CLI::Range(-4.0, 4.0))
      ->capture_default_str();
  app.add_flag("--anisotropic", options.anisotropic,
               "Texture filtering that keeps detail on surfaces seen at grazing angles (as GPUs' anisotropic "
               "filtering does)");
  app.add_option("--texture-scale", options.texture_scale,
                 "Size of one repeat of each photographic texture, relative to the default (0.5: twice the detail "
                 "per metre)")
      ->check(CLI::Range(0.1, 10.0))
      ->capture_default_str();
  svc::command_line::add_verbosity_options(&app, &verbosity);
  bool overwrite = false;
  svc::command_line::add_overwrite_flag(&app, &overwrite);
  app.get_option("OUT_DIR")->check(svc::command_line::not_standard_output());
  app.footer(
      "Photographic hall and house (OpenArena textures, Debian openarena-081-textures):\n"
      "  textures=$(scripts/fetch-textures.sh)\n"
      "  svc-scene photo-hall/ --kind hall --textures \"$textures\"\n"
      "  svc-scene photo-house/ --kind house --textures \"$textures\"\n"
      "Rendered as the development corpus renders (bench/corpus.json):\n"
      "  svc-scene street/ --kind street --spacing 1 --supersample 2 --anisotropic --texture-scale 1.5 \\\n"
      "      --textures \"$(scripts/fetch-textures.sh --set ufoai)\"\n\n" +
      svc::command_line::exit_codes_help(false));
  if (auto exit_code = svc::command_line::parse(app, argc, argv, "svc-scene")) return *exit_code;

  std::vector<std::filesystem::path> inputs;
  if (!options.textures.empty()) inputs.push_back(options.textures);
  const svc::Status writable =
      svc::command_line::check_output(out_dir, svc::command_line::OutputKind::kFolder, overwrite, inputs);
  if (!writable.ok()) {
    std::fprintf(stderr, "svc-scene: %s\n", writable.message().c_str());
    return svc::command_line::kExitUsage;
  }
  svc::samples::parse_scene_kind(kind, &options.kind);
  std::vector<int> dims;
  if (!parse_list(grid, &dims) || dims.size() != 3) {
    std::fprintf(stderr, "svc-scene: --grid wants X,Y,Z, got \"%s\"\n", grid.c_str());
    return svc::command_line::kExitUsage;
  }
  std::vector<double> steps;
  if (!parse_list(spacing, &steps) || (steps.size() != 1 && steps.size() != 3)) {
    std::fprintf(stderr, "svc-scene: --spacing wants S or SX,SY,SZ, got \"%s\"\n", spacing.c_str());
    return svc::command_line::kExitUsage;
  }
  if (!origin.empty()) {
    std::vector<double> at;
    if (!parse_list(origin, &at) || at.size() != 3) {
      std::fprintf(stderr, "svc-scene: --origin wants X,Y,Z, got \"%s\"\n", origin.c_str());
      return svc::command_line::kExitUsage;
    }
    options.origin = std::array<double, 3>{at[0], at[1], at[2]};
  }
  if (!eye.empty()) {
    std::vector<double> at;
    if (!parse_list(eye, &at) || at.size() != 3) {
      std::fprintf(stderr, "svc-scene: --eye wants X,Y,Z, got \"%s\"\n", eye.c_str());
      return svc::command_line::kExitUsage;
    }
    options.eye = std::array<double, 3>{at[0], at[1], at[2]};
  }
  options.threads =
      threads > 0 ? threads : std::min(256, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  options.grid = {dims[0], dims[1], dims[2]};
  options.spacing = steps.size() == 1 ? std::array<double, 3>{steps[0], steps[0], steps[0]}
                                      : std::array<double, 3>{steps[0], steps[1], steps[2]};

  svc::command_line::stop_on_interrupt();
  int cells_written = 0;
  const auto start = std::chrono::steady_clock::now();
  const svc::Status status = write_scene(options, out_dir, verbosity, &cells_written);
  if (!status.ok()) return svc::command_line::report_failure("svc-scene", status);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_result(options, out_dir, cells_written, seconds, verbosity);
  return 0;
}
