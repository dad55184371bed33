// SPDX-License-Identifier: BSD-2-Clause
// svc intra coding against libavcodec's MPEG-2 intra-only coding of the same faces:
// bytes at equal PSNR-Y, measured side by side on the sample scenes.
//
//   build/bin/svc-bench-intra [--kind hall|house|both] [--grid 9,1,9] [--face-size 256]
//
// Both codecs see the same 8-bit RGB faces; PSNR-Y is computed the same way for both
// (svc::luma_squared_error on the decoded RGB against the source), over all faces.
#include <chrono>
#include <cstdio>
#include <map>

#include <CLI/CLI.hpp>

#include "baseline/baseline.h"
#include "database/database.h"
#include "rd_curve.h"
#include "scene/scene.h"
#include "support/scene_cache.h"
#include "support/svc_measure.h"
#include "svc/encoder.h"
#include "svc/metrics.h"
#include "svc/reader.h"

namespace {

using namespace svc;
using bench::RdCurve;
using bench::RdPoint;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Result<RdPoint> measure_mpeg2(const bench::SceneFaces& scene, int qscale) {
  baseline::DatabaseFrames input = scene.baseline_frames();
  const auto t0 = std::chrono::steady_clock::now();
  SVC_ASSIGN_OR_RETURN(baseline::EncodedDatabase encoded,
                       baseline::encode_database(input, baseline::CellOrder::kRowMajor,
                                                 baseline::mpeg2_intra_only_settings(qscale)));
  RdPoint point;
  point.seconds = seconds_since(t0);
  point.setting = qscale;
  point.bytes = static_cast<double>(encoded.total_bytes());
  SquaredError error;
  for (Face face : kAllFaces) {
    const baseline::EncodedSequence& sequence = encoded.faces[static_cast<int>(face)];
    SVC_ASSIGN_OR_RETURN(std::vector<ImageRGB8> decoded, baseline::decode_all(sequence));
    for (size_t k = 0; k < decoded.size(); ++k) {
      const auto c = scene.ordinal_of(encoded.layout.cells[k]);
      SVC_ASSIGN_OR_RETURN(SquaredError e, luma_squared_error(scene.face(c, face), decoded[k]));
      error.add(e);
    }
  }
  point.psnr_y = error.psnr();
  return point;
}

void print_curve(const char* name, const RdCurve& curve, const char* setting_name) {
  std::printf("  %-14s %8s %12s %9s %9s\n", name, setting_name, "bytes", "PSNR-Y", "encode s");
  for (const RdPoint& p : curve.points()) {
    std::printf("  %-14s %8d %12.0f %9.2f %9.2f\n", "", p.setting, p.bytes, p.psnr_y, p.seconds);
  }
}

int run_scene(samples::SceneKind kind, const samples::SceneOptions& base, bool* all_ok) {
  samples::SceneOptions options = base;
  options.kind = kind;
  auto scene = bench::SceneFaces::generate(options);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().to_string().c_str());
    return 1;
  }
  std::printf("\n%s scene: %d x %d x %d cells, %dx%d faces, %zu faces\n", samples::scene_kind_name(kind),
              options.grid[0], options.grid[1], options.grid[2], options.face_size, options.face_size,
              (*scene)->cells.size() * kFaceCount);

  std::vector<RdPoint> svc_points, mpeg2_points;
  EncoderSettings intra;
  intra.intra_only = true;
  auto sweep = bench::sweep_svc(**scene, intra, {2, 3, 4, 6, 8, 11, 16, 24, 32});
  if (!sweep.ok()) {
    std::fprintf(stderr, "%s\n", sweep.status().to_string().c_str());
    return 1;
  }
  for (const auto& m : *sweep) svc_points.push_back(m.point);
  for (int q : {1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 31}) {
    auto p = measure_mpeg2(**scene, q);
    if (!p.ok()) {
      std::fprintf(stderr, "%s\n", p.status().to_string().c_str());
      return 1;
    }
    mpeg2_points.push_back(*p);
  }
  const RdCurve svc_curve(svc_points), mpeg2_curve(mpeg2_points);
  print_curve("svc intra", svc_curve, "qscale");
  print_curve("mpeg2 intra", mpeg2_curve, "qscale");

  std::printf("  bytes at equal PSNR-Y (svc / mpeg2; at most 1.00 is the goal):\n");
  for (double target : {34.0, 36.0, 38.0, 40.0, 42.0, 44.0}) {
    const auto a = svc_curve.bytes_at(target), b = mpeg2_curve.bytes_at(target);
    if (!a || !b) continue;
    const double ratio = *a / *b;
    std::printf("    %5.1f dB: svc %10.0f  mpeg2 %10.0f  ratio %.3f%s\n", target, *a, *b, ratio,
                ratio <= 1.0 ? "" : "  (above goal)");
    if (ratio > 1.0) *all_ok = false;
  }
  if (auto bd = bench::bd_rate_ratio(mpeg2_curve, svc_curve)) {
    std::printf("  BD-rate of svc intra against mpeg2 intra: %+.1f%% (ratio %.3f)\n", (*bd - 1) * 100, *bd);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  svc::configure_image_loading();
  CLI::App app{"svc intra coding against MPEG-2 intra-only (libavcodec) at equal PSNR-Y"};
  std::string kind = "both";
  samples::SceneOptions options;
  std::string grid = "9,1,9";
  app.add_option("--kind", kind, "hall, house or both")->capture_default_str();
  app.add_option("--grid", grid, "Cells X,Y,Z")->capture_default_str();
  app.add_option("--face-size", options.face_size, "Face size in pixels")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (std::sscanf(grid.c_str(), "%d,%d,%d", &options.grid[0], &options.grid[1], &options.grid[2]) != 3) {
    std::fprintf(stderr, "--grid takes X,Y,Z\n");
    return 2;
  }
  baseline::quiet_ffmpeg_logging();
  bool all_ok = true;
  std::printf("svc intra vs libavcodec MPEG-2 intra-only, same faces, PSNR-Y over all faces\n");
  if (kind == "hall" || kind == "both") {
    if (run_scene(samples::SceneKind::kHall, options, &all_ok) != 0) return 1;
  }
  if (kind == "house" || kind == "both") {
    if (run_scene(samples::SceneKind::kHouse, options, &all_ok) != 0) return 1;
  }
  std::printf("\n%s\n", all_ok ? "svc intra is no larger than MPEG-2 intra at every compared PSNR-Y"
                               : "svc intra is LARGER than MPEG-2 intra at some PSNR-Y");
  return 0;
}
