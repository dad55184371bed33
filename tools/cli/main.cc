// svc: encode, decode, check, inspect and verify spatial video databases.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/output_paths.h"
#ifdef SVC_WITH_BENCH
#include "cli/bench_command.h"
#endif

namespace {

using namespace svc;
using namespace svc::cli;
using namespace svc::command_line;

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
void add_encoder_options(CLI::App* cmd, EncoderSettings* settings, std::string* i_spacing, std::string* motion) {
  cmd->add_option("-q,--quality", settings->quality, "Quality 1 (smallest) to 100 (best)")
      ->check(integer_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--qscale", settings->quant_scale, "Quantiser scale 1..112 (overrides --quality)")
      ->check(integer_in(1, 112));
  add_threads_option(cmd, &settings->threads);
  cmd->add_flag("--intra-only", settings->intra_only, "Code every cell as an I-cube");
  cmd->add_option("--i-spacing", *i_spacing, "I-cube spacing X,Y,Z (or N for all axes)")->capture_default_str();
  cmd->add_option("--motion", *motion, "Motion source: depth (reprojection) or log (logarithmic search)")
      ->check(CLI::IsMember({"depth", "log"}))
      ->capture_default_str();
}

bool apply_encoder_options(EncoderSettings* settings, const std::string& i_spacing, const std::string& motion) {
  if (!parse_triple(i_spacing, &settings->i_spacing)) {
    std::fprintf(stderr, "svc: --i-spacing takes X,Y,Z or N with positive integers, not '%s'\n", i_spacing.c_str());
    return false;
  }
  settings->motion = motion == "log" ? MotionSearch::kLogarithmic : MotionSearch::kDepth;
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
  CLI::App app{"svc: spatial video codec for image-based impostor databases"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "svc 0.1.0");
  app.footer(command_line::exit_codes_help(true));

  EncodeOptions encode;
  std::string encode_spacing = "3,1,3", encode_motion = "depth";
  auto* encode_cmd = app.add_subcommand("encode", "Encode an svc-input database into an .svc file");
  encode_cmd->add_option("DB_DIR", encode.db_dir, "svc-input database folder")->required();
  encode_cmd->add_option("-o,--output", encode.output, "Output .svc file")
      ->required()
      ->check(not_standard_output());
  add_encoder_options(encode_cmd, &encode.settings, &encode_spacing, &encode_motion);
  encode_cmd->add_flag("--psnr", encode.psnr,
                       "Decode the result and report PSNR-Y, PSNR-RGB and SSIM against the source");
  add_outside_paths_flag(encode_cmd, &encode.settings.allow_outside_paths);
  add_verbosity_options(encode_cmd, &encode.verbosity);
  add_overwrite_flag(encode_cmd, &encode.overwrite);

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
  std::string demo_kind = "hall", demo_spacing = "3,1,3", demo_motion = "depth";
  auto* demo_cmd = app.add_subcommand("demo", "Generate the sample scene, encode it, decode random cells, report");
  demo_cmd->add_option("--kind", demo_kind, "Scene kind: hall or house")->capture_default_str();
  demo_cmd->add_option("--keep", demo.keep_dir, "Keep the scene and .svc file in this folder")
      ->check(not_standard_output());
  add_encoder_options(demo_cmd, &demo.settings, &demo_spacing, &demo_motion);
  add_overwrite_flag(demo_cmd, &demo.overwrite);

#ifdef SVC_WITH_BENCH
  BenchSubcommand bench(app);
#endif

  if (auto exit_code = command_line::parse(app, argc, argv, "svc")) return *exit_code;
  stop_on_interrupt();

  if (encode_cmd->parsed()) {
    if (!apply_encoder_options(&encode.settings, encode_spacing, encode_motion)) return kExitUsage;
    return encode_command(encode);
  }
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
    if (!apply_encoder_options(&demo.settings, demo_spacing, demo_motion)) return kExitUsage;
    return demo_command(demo);
  }
#ifdef SVC_WITH_BENCH
  if (bench.parsed()) return bench.run();
#endif
  return kExitUsage;
}
