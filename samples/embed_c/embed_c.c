// SPDX-License-Identifier: BSD-2-Clause
/* An engine's use of the svc decoder through its C API: open an .svc file through the
   engine's own file access (read callbacks; here stdio), decode the six faces of one
   cell straight into buffers whose rows end with padding (as a GPU staging buffer's rows
   often do), in the pixel format and row order asked for, and write the pixels out.

   Usage: svc-embed-c [--format rgba8|bgra8|rgb8|ycbcr420] [--bottom-up] FILE.svc OUT [X Y Z]
   Decodes the first cell, or the cell whose grid cell contains world point (X, Y, Z), by
   default into RGBA8 with the top row first. OUT gets the faces in svc_face order, each
   face's planes in order, each plane's rows in the buffer's order (bottom row first with
   --bottom-up), without the padding. Exit status 0 on success, 1 on failure, 2 on bad
   usage. */
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

typedef struct {
  svc_pixel_format format;
  svc_row_order rows;
  const char* input;
  const char* output;
  int has_position;
  double position[3];
} options;

/* One face's buffer: each plane's rows `strides[p]` bytes apart, padding after them. */
static int allocate_face(svc_image* image, const options* o, int width, int height) {
  int p;
  memset(image, 0, sizeof *image);
  image->format = o->format;
  image->rows = o->rows;
  for (p = 0; p < 3; ++p) {
    const size_t rows = svc_pixel_plane_rows(o->format, height, p);
    if (rows == 0) continue;
    image->strides[p] = svc_pixel_row_bytes(o->format, width, p) + kRowPadding;
    image->plane_sizes[p] = image->strides[p] * rows;
    image->planes[p] = malloc(image->plane_sizes[p]);
    if (image->planes[p] == NULL) return 1;
    memset(image->planes[p], kPaddingByte, image->plane_sizes[p]);
  }
  return 0;
}

static void free_face(svc_image* image) {
  int p;
  for (p = 0; p < 3; ++p) free(image->planes[p]);
}

/* Writes a plane's rows without the padding, after checking the padding untouched.
   Returns NULL, or what went wrong. */
static const char* write_plane(FILE* out, const svc_image* image, int p, int width, int height) {
  const size_t row_bytes = svc_pixel_row_bytes(image->format, width, p);
  const size_t rows = svc_pixel_plane_rows(image->format, height, p);
  size_t r, b;
  for (r = 0; r < rows; ++r) {
    const uint8_t* row = (const uint8_t*)image->planes[p] + r * image->strides[p];
    for (b = row_bytes; b < image->strides[p]; ++b) {
      if (row[b] != kPaddingByte) return "the decoder wrote into a row's padding";
    }
    if (fwrite(row, 1, row_bytes, out) != row_bytes) return "write failed";
  }
  return NULL;
}

static int write_faces(const char* path, const svc_image images[6], int width, int height) {
  const char* error = NULL;
  int f, p;
  FILE* out = fopen(path, "wb");
  if (out == NULL) return fail(path, "cannot create");
  for (f = 0; f < 6 && error == NULL; ++f) {
    for (p = 0; p < 3 && error == NULL; ++p) error = write_plane(out, &images[f], p, width, height);
  }
  if (fclose(out) != 0 && error == NULL) error = "write failed";
  return error == NULL ? 0 : fail(path, error);
}

static int decode_cell(svc_reader* reader, const options* o) {
  svc_file_info info;
  svc_cell cell;
  svc_image images[6];
  size_t ordinal = 0, f;
  int result = 1;
  if (svc_reader_info(reader, &info) != SVC_OK) return fail("info", svc_reader_last_error(reader));
  if (o->has_position && svc_reader_find_cell_at(reader, o->position, &ordinal) != SVC_OK) {
    return fail("position", svc_reader_last_error(reader));
  }
  if (svc_reader_cell(reader, ordinal, &cell) != SVC_OK) return fail("cell", svc_reader_last_error(reader));
  memset(images, 0, sizeof images);
  for (f = 0; f < 6; ++f) {
    if (allocate_face(&images[f], o, info.face_width, info.face_height) != 0) {
      fail("memory", "cannot allocate a face's buffer");
      goto done;
    }
  }
  if (svc_reader_decode_cube(reader, cell.index, images) != SVC_OK) {
    fail("decode", svc_reader_last_error(reader));
    goto done;
  }
  result = write_faces(o->output, images, info.face_width, info.face_height);
  if (result == 0) {
    printf("cell %d,%d,%d: 6 faces of %dx%d\n", (int)cell.index[0], (int)cell.index[1], (int)cell.index[2],
           (int)info.face_width, (int)info.face_height);
  }
done:
  for (f = 0; f < 6; ++f) free_face(&images[f]);
  return result;
}

static int parse_format(const char* name, svc_pixel_format* format) {
  static const char* const names[] = {"rgba8", "bgra8", "rgb8", "ycbcr420"};
  static const svc_pixel_format formats[] = {SVC_PIXEL_RGBA8, SVC_PIXEL_BGRA8, SVC_PIXEL_RGB8, SVC_PIXEL_YCBCR420};
  int i;
  for (i = 0; i < 4; ++i) {
    if (strcmp(name, names[i]) == 0) {
      *format = formats[i];
      return 0;
    }
  }
  return 1;
}

/* 0 when the arguments make sense. */
static int parse_options(int argc, char** argv, options* o) {
  const char* positional[5];
  int count = 0, i;
  memset(o, 0, sizeof *o);
  o->format = SVC_PIXEL_RGBA8;
  o->rows = SVC_ROWS_TOP_DOWN;
  for (i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--format") == 0 && i + 1 < argc) {
      if (parse_format(argv[++i], &o->format) != 0) return 1;
    } else if (strcmp(argv[i], "--bottom-up") == 0) {
      o->rows = SVC_ROWS_BOTTOM_UP;
    } else if (count < 5) {
      positional[count++] = argv[i];
    } else {
      return 1;
    }
  }
  if (count != 2 && count != 5) return 1;
  o->input = positional[0];
  o->output = positional[1];
  o->has_position = count == 5;
  for (i = 0; o->has_position && i < 3; ++i) o->position[i] = atof(positional[2 + i]);
  return 0;
}

int main(int argc, char** argv) {
  svc_reader* reader = NULL;
  options o;
  int result;
  if (parse_options(argc, argv, &o) != 0) {
    fprintf(stderr, "usage: %s [--format rgba8|bgra8|rgb8|ycbcr420] [--bottom-up] FILE.svc OUT [X Y Z]\n", argv[0]);
    return 2;
  }
  if (svc_abi_version() != SVC_ABI_VERSION) return fail("svc", "the library's ABI is not this header's");
  if (open_reader(o.input, &reader) != 0) return 1;
  result = decode_cell(reader, &o);
  svc_reader_destroy(reader);
  return result;
}
