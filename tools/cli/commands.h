// SPDX-License-Identifier: BSD-2-Clause
// The svc tool's subcommands. Each returns the process exit status.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "command_line/progress.h"
#include "scene/scene.h"
#include "svc/encoder.h"
#include "svc/types.h"

namespace svc::cli {

struct EncodeOptions {
  std::filesystem::path db_dir;
  std::filesystem::path output;
  EncoderSettings settings;
  bool psnr = false;  // measure PSNR-Y, PSNR-RGB and SSIM of the result against the source
  command_line::Verbosity verbosity;
  bool overwrite = false;  // -y: replace an existing output (never the input)
  int shard = 0;           // --shard K/N: write part K of N (0: the whole database)
  int shard_count = 0;
};

struct MergeOptions {
  std::vector<std::filesystem::path> parts;
  std::filesystem::path output;
  command_line::Verbosity verbosity;
  bool overwrite = false;  // -y: replace an existing output (never a part)
};

struct DecodeOptions {
  std::filesystem::path input;
  std::filesystem::path output;
  std::optional<CellIndex> cell;
  std::optional<Face> face;
  int threads = 0;
  command_line::Verbosity verbosity;
  bool overwrite = false;  // -y: replace an existing output (never the input)
};

struct InfoOptions {
  std::filesystem::path input;
  command_line::Verbosity verbosity;
};

struct VerifyOptions {
  std::filesystem::path input;
  int threads = 0;
  command_line::Verbosity verbosity;
};

struct CheckOptions {
  std::filesystem::path db_dir;
  int threads = 0;
  bool allow_outside_paths = false;
  command_line::Verbosity verbosity;
};

struct InspectOptions {
  std::filesystem::path input;
  std::filesystem::path output;  // PNG
  CellIndex cell;
  Face face = Face::kPX;
  int scale = 0;  // pixels per face pixel; 0: enough for a sheet at least 512 pixels tall
  command_line::Verbosity verbosity;
  bool overwrite = false;  // -y: replace an existing output (never the input)
};

struct AddOptions {
  std::filesystem::path input;   // .svc file, updated in place
  std::filesystem::path db_dir;  // svc-input database with the cells to add
  AddSettings settings;
  command_line::Verbosity verbosity;
};

struct DemoOptions {
  samples::SceneKind kind = samples::SceneKind::kHall;
  std::array<int, 3> grid = samples::SceneOptions{}.grid;
  int face_size = samples::SceneOptions{}.face_size;
  std::filesystem::path keep_dir;  // empty: a temporary folder, removed at the end
  EncoderSettings settings;
  command_line::Verbosity verbosity;
  bool overwrite = false;  // -y: replace an existing output (never the input)
};

int encode_command(const EncodeOptions& options);
int merge_command(const MergeOptions& options);
int decode_command(const DecodeOptions& options);
int info_command(const InfoOptions& options);
int verify_command(const VerifyOptions& options);
int check_command(const CheckOptions& options);
int demo_command(const DemoOptions& options);
int add_command(const AddOptions& options);
int inspect_command(const InspectOptions& options);

}  // namespace svc::cli
