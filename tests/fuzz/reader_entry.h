// SPDX-License-Identifier: BSD-2-Clause
// Entry points through the public svc::Reader, shared by the libFuzzer targets
// svc_alloc_failure_fuzzer and svc_threads_fuzzer and by the test programs that replay
// the seed corpus through them (tests/svc_alloc_failure_test.cc, which replaces operator
// new as the first target does, and tests/svc_fuzz_corpus_test.cc).
//
// Both take a whole .svc file (checksums repaired first, as the container target does
// for its second pass), so the container seeds and the conformance streams seed them as
// they are; what they vary beyond the file (which allocation fails, what each thread
// asks for) comes from a hash of the input. Each returns normally or reports a broken
// property and aborts (report_failure); a crash, sanitizer report, leak or hang is a bug.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "codec/common/color.h"
#include "fuzz/failing_allocator.h"
#include "fuzz/fuzz_entry.h"
#include "svc/byte_source.h"
#include "svc/reader.h"

namespace svc::fuzz {

// What happens when a property breaks: the fuzzers abort (a finding); the replay tests
// set this to count failures instead.
inline std::atomic<void (*)(const std::string&)> g_failure_handler{nullptr};

inline void report_failure(const std::string& what) {
  if (auto handler = g_failure_handler.load()) {
    handler(what);
    return;
  }
  std::fprintf(stderr, "property broken: %s\n", what.c_str());
  std::abort();
}

inline uint64_t input_hash(std::span<const uint8_t> data) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (uint8_t b : data) h = (h ^ b) * 1099511628211ull;
  return h;
}

// A small deterministic generator (splitmix64).
class InputRandom {
 public:
  explicit InputRandom(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  uint64_t below(uint64_t n) { return n == 0 ? 0 : next() % n; }

 private:
  uint64_t state_;
};

inline bool same_pixels(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  return a.width == b.width && a.height == b.height && a.y == b.y && a.cb == b.cb && a.cr == b.cr;
}

inline std::vector<uint8_t> repaired_file(std::span<const uint8_t> data) {
  std::vector<uint8_t> file(data.begin(), data.end());
  repair_checksums(file);
  return file;
}

// --- Allocation failures --------------------------------------------------------------

// Settings under which every allocation of the reader is made on the calling thread:
// no prefetch, one decode thread; small caches, so that evictions happen.
inline ReaderSettings single_thread_settings() {
  ReaderSettings settings;
  settings.limits = fuzz_limits();
  settings.prefetch_threads = 0;
  settings.decode_threads = 1;
  settings.coefficient_cache_bytes = 8 << 10;
  settings.face_cache_bytes = 8 << 10;
  settings.reference_cache_bytes = 16 << 10;
  settings.depth_cache_bytes = 8 << 10;
  return settings;
}

// The outcome of one call: its error code and, when it succeeded, what it gave.
struct CallOutcome {
  ErrorCode code = ErrorCode::kOk;
  std::vector<uint8_t> bytes;  // pixels (all planes) or depth codes
  bool operator==(const CallOutcome&) const = default;
};

template <typename T>
CallOutcome outcome_of(const Result<T>& result, std::vector<uint8_t> (*bytes)(const T&)) {
  CallOutcome outcome;
  outcome.code = result.status().code();
  if (result.ok()) outcome.bytes = bytes(*result);
  return outcome;
}

inline std::vector<uint8_t> ycbcr_bytes(const ImageYCbCr420& image) {
  std::vector<uint8_t> bytes(image.y);
  bytes.insert(bytes.end(), image.cb.begin(), image.cb.end());
  bytes.insert(bytes.end(), image.cr.begin(), image.cr.end());
  return bytes;
}

inline std::vector<uint8_t> cube_bytes(const std::array<ImageRGB8, kFaceCount>& cube) {
  std::vector<uint8_t> bytes;
  for (const ImageRGB8& face : cube) bytes.insert(bytes.end(), face.pixels.begin(), face.pixels.end());
  return bytes;
}

inline std::vector<uint8_t> depth_bytes(const std::vector<float>& depth) {
  const auto* p = reinterpret_cast<const uint8_t*>(depth.data());
  return std::vector<uint8_t>(p, p + depth.size() * sizeof(float));
}

// Every call the decode makes, in order: for each cell its cube (RGB), then each face
// (YCbCr), its RGBA form into a buffer, and its depth in a file with depth. Each call is
// a library_call: only its own allocations are counted (and failed).
inline std::vector<CallOutcome> decode_everything(Reader& reader) {
  std::vector<CallOutcome> outcomes;
  const int w = reader.info().face_width, h = reader.info().face_height;
  std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4);
  PixelBuffer buffer;
  buffer.planes[0] = rgba;
  buffer.strides[0] = static_cast<size_t>(w) * 4;
  for (const CellEntry& cell : reader.cells()) {
    outcomes.push_back(outcome_of(library_call([&] { return reader.decode_cube(cell.index); }), &cube_bytes));
    for (Face face : kAllFaces) {
      outcomes.push_back(
          outcome_of(library_call([&] { return reader.decode_face_ycbcr(cell.index, face); }), &ycbcr_bytes));
      CallOutcome into;
      into.code = library_call([&] { return reader.decode_face_into(cell.index, face, buffer); }).code();
      if (into.code == ErrorCode::kOk) into.bytes = rgba;
      outcomes.push_back(std::move(into));
      if (reader.info().has_depth) {
        outcomes.push_back(
            outcome_of(library_call([&] { return reader.decode_face_depth(cell.index, face); }), &depth_bytes));
      }
    }
  }
  return outcomes;
}

struct DecodeRun {
  ErrorCode open_code = ErrorCode::kOk;
  std::vector<CallOutcome> calls;
};

// Opens `file` and decodes everything with `reader` kept for the caller (null when the
// open failed).
inline DecodeRun open_and_decode(const std::vector<uint8_t>& file, std::unique_ptr<Reader>* kept = nullptr) {
  DecodeRun run;
  std::unique_ptr<ByteSource> source = memory_source(file, "fuzz.svc");
  const ReaderSettings settings = single_thread_settings();
  auto reader = library_call([&] { return Reader::open(std::move(source), settings); });
  run.open_code = reader.status().code();
  if (!reader.ok()) return run;
  run.calls = decode_everything(**reader);
  if (kept) *kept = std::move(reader).value();
  return run;
}

// The number of allocations a clean open and decode of `file` makes on this thread.
inline uint64_t count_allocations(const std::vector<uint8_t>& file) {
  reset_allocation_count();
  (void)open_and_decode(file);
  return t_allocator.counted;
}

// The property, for a file and the allocation to fail (the `n`-th of the open and decode;
// with `persistent`, every one after it too): every call returns; each fails with
// kOutOfMemory or gives exactly what the clean run gave; and the same reader, disarmed,
// then decodes exactly as the clean run. Returns the number of calls that reported
// kOutOfMemory (0 when the failure hit nothing the decode needed).
inline int check_allocation_failure(const std::vector<uint8_t>& file, const DecodeRun& clean, uint64_t n,
                                    bool persistent) {
  const std::string where = "allocation " + std::to_string(n) + (persistent ? " on" : "") + ": ";
  std::unique_ptr<Reader> reader;
  arm_allocation_failure(n, persistent);
  const DecodeRun failed = open_and_decode(file, &reader);
  disarm_allocation_failure();
  int out_of_memory = failed.open_code == ErrorCode::kOutOfMemory;
  if (failed.open_code != clean.open_code && failed.open_code != ErrorCode::kOutOfMemory) {
    report_failure(where + "open gave " + error_code_name(failed.open_code) + ", not " +
                   error_code_name(clean.open_code) + " or out of memory");
  }
  if (failed.open_code == ErrorCode::kOk && clean.open_code == ErrorCode::kOk) {
    for (size_t i = 0; i < clean.calls.size(); ++i) {
      const CallOutcome& got = failed.calls[i];
      if (got.code == ErrorCode::kOutOfMemory) {
        ++out_of_memory;
      } else if (!(got == clean.calls[i])) {
        report_failure(where + "call " + std::to_string(i) + " gave " + error_code_name(got.code) +
                       (got.code == clean.calls[i].code ? " with other bytes" : "") +
                       " instead of the clean run's " + error_code_name(clean.calls[i].code));
      }
    }
  }
  // The next calls work: on the same reader when it opened, else on a new one.
  const DecodeRun again = reader ? DecodeRun{ErrorCode::kOk, decode_everything(*reader)} : open_and_decode(file);
  if (again.open_code != clean.open_code || again.calls != clean.calls) {
    report_failure(where + "the calls after the failure differ from the clean run's");
  }
  return out_of_memory;
}

// Fuzz target: the input is an .svc file; a hash of it picks which allocation of the
// open and decode fails (1 + hash % the clean run's count) and whether every later one
// fails too.
inline void run_alloc_failure_input(std::span<const uint8_t> data) {
  const std::vector<uint8_t> file = repaired_file(data);
  const uint64_t allocations = count_allocations(file);
  const DecodeRun clean = open_and_decode(file);
  const uint64_t hash = input_hash(data);
  (void)check_allocation_failure(file, clean, 1 + (hash >> 1) % std::max<uint64_t>(allocations, 1), hash & 1);
}

// --- Threads -------------------------------------------------------------------------

// What a sequential, uncached, single-threaded decode gives for each face.
struct SequentialDecode {
  std::vector<CallOutcome> faces;  // YCbCr, indexed by cell ordinal * 6 + face
  std::vector<ImageYCbCr420> images;
};

inline SequentialDecode sequential_decode(Reader& reader) {
  SequentialDecode decode;
  for (const CellEntry& cell : reader.cells()) {
    for (Face face : kAllFaces) {
      auto image = reader.decode_face_ycbcr(cell.index, face);
      decode.faces.push_back(outcome_of(image, &ycbcr_bytes));
      decode.images.push_back(image.ok() ? std::move(image).value() : ImageYCbCr420{});
    }
  }
  return decode;
}

// Fuzz target: the input is an .svc file, decoded first sequentially (one thread, no
// caches, no prefetch), then by a reader with two prefetch workers, two decode threads
// and caches small enough to evict, from four threads at once: each asks for faces
// (YCbCr, RGBA into a buffer), cubes and the viewer's moves (cell and position) drawn
// from a generator seeded by the input's hash, and the last one closes the reader part-way.
// Every call that succeeds gives the sequential decode's pixels; one that fails gives the
// sequential decode's error for that face, or kCancelled once close() has begun; nothing
// hangs. Which interleaving happens varies from run to run; the properties hold for all.
// Returns the number of calls that succeeded (for the replay test).
inline int run_threads_input(std::span<const uint8_t> data) {
  const std::vector<uint8_t> file = repaired_file(data);
  ReaderSettings plain;
  plain.limits = fuzz_limits();
  plain.prefetch_threads = 0;
  plain.decode_threads = 1;
  plain.coefficient_cache_bytes = plain.face_cache_bytes = plain.reference_cache_bytes = plain.depth_cache_bytes =
      0;
  auto sequential_reader = Reader::open(memory_source(file), plain);
  if (!sequential_reader.ok()) return 0;
  const SequentialDecode expected = sequential_decode(**sequential_reader);
  sequential_reader = Status(ErrorCode::kCancelled, "done");

  ReaderSettings settings;
  settings.limits = fuzz_limits();
  settings.prefetch_threads = 2;
  settings.decode_threads = 2;
  settings.prefetch_radius = 2;
  settings.coefficient_cache_bytes = 4 << 10;
  settings.face_cache_bytes = 12 << 10;
  settings.reference_cache_bytes = 12 << 10;
  settings.depth_cache_bytes = 4 << 10;
  auto opened = Reader::open(memory_source(file), settings);
  if (!opened.ok()) {
    report_failure("the threaded reader refused a file the sequential reader opened: " +
                   opened.status().to_string());
    return 0;
  }
  Reader& reader = **opened;
  const auto& cells = reader.cells();
  const int w = reader.info().face_width, h = reader.info().face_height;
  const uint64_t hash = input_hash(data);
  constexpr int kThreads = 4;
  std::atomic<bool> closing{false};
  std::atomic<int> succeeded{0};
  // A failed call's code against the sequential decode's for `frame`.
  auto check_error = [&](ErrorCode code, size_t frame, const char* call) {
    if (code == ErrorCode::kCancelled && closing.load()) return;
    if (code != expected.faces[frame].code) {
      report_failure(std::string(call) + " of frame " + std::to_string(frame) + " gave " + error_code_name(code) +
                     ", the sequential decode " + error_code_name(expected.faces[frame].code));
    }
  };
  auto check_face = [&](const Result<std::shared_ptr<const ImageYCbCr420>>& got, size_t frame) {
    if (!got.ok()) return check_error(got.status().code(), frame, "acquire_face_ycbcr");
    if (expected.faces[frame].code != ErrorCode::kOk || !same_pixels(**got, expected.images[frame])) {
      report_failure("acquire_face_ycbcr of frame " + std::to_string(frame) +
                     " differs from the sequential decode");
    }
    ++succeeded;
  };
  auto check_into = [&](Status status, const std::vector<uint8_t>& rgba, size_t frame) {
    if (!status.ok()) return check_error(status.code(), frame, "decode_face_into");
    std::vector<uint8_t> want(rgba.size());
    if (expected.faces[frame].code == ErrorCode::kOk) {
      want.resize(static_cast<size_t>(w) * h * 3);
      codec::ycbcr420_to_rgb(expected.images[frame], want.data());
      for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p) {
        if (rgba[p * 4] != want[p * 3] || rgba[p * 4 + 1] != want[p * 3 + 1] ||
            rgba[p * 4 + 2] != want[p * 3 + 2] || rgba[p * 4 + 3] != 255) {
          report_failure("decode_face_into of frame " + std::to_string(frame) +
                         " differs from the sequential decode");
          return;
        }
      }
    } else {
      report_failure("decode_face_into of frame " + std::to_string(frame) +
                     " succeeded, the sequential decode failed");
    }
    ++succeeded;
  };
  auto check_cube = [&](const Result<std::array<ImageRGB8, kFaceCount>>& got, size_t cell) {
    size_t first_failed = kFaceCount;
    for (size_t f = 0; f < kFaceCount && first_failed == kFaceCount; ++f) {
      if (expected.faces[cell * kFaceCount + f].code != ErrorCode::kOk) first_failed = f;
    }
    if (!got.ok()) {
      if (got.status().code() == ErrorCode::kCancelled && closing.load()) return;
      if (first_failed == kFaceCount) return check_error(got.status().code(), cell * kFaceCount, "decode_cube");
      return check_error(got.status().code(), cell * kFaceCount + first_failed, "decode_cube");
    }
    for (size_t f = 0; f < kFaceCount; ++f) {
      const size_t frame = cell * kFaceCount + f;
      std::vector<uint8_t> want(static_cast<size_t>(w) * h * 3);
      if (expected.faces[frame].code == ErrorCode::kOk) codec::ycbcr420_to_rgb(expected.images[frame], want.data());
      if (expected.faces[frame].code != ErrorCode::kOk || (*got)[f].pixels != want) {
        report_failure("decode_cube of cell " + std::to_string(cell) + " differs from the sequential decode");
        return;
      }
    }
    ++succeeded;
  };
  auto caller = [&](int t) {
    InputRandom random(hash + static_cast<uint64_t>(t) * 0x9e3779b97f4a7c15ull);
    std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4);
    PixelBuffer buffer;
    buffer.planes[0] = rgba;
    buffer.strides[0] = static_cast<size_t>(w) * 4;
    const int calls = 6 + static_cast<int>(random.below(18));
    const int close_at = t == kThreads - 1 ? static_cast<int>(random.below(calls + 1)) : -1;
    for (int i = 0; i < calls; ++i) {
      if (i == close_at) {
        closing = true;
        reader.close();
      }
      const size_t c = random.below(cells.size());
      const size_t frame = c * kFaceCount + random.below(kFaceCount);
      switch (random.below(5)) {
        case 0: check_face(reader.acquire_face_ycbcr(cells[c].index, kAllFaces[frame % kFaceCount]), frame); break;
        case 1:
          check_into(reader.decode_face_into(cells[c].index, kAllFaces[frame % kFaceCount], buffer), rgba, frame);
          break;
        case 2: check_cube(reader.decode_cube(cells[c].index), c); break;
        case 3: {
          const Status moved = reader.set_viewer(cells[c].index, {1.0 * random.below(3) - 1, 0, 0});
          if (!moved.ok() && !(moved.code() == ErrorCode::kCancelled && closing.load())) {
            report_failure("set_viewer: " + moved.to_string());
          }
          break;
        }
        default: {
          const auto& p = cells[c].position;
          const Status moved = reader.set_viewer(std::array<double, 3>{p[0] + 0.3, p[1], p[2] - 0.2});
          if (!moved.ok() && !(moved.code() == ErrorCode::kCancelled && closing.load())) {
            report_failure("set_viewer: " + moved.to_string());
          }
          (void)reader.stats();
        }
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back(caller, t);
  for (std::thread& thread : threads) thread.join();
  // After close every decode is refused; before it, nothing is left to check.
  if (closing.load() && !cells.empty() &&
      reader.acquire_face_ycbcr(cells[0].index, Face::kPX).status().code() != ErrorCode::kCancelled) {
    report_failure("a decode after close() was not cancelled");
  }
  if (!reader.wait_for_prefetch(std::chrono::seconds(60))) report_failure("prefetch did not finish");
  return succeeded.load();
}

}  // namespace svc::fuzz
