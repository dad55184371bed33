// SPDX-License-Identifier: BSD-2-Clause
// Decoding speed of one .svc file, measured as `svc bench` measures svc's (docs/bench.md):
// every face through a fresh Reader in cell order on one thread (faces/s), the same on
// all threads, and cold access to one whole cell (a fresh reader, one decode thread, the
// cell's reference I-faces and its six faces) and to one face of a cell (`--mode face`:
// the face and the reference faces it needs; also the process's first face, which builds
// the cube-padding maps that later ones find cached).
//
//   build/bin/svc-bench-decode FILE.svc [--repeat 5] [--threads 0] [--cells 12]
//                              [--mode all|sequential|parallel|cells|face|buffers|depth|checksum]
//
// Each figure is the median over --repeat passes; the one-thread pass is the one to
// profile (`perf record build/bin/svc-bench-decode FILE --mode sequential`). The
// checksum (FNV-1a over every decoded face's RGB, in cell order) shows that a change to
// the decoder left its output as it was. `--mode buffers` times, pass by pass, the
// allocating decode_face (RGB8) against decode_face_into an RGBA8 buffer, as engines take
// faces, and the same from a warm face cache, where only the output step differs.
// `--mode depth` (files with depth) times, pass by pass in alternating order, every
// face's color and every face's depth (eye depth as floats), each through a fresh reader
// on one thread.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/parallel.h"
#include "support/statistics.h"
#include "svc/reader.h"

namespace {

using namespace svc;
using bench::median;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

uint64_t fnv1a(uint64_t hash, const std::vector<uint8_t>& bytes) {
  for (uint8_t b : bytes) hash = (hash ^ b) * 0x100000001b3ull;
  return hash;
}

// One face out as `svc bench` takes it (decode_face, an allocated RGB8 image) or, with
// `into_buffer`, into a reused RGBA8 buffer as an engine takes it (decode_face_into).
Status decode_one(Reader& reader, const CellIndex& cell, Face face, bool into_buffer) {
  if (!into_buffer) return reader.decode_face(cell, face).status();
  const int width = reader.info().face_width, height = reader.info().face_height;
  thread_local std::vector<uint8_t> pixels;
  pixels.resize(static_cast<size_t>(width) * height * 4);
  PixelBuffer buffer;
  buffer.format = PixelFormat::kRGBA8;
  buffer.planes[0] = pixels;
  buffer.strides[0] = static_cast<size_t>(width) * 4;
  return reader.decode_face_into(cell, face, buffer);
}

// Every face of the reader's file in cell order on `threads` threads. Returns seconds.
Result<double> time_faces(Reader& reader, int threads, bool into_buffer) {
  const auto& cells = reader.cells();
  const auto t0 = Clock::now();
  // One thread decodes in cell order, as `svc bench` does; more take the faces side by side.
  SVC_RETURN_IF_ERROR(parallel_for(cells.size() * kFaceCount, threads, [&](size_t k) {
    return decode_one(reader, cells[k / kFaceCount].index, kAllFaces[k % kFaceCount], into_buffer);
  }));
  return seconds_since(t0);
}

// Every face of the file through a fresh reader. Returns seconds; `stats` (optional)
// receives the reader's counters.
Result<double> decode_all(const std::string& file, int threads, ReaderStats* stats = nullptr,
                          bool into_buffer = false) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = threads;
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file, settings));
  SVC_ASSIGN_OR_RETURN(double seconds, time_faces(*reader, threads, into_buffer));
  if (stats != nullptr) *stats = reader->stats();
  return seconds;
}

// The output step alone: every face from a face cache that holds the whole file, out
// both ways, `repeat` passes in alternating order. Returns faces/s {allocating, buffer}.
Result<std::pair<std::vector<double>, std::vector<double>>> output_speed(const std::string& file, int repeat) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = 1;
  settings.face_cache_bytes = 1ull << 40;
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file, settings));
  const double faces = static_cast<double>(reader->cells().size() * kFaceCount);
  SVC_RETURN_IF_ERROR(time_faces(*reader, 1, false).status());  // fills the cache
  std::pair<std::vector<double>, std::vector<double>> speeds;
  for (int r = 0; r < 2 * repeat; ++r) {
    const bool into_buffer = (r % 2 == 1) != (r / 2 % 2 == 1);
    SVC_ASSIGN_OR_RETURN(double seconds, time_faces(*reader, 1, into_buffer));
    (into_buffer ? speeds.second : speeds.first).push_back(faces / seconds);
  }
  return speeds;
}

// Cold access to `count` cells spread over the file: a fresh one-thread reader each.
// Returns the mean milliseconds and the mean faces decoded.
// Every face's depth of the file, as eye depth into a reused buffer, through a fresh
// reader on one thread. Returns seconds.
Result<double> decode_all_depth(const std::string& file) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = 1;
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file, settings));
  std::vector<float> depth(static_cast<size_t>(reader->info().face_width) * reader->info().face_height);
  DepthBuffer buffer;
  buffer.data = depth.data();
  buffer.stride = static_cast<size_t>(reader->info().face_width) * sizeof(float);
  buffer.size = depth.size() * sizeof(float);
  const auto t0 = Clock::now();
  for (const CellEntry& cell : reader->cells()) {
    for (Face face : kAllFaces) SVC_RETURN_IF_ERROR(reader->decode_face_depth_into(cell.index, face, buffer));
  }
  return seconds_since(t0);
}

// Cold access through a fresh reader decoding on `threads` threads (its opening
// included) to `count` cells spread over the file: each whole cell, or one face of it
// (the faces in turn). Returns the mean milliseconds and faces decoded per access.
Result<std::pair<double, double>> cold_access(const std::string& file, int count, bool one_face, int threads = 1) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = threads;
  std::vector<CellIndex> picks;
  {
    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file, settings));
    const auto& cells = reader->cells();
    for (int i = 0; i < count && !cells.empty(); ++i) {
      picks.push_back(cells[(static_cast<size_t>(i) * 7919 + 13) % cells.size()].index);
    }
  }
  double ms = 0, faces = 0;
  for (size_t i = 0; i < picks.size(); ++i) {
    const CellIndex& cell = picks[i];
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file, settings));
    if (one_face) {
      SVC_RETURN_IF_ERROR(reader->decode_face(cell, kAllFaces[i % kFaceCount]).status());
    } else {
      SVC_RETURN_IF_ERROR(reader->decode_cube(cell).status());
    }
    ms += seconds_since(t0) * 1e3;
    const ReaderStats stats = reader->stats();
    faces += static_cast<double>(stats.intra_faces_parsed + stats.predicted_faces_decoded);
  }
  const double n = std::max<double>(1, static_cast<double>(picks.size()));
  return std::pair{ms / n, faces / n};
}

Result<uint64_t> checksum(const std::string& file) {
  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(file));
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const auto& cell : reader->cells()) {
    for (Face f : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(ImageRGB8 image, reader->decode_face(cell.index, f));
      hash = fnv1a(hash, image.pixels);
    }
  }
  return hash;
}

int run(const std::string& file, int repeat, int threads, int cells, const std::string& mode) {
  auto fail = [&](const Status& s) {
    std::fprintf(stderr, "svc-bench-decode: %s\n", s.message().c_str());
    return 1;
  };
  auto opened = Reader::open(file);
  if (!opened.ok()) return fail(opened.status());
  const double faces = static_cast<double>((*opened)->cells().size() * kFaceCount);
  // Faces a face needs decoded, itself included, summed over every face of the index.
  size_t faces_needed = 0;
  for (const CellEntry& cell : (*opened)->cells()) {
    for (const FaceEntry& entry : cell.faces) faces_needed += 1 + entry.references.size();
  }
  opened->reset();
  if (mode == "checksum") {
    auto hash = checksum(file);
    if (!hash.ok()) return fail(hash.status());
    std::printf("%s: %.0f faces, checksum %016llx\n", file.c_str(), faces, static_cast<unsigned long long>(*hash));
    return 0;
  }
  // The process's first face, before any pass: it also builds the cube-padding border
  // maps its references need, which every later face in the process finds cached.
  double first_face_ms = -1;
  if (mode == "all" || mode == "face") {
    auto c = cold_access(file, 1, true);
    if (!c.ok()) return fail(c.status());
    first_face_ms = c->first;
  }
  std::vector<double> one, all, cold, cold_face, cold_face_threads, into_buffer, allocating, buffer_ratios, color,
      depth, depth_ratios;
  double cold_faces = 0, cold_face_faces = 0;
  ReaderStats one_stats;
  for (int r = 0; r < repeat; ++r) {
    if (mode == "all" || mode == "sequential") {
      auto s = decode_all(file, 1, &one_stats);
      if (!s.ok()) return fail(s.status());
      one.push_back(faces / *s);
    }
    if (mode == "all" || mode == "parallel") {
      auto s = decode_all(file, threads);
      if (!s.ok()) return fail(s.status());
      all.push_back(faces / *s);
    }
    if (mode == "buffers") {
      // Side by side in each pass, in alternating order: decode_face, decode_face_into.
      const bool buffer_first = r % 2 == 1;
      auto a = decode_all(file, 1, nullptr, buffer_first);
      if (!a.ok()) return fail(a.status());
      auto b = decode_all(file, 1, nullptr, !buffer_first);
      if (!b.ok()) return fail(b.status());
      const double allocating_speed = faces / (buffer_first ? *b : *a);
      const double buffer_speed = faces / (buffer_first ? *a : *b);
      allocating.push_back(allocating_speed);
      into_buffer.push_back(buffer_speed);
      buffer_ratios.push_back(buffer_speed / allocating_speed);
    }
    if (mode == "depth") {
      const bool depth_first = r % 2 == 1;
      Result<double> a = depth_first ? decode_all_depth(file) : decode_all(file, 1);
      if (!a.ok()) return fail(a.status());
      Result<double> b = depth_first ? decode_all(file, 1) : decode_all_depth(file);
      if (!b.ok()) return fail(b.status());
      const double color_speed = faces / (depth_first ? *b : *a), depth_speed = faces / (depth_first ? *a : *b);
      color.push_back(color_speed);
      depth.push_back(depth_speed);
      depth_ratios.push_back(depth_speed / color_speed);
    }
    if (mode == "all" || mode == "cells") {
      auto c = cold_access(file, cells, false);
      if (!c.ok()) return fail(c.status());
      cold.push_back(c->first);
      cold_faces = c->second;
    }
    if (mode == "all" || mode == "face") {
      auto c = cold_access(file, cells, true);
      if (!c.ok()) return fail(c.status());
      cold_face.push_back(c->first);
      cold_face_faces = c->second;
      auto t = cold_access(file, cells, true, threads);
      if (!t.ok()) return fail(t.status());
      cold_face_threads.push_back(t->first);
    }
  }
  std::printf("%s: %.0f faces\n", file.c_str(), faces);
  if (!one.empty()) {
    std::printf("  decode, 1 thread      %8.1f faces/s (median of %d)\n", median(one), repeat);
    // Work behind that figure: I-face parses and B-face decodes, reference cache misses.
    std::printf("    %llu I-face parses, %llu B-face decodes, %llu reference I-faces rebuilt\n",
                static_cast<unsigned long long>(one_stats.intra_faces_parsed),
                static_cast<unsigned long long>(one_stats.predicted_faces_decoded),
                static_cast<unsigned long long>(one_stats.reference_cache.misses));
  }
  if (!all.empty()) std::printf("  decode, %2d threads    %8.1f faces/s\n", threads, median(all));
  if (!into_buffer.empty()) {
    std::printf("  decode, 1 thread, RGB8 allocated     %8.1f faces/s\n", median(allocating));
    std::printf("  decode, 1 thread, into RGBA8 buffer  %8.1f faces/s (%.3fx: median of %d passes' ratios)\n",
                median(into_buffer), median(buffer_ratios), repeat);
    auto output = output_speed(file, repeat);
    if (!output.ok()) return fail(output.status());
    std::printf("  from the face cache, RGB8 allocated  %8.1f faces/s\n", median(output->first));
    std::printf("  from the face cache, into RGBA8      %8.1f faces/s (%.3fx)\n", median(output->second),
                median(output->second) / median(output->first));
  }
  if (!depth.empty()) {
    std::printf("  decode, 1 thread, color  %8.1f faces/s\n", median(color));
    std::printf("  decode, 1 thread, depth  %8.1f faces/s (%.3fx: median of %d passes' ratios)\n", median(depth),
                median(depth_ratios), repeat);
  }
  if (!cold.empty()) {
    std::printf("  cold cell, 1 thread   %8.2f ms (%.1f faces decoded, mean over %d cells)\n", median(cold),
                cold_faces, cells);
  }
  if (!cold_face.empty()) {
    std::printf("  cold face, 1 thread   %8.2f ms (%.1f faces decoded, mean over %d faces)\n", median(cold_face),
                cold_face_faces, cells);
    std::printf("  cold face, %2d threads %8.2f ms\n", threads, median(cold_face_threads));
    std::printf("    every face: %.2f faces decoded on average\n", static_cast<double>(faces_needed) / faces);
    std::printf("  first face of the process %6.2f ms (border maps built for it)\n", first_face_ms);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Decoding speed of an .svc file: faces/s on one thread and on all, cold cell access"};
  std::string file, mode = "all";
  int repeat = 5, threads = 0, cells = 12;
  app.add_option("file", file, ".svc file")->required()->check(CLI::ExistingFile);
  app.add_option("--repeat", repeat, "passes; each figure is their median")->check(CLI::Range(1, 1000));
  app.add_option("--threads", threads, "threads of the parallel pass (0: all cores)")->check(CLI::Range(0, 1024));
  app.add_option("--cells", cells, "cells of the cold-access pass")->check(CLI::Range(1, 100000));
  app.add_option("--mode", mode, "what to measure")
      ->check(CLI::IsMember({"all", "sequential", "parallel", "cells", "face", "buffers", "depth", "checksum"}));
  CLI11_PARSE(app, argc, argv);
  threads = resolve_thread_count(threads);
  return run(file, repeat, threads, cells, mode);
}
