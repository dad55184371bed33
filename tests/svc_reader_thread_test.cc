// SPDX-License-Identifier: BSD-2-Clause
// The reader under concurrency: many threads, prefetch workers, in-flight
// deduplication and close() while work is pending. Run under ThreadSanitizer by
// scripts/test-tsan.sh.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <thread>
#include <utility>

#include "codec/common/color.h"
#include "reader/pixel_buffer.h"
#include "reader/shared_cache.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

bool same_image(const ImageYCbCr420& a, const ImageYCbCr420& b) {
  return a.width == b.width && a.height == b.height && a.y == b.y && a.cb == b.cb && a.cr == b.cr;
}

// A 6x1x6 hall of 32x32 faces, and every face decoded sequentially without caches.
class ReaderThreads : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-reader-threads");
    samples::SceneOptions options;
    options.grid = {6, 1, 6};
    options.face_size = 32;
    ASSERT_TRUE(samples::generate_scene(options, dir_->path() / "db").ok());
    EncoderSettings encoder;
    encoder.threads = 1;
    auto summary = encode_database(dir_->path() / "db", file(), encoder);
    ASSERT_TRUE(summary.ok()) << summary.status().to_string();
    ReaderSettings uncached;
    uncached.coefficient_cache_bytes = 0;
    uncached.face_cache_bytes = 0;
    uncached.reference_cache_bytes = 0;
    uncached.prefetch_threads = 0;
    auto reader = Reader::open(file(), uncached);
    ASSERT_TRUE(reader.ok()) << reader.status().to_string();
    reference_ = new std::vector<ImageYCbCr420>();
    for (const CellEntry& cell : (*reader)->cells()) {
      for (Face face : kAllFaces) {
        auto image = (*reader)->decode_face_ycbcr(cell.index, face);
        ASSERT_TRUE(image.ok()) << image.status().to_string();
        reference_->push_back(std::move(image).value());
      }
    }
  }
  static void TearDownTestSuite() {
    delete reference_;
    delete dir_;
  }
  static fs::path file() { return dir_->path() / "hall.svc"; }
  static const ImageYCbCr420& reference(size_t frame) { return (*reference_)[frame]; }
  static size_t frame_count() { return reference_->size(); }
  // A reader without prefetch decoding on `threads` threads, and the first cell whose
  // face `face` is a B-face.
  static std::pair<std::unique_ptr<Reader>, size_t> open_decoding_on(int threads, Face face) {
    ReaderSettings settings;
    settings.prefetch_threads = 0;
    settings.decode_threads = threads;
    auto opened = Reader::open(file(), settings);
    EXPECT_TRUE(opened.ok()) << opened.status().to_string();
    if (!opened.ok()) return {nullptr, 0};
    size_t b_cell = 0;
    while ((*opened)->cells()[b_cell].faces[static_cast<int>(face)].type != FaceType::kPredicted) ++b_cell;
    return {std::move(opened).value(), b_cell};
  }

  static testing::TempDir* dir_;
  static std::vector<ImageYCbCr420>* reference_;
};
testing::TempDir* ReaderThreads::dir_ = nullptr;
std::vector<ImageYCbCr420>* ReaderThreads::reference_ = nullptr;

// The working buffers a thread keeps for B-face decoding (outside the caches' budgets)
// are counted in the statistics: one face's worth for a thread that decoded one, given
// back when the thread ends.
TEST_F(ReaderThreads, ThreadBuffersAreCountedAndGivenBackWhenTheThreadEnds) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.face_cache_bytes = 0;
  auto reader = Reader::open(file(), settings);
  ASSERT_TRUE(reader.ok()) << reader.status().to_string();
  const auto& cells = (*reader)->cells();
  size_t b_cell = 0;
  while (b_cell < cells.size() && cells[b_cell].faces[0].type != FaceType::kPredicted) ++b_cell;
  ASSERT_LT(b_cell, cells.size());
  const uint64_t before = (*reader)->stats().thread_buffer_bytes;
  uint64_t during = 0;
  std::thread decoder([&] {
    for (Face face : kAllFaces) ASSERT_TRUE((*reader)->decode_face_ycbcr(cells[b_cell].index, face).ok());
    during = (*reader)->stats().thread_buffer_bytes;
  });
  decoder.join();
  const uint64_t pixels = 32 * 32;
  ASSERT_GT(during, before);
  const uint64_t held = during - before;
  std::printf("one thread's buffers after B-faces of 32x32: %llu bytes (%.1f a pixel)\n",
              static_cast<unsigned long long>(held), static_cast<double>(held) / pixels);
  EXPECT_GE(held, pixels * 3 / 2);  // at least the B-face's reconstructed planes
  EXPECT_LE(held, pixels * 32);     // and not more than about one face's worth
  EXPECT_EQ((*reader)->stats().thread_buffer_bytes, before);
}

TEST_F(ReaderThreads, EightThreadsOnRandomCellsEqualSequentialDecode) {
  ReaderSettings settings;
  settings.face_cache_bytes = 40 * (32 * 32 + 2 * 16 * 16 + 200);  // ~40 faces of 216
  settings.coefficient_cache_bytes = 8000;
  settings.prefetch_threads = 2;
  auto opened = Reader::open(file(), settings);
  ASSERT_TRUE(opened.ok());
  Reader& reader = **opened;
  const auto& cells = reader.cells();
  std::atomic<int> mismatches{0}, failures{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      std::mt19937 rng(100 + t);
      for (int i = 0; i < 60; ++i) {
        const size_t c = rng() % cells.size();
        if (t == 0) {
          // One thread plays the viewer, so prefetch workers join in.
          if (!reader.set_viewer(cells[c].index, {1.0 * (rng() % 3) - 1, 0, 1.0 * (rng() % 3) - 1}).ok())
            ++failures;
        }
        if (i % 5 == 0) {
          auto cube = reader.decode_cube(cells[c].index);
          if (!cube.ok()) {
            ++failures;
            continue;
          }
          for (int f = 0; f < kFaceCount; ++f) {
            if ((*cube)[f].pixels.size() != 32u * 32u * 3u) ++mismatches;
          }
          continue;
        }
        const int f = static_cast<int>(rng() % kFaceCount);
        auto image = reader.acquire_face_ycbcr(cells[c].index, kAllFaces[f]);
        if (!image.ok()) {
          ++failures;
        } else if (!same_image(**image, reference(c * kFaceCount + f))) {
          ++mismatches;
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(mismatches.load(), 0);
  ASSERT_TRUE(reader.wait_for_prefetch(std::chrono::seconds(30)));
  const ReaderStats stats = reader.stats();
  EXPECT_LE(stats.face_cache.peak_bytes, settings.face_cache_bytes);
  EXPECT_LE(stats.coefficient_cache.peak_bytes, settings.coefficient_cache_bytes);
  EXPECT_GT(stats.face_cache.evictions, 0u);
  // Every face the caches now hold is still the sequential decode.
  for (size_t frame = 0; frame < frame_count(); ++frame) {
    auto image = reader.decode_face_ycbcr(cells[frame / kFaceCount].index, kAllFaces[frame % kFaceCount]);
    ASSERT_TRUE(image.ok());
    ASSERT_TRUE(same_image(*image, reference(frame))) << frame;
  }
}

TEST_F(ReaderThreads, ConcurrentRequestsForOneFaceDecodeItOnce) {
  ReaderSettings settings;
  settings.prefetch_threads = 0;  // ample default budgets: nothing is evicted
  auto opened = Reader::open(file(), settings);
  ASSERT_TRUE(opened.ok());
  Reader& reader = **opened;
  const auto& cells = reader.cells();
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      std::vector<size_t> order(frame_count());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      // Half the threads walk the same order (maximal collisions), half shuffled.
      if (t % 2) std::shuffle(order.begin(), order.end(), std::mt19937(t));
      for (size_t frame : order) {
        auto image = reader.acquire_face_ycbcr(cells[frame / kFaceCount].index, kAllFaces[frame % kFaceCount]);
        if (!image.ok() || !same_image(**image, reference(frame))) ++mismatches;
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches.load(), 0);
  const ReaderStats stats = reader.stats();
  size_t intra = 0;
  for (const CellEntry& cell : cells) {
    for (const FaceEntry& face : cell.faces) intra += face.type == FaceType::kIntra;
  }
  // Each face decoded exactly once, each I-face entropy-decoded exactly once.
  EXPECT_EQ(stats.intra_faces_parsed, intra);
  EXPECT_EQ(stats.predicted_faces_decoded, frame_count() - intra);
  EXPECT_EQ(stats.face_cache.insertions, frame_count());
  EXPECT_EQ(stats.face_cache.misses, frame_count());
  EXPECT_EQ(stats.face_cache.hits + stats.face_cache.misses + stats.face_cache.in_flight_waits, 8 * frame_count());
  EXPECT_EQ(stats.face_cache.evictions, 0u);
}

// decode_cube on one, two and five threads gives the sequential decode's faces, and
// decodes each face of the cell and each reference I-face once.
TEST_F(ReaderThreads, CubeDecodeOnAnyThreadCountEqualsSequentialDecode) {
  for (int threads : {1, 2, 5}) {
    auto [opened, b_cell] = open_decoding_on(threads, Face::kPX);
    ASSERT_TRUE(opened);
    Reader& reader = *opened;
    const auto& cells = reader.cells();
    auto cube = reader.decode_cube(cells[b_cell].index);
    ASSERT_TRUE(cube.ok()) << cube.status().to_string();
    std::set<std::pair<uint32_t, Face>> references;
    for (int f = 0; f < kFaceCount; ++f) {
      ImageRGB8 expected;
      expected.width = reference(b_cell * kFaceCount + f).width;
      expected.height = reference(b_cell * kFaceCount + f).height;
      expected.pixels.resize(static_cast<size_t>(expected.width) * expected.height * 3);
      codec::ycbcr420_to_rgb(reference(b_cell * kFaceCount + f), expected.pixels.data());
      EXPECT_EQ((*cube)[f].pixels, expected.pixels) << threads << " threads, face " << f;
      for (const auto& dependency : cells[b_cell].faces[f].references) references.insert(dependency);
    }
    const ReaderStats stats = reader.stats();
    EXPECT_EQ(stats.predicted_faces_decoded, 6u) << threads << " threads";
    EXPECT_EQ(stats.intra_faces_parsed, references.size()) << threads << " threads";
  }
  ReaderSettings bad;
  bad.decode_threads = 65;
  auto refused = Reader::open(file(), bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("decode_threads 65 outside 0..64"), std::string::npos);
}

// One cold B-face on one, two and five threads: its reference I-faces are decoded side
// by side, each once, and the face is the sequential decode's.
TEST_F(ReaderThreads, FaceDecodeOnAnyThreadCountEqualsSequentialDecode) {
  for (int threads : {1, 2, 5}) {
    auto [opened, b_cell] = open_decoding_on(threads, Face::kPY);
    ASSERT_TRUE(opened);
    Reader& reader = *opened;
    const auto& cells = reader.cells();
    auto face = reader.decode_face_ycbcr(cells[b_cell].index, Face::kPY);
    ASSERT_TRUE(face.ok()) << face.status().to_string();
    const ImageYCbCr420& expected = reference(b_cell * kFaceCount + 2);
    EXPECT_EQ(face->y, expected.y) << threads << " threads";
    EXPECT_EQ(face->cb, expected.cb) << threads << " threads";
    EXPECT_EQ(face->cr, expected.cr) << threads << " threads";
    const ReaderStats stats = reader.stats();
    EXPECT_EQ(stats.predicted_faces_decoded, 1u) << threads << " threads";
    EXPECT_EQ(stats.intra_faces_parsed, cells[b_cell].faces[2].references.size()) << threads << " threads";
  }
}

TEST_F(ReaderThreads, PrefetchFillsTheNeighbourhoodAndRequestsJoinItsWork) {
  ReaderSettings settings;
  settings.prefetch_threads = 3;
  auto opened = Reader::open(file(), settings);
  ASSERT_TRUE(opened.ok());
  Reader& reader = **opened;
  const CellIndex viewer{2, 0, 3};
  ASSERT_TRUE(reader.set_viewer(viewer, {1, 0, 0}).ok());
  // Asked for at once: served by the workers' decodes or by this thread, never twice.
  auto cube = reader.decode_cube(viewer);
  ASSERT_TRUE(cube.ok());
  ASSERT_TRUE(reader.wait_for_prefetch(std::chrono::seconds(30)));
  ReaderStats stats = reader.stats();
  const size_t neighbourhood_faces = 9 * kFaceCount;
  EXPECT_EQ(stats.face_cache.entries, neighbourhood_faces);
  EXPECT_EQ(stats.face_cache.insertions, neighbourhood_faces);
  EXPECT_EQ(stats.intra_faces_parsed, stats.coefficient_cache.insertions);  // no I-face parsed twice
  EXPECT_EQ(stats.prefetch_faces + stats.face_cache.misses, neighbourhood_faces);

  // Every neighbour is now a hit, bit-exact.
  const uint64_t hits_before = stats.face_cache.hits;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dx = -1; dx <= 1; ++dx) {
      const CellIndex cell{viewer.x + dx, 0, viewer.z + dz};
      const size_t ordinal = *reader.find_cell(cell);
      for (int f = 0; f < kFaceCount; ++f) {
        auto image = reader.decode_face_ycbcr(cell, kAllFaces[f]);
        ASSERT_TRUE(image.ok());
        EXPECT_TRUE(same_image(*image, reference(ordinal * kFaceCount + f)));
      }
    }
  }
  stats = reader.stats();
  EXPECT_EQ(stats.face_cache.hits - hits_before, neighbourhood_faces);
  EXPECT_EQ(stats.face_cache.misses + stats.prefetch_faces, neighbourhood_faces);

  // The same viewer again queues nothing; moving on queues only the new cells.
  ASSERT_TRUE(reader.set_viewer(viewer, {1, 0, 0}).ok());
  ASSERT_TRUE(reader.set_viewer(CellIndex{3, 0, 3}, {1, 0, 0}).ok());
  ASSERT_TRUE(reader.wait_for_prefetch(std::chrono::seconds(30)));
  EXPECT_EQ(reader.stats().face_cache.insertions, neighbourhood_faces + 3 * kFaceCount);
}

TEST_F(ReaderThreads, CloseDuringPrefetchIsPromptAndClean) {
  for (int round = 0; round < 6; ++round) {
    ReaderSettings settings;
    settings.prefetch_threads = 4;
    settings.prefetch_radius = 8;  // the whole grid
    auto opened = Reader::open(file(), settings);
    ASSERT_TRUE(opened.ok());
    std::unique_ptr<Reader> reader = std::move(opened).value();
    ASSERT_TRUE(reader->set_viewer(CellIndex{round % 6, 0, 2}).ok());
    // Callers keep asking while another thread closes: each call either succeeds with
    // the right pixels or reports kCancelled.
    std::atomic<int> wrong{0};
    std::vector<std::thread> callers;
    for (int t = 0; t < 3; ++t) {
      callers.emplace_back([&, t] {
        std::mt19937 rng(round * 10 + t);
        for (int i = 0; i < 40; ++i) {
          const size_t frame = rng() % frame_count();
          auto image =
              reader->acquire_face_ycbcr(reader->cells()[frame / kFaceCount].index, kAllFaces[frame % kFaceCount]);
          if (image.ok() ? !same_image(**image, reference(frame))
                         : image.status().code() != ErrorCode::kCancelled) {
            ++wrong;
          }
        }
      });
    }
    if (round % 2) std::this_thread::sleep_for(std::chrono::milliseconds(round));
    std::thread closer([&] { reader->close(); });
    closer.join();
    for (auto& caller : callers) caller.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_TRUE(reader->wait_for_prefetch(std::chrono::milliseconds(0)));
    const ReaderStats stats = reader->stats();
    EXPECT_EQ(stats.face_cache.bytes_held, 0u);
    EXPECT_EQ(stats.coefficient_cache.bytes_held, 0u);
    EXPECT_EQ(reader->set_viewer(CellIndex{0, 0, 0}).code(), ErrorCode::kCancelled);
    EXPECT_EQ(reader->decode_face(CellIndex{0, 0, 0}, Face::kPX).status().code(), ErrorCode::kCancelled);
    reader.reset();
  }
  // Destroying a reader with prefetch in full swing, without close().
  for (int round = 0; round < 4; ++round) {
    ReaderSettings settings;
    settings.prefetch_threads = 4;
    settings.prefetch_radius = 8;
    auto opened = Reader::open(file(), settings);
    ASSERT_TRUE(opened.ok());
    ASSERT_TRUE((*opened)->set_viewer(std::array<double, 3>{0.5 * round, 0, 1.0}, {0, 0, 1}).ok());
  }
}

size_t pixel_buffer_bytes(PixelFormat format, int w, int h) {
  const size_t pixels = static_cast<size_t>(w) * h;
  if (format == PixelFormat::kYCbCr420) return pixels + 2 * static_cast<size_t>((w + 1) / 2) * ((h + 1) / 2);
  return pixels * (format == PixelFormat::kRGB8 ? 3 : 4);
}

// A top-down buffer of `format` for a w x h face over the start of `bytes` (planes one
// after the other), which holds at least pixel_buffer_bytes(format, w, h).
PixelBuffer pixel_buffer(PixelFormat format, int w, int h, std::span<uint8_t> bytes) {
  PixelBuffer buffer;
  buffer.format = format;
  if (format != PixelFormat::kYCbCr420) {
    buffer.planes[0] = bytes.first(pixel_buffer_bytes(format, w, h));
    buffer.strides[0] = static_cast<size_t>(w) * (format == PixelFormat::kRGB8 ? 3 : 4);
    return buffer;
  }
  const size_t cw = (w + 1) / 2, ch = (h + 1) / 2, luma = static_cast<size_t>(w) * h;
  buffer.planes = {bytes.subspan(0, luma), bytes.subspan(luma, cw * ch), bytes.subspan(luma + cw * ch, cw * ch)};
  buffer.strides = {static_cast<size_t>(w), cw, cw};
  return buffer;
}

// What decode_face_into writes for the sequential decode's face in `format` (top-down).
std::vector<uint8_t> expected_pixels(const ImageYCbCr420& face, PixelFormat format) {
  std::vector<uint8_t> bytes(pixel_buffer_bytes(format, face.width, face.height));
  reader_internal::write_pixels(face, pixel_buffer(format, face.width, face.height, bytes));
  return bytes;
}

// Several threads call every kind of method at once on one reader with prefetch workers
// and small budgets, and one closes it in the middle: every call made before close
// returns gives the sequential decode's pixels (or kCancelled, once close has begun),
// every call made after it is cancelled, and nothing hangs (scripts/test-tsan.sh runs
// it under ThreadSanitizer).
TEST_F(ReaderThreads, EveryCallFromManyThreadsWithCloseInTheMiddle) {
  for (int round = 0; round < 3; ++round) {
    ReaderSettings settings;
    settings.prefetch_threads = 2;
    settings.decode_threads = 2;
    settings.face_cache_bytes = 20 * (32 * 32 + 2 * 16 * 16 + 200);
    settings.coefficient_cache_bytes = 6000;
    settings.reference_cache_bytes = 30000;
    auto opened = Reader::open(file(), settings);
    ASSERT_TRUE(opened.ok());
    Reader& reader = **opened;
    const auto& cells = reader.cells();
    std::atomic<int> calls{0}, wrong{0}, after_close{0};
    std::atomic<bool> closing{false}, closed{false};
    // An outcome is right when ok with the right pixels, or cancelled once close began;
    // a call that started after close returned must be cancelled.
    auto judge = [&](bool started_closed, ErrorCode code, bool right_pixels) {
      ++calls;
      if (started_closed) {
        ++after_close;
        if (code != ErrorCode::kCancelled) ++wrong;
      } else if (code == ErrorCode::kOk ? !right_pixels : !(code == ErrorCode::kCancelled && closing.load())) {
        ++wrong;
      }
    };
    auto caller = [&](int t) {
      std::mt19937 rng(1000 * round + t);
      std::vector<uint8_t> buffer_bytes(pixel_buffer_bytes(PixelFormat::kYCbCr420, 32, 32) + 32 * 32 * 4);
      // 80 calls, and on until five were made after close returned.
      for (int i = 0, after = 0; i < 80 || after < 5; ++i) {
        const size_t c = rng() % cells.size();
        const int f = static_cast<int>(rng() % kFaceCount);
        const size_t frame = c * kFaceCount + f;
        const bool started_closed = closed.load();
        after += started_closed;
        switch ((t + i) % 6) {
          case 0: {
            auto image = reader.decode_face(cells[c].index, kAllFaces[f]);
            judge(started_closed, image.status().code(),
                  image.ok() && image->pixels == expected_pixels(reference(frame), PixelFormat::kRGB8));
            break;
          }
          case 1: {
            const auto format = static_cast<PixelFormat>(rng() % 4);
            const PixelBuffer out = pixel_buffer(format, 32, 32, buffer_bytes);
            const Status status = reader.decode_face_into(cells[c].index, kAllFaces[f], out);
            const std::vector<uint8_t> want = expected_pixels(reference(frame), format);
            judge(started_closed, status.code(),
                  status.ok() && std::equal(want.begin(), want.end(), buffer_bytes.begin()));
            break;
          }
          case 2: {
            auto cube = reader.decode_cube(cells[c].index);
            bool right = cube.ok();
            for (int g = 0; right && g < kFaceCount; ++g) {
              right = (*cube)[g].pixels == expected_pixels(reference(c * kFaceCount + g), PixelFormat::kRGB8);
            }
            judge(started_closed, cube.status().code(), right);
            break;
          }
          case 3: {
            auto image = reader.acquire_face_ycbcr(cells[c].index, kAllFaces[f]);
            judge(started_closed, image.status().code(), image.ok() && same_image(**image, reference(frame)));
            break;
          }
          case 4:
            judge(started_closed, reader.set_viewer(cells[c].index, {1.0 * (rng() % 3) - 1, 0, 0}).code(), true);
            break;
          default: {
            const auto& p = cells[c].position;
            judge(started_closed, reader.set_viewer(std::array<double, 3>{p[0] + 0.2, p[1], p[2] - 0.3}).code(),
                  true);
            const ReaderStats stats = reader.stats();
            if (stats.face_cache.bytes_held > settings.face_cache_bytes) ++wrong;
          }
        }
      }
    };
    std::vector<std::thread> threads;
    for (int t = 0; t < 5; ++t) threads.emplace_back(caller, t);
    std::thread closer([&] {
      while (calls.load() < 120 + 60 * round) std::this_thread::yield();
      closing = true;
      reader.close();
      closed = true;
    });
    for (auto& thread : threads) thread.join();
    closer.join();
    EXPECT_EQ(wrong.load(), 0) << "round " << round;
    EXPECT_GT(after_close.load(), 0) << "round " << round;
    EXPECT_TRUE(reader.wait_for_prefetch(std::chrono::milliseconds(0)));
    EXPECT_EQ(reader.stats().face_cache.bytes_held, 0u);
    EXPECT_EQ(reader.decode_cube(cells[0].index).status().code(), ErrorCode::kCancelled);
    std::vector<uint8_t> rgba(32 * 32 * 4);
    EXPECT_EQ(
        reader.decode_face_into(cells[0].index, Face::kPX, pixel_buffer(PixelFormat::kRGBA8, 32, 32, rgba)).code(),
        ErrorCode::kCancelled);
  }
}

// Seek stress: eight readers of one file, each on its own thread with its own seed, ask
// for random faces and cubes in random order and in random pixel formats; some with
// prefetch following a moving viewer, some with caches too small to hold a cube. Every
// result is the sequential decode's.
TEST_F(ReaderThreads, SeekStressManyReadersOnOneFileEqualSequentialDecode) {
  constexpr int kReaders = 8;
  std::atomic<int> wrong{0}, failed{0}, faces{0};
  auto run = [&](int r) {
    ReaderSettings settings;
    settings.decode_threads = 1 + r % 3;
    settings.prefetch_threads = r % 2 ? 2 : 0;
    if (r % 4 >= 2) {  // tiny caches: almost every request decodes again
      settings.face_cache_bytes = 3 * (32 * 32 + 2 * 16 * 16 + 200);
      settings.coefficient_cache_bytes = 2000;
      settings.reference_cache_bytes = 5000;
    }
    auto opened = Reader::open(file(), settings);
    if (!opened.ok()) {
      ++failed;
      return;
    }
    Reader& reader = **opened;
    const auto& cells = reader.cells();
    std::mt19937 rng(7000 + r);
    std::vector<uint8_t> bytes(pixel_buffer_bytes(PixelFormat::kRGBA8, 32, 32));
    for (int i = 0; i < 150; ++i) {
      const size_t c = rng() % cells.size();
      const int f = static_cast<int>(rng() % kFaceCount);
      const size_t frame = c * kFaceCount + f;
      if (settings.prefetch_threads > 0 && i % 10 == 0) {
        if (!reader.set_viewer(cells[c].index, {1.0 * (rng() % 3) - 1, 0, 1.0 * (rng() % 3) - 1}).ok()) ++failed;
      }
      switch (rng() % 3) {
        case 0: {
          auto image = reader.decode_face(cells[c].index, kAllFaces[f]);
          if (!image.ok())
            ++failed;
          else if (image->pixels != expected_pixels(reference(frame), PixelFormat::kRGB8))
            ++wrong;
          ++faces;
          break;
        }
        case 1: {
          const auto format = static_cast<PixelFormat>(rng() % 4);
          const auto rows = rng() % 2 ? RowOrder::kBottomUp : RowOrder::kTopDown;
          std::fill(bytes.begin(), bytes.end(), 0x5a);
          PixelBuffer out = pixel_buffer(format, 32, 32, bytes);
          out.rows = rows;
          if (!reader.decode_face_into(cells[c].index, kAllFaces[f], out).ok()) {
            ++failed;
            break;
          }
          std::vector<uint8_t> want(bytes.size(), 0x5a);
          PixelBuffer expected = pixel_buffer(format, 32, 32, want);
          expected.rows = rows;
          reader_internal::write_pixels(reference(frame), expected);
          if (want != bytes) ++wrong;
          ++faces;
          break;
        }
        default: {
          auto cube = reader.decode_cube(cells[c].index);
          if (!cube.ok()) {
            ++failed;
            break;
          }
          for (int g = 0; g < kFaceCount; ++g) {
            if ((*cube)[g].pixels != expected_pixels(reference(c * kFaceCount + g), PixelFormat::kRGB8)) ++wrong;
          }
          faces += kFaceCount;
        }
      }
    }
  };
  std::vector<std::thread> threads;
  for (int r = 0; r < kReaders; ++r) threads.emplace_back(run, r);
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(wrong.load(), 0);
  std::printf("seek stress: %d faces from %d readers\n", faces.load(), kReaders);
}

// A cache computation that throws (an allocation failure) releases its in-flight entry:
// the thread waiting for it gets the error, and the next request computes again.
TEST(SharedCache, AThrowingComputationWakesItsWaitersAndIsRetried) {
  using reader_internal::Origin;
  using reader_internal::Outcome;
  reader_internal::SharedCache<int> cache(1 << 20, [](const int&) -> uint64_t { return sizeof(int); });
  std::mutex mutex;
  std::condition_variable cv;
  bool release = false;
  ErrorCode owner_code = ErrorCode::kOk, waiter_code = ErrorCode::kOk;
  std::thread owner([&] {
    owner_code = cache
                     .get(7, Origin::kCaller,
                          [&]() -> Result<std::shared_ptr<const int>> {
                            std::unique_lock<std::mutex> lock(mutex);
                            cv.wait(lock, [&] { return release; });
                            throw std::bad_alloc();
                          })
                     .status()
                     .code();
  });
  while (cache.counters().misses == 0) std::this_thread::yield();
  std::thread waiter([&] {
    waiter_code = cache
                      .get(7, Origin::kCaller,
                           [&]() -> Result<std::shared_ptr<const int>> {
                             ADD_FAILURE() << "the waiter computed";
                             return std::make_shared<const int>(0);
                           })
                      .status()
                      .code();
  });
  while (cache.counters().in_flight_waits == 0) std::this_thread::yield();
  {
    std::lock_guard<std::mutex> lock(mutex);
    release = true;
  }
  cv.notify_all();
  owner.join();
  waiter.join();
  EXPECT_EQ(owner_code, ErrorCode::kOutOfMemory);
  EXPECT_EQ(waiter_code, ErrorCode::kOutOfMemory);
  EXPECT_EQ(cache.counters().entries, 0u);
  Outcome outcome = Outcome::kHit;
  auto again = cache.get(
      7, Origin::kCaller, [] { return Result<std::shared_ptr<const int>>(std::make_shared<const int>(5)); },
      &outcome);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(**again, 5);
  EXPECT_EQ(outcome, Outcome::kComputed);
  // Anything else thrown is an internal error, reported the same way.
  auto internal = cache.get(8, Origin::kCaller, []() -> Result<std::shared_ptr<const int>> {
    throw std::runtime_error("broken invariant");
  });
  EXPECT_EQ(internal.status().code(), ErrorCode::kInternal);
  EXPECT_NE(internal.status().message().find("broken invariant"), std::string::npos);
}

}  // namespace
}  // namespace svc
