// SPDX-License-Identifier: BSD-2-Clause
// svc-decode-digest FILE...: decodes every face of every cell of each .svc file in every
// pixel format and row order, as an embedder would, and prints one digest line per file
// (with the faces that fail, if any). Each file is opened four ways: the C API by path,
// from memory and through read callbacks, and the C++ reader by path; all four must
// decode the same bytes and fail on the same faces, or the program exits with 1. A path
// that is no readable file (missing, a folder) is opened by path alone, both ways. Paths
// are UTF-8 on both systems, names beyond ASCII included. Built
// for Linux and for Windows, so that the two can be compared (scripts/check-windows.sh).
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "decode_digest/face_walk.h"
#include "decode_digest/utf8_arguments.h"
#include "svc/reader.h"
#include "svc/svc.h"

namespace svc::testing {
namespace {

using Cells = std::vector<std::array<int32_t, 3>>;

struct Outcome {
  std::string open_error;  // the status name when the file did not open
  WalkResult walk;
};

svc_reader_settings threaded_settings() {
  svc_reader_settings settings;
  svc_reader_settings_default(&settings);
  settings.decode_threads = 2;
  settings.prefetch_threads = 2;
  return settings;
}

// Decodes through a C API reader, with prefetch workers running beside the calls.
Outcome walk_c_reader(svc_status opened, svc_reader* reader) {
  Outcome outcome;
  if (opened != SVC_OK) {
    outcome.open_error = svc_status_name(opened);
    return outcome;
  }
  svc_file_info info;
  svc_reader_info(reader, &info);
  Cells cells(info.cell_count);
  for (size_t i = 0; i < info.cell_count; ++i) {
    svc_cell cell;
    svc_reader_cell(reader, i, &cell);
    std::memcpy(cells[i].data(), cell.index, sizeof cell.index);
  }
  if (!cells.empty()) svc_reader_set_viewer_cell(reader, cells.front().data(), nullptr);
  outcome.walk = walk_faces(cells, info.face_width, info.face_height,
                            [&](const int32_t cell[3], svc_face face, const svc_image& out) {
                              return svc_reader_decode_face(reader, cell, face, &out);
                            });
  svc_reader_destroy(reader);
  return outcome;
}

Outcome walk_c_file(const std::string& path) {
  const svc_reader_settings settings = threaded_settings();
  svc_reader* reader = nullptr;
  const svc_status opened = svc_reader_open_file(path.c_str(), &settings, &reader);
  return walk_c_reader(opened, reader);
}

Outcome walk_c_memory(const std::vector<uint8_t>& bytes) {
  const svc_reader_settings settings = threaded_settings();
  svc_reader* reader = nullptr;
  const svc_status opened = svc_reader_open_memory(bytes.data(), bytes.size(), &settings, &reader);
  return walk_c_reader(opened, reader);
}

int read_from_memory(void* user, uint64_t offset, void* buffer, size_t size) {
  const auto* bytes = static_cast<const std::vector<uint8_t>*>(user);
  std::memcpy(buffer, bytes->data() + offset, size);
  return 0;
}

Outcome walk_c_callbacks(const std::vector<uint8_t>& bytes) {
  const svc_reader_settings settings = threaded_settings();
  svc_read_callbacks callbacks{};
  callbacks.user = const_cast<std::vector<uint8_t>*>(&bytes);
  callbacks.size = bytes.size();
  callbacks.read = read_from_memory;
  callbacks.name = "callbacks";
  svc_reader* reader = nullptr;
  const svc_status opened = svc_reader_open_callbacks(&callbacks, &settings, &reader);
  return walk_c_reader(opened, reader);
}

PixelBuffer pixel_buffer_of(const svc_image& image) {
  PixelBuffer buffer;
  buffer.format = static_cast<PixelFormat>(image.format);
  buffer.rows = static_cast<RowOrder>(image.rows);
  for (int p = 0; p < 3; ++p) {
    buffer.planes[p] = std::span<uint8_t>(image.planes[p], image.plane_sizes[p]);
    buffer.strides[p] = image.strides[p];
  }
  return buffer;
}

Outcome walk_cpp_reader(const std::filesystem::path& path) {
  Outcome outcome;
  ReaderSettings settings = default_reader_settings();
  settings.decode_threads = 2;
  auto reader = Reader::open(path, settings);
  if (!reader.ok()) {
    outcome.open_error = svc_status_name(static_cast<svc_status>(reader.status().code()));
    return outcome;
  }
  Cells cells;
  for (const CellEntry& cell : (*reader)->cells()) cells.push_back({cell.index.x, cell.index.y, cell.index.z});
  const FileInfo& info = (*reader)->info();
  outcome.walk = walk_faces(cells, info.face_width, info.face_height,
                            [&](const int32_t cell[3], svc_face face, const svc_image& out) {
                              const Status status =
                                  (*reader)->decode_face_into(CellIndex{cell[0], cell[1], cell[2]},
                                                              static_cast<Face>(face), pixel_buffer_of(out));
                              return static_cast<svc_status>(status.code());
                            });
  return outcome;
}

std::string summary(const Outcome& outcome) {
  if (!outcome.open_error.empty()) return "open: " + outcome.open_error;
  return "sha256=" + outcome.walk.digest + " faces=" + std::to_string(outcome.walk.faces) +
         " errors=" + std::to_string(outcome.walk.errors.size());
}

std::optional<std::vector<uint8_t>> read_bytes(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string utf8_of(const std::filesystem::path& path) {
  const std::u8string text = path.u8string();
  return std::string(text.begin(), text.end());
}

// Prints the file's line; false when the ways of opening it disagree. `utf8` is the
// path as the C API takes it.
bool digest_file(const std::string& utf8) {
  const std::filesystem::path path(std::u8string_view(reinterpret_cast<const char8_t*>(utf8.data()), utf8.size()));
  const std::string name = utf8_of(path.filename());
  const Outcome by_path = walk_c_file(utf8);
  std::printf("%s %s\n", name.c_str(), summary(by_path).c_str());
  for (const std::string& error : by_path.walk.errors) std::printf("  %s\n", error.c_str());
  std::vector<std::pair<const char*, Outcome>> others;
  others.emplace_back("C++ reader by path", walk_cpp_reader(path));
  if (const auto bytes = read_bytes(path)) {
    others.emplace_back("C API from memory", walk_c_memory(*bytes));
    others.emplace_back("C API through callbacks", walk_c_callbacks(*bytes));
  }
  bool agree = true;
  for (const auto& [how, outcome] : others) {
    if (summary(outcome) == summary(by_path) && outcome.walk.errors == by_path.walk.errors) continue;
    std::fprintf(stderr, "%s: the %s gives %s\n", name.c_str(), how, summary(outcome).c_str());
    agree = false;
  }
  return agree;
}

}  // namespace
}  // namespace svc::testing

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE.svc...\n", argv[0]);
    return 2;
  }
  const std::vector<std::string> arguments = svc::testing::utf8_arguments(argc, argv);
  bool ok = true;
  for (size_t i = 1; i < arguments.size(); ++i) ok = svc::testing::digest_file(arguments[i]) && ok;
  return ok ? 0 : 1;
}
