// SPDX-License-Identifier: BSD-2-Clause
/* An engine's use of the svc decoder through its C API: open an .svc file through the
   engine's own file access (read callbacks; here stdio), decode the six faces of one
   cell straight into RGBA8 buffers whose rows end with padding (as a GPU staging
   buffer's rows often do), and write the pixels out.

   Usage: svc-embed-c FILE.svc OUT.rgba [X Y Z]
   Decodes the first cell, or the cell whose grid cell contains world point (X, Y, Z),
   and writes its faces to OUT.rgba in svc_face order, each top row first, 4 bytes a
   pixel with no padding. Exit status 0 on success, 1 on failure, 2 on bad usage. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <svc/svc.h>

enum { kRowPadding = 24, kPaddingByte = 0xA5 };

/* stdio is not thread-safe for positioned reads, so the reader is opened below with
   its threads off; a callback built on pread or a memory-mapped archive need not be. */
static int read_at(void* user, uint64_t offset, void* buffer, size_t size) {
  FILE* file = (FILE*)user;
  if (offset > (uint64_t)LONG_MAX || fseek(file, (long)offset, SEEK_SET) != 0) return 1;
  return fread(buffer, 1, size, file) == size ? 0 : 2;
}

static void release(void* user) { fclose((FILE*)user); }

static int fail(const char* what, const char* message) {
  fprintf(stderr, "svc-embed-c: %s: %s\n", what, message);
  return 1;
}

static int open_reader(const char* path, svc_reader** reader) {
  svc_read_callbacks callbacks;
  svc_reader_settings settings;
  long size;
  FILE* file = fopen(path, "rb");
  if (file == NULL) return fail(path, "cannot open");
  if (fseek(file, 0, SEEK_END) != 0 || (size = ftell(file)) < 0) {
    fclose(file);
    return fail(path, "cannot tell its size");
  }
  memset(&callbacks, 0, sizeof callbacks);
  callbacks.user = file;
  callbacks.size = (uint64_t)size;
  callbacks.read = read_at;
  callbacks.release = release; /* the reader closes the file, also when opening fails */
  callbacks.name = path;
  svc_reader_settings_default(&settings);
  settings.decode_threads = 1;
  settings.prefetch_threads = 0;
  if (svc_reader_open_callbacks(&callbacks, &settings, reader) != SVC_OK) return fail(path, svc_last_open_error());
  return 0;
}

/* Writes the faces' pixels without the padding, after checking the padding untouched. */
static int write_faces(const char* path, uint8_t* const pixels[6], int width, int height, size_t stride) {
  size_t row_bytes = (size_t)width * 4;
  int f, y;
  size_t b;
  FILE* out = fopen(path, "wb");
  if (out == NULL) return fail(path, "cannot create");
  for (f = 0; f < 6; ++f) {
    for (y = 0; y < height; ++y) {
      const uint8_t* row = pixels[f] + (size_t)y * stride;
      for (b = row_bytes; b < stride; ++b) {
        if (row[b] != kPaddingByte) {
          fclose(out);
          return fail(path, "the decoder wrote into a row's padding");
        }
      }
      if (fwrite(row, 1, row_bytes, out) != row_bytes) {
        fclose(out);
        return fail(path, "write failed");
      }
    }
  }
  return fclose(out) == 0 ? 0 : fail(path, "write failed");
}

static int decode_cell(svc_reader* reader, const char* out_path, int argc, char** argv) {
  svc_file_info info;
  svc_cell cell;
  svc_image images[6];
  uint8_t* pixels[6] = {NULL, NULL, NULL, NULL, NULL, NULL};
  size_t ordinal = 0, stride, f;
  int result = 1;
  if (svc_reader_info(reader, &info) != SVC_OK) return fail("info", svc_reader_last_error(reader));
  if (argc == 6) {
    double position[3];
    position[0] = atof(argv[3]);
    position[1] = atof(argv[4]);
    position[2] = atof(argv[5]);
    if (svc_reader_find_cell_at(reader, position, &ordinal) != SVC_OK) {
      return fail("position", svc_reader_last_error(reader));
    }
  }
  if (svc_reader_cell(reader, ordinal, &cell) != SVC_OK) return fail("cell", svc_reader_last_error(reader));
  stride = svc_pixel_row_bytes(SVC_PIXEL_RGBA8, info.face_width, 0) + kRowPadding;
  for (f = 0; f < 6; ++f) {
    const size_t bytes = stride * (size_t)info.face_height;
    pixels[f] = (uint8_t*)malloc(bytes);
    if (pixels[f] == NULL) goto done;
    memset(pixels[f], kPaddingByte, bytes);
    memset(&images[f], 0, sizeof images[f]);
    images[f].format = SVC_PIXEL_RGBA8;
    images[f].rows = SVC_ROWS_TOP_DOWN;
    images[f].planes[0] = pixels[f];
    images[f].strides[0] = stride;
    images[f].plane_sizes[0] = bytes;
  }
  if (svc_reader_decode_cube(reader, cell.index, images) != SVC_OK) {
    fail("decode", svc_reader_last_error(reader));
    goto done;
  }
  result = write_faces(out_path, pixels, info.face_width, info.face_height, stride);
  if (result == 0) {
    printf("cell %d,%d,%d: 6 faces of %dx%d\n", (int)cell.index[0], (int)cell.index[1], (int)cell.index[2],
           (int)info.face_width, (int)info.face_height);
  }
done:
  for (f = 0; f < 6; ++f) free(pixels[f]);
  return result;
}

int main(int argc, char** argv) {
  svc_reader* reader = NULL;
  int result;
  if (argc != 3 && argc != 6) {
    fprintf(stderr, "usage: %s FILE.svc OUT.rgba [X Y Z]\n", argv[0]);
    return 2;
  }
  if (svc_abi_version() != SVC_ABI_VERSION) return fail("svc", "the library's ABI is not this header's");
  if (open_reader(argv[1], &reader) != 0) return 1;
  result = decode_cell(reader, argv[2], argc, argv);
  svc_reader_destroy(reader);
  return result;
}
