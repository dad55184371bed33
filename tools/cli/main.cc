// SPDX-License-Identifier: BSD-2-Clause
// svc: encode, decode, check, inspect and verify spatial video databases.
#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/output_paths.h"
#include "database/database.h"
#ifdef SVC_WITH_BENCH
#include "cli/bench_command.h"
#endif

namespace {

using namespace svc;
using namespace svc::cli;
using namespace svc::command_line;

// What each encoder speed costs against speed 0 on the quick corpus (the range over its
// seven scenes; docs/bench.md, "Speed settings").
constexpr std::array<const char*, kMaxEncoderSpeed + 1> kSpeedCosts = {"",
                                                                       "+0.0 to +1.8 % bytes, 1.2-1.3x as fast",
                                                                       "+3.0 to +5.2 % bytes, 1.9-2.9x as fast",
                                                                       "+1.1 to +10.4 % bytes, 2.1-3.8x as fast",
                                                                       "+5.3 to +12.8 % bytes, 2.5-5.2x as fast",
                                                                       "+9.4 to +20.1 % bytes, 3.6-8.0x as fast"};

// Encoder options given as text, checked after parsing.
struct EncoderOptionText {
  std::string i_spacing = "3,1,3";
  std::string motion = "depth";
  std::string layout = "visibility";
  CLI::Option* layout_option = nullptr;  // given on the command line: wins over --speed's layout
  std::string quant_matrix = "flat";
  std::vector<std::string> disabled_tools;
  int speed = 0;
};

void add_threads_option(CLI::App* cmd, int* threads) {
  cmd->add_option("--threads", *threads, "Worker threads (0: all cores); the output does not depend on it")
      ->check(integer_in(0, 1024))
      ->capture_default_str();
}

void add_outside_paths_flag(CLI::App* cmd, bool* allow) {
  cmd->add_flag("--allow-outside-paths", *allow,
                "Let the manifest name images outside the database folder (absolute paths, ../)");
}

// Options shared by encode and demo.
void add_encoder_options(CLI::App* cmd, EncoderSettings* settings, EncoderOptionText* text) {
  cmd->add_option("-q,--quality", settings->quality, "Quality 1 (smallest) to 100 (best)")
      ->check(integer_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--qindex", settings->qindex, "Quantizer index 0 (finest) ..255 (overrides --quality)")
      ->check(integer_in(0, 255));
  cmd->add_option("--b-qindex-offset", settings->b_qindex_offset,
                  "Quantizer indices the B-faces use above the I-faces' (default: 26..42, chosen per database "
                  "from trial B-faces)")
      ->check(integer_in(0, 255));
  cmd->add_option("--cube-border", settings->cube_border_units,
                  "Border of B-faces' padded references in units of 16 luma samples, 1..4 (default 4: vectors "
                  "reach furthest past a face's edge)")
      ->check(integer_in(1, 4));
  add_threads_option(cmd, &settings->threads);
  cmd->add_flag("--intra-only", settings->intra_only, "Code every cell as an I-cube");
  cmd->add_flag("--depth", settings->depth, "Store every face's depth (readers decode it beside the color)");
  cmd->add_option("--depth-max-error", settings->depth_max_error,
                  "With --depth: largest error of a decoded inverse-depth code, 0 (lossless) ..255 "
                  "(units of 1/65535 of the near plane's inverse depth; docs/codec.md 8)")
      ->check(integer_in(0, 255))
      ->capture_default_str();
  cmd->add_option("--i-spacing", text->i_spacing, "I-cube spacing X,Y,Z (or N for all axes)")
      ->capture_default_str();
  int first_regular_speed = 0;
  while (first_regular_speed < kMaxEncoderSpeed && speed_layout(first_regular_speed) != CubeLayout::kRegular)
    ++first_regular_speed;
  text->layout_option =
      cmd->add_option("--layout", text->layout,
                      "I-cube layout: visibility (the --i-spacing lattice plus I-cubes where references see too "
                      "little) or regular (the lattice alone; the default from --speed " +
                          std::to_string(first_regular_speed) + " on)")
          ->check(CLI::IsMember({"visibility", "regular"}))
          ->capture_default_str();
  cmd->add_option("--motion", text->motion, "Motion source: depth (reprojection) or log (logarithmic search)")
      ->check(CLI::IsMember({"depth", "log"}))
      ->capture_default_str();
  cmd->add_option("--quant-matrix", text->quant_matrix,
                  "I-face residual quantization: flat (one step per transform size; best PSNR) or weighted "
                  "(coarser high frequencies)")
      ->check(CLI::IsMember({"flat", "weighted"}))
      ->capture_default_str();
  cmd->add_option("--disable-tool", text->disabled_tools,
                  "Do not use this coding tool (repeatable; to measure its gain): " +
                      comma_list(coding_tool_names()));
  std::string speeds;
  for (int speed = 1; speed <= kMaxEncoderSpeed; ++speed) {
    const std::vector<std::string> before = speed_disabled_tools(speed - 1);
    std::vector<std::string> added;
    for (const std::string& name : speed_disabled_tools(speed)) {
      if (std::find(before.begin(), before.end(), name) == before.end()) added.push_back(name);
    }
    speeds += "; " + std::to_string(speed) + " (" + kSpeedCosts[static_cast<size_t>(speed)] +
              "): " + (speed > 1 ? "also " : "") + "without " + comma_list(added);
    if (speed_layout(speed) != speed_layout(speed - 1)) speeds += ", regular layout";
  }
  cmd->add_option("--speed", text->speed,
                  "Encoder speed: 0 every coding tool (smallest files)" + speeds +
                      " (BD-rate of PSNR-Y against 0 and processor time, on the quick corpus; docs/bench.md, "
                      "\"Speed settings\")")
      ->check(integer_in(0, kMaxEncoderSpeed))
      ->capture_default_str();
}

// "K/N" with 1 <= K <= N <= kMaxShards.
bool parse_shard(const std::string& text, int* shard, int* count) {
  const size_t slash = text.find('/');
  if (slash == std::string::npos) return false;
  const char* end = text.data() + text.size();
  const auto k = std::from_chars(text.data(), text.data() + slash, *shard);
  const auto n = std::from_chars(text.data() + slash + 1, end, *count);
  return k.ec == std::errc() && k.ptr == text.data() + slash && n.ec == std::errc() && n.ptr == end &&
         *shard >= 1 && *shard <= *count && *count <= kMaxShards;
}

bool apply_encoder_options(EncoderSettings* settings, const EncoderOptionText& text) {
  if (!parse_triple(text.i_spacing, &settings->i_spacing)) {
    std::fprintf(stderr, "svc: --i-spacing takes X,Y,Z or N with positive integers, not '%s'\n",
                 text.i_spacing.c_str());
    return false;
  }
  settings->motion = text.motion == "log" ? MotionSearch::kLogarithmic : MotionSearch::kDepth;
  settings->tools.weighted_quant_matrix = text.quant_matrix == "weighted";
  if (Status status = apply_encoder_speed(settings, text.speed); !status.ok()) {
    std::fprintf(stderr, "svc: --speed: %s\n", status.message().c_str());
    return false;
  }
  if (text.layout_option == nullptr || text.layout_option->count() > 0) {
    settings->layout = text.layout == "regular" ? CubeLayout::kRegular : CubeLayout::kVisibility;
  }
  for (const std::string& name : text.disabled_tools) {
    if (Status status = disable_coding_tool(&settings->tools, name); !status.ok()) {
      std::fprintf(stderr, "svc: --disable-tool: %s\n", status.message().c_str());
      return false;
    }
  }
  return true;
}

bool parse_cell_option(const std::string& text, CellIndex* cell) {
  if (parse_cell(text, cell)) return true;
  std::fprintf(stderr, "svc: --cell takes X,Y,Z, not '%s'\n", text.c_str());
  return false;
}

bool parse_face_option(const std::string& text, Face* face) {
  const auto parsed = face_from_name(text);
  if (parsed) *face = *parsed;
  if (!parsed) std::fprintf(stderr, "svc: --face takes px, nx, py, ny, pz or nz, not '%s'\n", text.c_str());
  return parsed.has_value();
}

}  // namespace

int main(int argc, char** argv) {
  configure_image_loading();
  CLI::App app{"svc: spatial video codec for image-based impostor databases"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "svc 0.1.0");
  app.footer(command_line::exit_codes_help(true));

  EncodeOptions encode;
  EncoderOptionText encode_text;
  auto* encode_cmd = app.add_subcommand("encode", "Encode an svc-input database into an .svc file");
  encode_cmd->add_option("DB_DIR", encode.db_dir, "svc-input database folder")->required();
  encode_cmd->add_option("-o,--output", encode.output, "Output .svc file")
      ->required()
      ->check(not_standard_output());
  add_encoder_options(encode_cmd, &encode.settings, &encode_text);
  encode_cmd->add_flag("--psnr", encode.psnr,
                       "Decode the result and report PSNR-Y, PSNR-RGB and SSIM against the source");
  add_outside_paths_flag(encode_cmd, &encode.settings.allow_outside_paths);
  add_verbosity_options(encode_cmd, &encode.verbosity);
  std::string encode_shard;
  encode_cmd->add_option("--shard", encode_shard, "Write part K/N of a sharded encode (join with svc merge)");
  add_overwrite_flag(encode_cmd, &encode.overwrite);

  MergeOptions merge;
  auto* merge_cmd = app.add_subcommand("merge", "Join the part files of a sharded encode into one .svc file");
  merge_cmd->add_option("PARTS", merge.parts, "Part files from svc encode --shard K/N, in any order")->required();
  merge_cmd->add_option("-o,--output", merge.output, "Output .svc file")->required()->check(not_standard_output());
  add_verbosity_options(merge_cmd, &merge.verbosity);
  add_overwrite_flag(merge_cmd, &merge.overwrite);

  AddOptions add;
  auto* add_cmd = app.add_subcommand("add", "Add a database's new cells to an .svc file in place (crash-safe)");
  add_cmd->add_option("IN", add.input, "The .svc file to add to")->required();
  add_cmd->add_option("DB_DIR", add.db_dir, "svc-input database holding the cells to add")->required();
  add_threads_option(add_cmd, &add.settings.threads);
  add_outside_paths_flag(add_cmd, &add.settings.allow_outside_paths);
  add_verbosity_options(add_cmd, &add.verbosity);

  CheckOptions check;
  auto* check_cmd = app.add_subcommand(
      "check", "Check an svc-input database as the encoder reads it (manifest, every image), without encoding");
  check_cmd->add_option("DB_DIR", check.db_dir, "svc-input database folder")->required();
  add_threads_option(check_cmd, &check.threads);
  add_outside_paths_flag(check_cmd, &check.allow_outside_paths);
  add_verbosity_options(check_cmd, &check.verbosity);

  DecodeOptions decode;
  std::string decode_cell, decode_face;
  auto* decode_cmd = app.add_subcommand("decode", "Decode faces into an svc-input database of PNGs");
  decode_cmd->add_option("IN", decode.input, "Input .svc file")->required();
  decode_cmd->add_option("-o,--output", decode.output, "Output folder")->required()->check(not_standard_output());
  decode_cmd->add_option("--cell", decode_cell, "Only this cell, X,Y,Z");
  decode_cmd->add_option("--face", decode_face, "Only this face: px nx py ny pz nz");
  add_threads_option(decode_cmd, &decode.threads);
  add_verbosity_options(decode_cmd, &decode.verbosity);
  add_overwrite_flag(decode_cmd, &decode.overwrite);

  InfoOptions info;
  auto* info_cmd =
      app.add_subcommand("info", "Describe an .svc file: grid, coding settings, bytes per face type and cell");
  info_cmd->add_option("IN", info.input, "Input .svc file")->required();
  add_verbosity_options(info_cmd, &info.verbosity);

  VerifyOptions verify;
  auto* verify_cmd = app.add_subcommand("verify", "Check every CRC and decode every face");
  verify_cmd->add_option("IN", verify.input, "Input .svc file")->required();
  add_threads_option(verify_cmd, &verify.threads);
  add_verbosity_options(verify_cmd, &verify.verbosity);

  InspectOptions inspect;
  std::string inspect_cell, inspect_face;
  auto* inspect_cmd =
      app.add_subcommand("inspect", "Write a decoded face beside its macroblock classification as PNG");
  inspect_cmd->add_option("IN", inspect.input, "Input .svc file")->required();
  inspect_cmd->add_option("--cell", inspect_cell, "Cell X,Y,Z")->required();
  inspect_cmd->add_option("--face", inspect_face, "Face: px nx py ny pz nz")->required();
  inspect_cmd->add_option("-o,--output", inspect.output, "Output PNG")->required()->check(not_standard_output());
  inspect_cmd->add_option("--scale", inspect.scale, "Output pixels per face pixel (0: at least 512 pixels tall)")
      ->check(integer_in(0, 64))
      ->capture_default_str();
  add_verbosity_options(inspect_cmd, &inspect.verbosity);
  add_overwrite_flag(inspect_cmd, &inspect.overwrite);

  DemoOptions demo;
  std::string demo_kind = "hall";
  EncoderOptionText demo_text;
  auto* demo_cmd = app.add_subcommand("demo", "Generate the sample scene, encode it, decode random cells, report");
  demo_cmd->add_option("--kind", demo_kind, "Scene kind: hall or house")->capture_default_str();
  std::string demo_grid = "9,1,9";
  demo_cmd->add_option("--grid", demo_grid, "Scene cells X,Y,Z (or N for all axes)")->capture_default_str();
  demo_cmd->add_option("--face-size", demo.face_size, "Scene face size in pixels")
      ->check(integer_in(16, 1024))
      ->capture_default_str();
  demo_cmd->add_option("--keep", demo.keep_dir, "Keep the scene and .svc file in this folder")
      ->check(not_standard_output());
  add_encoder_options(demo_cmd, &demo.settings, &demo_text);
  add_verbosity_options(demo_cmd, &demo.verbosity);
  add_overwrite_flag(demo_cmd, &demo.overwrite);

#ifdef SVC_WITH_BENCH
  BenchSubcommand bench(app);
#endif

  if (auto exit_code = command_line::parse(app, argc, argv, "svc")) return *exit_code;
  stop_on_interrupt();

  if (encode_cmd->parsed()) {
    if (!apply_encoder_options(&encode.settings, encode_text)) return kExitUsage;
    if (!encode_shard.empty() && !parse_shard(encode_shard, &encode.shard, &encode.shard_count)) {
      std::fprintf(stderr, "svc: --shard takes K/N with 1 <= K <= N <= %d, not '%s'\n", kMaxShards,
                   encode_shard.c_str());
      return kExitUsage;
    }
    if (encode.shard_count > 0 && encode.psnr) {
      std::fprintf(stderr, "svc: --psnr measures a whole database; measure the merged file's, not a part's\n");
      return kExitUsage;
    }
    return encode_command(encode);
  }
  if (merge_cmd->parsed()) return merge_command(merge);
  if (add_cmd->parsed()) return add_command(add);
  if (check_cmd->parsed()) return check_command(check);
  if (decode_cmd->parsed()) {
    if (!decode_cell.empty()) {
      CellIndex cell;
      if (!parse_cell_option(decode_cell, &cell)) return kExitUsage;
      decode.cell = cell;
    }
    if (!decode_face.empty()) {
      Face face;
      if (!parse_face_option(decode_face, &face)) return kExitUsage;
      decode.face = face;
    }
    return decode_command(decode);
  }
  if (info_cmd->parsed()) return info_command(info);
  if (inspect_cmd->parsed()) {
    if (!parse_cell_option(inspect_cell, &inspect.cell) || !parse_face_option(inspect_face, &inspect.face)) {
      return kExitUsage;
    }
    return inspect_command(inspect);
  }
  if (verify_cmd->parsed()) return verify_command(verify);
  if (demo_cmd->parsed()) {
    if (!samples::parse_scene_kind(demo_kind, &demo.kind)) {
      std::fprintf(stderr, "svc: --kind takes hall or house, not '%s'\n", demo_kind.c_str());
      return kExitUsage;
    }
    if (!apply_encoder_options(&demo.settings, demo_text)) return kExitUsage;
    std::array<int32_t, 3> grid;
    if (!parse_triple(demo_grid, &grid)) {
      std::fprintf(stderr, "svc: --grid takes X,Y,Z or N with positive integers, not '%s'\n", demo_grid.c_str());
      return kExitUsage;
    }
    demo.grid = {grid[0], grid[1], grid[2]};
    return demo_command(demo);
  }
#ifdef SVC_WITH_BENCH
  if (bench.parsed()) return bench.run();
#endif
  return kExitUsage;
}
