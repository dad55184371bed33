// SPDX-License-Identifier: BSD-2-Clause
// Runs `svc bench` (see svc_bench.h): each codec's sweep in report order, BD-rates of svc
// against each, then the dissertation's experiments.
#include "svc_bench.h"

#include <algorithm>
#include <thread>

#include "bd_rate.h"
#include "before_comparison.h"
#include "bench_runner.h"

namespace svc::bench {

namespace {

std::vector<RatePoint> rate_points(const CodecResult& c, bool rgb) {
  std::vector<RatePoint> points;
  for (const QualityPoint& p : c.points) points.push_back({double(p.bytes), rgb ? p.psnr_rgb : p.psnr_y});
  return points;
}

// The codec the BD-rates are against: the first svc layout that ran, in report order
// (all_codec_names: svc first).
const CodecResult* bd_reference(const std::vector<CodecResult>& codecs) {
  for (const CodecResult& c : codecs) {
    if (is_svc_layout(c.name) && !c.skipped && c.points.size() >= 2) return &c;
  }
  return nullptr;
}

// BD-rate of the reference against each other codec, on PSNR-Y (over the whole overlap
// and over kTargetPsnrRange) and PSNR-RGB.
void compute_bd_rates(BenchResults* results) {
  const CodecResult* reference = bd_reference(results->codecs);
  if (!reference) return;
  results->bd_reference = reference->name;
  for (CodecResult& c : results->codecs) {
    if (c.skipped || c.points.size() < 2 || &c == reference) continue;
    if (auto bd = bd_rate(rate_points(c, false), rate_points(*reference, false))) {
      c.bd_rate_svc = bd->ratio - 1;
      c.bd_range_y = {bd->psnr_low, bd->psnr_high};
    }
    if (auto bd = bd_rate(rate_points(c, false), rate_points(*reference, false), kTargetPsnrRange[0],
                          kTargetPsnrRange[1])) {
      c.bd_rate_svc_target = bd->ratio - 1;
      c.bd_range_target = {bd->psnr_low, bd->psnr_high};
    }
    if (auto bd = bd_rate(rate_points(c, true), rate_points(*reference, true))) {
      c.bd_rate_svc_rgb = bd->ratio - 1;
      c.bd_range_rgb = {bd->psnr_low, bd->psnr_high};
    }
  }
  // svc's intra-only coding against every other codec, over the target range: how the
  // intra coding alone stands against the image codecs.
  const auto intra = std::find_if(results->codecs.begin(), results->codecs.end(), [](const CodecResult& c) {
    return c.name == "svc-intra" && !c.skipped && c.points.size() >= 2;
  });
  if (intra == results->codecs.end()) return;
  for (CodecResult& c : results->codecs) {
    if (c.skipped || c.points.size() < 2 || &c == &*intra) continue;
    if (auto bd =
            bd_rate(rate_points(c, false), rate_points(*intra, false), kTargetPsnrRange[0], kTargetPsnrRange[1])) {
      c.bd_rate_svc_intra_target = bd->ratio - 1;
    }
  }
}

Status run_ablation(Bench& bench, BenchResults* results) {
  const auto svc = std::find_if(results->codecs.begin(), results->codecs.end(),
                                [](const CodecResult& c) { return c.name == "svc" && !c.skipped; });
  if (svc == results->codecs.end()) {
    bench.log("ablation skipped: it needs the svc codec in --codecs");
    return Status::Ok();
  }
  const auto t0 = Clock::now();
  SVC_ASSIGN_OR_RETURN(results->ablation, bench.run_ablation(*svc));
  results->timings.push_back({"ablation", seconds_since(t0)});
  return Status::Ok();
}

AnchorOptions anchor_options_of(const BenchOptions& options) {
  return AnchorOptions{options.gop, options.anchor_presets, options.anchor_options};
}

// The requested codecs in report order, svc first: the others pick their reference
// point by svc's PSNR.
Result<std::vector<std::string>> ordered_codecs(const BenchOptions& options) {
  const std::vector<std::string>& all = all_codec_names();
  const std::vector<std::string>& codecs = options.codecs.empty() ? default_codec_names() : options.codecs;
  auto unknown = [&](const std::string& name) { return std::find(all.begin(), all.end(), name) == all.end(); };
  std::string valid;
  for (const std::string& name : all) valid += (valid.empty() ? "" : ", ") + name;
  for (const std::string& name : codecs) {
    if (unknown(name)) {
      return Status(ErrorCode::kInvalidArgument, "svc bench: unknown codec '" + name + "' (valid: " + valid + ")");
    }
  }
  for (const auto& [name, preset] : options.anchor_presets) {
    if (unknown(name))
      return Status(ErrorCode::kInvalidArgument, "svc bench: preset for unknown codec '" + name + "'");
  }
  for (const auto& [name, codec_options] : options.anchor_options) {
    if (unknown(name)) {
      return Status(ErrorCode::kInvalidArgument, "svc bench: encoder options for unknown codec '" + name + "'");
    }
  }
  std::vector<std::string> ordered;
  for (const std::string& name : all) {
    if (std::find(codecs.begin(), codecs.end(), name) != codecs.end()) ordered.push_back(name);
  }
  // Bad presets are refused before any work (the face size is checked again per run).
  for (const std::string& name : ordered) {
    auto plan = make_plan(name, anchor_options_of(options), 64, 64);
    if (!plan.ok()) return plan.status().with_context("svc bench: " + name);
  }
  return ordered;
}

Status run_codecs(Bench& bench, const std::vector<std::string>& names, const BenchOptions& options,
                  BenchResults* results) {
  const AnchorOptions anchors = anchor_options_of(options);
  for (const std::string& name : names) {
    const auto t0 = Clock::now();
    bench.log(name + ": quality search");
    auto plan = make_plan(name, anchors, results->face_width, results->face_height);
    if (!plan.ok()) return plan.status().with_context("svc bench: " + name);
    auto result = bench.run_codec(*plan);
    if (!result.ok()) return result.status().with_context("svc bench: " + name);
    results->codecs.push_back(std::move(result).value());
    results->timings.push_back({name, seconds_since(t0)});
  }
  const auto t0 = Clock::now();
  SVC_RETURN_IF_ERROR(bench.measure_speeds(&results->codecs).with_context("svc bench: speed"));
  results->timings.push_back({"speed", seconds_since(t0)});
  return Status::Ok();
}

}  // namespace

const std::vector<std::string>& all_codec_names() {
  static const std::vector<std::string> kNames = {"svc",         "svc-regular", "svc-intra",     "svc-fast",
                                                  "svc-fastest", "mpeg2",       "mpeg2-hilbert", "x264",
                                                  "x265",        "x265-ra",     "av1",           "jpeg",
                                                  "webp",        "jxl",         "avif",          "x265-intra",
                                                  "png",         "av1-slow",    "av1-svt-slow"};
  return kNames;
}

const std::vector<std::string>& default_codec_names() {
  // The slow AV1 anchors take longer than all the others together: asked for by name.
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names = all_codec_names();
    std::erase_if(names, [](const std::string& n) { return n == "av1-slow" || n == "av1-svt-slow"; });
    return names;
  }();
  return kNames;
}

Result<BenchResults> run_bench(const BenchOptions& options) {
  const auto start = Clock::now();
  if (options.gop < 1) return Status(ErrorCode::kInvalidArgument, "svc bench: GOP must be at least 1");
  SVC_ASSIGN_OR_RETURN(std::vector<std::string> ordered, ordered_codecs(options));
  if (options.random_accesses < 1) {
    return Status(ErrorCode::kInvalidArgument, "svc bench: random_accesses must be at least 1");
  }
  std::vector<QualityPoint> before;
  if (!options.before_results.empty()) {
    SVC_ASSIGN_OR_RETURN(before, load_svc_points(options.before_results));
  }
  const int threads = resolve_thread_count(options.threads);
  BenchResults results;
  results.database = options.db_dir.string();
  results.threads = threads;
  auto t0 = Clock::now();
  // The database is read before anything is created, so a bad one leaves no folder.
  SVC_ASSIGN_OR_RETURN(SourceFaces source, load_sources(options.db_dir, threads));
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir / "work", ec);
  if (ec)
    return Status(ErrorCode::kIoError,
                  "cannot create " + (options.out_dir / "work").string() + ": " + ec.message());
  results.grid = {source.manifest.grid.dims[0], source.manifest.grid.dims[1], source.manifest.grid.dims[2]};
  results.cells = source.manifest.cells.size();
  results.faces = source.faces.size();
  results.face_width = source.manifest.face_width;
  results.face_height = source.manifest.face_height;
  results.content = content_stats(source, threads);
  results.timings.push_back({"load faces", seconds_since(t0)});

  Bench bench(options, std::move(source), threads, start);
  results.raw_bytes = bench.raw_bytes();
  bench.log("loaded " + std::to_string(results.cells) + " cells, " + std::to_string(results.faces) + " faces of " +
            std::to_string(results.face_width) + "x" + std::to_string(results.face_height) + " from " +
            options.db_dir.string());

  Status status = run_codecs(bench, ordered, options, &results);
  if (status.ok()) compute_bd_rates(&results);
  const bool has_svc = std::find(ordered.begin(), ordered.end(), "svc") != ordered.end();
  if (status.ok() && options.experiments && has_svc) {
    bench.log("dissertation experiments: table 7.5, figure 7.16, table 7.4");
    auto experiments = bench.run_experiments(results.codecs, &results.timings);
    if (experiments.ok()) {
      results.experiments = std::move(experiments).value();
    } else {
      status = experiments.status().with_context("svc bench: experiments");
    }
  } else if (status.ok() && options.experiments) {
    bench.log("dissertation experiments skipped: they need the svc codec in --codecs");
  }
  if (status.ok() && options.ablation) status = run_ablation(bench, &results);
  if (status.ok() && !before.empty()) {
    for (const CodecResult& c : results.codecs) {
      if (c.name == "svc" && !c.skipped)
        results.before = compare_with_before(options.before_results, before, c.points);
    }
  }
  bench.remove_work_dir();
  SVC_RETURN_IF_ERROR(status);
  results.total_seconds = seconds_since(start);
  return results;
}

}  // namespace svc::bench
