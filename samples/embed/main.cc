// SPDX-License-Identifier: BSD-2-Clause
// An engine's use of the svc decoder through its C++ API: open an .svc file, decode the
// six faces of one cell straight into the program's own buffers in the pixel format and
// row order it asks for, print a checksum of the pixels, and optionally write them out.
//
// Usage: svc-embed-example [--format rgba8|bgra8|rgb8|ycbcr420] [--bottom-up]
//                          [--out FILE] FILE.svc [X Y Z]
// Decodes the first cell, or the cell whose grid cell contains world point (X, Y, Z).
// --out writes the faces in Face order, each face's planes in order, each plane's rows in
// the buffer's order (bottom row first with --bottom-up), without padding: the layout
// samples/embed_c writes, so the two can be compared byte for byte.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <svc/reader.h>

namespace {

struct Options {
  svc::PixelFormat format = svc::PixelFormat::kRGBA8;
  svc::RowOrder rows = svc::RowOrder::kTopDown;
  std::string input;
  std::string output;
  std::optional<std::array<double, 3>> position;
};

std::optional<svc::PixelFormat> parse_format(const std::string& name) {
  if (name == "rgba8") return svc::PixelFormat::kRGBA8;
  if (name == "bgra8") return svc::PixelFormat::kBGRA8;
  if (name == "rgb8") return svc::PixelFormat::kRGB8;
  if (name == "ycbcr420") return svc::PixelFormat::kYCbCr420;
  return std::nullopt;
}

std::optional<Options> parse_options(int argc, char** argv) {
  Options options;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--format" && i + 1 < argc) {
      auto format = parse_format(argv[++i]);
      if (!format) return std::nullopt;
      options.format = *format;
    } else if (arg == "--bottom-up") {
      options.rows = svc::RowOrder::kBottomUp;
    } else if (arg == "--out" && i + 1 < argc) {
      options.output = argv[++i];
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 1 && positional.size() != 4) return std::nullopt;
  options.input = positional[0];
  if (positional.size() == 4) {
    options.position = std::array<double, 3>{std::atof(positional[1].c_str()), std::atof(positional[2].c_str()),
                                             std::atof(positional[3].c_str())};
  }
  return options;
}

// One face's planes, rows packed with no padding.
using FaceStorage = std::array<std::vector<uint8_t>, 3>;

std::array<svc::PixelBuffer, svc::kFaceCount> make_buffers(const Options& options, int width, int height,
                                                           std::array<FaceStorage, svc::kFaceCount>& storage) {
  std::array<svc::PixelBuffer, svc::kFaceCount> buffers;
  for (int f = 0; f < svc::kFaceCount; ++f) {
    buffers[f].format = options.format;
    buffers[f].rows = options.rows;
    for (int p = 0; p < 3; ++p) {
      const size_t row_bytes = svc::pixel_row_bytes(options.format, width, p);
      storage[f][p].resize(row_bytes * svc::pixel_plane_rows(options.format, height, p));
      buffers[f].planes[p] = storage[f][p];
      buffers[f].strides[p] = row_bytes;
    }
  }
  return buffers;
}

bool write_faces(const std::string& path, const std::array<FaceStorage, svc::kFaceCount>& storage) {
  std::ofstream out(path, std::ios::binary);
  for (const FaceStorage& face : storage) {
    for (const std::vector<uint8_t>& plane : face) {
      out.write(reinterpret_cast<const char*>(plane.data()), static_cast<std::streamsize>(plane.size()));
    }
  }
  out.close();
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  const std::optional<Options> options = parse_options(argc, argv);
  if (!options) {
    std::fprintf(stderr,
                 "usage: %s [--format rgba8|bgra8|rgb8|ycbcr420] [--bottom-up] [--out FILE] FILE.svc [X Y Z]\n",
                 argv[0]);
    return 2;
  }
  auto reader = svc::Reader::open(options->input);
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.status().to_string().c_str());
    return 1;
  }
  size_t ordinal = 0;
  if (options->position) {
    auto found = (*reader)->find_cell_at(*options->position);
    if (!found) {
      std::fprintf(stderr, "no cell contains that point\n");
      return 1;
    }
    ordinal = *found;
  }
  const svc::CellEntry& cell = (*reader)->cells()[ordinal];
  const svc::FileInfo& info = (*reader)->info();
  std::array<FaceStorage, svc::kFaceCount> storage;
  const auto buffers = make_buffers(*options, info.face_width, info.face_height, storage);
  if (svc::Status status = (*reader)->decode_cube_into(cell.index, buffers); !status.ok()) {
    std::fprintf(stderr, "%s\n", status.to_string().c_str());
    return 1;
  }
  unsigned long long checksum = 0;
  for (const FaceStorage& face : storage) {
    for (const std::vector<uint8_t>& plane : face) {
      for (uint8_t v : plane) checksum = checksum * 31 + v;
    }
  }
  if (!options->output.empty() && !write_faces(options->output, storage)) {
    std::fprintf(stderr, "%s: write failed\n", options->output.c_str());
    return 1;
  }
  std::printf("cell %d,%d,%d: 6 faces of %dx%d, checksum %llu\n", cell.index.x, cell.index.y, cell.index.z,
              info.face_width, info.face_height, checksum);
  return 0;
}
