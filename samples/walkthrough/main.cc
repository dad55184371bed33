// SPDX-License-Identifier: BSD-2-Clause
// svc-walkthrough: replays a viewer path through an .svc database and reports how long
// the viewer waits for the six faces of each cell it enters, with the reader's
// background prefetch on and off.
//
//   svc-walkthrough IN.svc [--path FILE] [--speed CELLS_PER_S] [--no-prefetch] [--json]
//                          [--steps N] [--realtime] [--prefetch-threads N]
//                          [--face-cache-mb MB] [--coefficient-cache-mb MB]
//                          [--reference-cache-mb MB]
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command_line/command_line.h"
#include "command_line/report.h"
#include "walkthrough/replay.h"

namespace {

using svc::walkthrough::ReplayResult;

nlohmann::json to_json(const ReplayResult& r) {
  const svc::ReaderStats& s = r.stats;
  return {
      {"prefetch", r.prefetch},
      {"steps", r.steps},
      {"simulated_seconds", r.simulated_seconds},
      {"wall_seconds", r.wall_seconds},
      {"latency_ms", {{"p50", r.p50_ms}, {"p99", r.p99_ms}, {"max", r.max_ms}, {"mean", r.mean_ms}}},
      {"steps_waiting_on_decode", r.steps_waiting},
      {"face_cache_hit_rate", r.face_hit_rate},
      {"coefficient_cache_hit_rate", r.coefficient_hit_rate},
      {"bytes_read", s.bytes_read},
      {"chunks_read", s.chunks_read},
      {"intra_faces_parsed", s.intra_faces_parsed},
      {"predicted_faces_decoded", s.predicted_faces_decoded},
      {"prefetch_faces", s.prefetch_faces},
      {"prefetch_dropped", s.prefetch_dropped},
      {"memory_held_bytes", r.memory_held},
      {"memory_peak_bytes", r.memory_peak},
      {"face_cache",
       {{"entries", s.face_cache.entries},
        {"bytes", s.face_cache.bytes_held},
        {"budget", s.face_cache.budget_bytes},
        {"evictions", s.face_cache.evictions}}},
      {"coefficient_cache",
       {{"entries", s.coefficient_cache.entries},
        {"bytes", s.coefficient_cache.bytes_held},
        {"budget", s.coefficient_cache.budget_bytes},
        {"evictions", s.coefficient_cache.evictions}}},
      {"reference_cache",
       {{"entries", s.reference_cache.entries},
        {"bytes", s.reference_cache.bytes_held},
        {"budget", s.reference_cache.budget_bytes},
        {"evictions", s.reference_cache.evictions}}},
  };
}

std::string mib(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f MiB", bytes / 1048576.0);
  return text;
}

void print_table(const std::vector<ReplayResult>& runs) {
  auto row = [&](const char* label, auto&& cell) {
    std::printf("  %-34s", label);
    for (const ReplayResult& r : runs) std::printf(" %18s", cell(r).c_str());
    std::printf("\n");
  };
  auto fixed = [](double v, int digits) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", digits, v);
    return std::string(text);
  };
  row("", [](const ReplayResult& r) { return std::string(r.prefetch ? "prefetch" : "on demand"); });
  row("steps (cells entered)", [](const ReplayResult& r) { return std::to_string(r.steps); });
  row("latency p50 (ms)", [&](const ReplayResult& r) { return fixed(r.p50_ms, 3); });
  row("latency p99 (ms)", [&](const ReplayResult& r) { return fixed(r.p99_ms, 3); });
  row("latency max (ms)", [&](const ReplayResult& r) { return fixed(r.max_ms, 3); });
  row("steps waiting on decoding", [](const ReplayResult& r) { return std::to_string(r.steps_waiting); });
  row("face cache hit rate", [&](const ReplayResult& r) { return fixed(100 * r.face_hit_rate, 1) + " %"; });
  row("semi-decoded I-face hit rate", [&](const ReplayResult& r) {
    return r.coefficient_hit_rate < 0 ? std::string("- (none asked)")
                                      : fixed(100 * r.coefficient_hit_rate, 1) + " %";
  });
  row("faces decoded by prefetch", [](const ReplayResult& r) { return std::to_string(r.stats.prefetch_faces); });
  row("bytes read", [](const ReplayResult& r) { return mib(r.stats.bytes_read); });
  row("memory held at end", [](const ReplayResult& r) { return mib(r.memory_held); });
  row("memory peak (three caches)", [](const ReplayResult& r) { return mib(r.memory_peak); });
  row("simulated walk (s)", [&](const ReplayResult& r) { return fixed(r.simulated_seconds, 1); });
  row("replay wall time (s)", [&](const ReplayResult& r) { return fixed(r.wall_seconds, 2); });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Replays a viewer path through an .svc database and reports the latency of the six faces of "
      "each cell entered, with background prefetch on and off."};
  std::string input, path_file;
  double speed = 1.0;
  bool no_prefetch = false, json = false, realtime = false;
  int steps = 200;
  svc::ReaderSettings settings = svc::default_reader_settings();
  double face_mb = settings.face_cache_bytes / 1048576.0;
  double coefficient_mb = settings.coefficient_cache_bytes / 1048576.0;
  double reference_mb = settings.reference_cache_bytes / 1048576.0;
  app.add_option("input", input, "the .svc file")->required()->check(CLI::ExistingFile);
  app.add_option("--path", path_file,
                 "waypoints, one \"x y z\" world position per line, '#' starts a comment "
                 "(default: a serpentine through every cell)")
      ->check(CLI::ExistingFile);
  app.add_option("--speed", speed, "viewer speed in cells per second")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_flag("--no-prefetch", no_prefetch, "only the run without prefetch");
  app.add_flag("--json", json, "print JSON instead of a table");
  app.add_option("--steps", steps, "stop after this many cells entered; 0 = the whole path")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--realtime", realtime,
               "sleep the whole interval between cells (default: skip time in which nothing runs)");
  app.add_option("--prefetch-threads", settings.prefetch_threads, "prefetch workers")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--face-cache-mb", face_mb, "decoded-face cache budget")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--coefficient-cache-mb", coefficient_mb, "semi-decoded I-face cache budget")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--reference-cache-mb", reference_mb, "reconstructed and padded reference I-face cache budget")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.footer(svc::command_line::exit_codes_help(true));
  if (auto exit_code = svc::command_line::parse(app, argc, argv, "svc-walkthrough")) return *exit_code;
  settings.face_cache_bytes = static_cast<uint64_t>(face_mb * 1048576.0);
  settings.coefficient_cache_bytes = static_cast<uint64_t>(coefficient_mb * 1048576.0);
  settings.reference_cache_bytes = static_cast<uint64_t>(reference_mb * 1048576.0);

  auto reader = svc::Reader::open(input, settings);
  if (!reader.ok()) return svc::command_line::report_failure("svc-walkthrough", reader.status());
  std::vector<svc::walkthrough::Position> path;
  if (path_file.empty()) {
    path = svc::walkthrough::builtin_path(**reader);
  } else {
    auto loaded = svc::walkthrough::read_path_file(path_file);
    if (!loaded.ok()) return svc::command_line::report_failure("svc-walkthrough", loaded.status());
    path = std::move(loaded).value();
  }
  const svc::FileInfo info = (*reader)->info();
  reader->reset();

  std::vector<ReplayResult> runs;
  for (bool prefetch : {true, false}) {
    if (prefetch && no_prefetch) continue;
    svc::walkthrough::ReplayOptions options;
    options.cells_per_second = speed;
    options.prefetch = prefetch;
    options.max_steps = steps;
    options.realtime = realtime;
    options.reader = settings;
    auto result = svc::walkthrough::replay(input, path, options);
    if (!result.ok()) return svc::command_line::report_failure("svc-walkthrough", result.status());
    if (result->steps == 0) {
      std::fprintf(stderr,
                   "svc-walkthrough: the path never enters a cell of %s (grid origin %g,%g,%g, spacing "
                   "%g,%g,%g)\n",
                   input.c_str(), info.grid_origin[0], info.grid_origin[1], info.grid_origin[2],
                   info.grid_spacing[0], info.grid_spacing[1], info.grid_spacing[2]);
      return svc::command_line::kExitFailure;
    }
    runs.push_back(std::move(result).value());
  }

  if (json) {
    nlohmann::json out = {{"command", "svc-walkthrough"},
                          {"input", input},
                          {"face_size", {info.face_width, info.face_height}},
                          {"grid", info.grid_dims},
                          {"path", path_file.empty() ? "built-in" : path_file},
                          {"waypoints", path.size()},
                          {"speed_cells_per_s", speed},
                          {"prefetch_threads", settings.prefetch_threads},
                          {"runs", nlohmann::json::array()}};
    for (const ReplayResult& r : runs) out["runs"].push_back(to_json(r));
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
  }
  std::printf("svc-walkthrough %s: grid %dx%dx%d, faces %dx%d, %s path (%zu waypoints), %.3g cells/s\n",
              input.c_str(), info.grid_dims[0], info.grid_dims[1], info.grid_dims[2], info.face_width,
              info.face_height, path_file.empty() ? "built-in" : "file", path.size(), speed);
  std::printf("  (latency: time to obtain the entered cell's six faces as RGB; prefetch run starts warm)\n");
  print_table(runs);
  return 0;
}
