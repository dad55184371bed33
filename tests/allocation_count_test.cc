// SPDX-License-Identifier: BSD-2-Clause
// Decoding into the caller's buffer allocates nothing once the caches hold the face: every
// operator new of this program is counted (a program of its own, so that the count
// replaces no other test's allocator).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"
#include "svc/svc.h"

namespace {
std::atomic<uint64_t> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

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

}  // namespace
}  // namespace svc
