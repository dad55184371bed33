// SPDX-License-Identifier: BSD-2-Clause
#include "command_line/output_paths.h"

#include <string>

namespace svc::command_line {

namespace fs = std::filesystem;

namespace {

fs::path absolute_form(const fs::path& path) {
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(path, ec);
  return ec ? fs::absolute(path).lexically_normal() : canonical;
}

// Whether `path` is `folder` or lies under it.
bool is_within(const fs::path& path, const fs::path& folder) {
  auto p = path.begin();
  for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
    if (f->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *f) return false;
  }
  return true;
}

Status refused(const fs::path& output, const std::string& why) {
  return Status(ErrorCode::kInvalidArgument, "will not write " + output.string() + ": " + why);
}

bool is_empty_folder(const fs::path& path) {
  std::error_code ec;
  return fs::is_empty(path, ec) && !ec;
}

Status check_against_input(const fs::path& output, const fs::path& input) {
  const fs::path out = absolute_form(output);
  const fs::path in = absolute_form(input);
  std::error_code ec;
  if (out == in) return refused(output, "it is the input being read");
  if (is_within(in, out)) return refused(output, "it holds the input " + input.string());
  if (fs::is_directory(in, ec) && is_within(out, in) && fs::exists(out, ec)) {
    return refused(output, "it is part of the input " + input.string());
  }
  return Status::Ok();
}

}  // namespace

CLI::Validator not_standard_output() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        if (path != "-") return {};
        return "standard output ('-') is not supported: the output must be a named file or folder "
               "(an .svc file needs a seekable file)";
      },
      "PATH");
}

Status check_output(const fs::path& output, OutputKind kind, bool overwrite, const std::vector<fs::path>& inputs) {
  for (const fs::path& input : inputs) {
    Status status = check_against_input(output, input);
    if (!status.ok()) return status;
  }
  std::error_code ec;
  if (!fs::exists(output, ec)) return Status::Ok();
  const bool folder = fs::is_directory(output, ec);
  if (kind == OutputKind::kFile && folder) return refused(output, "it is a folder");
  if (kind == OutputKind::kFolder && !folder) return refused(output, "it is a file, not a folder");
  if (overwrite || (folder && is_empty_folder(output))) return Status::Ok();
  return refused(output,
                 folder ? "the folder is not empty (-y to replace it)" : "the file exists (-y to overwrite it)");
}

void add_overwrite_flag(CLI::App* command, bool* overwrite) {
  command->add_flag("-y,--overwrite", *overwrite, "Replace an existing output file or folder (never the input)");
}

}  // namespace svc::command_line
