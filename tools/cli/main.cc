// svc: encode, decode, inspect and verify spatial video databases.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/cli_util.h"
#include "cli/commands.h"
#include "command_line/command_line.h"
#include "command_line/output_paths.h"
#ifdef SVC_WITH_BENCH
#include "cli/bench_command.h"
#endif

namespace {

using namespace svc;
using namespace svc::cli;
using namespace svc::command_line;

// Encoder options given as text, checked after parsing.
struct EncoderOptionText {
  std::string i_spacing = "3,1,3";
  std::string motion = "depth";
  std::vector<std::string> disabled_tools;
};

// Options shared by encode and demo.
void add_encoder_options(CLI::App* cmd, EncoderSettings* settings, EncoderOptionText* text) {
  cmd->add_option("-q,--quality", settings->quality, "Quality 1 (smallest) to 100 (best)")
      ->check(integer_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--qindex", settings->qindex, "Quantiser index 0 (finest) ..255 (overrides --quality)")
      ->check(integer_in(0, 255));
  cmd->add_option("--threads", settings->threads, "Worker threads (0: all cores); output does not depend on it")
      ->check(integer_in(0, 1024))
      ->capture_default_str();
  cmd->add_flag("--intra-only", settings->intra_only, "Code every cell as an I-cube");
  cmd->add_option("--i-spacing", text->i_spacing, "I-cube spacing X,Y,Z (or N for all axes)")
      ->capture_default_str();
  cmd->add_option("--motion", text->motion, "Motion source: depth (reprojection) or log (logarithmic search)")
      ->check(CLI::IsMember({"depth", "log"}))
      ->capture_default_str();
  std::string tools;
  for (const std::string& name : coding_tool_names()) tools += (tools.empty() ? "" : ", ") + name;
  cmd->add_option("--disable-tool", text->disabled_tools,
                  "Do not use this coding tool (repeatable; to measure its gain): " + tools);
}

bool apply_encoder_options(EncoderSettings* settings, const EncoderOptionText& text) {
  if (!parse_triple(text.i_spacing, &settings->i_spacing)) {
    std::fprintf(stderr, "svc: --i-spacing takes X,Y,Z or N with positive integers, not '%s'\n",
                 text.i_spacing.c_str());
    return false;
  }
  settings->motion = text.motion == "log" ? MotionSearch::kLogarithmic : MotionSearch::kDepth;
  for (const std::string& name : text.disabled_tools) {
    if (Status status = disable_coding_tool(&settings->tools, name); !status.ok()) {
      std::fprintf(stderr, "svc: --disable-tool: %s\n", status.message().c_str());
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
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
  encode_cmd->add_flag("--json", encode.json, "Print the summary as JSON");
  encode_cmd->add_flag("--quiet", encode.quiet, "Print nothing on success");
  add_overwrite_flag(encode_cmd, &encode.overwrite);

  AddOptions add;
  auto* add_cmd = app.add_subcommand("add", "Add a database's new cells to an .svc file in place (crash-safe)");
  add_cmd->add_option("IN", add.input, "The .svc file to add to")->required();
  add_cmd->add_option("DB_DIR", add.db_dir, "svc-input database holding the cells to add")->required();
  add_cmd->add_option("--threads", add.threads, "Worker threads (0: all cores); output does not depend on it")
      ->check(integer_in(0, 1024))
      ->capture_default_str();
  add_cmd->add_flag("--quiet", add.quiet, "Print nothing on success");

  DecodeOptions decode;
  std::string decode_cell, decode_face;
  auto* decode_cmd = app.add_subcommand("decode", "Decode faces into an svc-input database of PNGs");
  decode_cmd->add_option("IN", decode.input, "Input .svc file")->required();
  decode_cmd->add_option("-o,--output", decode.output, "Output folder")->required()->check(not_standard_output());
  decode_cmd->add_option("--cell", decode_cell, "Only this cell, X,Y,Z");
  decode_cmd->add_option("--face", decode_face, "Only this face: px nx py ny pz nz");
  decode_cmd->add_flag("--quiet", decode.quiet, "Print nothing on success");
  add_overwrite_flag(decode_cmd, &decode.overwrite);

  InfoOptions info;
  auto* info_cmd = app.add_subcommand("info", "Describe an .svc file: grid, coding settings, bytes");
  info_cmd->add_option("IN", info.input, "Input .svc file")->required();
  info_cmd->add_flag("--json", info.json, "Print as JSON");

  VerifyOptions verify;
  auto* verify_cmd = app.add_subcommand("verify", "Check every CRC and decode every face");
  verify_cmd->add_option("IN", verify.input, "Input .svc file")->required();
  verify_cmd->add_flag("--quiet", verify.quiet, "Print nothing on success");

  InspectOptions inspect;
  std::string inspect_cell, inspect_face;
  auto* inspect_cmd =
      app.add_subcommand("inspect", "Write a decoded face beside its macroblock classification as PNG");
  inspect_cmd->add_option("IN", inspect.input, "Input .svc file")->required();
  inspect_cmd->add_option("--cell", inspect_cell, "Cell X,Y,Z")->required();
  inspect_cmd->add_option("--face", inspect_face, "Face: px nx py ny pz nz")->required();
  inspect_cmd->add_option("-o,--output", inspect.output, "Output PNG")->required()->check(not_standard_output());
  add_overwrite_flag(inspect_cmd, &inspect.overwrite);

  DemoOptions demo;
  std::string demo_kind = "hall";
  EncoderOptionText demo_text;
  auto* demo_cmd = app.add_subcommand("demo", "Generate the sample scene, encode it, decode random cells, report");
  demo_cmd->add_option("--kind", demo_kind, "Scene kind: hall or house")->capture_default_str();
  demo_cmd->add_option("--keep", demo.keep_dir, "Keep the scene and .svc file in this folder")
      ->check(not_standard_output());
  add_encoder_options(demo_cmd, &demo.settings, &demo_text);
  add_overwrite_flag(demo_cmd, &demo.overwrite);

#ifdef SVC_WITH_BENCH
  BenchSubcommand bench(app);
#endif

  if (auto exit_code = command_line::parse(app, argc, argv, "svc")) return *exit_code;

  if (encode_cmd->parsed()) {
    if (!apply_encoder_options(&encode.settings, encode_text)) return kExitUsage;
    return encode_command(encode);
  }
  if (add_cmd->parsed()) return add_command(add);
  if (decode_cmd->parsed()) {
    if (!decode_cell.empty()) {
      CellIndex cell;
      if (!parse_cell(decode_cell, &cell)) {
        std::fprintf(stderr, "svc: --cell takes X,Y,Z, not '%s'\n", decode_cell.c_str());
        return kExitUsage;
      }
      decode.cell = cell;
    }
    if (!decode_face.empty()) {
      decode.face = face_from_name(decode_face);
      if (!decode.face) {
        std::fprintf(stderr, "svc: --face takes px, nx, py, ny, pz or nz, not '%s'\n", decode_face.c_str());
        return kExitUsage;
      }
    }
    return decode_command(decode);
  }
  if (info_cmd->parsed()) return info_command(info);
  if (inspect_cmd->parsed()) {
    const auto face = face_from_name(inspect_face);
    if (!parse_cell(inspect_cell, &inspect.cell) || !face) {
      std::fprintf(stderr, "svc: inspect takes --cell X,Y,Z and --face px|nx|py|ny|pz|nz\n");
      return kExitUsage;
    }
    inspect.face = *face;
    return inspect_command(inspect);
  }
  if (verify_cmd->parsed()) return verify_command(verify);
  if (demo_cmd->parsed()) {
    if (!samples::parse_scene_kind(demo_kind, &demo.kind)) {
      std::fprintf(stderr, "svc: --kind takes hall or house, not '%s'\n", demo_kind.c_str());
      return kExitUsage;
    }
    if (!apply_encoder_options(&demo.settings, demo_text)) return kExitUsage;
    return demo_command(demo);
  }
#ifdef SVC_WITH_BENCH
  if (bench.parsed()) return bench.run();
#endif
  return kExitUsage;
}
