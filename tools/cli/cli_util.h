// SPDX-License-Identifier: BSD-2-Clause
// Shared pieces of the svc command-line tool.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_line/progress.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc::cli {

using command_line::ProgressBar;
using command_line::Verbosity;
using json = nlohmann::ordered_json;

// Prints "svc: <message>" on stderr and returns the exit status for it. After SIGINT or
// SIGTERM it reports the interruption instead and returns 128 + the signal number.
int report_error(const Status& status);

// For progress callbacks: false once SIGINT or SIGTERM asked the program to stop.
bool keep_going();

// Prints a command's JSON result on standard output.
void print_json(const json& value);

// One face's statistics as every --json output names them.
json face_type_stats_json(const FaceTypeStats& stats);

// "  I-faces  N faces  SIZE  macroblocks: ..." for the human-readable summaries.
void print_face_type_stats(const char* name, const FaceTypeStats& stats);

// "X,Y,Z" -> CellIndex.
bool parse_cell(const std::string& text, CellIndex* out);
// "X,Y,Z" or "N" (all axes) -> three positive integers.
bool parse_triple(const std::string& text, std::array<int32_t, 3>* out);

// "cells/X_Y_Z": where svc-input databases written by svc keep a cell's faces.
std::string cell_folder(const CellIndex& cell);

std::string human_bytes(uint64_t bytes);

// "a, b, c" (empty for no names).
std::string comma_list(const std::vector<std::string>& names);

// Writes an 8-bit RGB PNG.
Status write_png(const std::filesystem::path& path, const ImageRGB8& image);

}  // namespace svc::cli
