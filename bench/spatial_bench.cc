// SPDX-License-Identifier: BSD-2-Clause
// Spatial prediction against intra-only coding, and depth-derived motion against
// logarithmic search, on the sample scenes, side by side in one run:
//
//   build/bin/svc-bench-spatial [--kind hall|house|both] [--grid 9,1,9] [--face-size 256]
//                               [--target 38] [--threads N] [--repeat 2] [--spacing 0.5]
//                               [--qindices 128,147,160]
//
// For each scene it sweeps the quantizer index for three encoder configurations
// (intra-only; default I/B layout with motion from depth; the same layout with
// logarithmic search) and prints: bytes at equal PSNR-Y (interpolated on log bytes),
// the encode-time ratio of depth over log search summed over the sweep (configurations
// interleaved per scale, fastest of --repeat encodes each), and
// the mean number of unique candidate vectors per macroblock. Before the sweep it prints
// how much of the B-faces their references see, and the time to derive motion alone
// (depth reprojection against logarithmic search, per B-face and reference).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "baseline/baseline.h"
#include "codec/encoder/log_search.h"
#include "codec/encoder/rgb_to_ycbcr.h"
#include "database/database.h"
#include "rd_curve.h"
#include "spatial/placement.h"
#include "spatial/reprojection.h"
#include "support/scene_cache.h"
#include "support/svc_measure.h"

namespace {

using namespace svc;
using bench::RdCurve;
using bench::SvcMeasurement;

std::vector<int> kScales = {83, 96, 115, 128, 143, 160, 175, 192};  // quantizer indices

struct Config {
  const char* name;
  EncoderSettings settings;
};

RdCurve curve_of(const std::vector<SvcMeasurement>& ms) {
  std::vector<bench::RdPoint> points;
  for (const auto& m : ms) points.push_back(m.point);
  return RdCurve(points);
}

// The measurement whose PSNR-Y lies closest to the target.
const SvcMeasurement& nearest(const std::vector<SvcMeasurement>& ms, double target) {
  const SvcMeasurement* best = &ms.front();
  for (const auto& m : ms) {
    if (std::abs(m.point.psnr_y - target) < std::abs(best->point.psnr_y - target)) best = &m;
  }
  return *best;
}

// Per B-face and reference, on the source faces (references uncoded):
// - how much of the B-faces their references see at all (spatial/reprojection.h,
//   visible_in_reference): what no reference sees (hidden behind other geometry, or
//   beyond the reference face's edges) can only be coded intra, which caps the gain of
//   prediction;
// - the time to derive motion alone: flow, candidates and warp nodes from depth, against
//   the logarithmic search (the encoder then scores up to 16 depth candidates per
//   macroblock, but only one from the search).
bool print_reference_analysis(const std::filesystem::path& db_dir) {
  auto manifest = load_manifest(db_dir);
  if (!manifest.ok()) {
    std::fprintf(stderr, "%s\n", manifest.status().to_string().c_str());
    return false;
  }
  std::vector<CellIndex> cells;
  for (const ManifestCell& cell : manifest->cells) cells.push_back(cell.index);
  auto placement = place_cubes(cells, manifest->grid.dims, PlacementSettings{}, manifest->grid.spacing);
  if (!placement.ok()) {
    std::fprintf(stderr, "%s\n", placement.status().to_string().c_str());
    return false;
  }
  constexpr int kMb = 16;
  uint64_t pixels = 0, seen_pixels = 0, macroblocks = 0, covered_macroblocks = 0;
  double depth_seconds = 0, log_seconds = 0;
  size_t pairs = 0, checksum = 0;
  FlowField flow;
  // A face and its YCbCr form, loaded once: each I-face serves several B-faces.
  struct LoadedFace {
    FaceData data;
    ImageYCbCr420 image;
  };
  std::map<size_t, LoadedFace> references;
  auto load = [&](size_t cell, Face face, LoadedFace* out) {
    auto data = load_face(*manifest, cell, face);
    if (!data.ok()) {
      std::fprintf(stderr, "%s\n", data.status().to_string().c_str());
      return false;
    }
    out->data = std::move(data).value();
    out->image =
        codec::rgb_to_ycbcr420(out->data.color.pixels.data(), out->data.color.width, out->data.color.height);
    return true;
  };
  for (size_t c = 0; c < cells.size(); ++c) {
    const CellPlacement& p = (*placement)[c];
    if (p.intra) continue;
    for (Face face : kAllFaces) {
      LoadedFace current;
      if (!load(c, face, &current)) return false;
      const int w = current.data.color.width, h = current.data.color.height;
      std::vector<std::vector<uint8_t>> seen;
      for (uint32_t r : p.references) {
        const size_t frame = static_cast<size_t>(r) * kFaceCount + static_cast<size_t>(face);
        auto [slot, added] = references.try_emplace(frame);
        if (added && !load(r, face, &slot->second)) return false;
        const LoadedFace& reference = slot->second;
        const auto current_cell = read_cell(*manifest, c);
        const auto reference_cell = read_cell(*manifest, r);
        if (!current_cell.ok() || !reference_cell.ok()) {
          std::fprintf(stderr, "%s\n",
                       (current_cell.ok() ? reference_cell : current_cell).status().to_string().c_str());
          return false;
        }
        const Camera& current_camera = current_cell->faces[static_cast<int>(face)].camera;
        const Camera& reference_camera = reference_cell->faces[static_cast<int>(face)].camera;
        seen.push_back(
            visible_in_reference(current_camera, reference_camera, w, h, current.data.depth, reference.data.depth));

        const auto t0 = std::chrono::steady_clock::now();
        compute_flow(current_camera, reference_camera, w, h, current.data.depth, &flow);
        checksum += macroblock_candidates(flow).size() + warp_nodes(flow).nodes.size();
        const auto t1 = std::chrono::steady_clock::now();
        checksum += codec::log_search_candidates(current.image, reference.image).size();
        const auto t2 = std::chrono::steady_clock::now();
        depth_seconds += std::chrono::duration<double>(t1 - t0).count();
        log_seconds += std::chrono::duration<double>(t2 - t1).count();
        ++pairs;
      }
      for (int my = 0; my * kMb < h; ++my) {
        for (int mx = 0; mx * kMb < w; ++mx) {
          std::vector<int> by_reference(seen.size(), 0);
          int area = 0;
          for (int y = my * kMb; y < std::min(h, (my + 1) * kMb); ++y) {
            for (int x = mx * kMb; x < std::min(w, (mx + 1) * kMb); ++x) {
              const size_t k = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
              bool any = false;
              for (size_t r = 0; r < seen.size(); ++r) {
                by_reference[r] += seen[r][k];
                any = any || seen[r][k];
              }
              seen_pixels += any;
              ++area;
            }
          }
          pixels += static_cast<uint64_t>(area);
          ++macroblocks;
          const int best = by_reference.empty() ? 0 : *std::max_element(by_reference.begin(), by_reference.end());
          covered_macroblocks += 10 * best >= 9 * area;
        }
      }
    }
  }
  if (macroblocks == 0 || checksum == 0) return true;
  std::printf(
      "  B-face pixels seen by a reference: %.1f%%; macroblocks at least 90%% seen by one reference: %.1f%%\n",
      100.0 * static_cast<double>(seen_pixels) / static_cast<double>(pixels),
      100.0 * static_cast<double>(covered_macroblocks) / static_cast<double>(macroblocks));
  std::printf(
      "  motion per B-face and reference (one thread): from depth %.3f ms, log search %.3f ms (ratio %.2f)\n",
      1e3 * depth_seconds / static_cast<double>(pairs), 1e3 * log_seconds / static_cast<double>(pairs),
      depth_seconds / log_seconds);
  return true;
}

bool run_scene(samples::SceneKind kind, samples::SceneOptions options, double target, int threads, int repeats) {
  options.kind = kind;
  auto scene = bench::SceneFaces::generate(options);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().to_string().c_str());
    return false;
  }
  std::printf("\n%s scene: %d x %d x %d cells of %d px faces (%zu faces)\n", samples::scene_kind_name(kind),
              options.grid[0], options.grid[1], options.grid[2], options.face_size,
              (*scene)->cells.size() * kFaceCount);
  if (!print_reference_analysis((*scene)->db_dir)) return false;

  Config configs[3] = {{"intra-only", {}}, {"spatial+depth", {}}, {"spatial+log", {}}};
  configs[0].settings.intra_only = true;
  configs[2].settings.motion = MotionSearch::kLogarithmic;
  std::vector<SvcMeasurement> results[3];
  // Scales outer, configurations inner, so that a change in machine load hits all three
  // alike; each timed encode is repeated and the fastest kept (the bytes must not change).
  for (int q : kScales) {
    for (int k = 0; k < 3; ++k) {
      configs[k].settings.threads = threads;
      configs[k].settings.qindex = q;
      auto measured = bench::measure_svc(**scene, configs[k].settings);
      if (!measured.ok()) {
        std::fprintf(stderr, "%s\n", measured.status().to_string().c_str());
        return false;
      }
      for (int r = 1; r < repeats; ++r) {
        const auto path = (*scene)->work_dir / "repeat.svc";
        const auto t0 = std::chrono::steady_clock::now();
        auto again = encode_database((*scene)->db_dir, path, configs[k].settings);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::error_code ec;
        std::filesystem::remove(path, ec);
        if (!again.ok() || again->file_bytes != measured->summary.file_bytes) {
          std::fprintf(stderr, "%s at qindex %d: a repeated encode gave different bytes\n", configs[k].name, q);
          return false;
        }
        measured->point.seconds = std::min(measured->point.seconds, seconds);
      }
      results[k].push_back(std::move(measured).value());
    }
  }

  std::printf("  %-14s %6s %11s %8s %9s %7s %7s %7s %7s %7s %6s\n", "config", "qindex", "bytes", "PSNR-Y",
              "encode s", "B intra", "fwd", "bwd", "bi", "skip", "cand");
  for (int k = 0; k < 3; ++k) {
    for (const auto& m : results[k]) {
      const FaceTypeStats& b = m.summary.predicted;
      const double mbs =
          static_cast<double>(b.mb_intra + b.mb_forward + b.mb_backward + b.mb_bidirectional + b.mb_skipped);
      auto pct = [&](uint64_t v) { return mbs > 0 ? 100.0 * v / mbs : 0.0; };
      std::printf("  %-14s %6d %11.0f %8.2f %9.2f %6.1f%% %6.1f%% %6.1f%% %6.1f%% %6.1f%% %6.2f\n", configs[k].name,
                  m.point.setting, m.point.bytes, m.point.psnr_y, m.point.seconds, pct(b.mb_intra),
                  pct(b.mb_forward), pct(b.mb_backward), pct(b.mb_bidirectional), pct(b.mb_skipped),
                  b.candidate_macroblocks ? static_cast<double>(b.candidate_vectors) / b.candidate_macroblocks
                                          : 0.0);
    }
  }

  const RdCurve intra = curve_of(results[0]), depth = curve_of(results[1]), log = curve_of(results[2]);
  bool ok = true;
  const auto b_intra = intra.bytes_at(target), b_depth = depth.bytes_at(target), b_log = log.bytes_at(target);
  std::printf("  at PSNR-Y %.1f dB:\n", target);
  if (b_intra && b_depth && b_log) {
    const double spatial_gain = *b_intra / *b_depth;
    const double log_ratio = *b_depth / *b_log;
    std::printf("    bytes: intra-only %.0f, spatial+depth %.0f, spatial+log %.0f\n", *b_intra, *b_depth, *b_log);
    std::printf("    intra-only / spatial+depth = %.2fx (goal: at least 2x)%s\n", spatial_gain,
                spatial_gain >= 2.0 ? "" : "  BELOW GOAL");
    std::printf("    spatial+depth / spatial+log = %.3f (goal: below 1)%s\n", log_ratio,
                log_ratio < 1.0 ? "" : "  ABOVE GOAL");
    ok = ok && spatial_gain >= 2.0 && log_ratio < 1.0;
  } else {
    std::printf("    target outside the measured range (intra %.1f-%.1f, depth %.1f-%.1f, log %.1f-%.1f dB)\n",
                intra.min_psnr(), intra.max_psnr(), depth.min_psnr(), depth.max_psnr(), log.min_psnr(),
                log.max_psnr());
    ok = false;
  }
  if (auto bd = bench::bd_rate_ratio(intra, depth)) {
    std::printf("    BD-rate spatial+depth vs intra-only: %+.1f%%\n", (*bd - 1) * 100);
  }
  if (auto bd = bench::bd_rate_ratio(log, depth)) {
    std::printf("    BD-rate spatial+depth vs spatial+log: %+.1f%%\n", (*bd - 1) * 100);
  }
  const SvcMeasurement& d = nearest(results[1], target);
  const SvcMeasurement& l = nearest(results[2], target);
  double depth_seconds = 0, log_seconds = 0;
  for (const auto& m : results[1]) depth_seconds += m.point.seconds;
  for (const auto& m : results[2]) log_seconds += m.point.seconds;
  const double time_ratio = depth_seconds / log_seconds;
  std::printf("    encode time depth / log search over the sweep = %.3f (goal: below 1)%s\n", time_ratio,
              time_ratio < 1.0 ? "" : "  ABOVE GOAL");
  std::printf("    at qindex %d: depth %.2f s, log search %.2f s\n", d.point.setting, d.point.seconds,
              l.point.seconds);
  const FaceTypeStats& b = d.summary.predicted;
  std::printf("    unique candidate vectors per macroblock and reference (depth): %.2f\n",
              b.candidate_macroblocks ? static_cast<double>(b.candidate_vectors) / b.candidate_macroblocks : 0.0);
  return ok && time_ratio < 1.0;
}

}  // namespace

int main(int argc, char** argv) {
  svc::configure_image_loading();
  CLI::App app{"svc spatial prediction against intra-only and against logarithmic search"};
  std::string kind = "both", grid = "9,1,9";
  samples::SceneOptions options;
  double target = 38.0;
  int threads = 0;
  app.add_option("--kind", kind, "hall, house or both")->capture_default_str();
  app.add_option("--grid", grid, "Cells X,Y,Z")->capture_default_str();
  app.add_option("--face-size", options.face_size, "Face size in pixels")->capture_default_str();
  app.add_option("--target", target, "PSNR-Y at which sizes are compared, dB")->capture_default_str();
  app.add_option("--threads", threads, "Encoder threads (0: all cores)")->capture_default_str();
  int repeats = 2;
  app.add_option("--repeat", repeats, "Timed encodes per configuration and scale; the fastest counts")
      ->capture_default_str()
      ->check(CLI::Range(1, 20));
  double spacing = options.spacing[0];
  app.add_option("--spacing", spacing, "Cell spacing along x and z, metres")->capture_default_str();
  std::string scales_text;
  app.add_option("--qindices", scales_text, "Quantizer indices to sweep, comma-separated");
  CLI11_PARSE(app, argc, argv);
  if (std::sscanf(grid.c_str(), "%d,%d,%d", &options.grid[0], &options.grid[1], &options.grid[2]) != 3) {
    std::fprintf(stderr, "--grid takes X,Y,Z\n");
    return 2;
  }
  options.spacing[0] = options.spacing[2] = spacing;
  if (!scales_text.empty()) {
    kScales.clear();
    std::stringstream in(scales_text);
    for (std::string item; std::getline(in, item, ',');) kScales.push_back(std::stoi(item));
  }
  options.threads = 2;
  bool ok = true;
  if (kind == "hall" || kind == "both")
    ok = run_scene(samples::SceneKind::kHall, options, target, threads, repeats) && ok;
  if (kind == "house" || kind == "both")
    ok = run_scene(samples::SceneKind::kHouse, options, target, threads, repeats) && ok;
  std::printf("\n%s\n", ok ? "all goals met" : "some goals NOT met");
  return 0;
}
