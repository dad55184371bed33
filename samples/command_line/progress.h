// SPDX-License-Identifier: BSD-2-Clause
// What svc and svc-scene print while they work: a one-line progress bar on stderr, and
// the options that decide whether it is drawn (--quiet, --json, --progress,
// --no-progress, -v).
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace svc::command_line {

// How much a command prints. Progress is drawn on a terminal only, unless forced with
// --progress; never with --quiet or --json (standard output then holds only JSON).
struct Verbosity {
  bool json = false;
  bool quiet = false;
  bool verbose = false;
  bool progress = false;     // --progress: draw even when stderr is not a terminal
  bool no_progress = false;  // --no-progress
  bool show_progress() const;
  // The human-readable summary on standard output.
  bool show_summary() const { return !quiet && !json; }
};

// Adds -v/--verbose, --quiet, --progress and --no-progress, and --json when `json`.
void add_verbosity_options(CLI::App* command, Verbosity* verbosity, bool json = true);

// A one-line progress bar on stderr. Not thread-safe: one thread updates it.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  void update(uint64_t done, uint64_t total);
  // Clears the line, so that what follows starts on a clean line.
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace svc::command_line
