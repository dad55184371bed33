// SPDX-License-Identifier: BSD-2-Clause
// Command-line conventions shared by svc and svc-scene: one set of exit codes, every
// message prefixed with the program's name, numeric options that say what is wrong.
#pragma once

#include <charconv>
#include <cstdio>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace svc::command_line {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;  // the work failed: unreadable or invalid input, I/O error
constexpr int kExitUsage = 2;    // the command line is wrong (unknown option, bad value)
constexpr int kExitCorrupt = 3;  // a damaged .svc file

// The --help footer that lists the exit codes; `corrupt` when the program reads .svc files.
inline std::string exit_codes_help(bool corrupt) {
  std::string text =
      "Exit status: 0 success; 1 the work failed (unreadable or invalid input, I/O error); "
      "2 usage error (bad command line or setting)";
  if (corrupt) text += "; 3 damaged .svc file";
  return text + "; 130 or 143 stopped by SIGINT (Ctrl-C) or SIGTERM, nothing left behind.";
}

// Parses the command line. Returns the status to exit with when the program should stop
// here (help or version printed: 0; any usage error, reported as "PROGRAM: ...": 2), or
// nothing when it should go on.
inline std::optional<int> parse(CLI::App& app, int argc, char** argv, const char* program) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(error);
    std::fprintf(stderr, "%s: %s\nRun with --help for more information.\n", program, error.what());
    return kExitUsage;
  }
}

// A whole number in lo..hi; "abc" is reported as not a number, 500 as out of range.
inline CLI::Validator integer_in(long long lo, long long hi) {
  const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (error == std::errc::result_out_of_range) return "'" + text + "' is outside " + range;
        if (error != std::errc() || stop != end) return "'" + text + "' is not a whole number";
        if (value < lo || value > hi) return "'" + text + "' is outside " + range;
        return {};
      },
      "INT in " + range);
}

}  // namespace svc::command_line
