// SPDX-License-Identifier: BSD-2-Clause
// Rules for where svc and svc-scene may write, checked before any work is done.
#pragma once

#include <filesystem>
#include <vector>

#include <CLI/CLI.hpp>

#include "svc/status.h"

namespace svc::command_line {

// Refuses "-" as an output: the tool writes only to named, seekable files and folders
// (an .svc file is written with its index patched in place, so standard output cannot
// hold one).
CLI::Validator not_standard_output();

enum class OutputKind { kFile, kFolder };

// Whether `output` may be written. An existing file or a non-empty folder is kept unless
// `overwrite` (-y); an input is never written over, with or without it: the output may
// not be an input, hold one (a folder around an input file), or be an existing file or
// folder inside an input folder. Errors are kInvalidArgument naming the path.
Status check_output(const std::filesystem::path& output, OutputKind kind, bool overwrite,
                    const std::vector<std::filesystem::path>& inputs);

// Adds -y/--overwrite to a command that writes.
void add_overwrite_flag(CLI::App* command, bool* overwrite);

}  // namespace svc::command_line
