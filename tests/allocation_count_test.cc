// SPDX-License-Identifier: BSD-2-Clause
// What the reader allocates, measured by a program of its own (it replaces operator new,
// so that the count replaces no other test's allocator): every operator new is counted,
// with the bytes held now and at most (malloc_usable_size). Decoding into the caller's
// buffer allocates nothing once the caches hold the face; a file whose index claims huge
// sizes is refused before it allocates more than a small cap; and the peak heap of
// opening and decoding every fuzz-corpus file (and conformance stream) stays under a
// bound set by its face size and face count (docs/format.md, "Validation and caps").
#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>

#include "codec/common/cube_padding.h"
#include "container/container.h"
#include "fuzz/fuzz_entry.h"
#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"
#include "svc/svc.h"

namespace {
std::atomic<uint64_t> g_allocations{0};
std::atomic<int64_t> g_bytes_held{0};
std::atomic<int64_t> g_peak_bytes{0};

void note_allocation(void* p) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const int64_t held = g_bytes_held.fetch_add(static_cast<int64_t>(malloc_usable_size(p))) +
                       static_cast<int64_t>(malloc_usable_size(p));
  int64_t peak = g_peak_bytes.load(std::memory_order_relaxed);
  while (held > peak && !g_peak_bytes.compare_exchange_weak(peak, held)) {
  }
}

void release(void* p) {
  if (p == nullptr) return;
  g_bytes_held.fetch_sub(static_cast<int64_t>(malloc_usable_size(p)));
  std::free(p);
}
}  // namespace

void* operator new(std::size_t size) {
  if (void* p = std::malloc(size == 0 ? 1 : size)) {
    note_allocation(p);
    return p;
  }
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }

namespace {
// The most bytes held at once since it was made, above what was held then.
class PeakHeap {
 public:
  PeakHeap() : start_(g_bytes_held.load()) { g_peak_bytes.store(start_); }
  int64_t above_start() const { return g_peak_bytes.load() - start_; }

 private:
  int64_t start_;
};
}  // namespace

namespace svc {
namespace {

TEST(Allocations, DecodingACachedFaceIntoTheCallersBufferAllocatesNothing) {
  testing::TempDir dir("svc-allocations");
  samples::SceneOptions options;
  options.grid = {3, 1, 1};
  options.face_size = 64;
  ASSERT_TRUE(samples::generate_scene(options, dir.path() / "db").ok());
  EncoderSettings encoder;
  encoder.threads = 1;
  ASSERT_TRUE(encode_database(dir.path() / "db", dir.path() / "db.svc", encoder).ok());
  ReaderSettings settings;
  settings.prefetch_threads = 0;
  settings.decode_threads = 1;
  auto reader = Reader::open(dir.path() / "db.svc", settings);
  ASSERT_TRUE(reader.ok());
  std::vector<uint8_t> pixels(64 * 64 * 4);
  PixelBuffer buffer;
  buffer.format = PixelFormat::kBGRA8;
  buffer.planes[0] = pixels;
  buffer.strides[0] = 64 * 4;
  const CellIndex b_cell{1, 0, 0};  // a B-cube's face and the I-faces it predicts from
  const uint64_t cold = g_allocations.load();
  for (Face face : kAllFaces) ASSERT_TRUE((*reader)->decode_face_into(b_cell, face, buffer).ok());
  EXPECT_GT(g_allocations.load() - cold, 0u);  // decoding does allocate: the count sees it

  const uint64_t before = g_allocations.load();
  for (int pass = 0; pass < 3; ++pass) {
    for (Face face : kAllFaces) ASSERT_TRUE((*reader)->decode_face_into(b_cell, face, buffer).ok());
  }
  EXPECT_EQ(g_allocations.load() - before, 0u);

  // The C API's call over it, the same.
  svc_reader* c_reader = nullptr;
  svc_reader_settings c_settings;
  svc_reader_settings_default(&c_settings);
  c_settings.prefetch_threads = 0;
  c_settings.decode_threads = 1;
  ASSERT_EQ(svc_reader_open_file((dir.path() / "db.svc").c_str(), &c_settings, &c_reader), SVC_OK);
  const int32_t cell[3] = {1, 0, 0};
  const svc_image image{SVC_PIXEL_RGBA8, SVC_ROWS_BOTTOM_UP, {pixels.data()}, {64 * 4}, {pixels.size()}};
  ASSERT_EQ(svc_reader_decode_face(c_reader, cell, SVC_FACE_PZ, &image), SVC_OK);
  const uint64_t c_before = g_allocations.load();
  for (int pass = 0; pass < 3; ++pass)
    ASSERT_EQ(svc_reader_decode_face(c_reader, cell, SVC_FACE_PZ, &image), SVC_OK);
  EXPECT_EQ(g_allocations.load() - c_before, 0u);
  svc_reader_destroy(c_reader);
}

namespace fs = std::filesystem;

uint64_t get_u64(const std::vector<uint8_t>& bytes, size_t at) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t{bytes[at + i]} << (8 * i);
  return v;
}

// Where the index chunk of an intact file written by the encoder starts (commit slot 0).
uint64_t index_chunk_at(const std::vector<uint8_t>& bytes) { return get_u64(bytes, kFileHeaderSize + 8); }

// The file with its index replaced by `index`, serialized into a chunk appended at the
// end that both commit slots point at.
std::vector<uint8_t> with_index(std::vector<uint8_t> bytes, const ContainerIndex& index) {
  const uint64_t at = bytes.size();
  const std::vector<uint8_t> chunk = make_chunk(kIndexChunkTag, serialize_index(index));
  bytes.insert(bytes.end(), chunk.begin(), chunk.end());
  const std::vector<uint8_t> slot = make_commit_slot(1000, at, chunk.size());
  for (int s = 0; s < 2; ++s)
    std::copy(slot.begin(), slot.end(), bytes.begin() + kFileHeaderSize + s * kCommitSlotSize);
  return bytes;
}

struct Refusal {
  Status status;
  int64_t peak = 0;
};

Refusal open_with_default_limits(const std::vector<uint8_t>& bytes) {
  Refusal refusal;
  PeakHeap peak;
  auto reader = Reader::open(memory_source(bytes, "forged.svc"));
  refusal.status = reader.ok() ? Status::Ok() : reader.status();
  refusal.peak = peak.above_start();
  return refusal;
}

// The cap docs/format.md states on what opening a file may allocate before a size in its
// header or index is refused: the index read whole (here a few hundred bytes), the error
// message and the reader's own state, far below this.
constexpr int64_t kRefusalCapBytes = 256 << 10;

// Files whose index claims huge sizes are refused with kLimitExceeded, naming the field
// and its byte offset, under the default limits and before allocating for those sizes.
TEST(MemoryCaps, HugeSizesInTheIndexAreRefusedBeforeAllocating) {
  testing::TempDir dir("svc-memory-caps");
  samples::SceneOptions options;
  options.grid = {3, 1, 1};
  options.face_size = 16;
  ASSERT_TRUE(samples::generate_scene(options, dir.path() / "db").ok());
  EncoderSettings encoder;
  encoder.threads = 1;
  ASSERT_TRUE(encode_database(dir.path() / "db", dir.path() / "small.svc", encoder).ok());
  const std::vector<uint8_t> intact = testing::read_file_data(dir.path() / "small.svc");
  auto file = ReadOnlyFile::open(dir.path() / "small.svc");
  ASSERT_TRUE(file.ok());
  auto opened = open_container(**file, ReaderLimits{});
  ASSERT_TRUE(opened.ok()) << opened.status().to_string();
  const ContainerIndex& index = opened->index;
  ASSERT_EQ(index.cells.size(), 3u);
  // The default limits are those this test means.
  const ReaderLimits defaults;
  ASSERT_LT(defaults.max_face_dimension, 65535u);
  ASSERT_LT(defaults.max_cells, 0xffffffffull);

  struct Forged {
    std::string name;
    std::vector<uint8_t> bytes;
    std::string message;  // a part of the expected message
  };
  std::vector<Forged> forged;
  ContainerIndex edited = index;
  edited.face_width = edited.face_height = 65535;
  forged.push_back({"faces of 65535x65535", with_index(intact, edited), "face size 65535x65535"});
  edited = index;
  edited.face_width = edited.face_height = 16384;  // each side at its cap, the pixels above theirs
  forged.push_back({"faces of 16384x16384", with_index(intact, edited), "face size 16384x16384"});
  edited = index;
  edited.grid.dims = {2147483647, 1, 1};
  forged.push_back({"a grid of 2^31 - 1 cells along x", with_index(intact, edited), "grid dimension 2147483647"});
  edited = index;
  edited.frames[0].payload_size = 0xffffffffu;
  forged.push_back({"a face of 4 GiB", with_index(intact, edited), "4294967295 bytes, above the reader's limit"});
  {
    // 2^32 - 1 cells: the cell count follows the 100-byte header and the six square rig
    // entries (28 bytes each) of a cube rig, after the chunk's 12-byte framing.
    std::vector<uint8_t> bytes = intact;
    const uint64_t count_at = index_chunk_at(bytes) + 12 + 100 + 1 + 6 * 28;
    ASSERT_EQ(bytes[count_at], 3);
    ASSERT_EQ(bytes[count_at + 1], 0);
    for (int i = 0; i < 4; ++i) bytes[count_at + i] = 0xff;
    fuzz::repair_checksums(bytes);
    forged.push_back({"2^32 - 1 cells", bytes, "cell count 4294967295"});
  }
  {
    // An index chunk of 1 TiB in both commit slots.
    std::vector<uint8_t> bytes = intact;
    for (int s = 0; s < 2; ++s) {
      const size_t slot_at = kFileHeaderSize + s * kCommitSlotSize;
      if (get_u64(bytes, slot_at) == 0) continue;
      for (int i = 0; i < 8; ++i) bytes[slot_at + 16 + i] = static_cast<uint8_t>((1ull << 40) >> (8 * i));
    }
    fuzz::repair_checksums(bytes);
    forged.push_back({"an index of 1 TiB", bytes, "index of 1099511627776"});
  }
  int64_t largest = 0;
  for (const Forged& f : forged) {
    SCOPED_TRACE(f.name);
    const Refusal refusal = open_with_default_limits(f.bytes);
    EXPECT_EQ(refusal.status.code(), ErrorCode::kLimitExceeded) << refusal.status.to_string();
    EXPECT_NE(refusal.status.message().find(f.message), std::string::npos) << refusal.status.message();
    EXPECT_NE(refusal.status.message().find("offset"), std::string::npos) << refusal.status.message();
    EXPECT_LT(refusal.peak, kRefusalCapBytes);
    largest = std::max(largest, refusal.peak);
    std::printf("%s: refused, peak heap %lld bytes: %s\n", f.name.c_str(), static_cast<long long>(refusal.peak),
                refusal.status.message().c_str());
  }
  std::printf("largest peak heap of a refusal: %lld bytes (cap %lld)\n", static_cast<long long>(largest),
              static_cast<long long>(kRefusalCapBytes));
}

// The peak heap of opening a file with the default settings and decoding everything in
// it (each cube, then each face as RGB, and its depth) stays under a bound set by the
// file: 1 MiB, plus 16 bytes a sample for every face the file holds (what the caches can
// hold of it: decoded, reference, padded and semi-decoded forms, and depth) and for ten
// faces more (the decoding threads' working buffers and the faces being returned), a
// face counted with the widest cube border around it when faces are square (the
// reference cache holds I-faces padded for the edges B-faces read, which for small faces
// is many times the face); plus, then, 16 bytes a border sample of the cube-padding maps
// of its face size (six faces, luma and chroma: codec/common/cube_padding_map.h), which a
// process shares between files but rebuilds when files of many sizes evict them.
TEST(MemoryCaps, PeakHeapOfDecodingEveryCorpusFileIsBounded) {
  const fs::path source(SVC_SOURCE_DIR);
  std::vector<fs::path> files;
  for (const fs::path dir : {source / "tests/fuzz/corpus/container", source / "tests/conformance/streams"}) {
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() == ".svc") files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  // Opens and decodes everything; returns the bound (the file's face size and count).
  auto decode_all = [](const std::vector<uint8_t>& bytes, const std::string& name) {
    auto reader = Reader::open(memory_source(bytes, name));
    int64_t bound = 1 << 20;
    if (!reader.ok()) return bound;
    Reader& r = **reader;
    const bool square = r.info().face_width == r.info().face_height;
    const int64_t n = r.info().face_width, border = square ? 16 * codec::kMaxCubeBorderUnits : 0;
    const int64_t samples = (n + 2 * border) * (r.info().face_height + 2 * border);
    bound += 16 * samples * (static_cast<int64_t>(r.cells().size()) * kFaceCount + 10);
    if (square) {
      const int64_t c = (n + 1) / 2;
      bound += 16 * kFaceCount * (samples - n * n + (c + border) * (c + border) - c * c);
    }
    for (const CellEntry& cell : r.cells()) {
      (void)r.decode_cube(cell.index);
      for (Face face : kAllFaces) {
        (void)r.decode_face(cell.index, face);
        if (r.info().has_depth) (void)r.decode_face_depth(cell.index, face);
      }
    }
    return bound;
  };
  // Once first, unmeasured: the process's one-time tables (about 1.3 MB) are no file's.
  for (const fs::path& path : files) (void)decode_all(testing::read_file_data(path), path.filename().string());
  double largest_share = 0;
  for (const fs::path& path : files) {
    SCOPED_TRACE(path.string());
    const std::vector<uint8_t> bytes = testing::read_file_data(path);
    PeakHeap peak;
    const int64_t bound = decode_all(bytes, path.filename().string());
    const int64_t measured = peak.above_start();
    EXPECT_LE(measured, bound);
    largest_share = std::max(largest_share, static_cast<double>(measured) / static_cast<double>(bound));
    std::printf("%s: peak heap %lld bytes, bound %lld\n", path.filename().c_str(), static_cast<long long>(measured),
                static_cast<long long>(bound));
  }
  std::printf("largest peak heap: %.0f%% of its bound\n", 100 * largest_share);
}

}  // namespace
}  // namespace svc
