// SPDX-License-Identifier: BSD-2-Clause
// The C API (svc/svc.h) against the C++ reader: the same pixels from every way of
// opening, every pixel format and row order, the same cells and cameras, and errors as
// status codes with messages kept per reader and thread.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <thread>

#include "scene/scene.h"
#include "support/test_support.h"
#include "svc/encoder.h"
#include "svc/reader.h"
#include "svc/svc.h"

namespace svc {
namespace {

namespace fs = std::filesystem;

class CApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir("svc-c-api");
    samples::SceneOptions options;
    options.grid = {3, 1, 2};
    options.face_size = 32;
    ASSERT_TRUE(samples::generate_scene(options, dir_->path() / "db").ok());
    EncoderSettings encoder;
    encoder.threads = 1;
    ASSERT_TRUE(encode_database(dir_->path() / "db", path(), encoder).ok());
    bytes_ = new std::vector<uint8_t>(testing::read_file_data(path()));
  }
  static void TearDownTestSuite() {
    delete bytes_;
    delete dir_;
  }
  static fs::path path() { return dir_->path() / "scene.svc"; }
  static const std::vector<uint8_t>& bytes() { return *bytes_; }

  static testing::TempDir* dir_;
  static std::vector<uint8_t>* bytes_;
};
testing::TempDir* CApi::dir_ = nullptr;
std::vector<uint8_t>* CApi::bytes_ = nullptr;

struct CallbackState {
  const std::vector<uint8_t>* bytes = nullptr;
  std::atomic<int> releases{0};
  std::atomic<bool> failing{false};
};

int read_bytes(void* user, uint64_t offset, void* buffer, size_t size) {
  auto* state = static_cast<CallbackState*>(user);
  if (state->failing.load()) return -5;
  std::memcpy(buffer, state->bytes->data() + offset, size);
  return 0;
}

void release_state(void* user) { static_cast<CallbackState*>(user)->releases.fetch_add(1); }

svc_read_callbacks callbacks_for(CallbackState* state) {
  svc_read_callbacks callbacks{};
  callbacks.user = state;
  callbacks.size = state->bytes->size();
  callbacks.read = read_bytes;
  callbacks.release = release_state;
  callbacks.name = "pak:scene.svc";
  return callbacks;
}

// The face through the C API in `format` and `rows` with 8 bytes of padding a row,
// repacked tightly top-down (planes one after the other).
std::vector<uint8_t> c_face(svc_reader* reader, const int32_t cell[3], svc_face face, svc_pixel_format format,
                            svc_row_order rows, int size) {
  std::array<std::vector<uint8_t>, 3> planes;
  svc_image image{};
  image.format = format;
  image.rows = rows;
  for (int p = 0; p < 3; ++p) {
    const size_t row = svc_pixel_row_bytes(format, size, p), count = svc_pixel_plane_rows(format, size, p);
    if (row == 0) continue;
    planes[p].assign((row + 8) * count, 0x5A);
    image.planes[p] = planes[p].data();
    image.strides[p] = row + 8;
    image.plane_sizes[p] = planes[p].size();
  }
  const svc_status status = svc_reader_decode_face(reader, cell, face, &image);
  EXPECT_EQ(status, SVC_OK) << svc_reader_last_error(reader);
  std::vector<uint8_t> packed;
  for (int p = 0; p < 3; ++p) {
    const size_t row = svc_pixel_row_bytes(format, size, p), count = svc_pixel_plane_rows(format, size, p);
    for (size_t r = 0; r < count; ++r) {
      const size_t stored = rows == SVC_ROWS_TOP_DOWN ? r : count - 1 - r;
      const uint8_t* start = planes[p].data() + stored * (row + 8);
      packed.insert(packed.end(), start, start + row);
    }
  }
  return packed;
}

// The same face from the C++ reader, packed as c_face packs it.
std::vector<uint8_t> cpp_face(Reader& reader, const CellIndex& cell, Face face, svc_pixel_format format) {
  if (format == SVC_PIXEL_YCBCR420) {
    auto planes = reader.decode_face_ycbcr(cell, face);
    EXPECT_TRUE(planes.ok());
    std::vector<uint8_t> packed = planes->y;
    packed.insert(packed.end(), planes->cb.begin(), planes->cb.end());
    packed.insert(packed.end(), planes->cr.begin(), planes->cr.end());
    return packed;
  }
  auto rgb = reader.decode_face(cell, face);
  EXPECT_TRUE(rgb.ok());
  if (format == SVC_PIXEL_RGB8) return rgb->pixels;
  std::vector<uint8_t> packed;
  for (size_t i = 0; i < rgb->pixels.size(); i += 3) {
    const uint8_t r = rgb->pixels[i], g = rgb->pixels[i + 1], b = rgb->pixels[i + 2];
    if (format == SVC_PIXEL_RGBA8) {
      packed.insert(packed.end(), {r, g, b, 255});
    } else {
      packed.insert(packed.end(), {b, g, r, 255});
    }
  }
  return packed;
}

TEST_F(CApi, VersionsAreTheHeaders) {
  EXPECT_EQ(svc_abi_version(), static_cast<uint32_t>(SVC_ABI_VERSION));
  EXPECT_STREQ(svc_version_string(), "0.1.0");
  EXPECT_STREQ(svc_status_name(SVC_CORRUPT_DATA), "corrupt data");
  EXPECT_STREQ(svc_status_name(static_cast<svc_status>(77)), "unknown");
}

TEST_F(CApi, EveryOpeningFormatAndRowOrderGivesTheCppPixels) {
  auto cpp = Reader::open(path());
  ASSERT_TRUE(cpp.ok());
  CallbackState state;
  state.bytes = &bytes();
  const svc_read_callbacks callbacks = callbacks_for(&state);
  std::array<svc_reader*, 3> readers{};
  ASSERT_EQ(svc_reader_open_file(path().c_str(), nullptr, &readers[0]), SVC_OK) << svc_last_open_error();
  ASSERT_EQ(svc_reader_open_memory(bytes().data(), bytes().size(), nullptr, &readers[1]), SVC_OK);
  ASSERT_EQ(svc_reader_open_callbacks(&callbacks, nullptr, &readers[2]), SVC_OK) << svc_last_open_error();
  for (svc_reader* reader : readers) {
    for (const CellEntry& cell : (*cpp)->cells()) {
      const int32_t index[3] = {cell.index.x, cell.index.y, cell.index.z};
      for (Face face : kAllFaces) {
        for (svc_pixel_format format : {SVC_PIXEL_RGBA8, SVC_PIXEL_BGRA8, SVC_PIXEL_RGB8, SVC_PIXEL_YCBCR420}) {
          const std::vector<uint8_t> expected = cpp_face(**cpp, cell.index, face, format);
          for (svc_row_order rows : {SVC_ROWS_TOP_DOWN, SVC_ROWS_BOTTOM_UP}) {
            ASSERT_EQ(c_face(reader, index, static_cast<svc_face>(face), format, rows, 32), expected)
                << face_label(cell.index, face) << " format " << format << " rows " << rows;
          }
        }
      }
    }
  }
  for (svc_reader* reader : readers) svc_reader_destroy(reader);
  EXPECT_EQ(state.releases.load(), 1);
}

TEST_F(CApi, CubeDecodeFillsSixBuffers) {
  svc_reader* reader = nullptr;
  ASSERT_EQ(svc_reader_open_file(path().c_str(), nullptr, &reader), SVC_OK);
  auto cpp = Reader::open(path());
  ASSERT_TRUE(cpp.ok());
  const int32_t cell[3] = {2, 0, 1};
  std::array<std::vector<uint8_t>, 6> pixels;
  svc_image images[6] = {};
  for (int f = 0; f < 6; ++f) {
    pixels[f].assign(32 * 32 * 4, 0);
    images[f] = svc_image{SVC_PIXEL_RGBA8, SVC_ROWS_TOP_DOWN, {pixels[f].data()}, {128}, {pixels[f].size()}};
  }
  ASSERT_EQ(svc_reader_decode_cube(reader, cell, images), SVC_OK) << svc_reader_last_error(reader);
  for (Face face : kAllFaces) {
    EXPECT_EQ(pixels[static_cast<size_t>(face)], cpp_face(**cpp, CellIndex{2, 0, 1}, face, SVC_PIXEL_RGBA8));
  }
  svc_reader_destroy(reader);
}

TEST_F(CApi, InfoAndCellsAreTheCppReaders) {
  auto cpp = Reader::open(path());
  ASSERT_TRUE(cpp.ok());
  svc_reader* reader = nullptr;
  ASSERT_EQ(svc_reader_open_file(path().c_str(), nullptr, &reader), SVC_OK);
  svc_file_info info{};
  ASSERT_EQ(svc_reader_info(reader, &info), SVC_OK);
  const FileInfo& expected = (*cpp)->info();
  EXPECT_EQ(info.file_bytes, expected.file_bytes);
  EXPECT_EQ(info.face_width, 32);
  EXPECT_EQ(info.grid_dims[0], 3);
  EXPECT_EQ(info.grid_spacing[2], expected.grid_spacing[2]);
  EXPECT_EQ(info.qindex, expected.qindex);
  EXPECT_EQ(info.up_axis, 'y');
  ASSERT_EQ(info.cell_count, (*cpp)->cells().size());
  for (size_t c = 0; c < info.cell_count; ++c) {
    svc_cell cell{};
    ASSERT_EQ(svc_reader_cell(reader, c, &cell), SVC_OK);
    const CellEntry& want = (*cpp)->cells()[c];
    EXPECT_EQ(cell.index[0], want.index.x);
    EXPECT_EQ(cell.index[2], want.index.z);
    EXPECT_EQ(cell.position[1], want.position[1]);
    for (int f = 0; f < 6; ++f) {
      EXPECT_EQ(std::memcmp(cell.cameras[f].world_to_camera, want.cameras[f].world_to_camera.data(),
                            16 * sizeof(double)),
                0);
      EXPECT_EQ(cell.cameras[f].near_plane, want.cameras[f].frustum.near_plane);
      EXPECT_EQ(cell.face_types[f], static_cast<uint8_t>(want.faces[f].type));
      EXPECT_EQ(cell.face_bytes[f], want.faces[f].coded_bytes);
    }
    size_t found = 99;
    ASSERT_EQ(svc_reader_find_cell(reader, cell.index, &found), SVC_OK);
    EXPECT_EQ(found, c);
    ASSERT_EQ(svc_reader_find_cell_at(reader, cell.position, &found), SVC_OK);
    EXPECT_EQ(found, c);
  }
  svc_cell cell{};
  EXPECT_EQ(svc_reader_cell(reader, info.cell_count, &cell), SVC_INVALID_ARGUMENT);
  const int32_t absent[3] = {7, 0, 0};
  size_t found = 0;
  EXPECT_EQ(svc_reader_find_cell(reader, absent, &found), SVC_NOT_FOUND);
  EXPECT_NE(std::string(svc_reader_last_error(reader)).find("cell (7,0,0)"), std::string::npos);
  svc_reader_destroy(reader);
}

TEST_F(CApi, ErrorsAreCodesWithMessagesPerReaderAndThread) {
  svc_reader* reader = reinterpret_cast<svc_reader*>(1);
  EXPECT_EQ(svc_reader_open_file((dir_->path() / "absent.svc").c_str(), nullptr, &reader), SVC_NOT_FOUND);
  EXPECT_EQ(reader, nullptr);
  EXPECT_NE(std::string(svc_last_open_error()).find("absent.svc"), std::string::npos) << svc_last_open_error();
  EXPECT_EQ(svc_reader_open_file(path().c_str(), nullptr, nullptr), SVC_INVALID_ARGUMENT);
  EXPECT_EQ(svc_reader_open_memory(bytes().data(), bytes().size() / 3, nullptr, &reader), SVC_CORRUPT_DATA);
  svc_reader_settings settings;
  svc_reader_settings_default(&settings);
  EXPECT_EQ(settings.prefetch_threads, 2);
  settings.prefetch_radius = 9;
  EXPECT_EQ(svc_reader_open_file(path().c_str(), &settings, &reader), SVC_INVALID_ARGUMENT);
  EXPECT_NE(std::string(svc_last_open_error()).find("prefetch_radius 9"), std::string::npos);

  ASSERT_EQ(svc_reader_open_file(path().c_str(), nullptr, &reader), SVC_OK);
  EXPECT_STREQ(svc_last_open_error(), "");
  EXPECT_STREQ(svc_reader_last_error(reader), "");
  const int32_t absent[3] = {0, 0, 5}, present[3] = {0, 0, 0};
  std::vector<uint8_t> pixels(32 * 32 * 4);
  svc_image image{SVC_PIXEL_RGBA8, SVC_ROWS_TOP_DOWN, {pixels.data()}, {128}, {pixels.size()}};
  EXPECT_EQ(svc_reader_decode_face(reader, absent, SVC_FACE_PX, &image), SVC_NOT_FOUND);
  const std::string not_found = svc_reader_last_error(reader);
  EXPECT_NE(not_found.find("cell (0,0,5)"), std::string::npos) << not_found;
  // Another thread's failure is its own; this thread's message stays.
  std::thread other([&] {
    EXPECT_STREQ(svc_reader_last_error(reader), "");
    EXPECT_EQ(svc_reader_decode_face(reader, present, static_cast<svc_face>(6), &image), SVC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(svc_reader_last_error(reader)).find("face 6"), std::string::npos);
  });
  other.join();
  EXPECT_EQ(svc_reader_last_error(reader), not_found);
  image.plane_sizes[0] = 100;
  EXPECT_EQ(svc_reader_decode_face(reader, present, SVC_FACE_PX, &image), SVC_INVALID_ARGUMENT);
  EXPECT_NE(std::string(svc_reader_last_error(reader)).find("plane 0 holds 100 bytes"), std::string::npos);
  EXPECT_EQ(svc_reader_decode_face(reader, present, SVC_FACE_PX, nullptr), SVC_INVALID_ARGUMENT);
  EXPECT_EQ(svc_reader_decode_face(nullptr, present, SVC_FACE_PX, &image), SVC_INVALID_ARGUMENT);
  const double nowhere[3] = {NAN, 0, 0};
  EXPECT_EQ(svc_reader_set_viewer_position(reader, nowhere, nullptr), SVC_INVALID_ARGUMENT);

  // Closed: decodes are cancelled, information stays.
  svc_reader_close(reader);
  image.plane_sizes[0] = pixels.size();
  EXPECT_EQ(svc_reader_decode_face(reader, present, SVC_FACE_PX, &image), SVC_CANCELLED);
  svc_file_info info{};
  EXPECT_EQ(svc_reader_info(reader, &info), SVC_OK);
  svc_reader_destroy(reader);
  svc_reader_destroy(nullptr);
}

TEST_F(CApi, ReadCallbacksFailAsIoErrorsAndAreReleasedOnce) {
  CallbackState state;
  state.bytes = &bytes();
  svc_read_callbacks callbacks = callbacks_for(&state);
  svc_reader* reader = nullptr;
  state.failing = true;
  EXPECT_EQ(svc_reader_open_callbacks(&callbacks, nullptr, &reader), SVC_IO_ERROR);
  EXPECT_NE(std::string(svc_last_open_error()).find("pak:scene.svc"), std::string::npos) << svc_last_open_error();
  EXPECT_EQ(state.releases.load(), 1);  // released before the failed open returned

  state.failing = false;
  svc_reader_settings settings;
  svc_reader_settings_default(&settings);
  settings.face_cache_bytes = 0;
  settings.coefficient_cache_bytes = 0;
  settings.reference_cache_bytes = 0;
  ASSERT_EQ(svc_reader_open_callbacks(&callbacks, &settings, &reader), SVC_OK);
  state.failing = true;
  const int32_t cell[3] = {1, 0, 1};
  std::vector<uint8_t> pixels(32 * 32 * 3);
  const svc_image image{SVC_PIXEL_RGB8, SVC_ROWS_BOTTOM_UP, {pixels.data()}, {96}, {pixels.size()}};
  EXPECT_EQ(svc_reader_decode_face(reader, cell, SVC_FACE_NZ, &image), SVC_IO_ERROR);
  const std::string message = svc_reader_last_error(reader);
  EXPECT_NE(message.find("returned -5"), std::string::npos) << message;
  EXPECT_NE(message.find("face nz"), std::string::npos) << message;
  state.failing = false;
  EXPECT_EQ(svc_reader_decode_face(reader, cell, SVC_FACE_NZ, &image), SVC_OK);
  EXPECT_EQ(state.releases.load(), 1);
  svc_reader_destroy(reader);
  EXPECT_EQ(state.releases.load(), 2);

  callbacks.read = nullptr;
  EXPECT_EQ(svc_reader_open_callbacks(&callbacks, nullptr, &reader), SVC_INVALID_ARGUMENT);
  EXPECT_EQ(state.releases.load(), 3);
}

TEST_F(CApi, ViewerPrefetchAndStats) {
  svc_reader* reader = nullptr;
  ASSERT_EQ(svc_reader_open_file(path().c_str(), nullptr, &reader), SVC_OK);
  const int32_t cell[3] = {1, 0, 0};
  const double velocity[3] = {1, 0, 0};
  ASSERT_EQ(svc_reader_set_viewer_cell(reader, cell, velocity), SVC_OK) << svc_reader_last_error(reader);
  EXPECT_EQ(svc_reader_wait_for_prefetch(reader, 60000), 1);
  svc_reader_stats stats{};
  ASSERT_EQ(svc_reader_get_stats(reader, &stats), SVC_OK);
  EXPECT_GT(stats.prefetch_faces, 0u);
  EXPECT_GT(stats.face_cache.insertions, 0u);
  EXPECT_EQ(stats.face_cache.budget_bytes, uint64_t{64} << 20);
  const int32_t outside[3] = {3, 0, 0};
  EXPECT_EQ(svc_reader_set_viewer_cell(reader, outside, nullptr), SVC_INVALID_ARGUMENT);
  svc_reader_destroy(reader);
}

// samples/embed_c, built as strict C99, writes the cube it decodes through read
// callbacks into padded RGBA8 rows: the C++ reader's pixels, cell by position too.
TEST_F(CApi, TheCExampleDecodesACellAsTheCppReader) {
  auto cpp = Reader::open(path());
  ASSERT_TRUE(cpp.ok());
  const fs::path out = dir_->path() / "cube.rgba";
  for (const size_t ordinal : {size_t{0}, size_t{4}}) {
    const CellEntry& cell = (*cpp)->cells()[ordinal];
    std::string args = testing::quoted(path()) + " " + testing::quoted(out);
    if (ordinal != 0) {
      for (double p : cell.position) args += " " + std::to_string(p);
    }
    const testing::CliRun run = testing::run_program("svc-embed-c", args, dir_->path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("cell " + std::to_string(cell.index.x) + ",0," + std::to_string(cell.index.z)),
              std::string::npos)
        << run.output;
    std::vector<uint8_t> expected;
    for (Face face : kAllFaces) {
      const std::vector<uint8_t> pixels = cpp_face(**cpp, cell.index, face, SVC_PIXEL_RGBA8);
      expected.insert(expected.end(), pixels.begin(), pixels.end());
    }
    EXPECT_EQ(testing::read_file_data(out), expected) << face_label(cell.index, Face::kPX);
  }
  const testing::CliRun missing = testing::run_program("svc-embed-c", "absent.svc out.rgba", dir_->path());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("absent.svc: cannot open"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace svc
