// SPDX-License-Identifier: BSD-2-Clause
// Random access cost, side by side: svc's reader (caches, prefetch) against the
// libavcodec MPEG-2 baseline decoded the way the dissertation's MPEGWALK did (a fresh
// decoder from the GOP's I-frame for every request), on a generated sample scene.
//
//   build/bin/svc-bench-access [--kind hall|house] [--grid 9,1,9] [--face-size 256]
//                              [--samples 12] [--quality 75] [--speed 1] [--textures DIR]
//
// Prints: cold and warm time to obtain one face and one cube (svc and baseline, with the
// frames each decodes), semi-decoded bytes per I-face against RGB, and the walkthrough's
// latency at the given speed with prefetch on and off. Times are medians over the
// sampled cells; "cold" is a reader with empty caches, "warm" the same request again
// (median of 5 repeats).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "baseline/baseline.h"
#include "database/database.h"
#include "scene/scene.h"
#include "support/scene_cache.h"
#include "support/statistics.h"
#include "svc/encoder.h"
#include "svc/reader.h"
#include "walkthrough/replay.h"

namespace {

using namespace svc;
using bench::median;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0 : sum / v.size();
}

double max_of(const std::vector<double>& v) { return v.empty() ? 0 : *std::max_element(v.begin(), v.end()); }

struct Timings {
  std::vector<double> face_cold, face_warm, face_refs_cached, cube_cold, cube_warm;
  std::vector<double> face_frames, cube_frames;  // frames (faces) decoded by a cold request
};

ReaderSettings no_prefetch() {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  return settings;
}

Status measure_svc(const std::filesystem::path& file, const std::vector<CellIndex>& cells, Timings* t) {
  for (size_t i = 0; i < cells.size(); ++i) {
    const Face face = kAllFaces[i % kFaceCount];
    {
      SVC_ASSIGN_OR_RETURN(auto reader, Reader::open(file, no_prefetch()));
      auto t0 = Clock::now();
      SVC_ASSIGN_OR_RETURN(ImageRGB8 cold, reader->decode_face(cells[i], face));
      t->face_cold.push_back(ms_since(t0));
      const ReaderStats s = reader->stats();
      t->face_frames.push_back(static_cast<double>(s.intra_faces_parsed + s.predicted_faces_decoded));
      std::vector<double> repeats;
      for (int r = 0; r < 5; ++r) {
        t0 = Clock::now();
        SVC_ASSIGN_OR_RETURN(ImageRGB8 warm, reader->decode_face(cells[i], face));
        repeats.push_back(ms_since(t0));
        if (warm.pixels != cold.pixels) return Status(ErrorCode::kInternal, "warm face differs from cold");
      }
      t->face_warm.push_back(median(repeats));
    }
    {
      // Without a decoded-face cache the second request decodes the face again, but its
      // references come reconstructed and padded from the reference cache.
      ReaderSettings settings = no_prefetch();
      settings.face_cache_bytes = 0;
      SVC_ASSIGN_OR_RETURN(auto reader, Reader::open(file, settings));
      SVC_ASSIGN_OR_RETURN(ImageRGB8 first, reader->decode_face(cells[i], face));
      const auto t0 = Clock::now();
      SVC_ASSIGN_OR_RETURN(ImageRGB8 second, reader->decode_face(cells[i], face));
      t->face_refs_cached.push_back(ms_since(t0));
    }
    {
      SVC_ASSIGN_OR_RETURN(auto reader, Reader::open(file, no_prefetch()));
      auto t0 = Clock::now();
      SVC_ASSIGN_OR_RETURN(auto cold, reader->decode_cube(cells[i]));
      t->cube_cold.push_back(ms_since(t0));
      const ReaderStats s = reader->stats();
      t->cube_frames.push_back(static_cast<double>(s.intra_faces_parsed + s.predicted_faces_decoded));
      std::vector<double> repeats;
      for (int r = 0; r < 5; ++r) {
        t0 = Clock::now();
        SVC_ASSIGN_OR_RETURN(auto warm, reader->decode_cube(cells[i]));
        repeats.push_back(ms_since(t0));
      }
      t->cube_warm.push_back(median(repeats));
    }
  }
  return Status::Ok();
}

Status measure_baseline(const baseline::EncodedDatabase& db, const std::vector<CellIndex>& cells, Timings* t) {
  for (size_t i = 0; i < cells.size(); ++i) {
    const Face face = kAllFaces[i % kFaceCount];
    auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame cold, baseline::decode_cell_face(db, cells[i], face));
    t->face_cold.push_back(ms_since(t0));
    t->face_frames.push_back(cold.frames_decoded);
    // No cache: a repeated request decodes from the GOP start again.
    t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame warm, baseline::decode_cell_face(db, cells[i], face));
    t->face_warm.push_back(ms_since(t0));
    double frames = 0;
    t0 = Clock::now();
    for (Face f : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame decoded, baseline::decode_cell_face(db, cells[i], f));
      frames += decoded.frames_decoded;
    }
    t->cube_cold.push_back(ms_since(t0));
    t->cube_frames.push_back(frames);
    t0 = Clock::now();
    for (Face f : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame decoded, baseline::decode_cell_face(db, cells[i], f));
    }
    t->cube_warm.push_back(ms_since(t0));
  }
  return Status::Ok();
}

void row(const char* label, double svc_value, double base_value, const char* unit, bool ratio = true) {
  std::printf("  %-40s %12.3f %12.3f  %-5s", label, svc_value, base_value, unit);
  if (ratio && svc_value > 0) std::printf(" %9.1fx", base_value / svc_value);
  std::printf("\n");
}

int run(const samples::SceneOptions& options, int sample_count, int quality, double speed) {
  baseline::quiet_ffmpeg_logging();
  std::printf("svc-bench-access: %s%s scene, grid %dx%dx%d, faces %dx%d\n",
              options.textures.empty() ? "" : "photographic ", samples::scene_kind_name(options.kind),
              options.grid[0], options.grid[1], options.grid[2], options.face_size, options.face_size);
  auto scene = bench::SceneFaces::generate(options);
  if (!scene.ok()) {
    std::fprintf(stderr, "%s\n", scene.status().to_string().c_str());
    return 1;
  }
  const std::filesystem::path file = (*scene)->work_dir / "scene.svc";
  EncoderSettings encoder;
  encoder.quality = quality;
  auto summary = encode_database((*scene)->db_dir, file, encoder);
  if (!summary.ok()) {
    std::fprintf(stderr, "%s\n", summary.status().to_string().c_str());
    return 1;
  }
  auto mpeg2 = baseline::encode_database((*scene)->baseline_frames(), baseline::CellOrder::kRowMajor,
                                         baseline::EncodeSettings{});
  if (!mpeg2.ok()) {
    std::fprintf(stderr, "%s\n", mpeg2.status().to_string().c_str());
    return 1;
  }

  // Evenly spread sample cells (I-cells and B-cells alike).
  const std::vector<CellIndex>& all = (*scene)->cells;
  std::vector<CellIndex> sampled;
  const size_t count = std::min<size_t>(std::max(sample_count, 1), all.size());
  for (size_t i = 0; i < count; ++i) sampled.push_back(all[(i * all.size() * 7 / count + i) % all.size()]);

  Timings svc_t, base_t;
  Status status = measure_svc(file, sampled, &svc_t);
  if (status.ok()) status = measure_baseline(*mpeg2, sampled, &base_t);
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.to_string().c_str());
    return 1;
  }

  std::printf(
      "\n  files: svc %.2f MiB (quality %d, quantizer index %d), MPEG-2 baseline %.2f MiB (qscale 4, "
      "GOP IBBPBB, row-major), raw RGB %.2f MiB\n",
      summary->file_bytes / 1048576.0, quality, summary->qindex, mpeg2->total_bytes() / 1048576.0,
      summary->raw_bytes / 1048576.0);
  std::printf("\n  random access, median of %zu cells %43s\n", sampled.size(), "");
  std::printf("  %-40s %12s %12s  %-5s %10s\n", "", "svc", "MPEG-2", "", "MPEG-2/svc");
  row("one face, cold", median(svc_t.face_cold), median(base_t.face_cold), "ms");
  row("one face, warm (same request again)", median(svc_t.face_warm), median(base_t.face_warm), "ms");
  row("one face, only references cached", median(svc_t.face_refs_cached), median(base_t.face_warm), "ms");
  row("one cube, cold", median(svc_t.cube_cold), median(base_t.cube_cold), "ms");
  row("one cube, warm", median(svc_t.cube_warm), median(base_t.cube_warm), "ms");
  row("frames decoded for one cold face, mean", mean(svc_t.face_frames), mean(base_t.face_frames), "");
  row("frames decoded for one cold face, max", max_of(svc_t.face_frames), max_of(base_t.face_frames), "");
  row("frames decoded for one cold cube, mean", mean(svc_t.cube_frames), mean(base_t.cube_frames), "");
  row("one face, cold, worst sampled", max_of(svc_t.face_cold), max_of(base_t.face_cold), "ms");

  // Semi-decoded I-faces against RGB.
  {
    auto reader = Reader::open(file, no_prefetch());
    if (!reader.ok()) return 1;
    uint64_t faces = 0, largest = 0, previous = 0;
    for (const CellEntry& cell : (*reader)->cells()) {
      for (Face face : kAllFaces) {
        if (cell.faces[static_cast<int>(face)].type != FaceType::kIntra) continue;
        if (!(*reader)->acquire_face_ycbcr(cell.index, face).ok()) return 1;
        const uint64_t held = (*reader)->stats().coefficient_cache.bytes_held;
        largest = std::max(largest, held - previous);
        previous = held;
        ++faces;
      }
    }
    const ReaderStats s = (*reader)->stats();
    const double rgb = 3.0 * (*reader)->info().face_width * (*reader)->info().face_height;
    const double per_face = faces ? static_cast<double>(s.coefficient_cache.bytes_held) / faces : 0;
    std::printf(
        "\n  semi-decoded I-faces: %llu faces, %.0f bytes each on average (largest %llu) = %.3f of RGB "
        "(largest %.3f; goal <= 0.25); coded %.0f bytes each\n",
        static_cast<unsigned long long>(faces), per_face, static_cast<unsigned long long>(largest), per_face / rgb,
        largest / rgb, faces ? static_cast<double>(summary->intra.bytes) / summary->intra.faces : 0.0);
  }

  // The walkthrough at the given speed.
  std::printf("\n  walkthrough, built-in serpentine path, %.3g cells/s %26s %12s\n", speed, "prefetch",
              "on demand");
  std::vector<walkthrough::ReplayResult> runs;
  for (bool prefetch : {true, false}) {
    auto reader = Reader::open(file, no_prefetch());
    if (!reader.ok()) return 1;
    walkthrough::ReplayOptions replay_options;
    replay_options.cells_per_second = speed;
    replay_options.prefetch = prefetch;
    auto result = walkthrough::replay(file, walkthrough::builtin_path(**reader), replay_options);
    if (!result.ok()) {
      std::fprintf(stderr, "%s\n", result.status().to_string().c_str());
      return 1;
    }
    runs.push_back(std::move(result).value());
  }
  auto wrow = [&](const char* label, double a, double b) { std::printf("  %-64s %12.3f %12.3f\n", label, a, b); };
  wrow("steps (cells entered)", runs[0].steps, runs[1].steps);
  wrow("latency p50 (ms)", runs[0].p50_ms, runs[1].p50_ms);
  wrow("latency p99 (ms)", runs[0].p99_ms, runs[1].p99_ms);
  wrow("latency max (ms)", runs[0].max_ms, runs[1].max_ms);
  wrow("steps waiting on decoding (goal with prefetch: 0)", runs[0].steps_waiting, runs[1].steps_waiting);
  wrow("face cache hit rate (%)", 100 * runs[0].face_hit_rate, 100 * runs[1].face_hit_rate);
  wrow("memory held at end (MiB)", runs[0].memory_held / 1048576.0, runs[1].memory_held / 1048576.0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  svc::configure_image_loading();
  CLI::App app{"Random access cost of svc against the MPEG-2 baseline, side by side."};
  std::string kind = "hall";
  std::vector<int> grid{9, 1, 9};
  int face_size = 256, samples = 12, quality = 75;
  double speed = 1.0;
  std::string textures;
  app.add_option("--kind", kind, "hall or house")->capture_default_str();
  app.add_option("--grid", grid, "cells along x,y,z")->delimiter(',')->expected(3)->capture_default_str();
  app.add_option("--face-size", face_size, "face width and height")->capture_default_str();
  app.add_option("--samples", samples, "cells sampled for the access timings")->capture_default_str();
  app.add_option("--quality", quality, "svc encoder quality")->capture_default_str();
  app.add_option("--speed", speed, "walkthrough speed, cells per second")->capture_default_str();
  app.add_option("--textures", textures,
                 "photographic scene: the image folder svc-scene --textures takes (scripts/fetch-textures.sh)");
  CLI11_PARSE(app, argc, argv);
  samples::SceneOptions options;
  options.textures = textures;
  if (!samples::parse_scene_kind(kind, &options.kind)) {
    std::fprintf(stderr, "unknown scene kind %s\n", kind.c_str());
    return 2;
  }
  options.grid = {grid[0], grid[1], grid[2]};
  options.face_size = face_size;
  options.threads = 2;
  return run(options, samples, quality, speed);
}
