// SPDX-License-Identifier: BSD-2-Clause
#include "cli/bench_command.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "baseline/baseline.h"
#include "cli/cli_util.h"
#include "command_line/command_line.h"
#include "command_line/interrupt.h"
#include "command_line/output_paths.h"
#include "command_line/progress.h"
#include "svc_bench.h"

namespace svc::cli {

using command_line::add_overwrite_flag;
using command_line::check_output;
using command_line::not_standard_output;
using command_line::OutputKind;

namespace {

namespace fs = std::filesystem;

// Removes what an unfinished run wrote: the work folder, and the output folder when this
// run created it and nothing else is in it.
void remove_unfinished(const fs::path& out_dir, bool out_dir_existed) {
  std::error_code ec;
  fs::remove_all(out_dir / "work", ec);
  if (!out_dir_existed && fs::is_empty(out_dir, ec)) fs::remove(out_dir, ec);
}

// The benchmark cannot be cancelled from inside; on SIGINT or SIGTERM this watcher
// removes its unfinished output and ends the program with the signal's exit status.
class InterruptWatcher {
 public:
  InterruptWatcher(fs::path out_dir, bool out_dir_existed)
      : thread_([this, out_dir, out_dir_existed] {
          while (!done_) {
            if (command_line::interrupted()) {
              std::fprintf(stderr, "\nsvc: stopped by %s; removing %s\n", command_line::interrupting_signal_name(),
                           (out_dir / "work").string().c_str());
              remove_unfinished(out_dir, out_dir_existed);
              std::_Exit(command_line::interrupted_exit_code());
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
          }
        }) {}
  ~InterruptWatcher() {
    done_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// --json: the command, its input and output as the other commands name them, and the
// results.json just written.
int print_bench_json(const bench::BenchOptions& options, const bench::BenchResults& results) {
  std::ifstream file(options.out_dir / "results.json");
  const json written = json::parse(file, nullptr, false);
  if (written.is_discarded()) {
    return report_error(
        Status(ErrorCode::kIoError, "cannot read back " + (options.out_dir / "results.json").string()));
  }
  print_json({{"command", "bench"},
              {"input", options.db_dir.string()},
              {"output", options.out_dir.string()},
              {"seconds", results.total_seconds},
              {"results", written}});
  return 0;
}

}  // namespace

struct BenchSubcommand::Options {
  bench::BenchOptions bench;
  std::string codecs;
  std::string out_dir = "bench-results";
  bool no_experiments = false;
  bool overwrite = false;
  std::vector<std::string> presets;        // CODEC=PRESET
  std::vector<std::string> codec_options;  // CODEC=KEY=VALUE
  command_line::Verbosity verbosity;
};

BenchSubcommand::BenchSubcommand(CLI::App& app) : options_(std::make_unique<Options>()) {
  std::string defaults, all;
  for (const std::string& name : bench::default_codec_names()) defaults += (defaults.empty() ? "" : ",") + name;
  for (const std::string& name : bench::all_codec_names()) all += (all.empty() ? "" : ", ") + name;
  options_->codecs = defaults;
  command_ = app.add_subcommand(
      "bench",
      "Compare svc with the MPEG-2 baseline and other codecs on one database: quality, speed, access cost");
  command_->add_option("DB_DIR", options_->bench.db_dir, "svc-input database folder")->required();
  command_->add_option("--codecs", options_->codecs, "Comma-separated codecs to run, of: " + all)
      ->capture_default_str();
  command_->add_option("--out", options_->out_dir, "Output folder for results.json, results.csv, plots, report.md")
      ->capture_default_str()
      ->check(not_standard_output());
  command_->add_option("--threads", options_->bench.threads, "Worker threads (0: all cores)")
      ->check(command_line::integer_in(0, 1024))
      ->capture_default_str();
  command_->add_option("--accesses", options_->bench.random_accesses, "Random faces per codec for access cost")
      ->check(command_line::integer_in(1, 1000000))
      ->capture_default_str();
  command_->add_option("--seed", options_->bench.seed, "Seed of the random access picks")->capture_default_str();
  command_->add_flag("--quick", options_->bench.quick, "Two PSNR targets, at most four encodes per codec");
  command_->add_option("--gop", options_->bench.gop, "GOP (frames between I-frames) of x264, x265 and AV1")
      ->check(command_line::integer_in(1, 1000))
      ->capture_default_str();
  command_->add_option(
      "--anchor-preset", options_->presets,
      "CODEC=PRESET, repeatable: x264/x265/x265-ra/x265-intra=medium, av1=6 (SVT-AV1 preset; "
      "libaom cpu-used where SVT-AV1 is missing), av1-slow=2 (libaom cpu-used), av1-svt-slow=2 (SVT-AV1 "
      "preset), avif=6 (libaom cpu-used), jxl=7 (effort)");
  command_->add_option("--anchor-option", options_->codec_options,
                       "CODEC=KEY=VALUE, repeatable: a private option of that anchor's libavcodec encoder, e.g. "
                       "avif=aom-params=enable-rect-partitions=0 (to measure an anchor's tools)");
  add_overwrite_flag(command_, &options_->overwrite);
  command_line::add_verbosity_options(command_, &options_->verbosity);
  command_->add_flag("--no-experiments", options_->no_experiments,
                     "Skip the dissertation experiments (Table 7.5, Figure 7.16, Table 7.4)");
  command_->add_flag("--ablation", options_->bench.ablation,
                     "Also encode svc without each coding tool and report the BD-rate of each");
  command_
      ->add_option("--before", options_->bench.before_results,
                   "results.json of an earlier run on the same database: BD-rate of svc (and of its B-faces) "
                   "against that run's svc")
      ->check(CLI::ExistingFile);
  command_->add_flag("!--no-speed", options_->bench.measure_speed,
                     "Quality points and BD-rates only: no speed or random-access measurements");
  command_->add_option("--anchor-cache", options_->bench.anchor_cache,
                       "Folder keeping the anchors' quality points between runs: an anchor already run on the same "
                       "faces with the same settings and libraries is read back instead of encoded (its speed and "
                       "access are then not measured)");
}

BenchSubcommand::~BenchSubcommand() = default;

bool BenchSubcommand::parsed() const { return command_->parsed(); }

int BenchSubcommand::run() const {
  const Status writable =
      check_output(options_->out_dir, OutputKind::kFolder, options_->overwrite, {options_->bench.db_dir});
  if (!writable.ok()) return report_error(writable);
  bench::BenchOptions options = options_->bench;
  options.out_dir = options_->out_dir;
  options.experiments = !options_->no_experiments;
  std::stringstream list(options_->codecs);
  for (std::string name; std::getline(list, name, ',');) {
    if (!name.empty()) options.codecs.push_back(name);
  }
  for (const std::string& entry : options_->presets) {
    const size_t eq = entry.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == entry.size()) {
      return report_error(
          Status(ErrorCode::kInvalidArgument, "--anchor-preset wants CODEC=PRESET, not '" + entry + "'"));
    }
    options.anchor_presets[entry.substr(0, eq)] = entry.substr(eq + 1);
  }
  for (const std::string& entry : options_->codec_options) {
    const size_t codec_end = entry.find('=');
    const size_t key_end = codec_end == std::string::npos ? codec_end : entry.find('=', codec_end + 1);
    if (codec_end == 0 || key_end == std::string::npos || key_end == codec_end + 1) {
      return report_error(
          Status(ErrorCode::kInvalidArgument, "--anchor-option wants CODEC=KEY=VALUE, not '" + entry + "'"));
    }
    options.anchor_options[entry.substr(0, codec_end)][entry.substr(codec_end + 1, key_end - codec_end - 1)] =
        entry.substr(key_end + 1);
  }
  // The benchmark reports its steps as lines on stderr, not a bar: shown unless
  // --quiet, --no-progress or --json (there only with --progress).
  const command_line::Verbosity& verbosity = options_->verbosity;
  if (!verbosity.quiet && !verbosity.no_progress && (!verbosity.json || verbosity.progress)) {
    options.progress = [](const std::string& line) {
      std::fprintf(stderr, "%s\n", line.c_str());
      std::fflush(stderr);
    };
  }
  baseline::quiet_ffmpeg_logging();
  // SVT-AV1 prints its configuration to the terminal unless told otherwise (errors only).
  setenv("SVT_LOG", "1", 0);
  std::error_code ec;
  const bool out_dir_existed = fs::exists(options.out_dir, ec);
  auto results = [&] {
    InterruptWatcher watcher(options.out_dir, out_dir_existed);
    return bench::run_bench(options);
  }();
  if (!results.ok()) {
    remove_unfinished(options.out_dir, out_dir_existed);
    return report_error(results.status());
  }
  Status written = bench::write_all(*results, options.out_dir);
  if (!written.ok()) return report_error(written);
  if (verbosity.json) return print_bench_json(options, *results);
  if (!verbosity.show_summary()) return 0;
  std::printf("%s\n", bench::summary_table_markdown(*results).c_str());
  for (const bench::PartTiming& t : results->timings) std::printf("  %-16s %7.1f s\n", t.part.c_str(), t.seconds);
  std::printf("  %-16s %7.1f s\n", "total", results->total_seconds);
  std::printf("wrote results.json, results.csv, plots and report.md to %s\n", options.out_dir.string().c_str());
  return 0;
}

}  // namespace svc::cli
