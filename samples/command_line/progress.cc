// SPDX-License-Identifier: BSD-2-Clause
#include "command_line/progress.h"

#include <cstdio>

#include <unistd.h>

namespace svc::command_line {

bool Verbosity::show_progress() const {
  if (quiet || json || no_progress) return false;
  return progress || ::isatty(STDERR_FILENO);
}

void add_verbosity_options(CLI::App* command, Verbosity* verbosity, bool json) {
  if (json)
    command->add_flag("--json", verbosity->json, "Print the result as JSON on standard output, nothing else");
  command->add_flag("--quiet", verbosity->quiet, "Print nothing but errors");
  command->add_flag("-v,--verbose", verbosity->verbose, "Print more detail (per-stage timings, per-cell results)");
  auto* on =
      command->add_flag("--progress", verbosity->progress, "Draw the progress bar even when not on a terminal");
  auto* off = command->add_flag("--no-progress", verbosity->no_progress, "Never draw the progress bar");
  on->excludes(off);
}

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(uint64_t done, uint64_t total) {
  if (!enabled_ || total == 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  drawn_ = true;
  const int width = 30;
  const double fraction = static_cast<double>(done) / static_cast<double>(total);
  const int filled = static_cast<int>(fraction * width);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = done > 0 ? elapsed * (static_cast<double>(total) - done) / done : 0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %llu/%llu %3.0f%%  %.1fs elapsed, %.1fs left ", label_.c_str(), filled,
               "##############################", width - filled, "", static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(total), fraction * 100.0, elapsed, eta);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (enabled_ && drawn_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
  drawn_ = false;
}

}  // namespace svc::command_line
