// SPDX-License-Identifier: BSD-2-Clause
// Opens an .svc file, decodes the six faces of one cell (by world position or the
// first cell) and prints their sizes and a checksum of the pixels.
#include <cstdio>
#include <cstdlib>

#include <svc/reader.h>

int main(int argc, char** argv) {
  if (argc != 2 && argc != 5) {
    std::fprintf(stderr, "usage: %s FILE.svc [X Y Z]\n", argv[0]);
    return 2;
  }
  auto reader = svc::Reader::open(argv[1]);
  if (!reader.ok()) {
    std::fprintf(stderr, "%s\n", reader.status().to_string().c_str());
    return 1;
  }
  size_t ordinal = 0;
  if (argc == 5) {
    auto found = (*reader)->find_cell_at({std::atof(argv[2]), std::atof(argv[3]), std::atof(argv[4])});
    if (!found) {
      std::fprintf(stderr, "no cell contains that point\n");
      return 1;
    }
    ordinal = *found;
  }
  const svc::CellEntry& cell = (*reader)->cells()[ordinal];
  auto cube = (*reader)->decode_cube(cell.index);
  if (!cube.ok()) {
    std::fprintf(stderr, "%s\n", cube.status().to_string().c_str());
    return 1;
  }
  unsigned long long checksum = 0;
  for (const svc::ImageRGB8& face : *cube) {
    for (uint8_t v : face.pixels) checksum = checksum * 31 + v;
  }
  std::printf("cell %d,%d,%d: 6 faces of %dx%d, checksum %llu\n", cell.index.x, cell.index.y, cell.index.z,
              (*cube)[0].width, (*cube)[0].height, checksum);
  return 0;
}
