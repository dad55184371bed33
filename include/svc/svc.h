// SPDX-License-Identifier: BSD-2-Clause
/* The svc decoder's C API (C99): random access by cell to an .svc file, for engines and
   languages that bind to a C ABI (C#, Rust, Python ctypes, GDExtension). It wraps the C++
   reader (svc/reader.h) and shares its implementation, caches and prefetch.

   Errors: every call that can fail returns an svc_status; SVC_OK is 0. The message of a
   failed call is kept per reader and per calling thread (svc_reader_last_error), or per
   thread for the open calls (svc_last_open_error). No call throws or aborts on bad
   input or damaged files; a damaged face fails alone while the others stay readable.

   Threading: after an open call returns, every svc_reader_* call may be made on one
   reader from any number of threads at once, except svc_reader_destroy, which must not
   run while another call on the same reader is in progress. Decoded pixels are the same
   whatever the thread count, call order or cache settings.

   Ownership: a reader owns what it opened (the file handle, the callbacks' source) until
   svc_reader_destroy. Buffers passed in are the caller's: the library writes into them
   during the call and keeps no pointer to them. Returned strings belong to the library.

   Versions: SVC_ABI_VERSION changes whenever a type or call of this header changes
   incompatibly; svc_abi_version() is the ABI of the library actually loaded. */
#ifndef SVC_SVC_H
#define SVC_SVC_H

#include <stddef.h>
#include <stdint.h>

#include "svc/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SVC_ABI_VERSION 2

/* The ABI version of the loaded library (compare with SVC_ABI_VERSION) and its release
   ("0.1.0"). Thread-safe. */
SVC_API uint32_t svc_abi_version(void);
SVC_API const char* svc_version_string(void);

typedef enum svc_status {
  SVC_OK = 0,
  SVC_INVALID_ARGUMENT = 1, /* a caller's argument or setting out of range */
  SVC_NOT_FOUND = 2,        /* a file, cell or face that does not exist */
  SVC_IO_ERROR = 3,         /* the operating system or a read callback refused a read */
  SVC_BAD_INPUT = 4,        /* (encoder input; not returned by the decoder) */
  SVC_CORRUPT_DATA = 5,     /* bytes that fail validation (CRC, bounds, syntax) */
  SVC_LIMIT_EXCEEDED = 6,   /* a size above the reader's limits */
  SVC_UNSUPPORTED = 7,      /* a valid file using a feature this library cannot decode */
  SVC_CANCELLED = 8,        /* the reader was closed */
  SVC_INTERNAL = 9,         /* a broken invariant inside svc; please report it */
  SVC_OUT_OF_MEMORY = 10    /* an allocation failed; the reader stays usable */
} svc_status;

/* "ok", "invalid argument", ...; "unknown" for a value outside the enum. Thread-safe. */
SVC_API const char* svc_status_name(svc_status status);

/* The six faces of a cell's cube map, named by the axis each looks along. */
typedef enum svc_face {
  SVC_FACE_PX = 0,
  SVC_FACE_NX = 1,
  SVC_FACE_PY = 2,
  SVC_FACE_NY = 3,
  SVC_FACE_PZ = 4,
  SVC_FACE_NZ = 5
} svc_face;

typedef enum svc_pixel_format {
  SVC_PIXEL_RGBA8 = 0,   /* 4 bytes a pixel in memory order R, G, B, A; alpha is 255 */
  SVC_PIXEL_BGRA8 = 1,   /* B, G, R, A */
  SVC_PIXEL_RGB8 = 2,    /* R, G, B */
  SVC_PIXEL_YCBCR420 = 3 /* planes Y (w x h), Cb, Cr ((w+1)/2 x (h+1)/2), full-range BT.601 */
} svc_pixel_format;

typedef enum svc_row_order {
  SVC_ROWS_TOP_DOWN = 0, /* the first row in memory is the image's top */
  SVC_ROWS_BOTTOM_UP = 1 /* the first row is the bottom, as OpenGL texture uploads take it */
} svc_row_order;

/* A caller's buffer to decode a face into. Packed formats use planes[0] alone; YCbCr
   4:2:0 the three. Rows of plane p start strides[p] bytes apart (at least the row's
   bytes; padding after each row is left untouched) and plane_sizes[p] is how many bytes
   planes[p] holds: at least (rows - 1) * strides[p] + the row's bytes. */
typedef struct svc_image {
  svc_pixel_format format;
  svc_row_order rows;
  uint8_t* planes[3];
  size_t strides[3];
  size_t plane_sizes[3];
} svc_image;

/* The bytes of a row and the rows of plane `plane` (0..2) of a width x height face in
   `format`; 0 for a plane the format lacks. Thread-safe. */
SVC_API size_t svc_pixel_row_bytes(svc_pixel_format format, int32_t width, int32_t plane);
SVC_API size_t svc_pixel_plane_rows(svc_pixel_format format, int32_t height, int32_t plane);

/* The reader's caches and threads (svc/reader.h, ReaderSettings, says what each does). */
typedef struct svc_reader_settings {
  uint64_t coefficient_cache_bytes; /* semi-decoded I-faces; 0 disables */
  uint64_t face_cache_bytes;        /* decoded faces; 0 disables it and prefetch */
  uint64_t reference_cache_bytes;   /* reference I-faces for B-faces; 0 disables */
  int32_t decode_threads;           /* threads of one svc_reader_decode_cube; 0: one a core */
  int32_t prefetch_threads;         /* workers after svc_reader_set_viewer_*; 0: no prefetch */
  int32_t prefetch_radius;          /* cells around the viewer prefetched, 0..8 */
  uint64_t depth_cache_bytes;       /* decoded depth planes (files with depth); 0 disables */
} svc_reader_settings;

/* Fills `settings` with the defaults (64 MiB, 64 MiB, 32 MiB, 0, 2, 1, 32 MiB).
   Thread-safe. */
SVC_API void svc_reader_settings_default(svc_reader_settings* settings);

/* The embedder's own file access. */
typedef struct svc_read_callbacks {
  void* user;    /* passed to read and release */
  uint64_t size; /* the source's total bytes */
  /* Fills buffer with the `size` bytes at `offset` (always within the source's size);
     returns 0 on success, anything else on failure. Called from several threads at once
     (decoding callers and prefetch workers): it must be thread-safe. */
  int (*read)(void* user, uint64_t offset, void* buffer, size_t size);
  /* Called exactly once when the reader no longer needs the source: at
     svc_reader_destroy, or before svc_reader_open_callbacks returns if opening fails.
     May be NULL. */
  void (*release)(void* user);
  const char* name; /* names the source in error messages (copied); NULL: "callbacks" */
} svc_read_callbacks;

typedef struct svc_reader svc_reader;

/* Open a reader on a file, on `size` bytes of memory (not copied: they must stay valid
   and unchanged until svc_reader_destroy), or on read callbacks. Reads the header and
   the index only. The path is UTF-8, on Windows too. settings NULL: the defaults. On
   success *out is a new reader to pass to svc_reader_destroy; on failure *out is NULL
   and svc_last_open_error() says why.
   SVC_INVALID_ARGUMENT for NULL arguments, settings out of range or (on Windows) a path
   that is not UTF-8; SVC_NOT_FOUND, SVC_IO_ERROR, SVC_CORRUPT_DATA, SVC_LIMIT_EXCEEDED,
   SVC_UNSUPPORTED from the file. */
SVC_API svc_status svc_reader_open_file(const char* path, const svc_reader_settings* settings, svc_reader** out);
SVC_API svc_status svc_reader_open_memory(const void* data, size_t size, const svc_reader_settings* settings,
                                          svc_reader** out);
SVC_API svc_status svc_reader_open_callbacks(const svc_read_callbacks* callbacks,
                                             const svc_reader_settings* settings, svc_reader** out);

/* The message of the last failed open call on the calling thread ("" if none). Valid
   until the next open call on that thread. */
SVC_API const char* svc_last_open_error(void);

/* Stops prefetch, joins its threads, frees the caches and everything the reader owns.
   NULL is ignored. Not concurrently with other calls on the same reader. */
SVC_API void svc_reader_destroy(svc_reader* reader);

/* Stops prefetch and empties the caches; later decode and viewer calls fail with
   SVC_CANCELLED, while info, cell and stats calls keep working. Idempotent. */
SVC_API void svc_reader_close(svc_reader* reader);

/* The message of the last failed call on `reader` made by the calling thread ("" if
   none), valid until that thread's next failing call on the reader. */
SVC_API const char* svc_reader_last_error(const svc_reader* reader);

typedef struct svc_file_info {
  uint16_t format_major, format_minor;
  uint64_t file_bytes;
  int32_t face_width, face_height;
  int32_t grid_dims[3];
  double grid_origin[3];
  double grid_spacing[3];
  int32_t quality; /* 0 when encoded with an explicit quantizer index */
  int32_t qindex;  /* the I-faces' quantizer index */
  int32_t i_spacing[3];
  char up_axis; /* 'x', 'y' or 'z' */
  size_t cell_count;
  int32_t has_depth;       /* 1 when every face's depth is stored (svc_reader_decode_face_depth) */
  int32_t depth_max_error; /* largest error of a decoded SVC_DEPTH_INVERSE_U16 code, 0..255 */
  uint64_t depth_bytes;    /* coded depth bytes of all faces */
} svc_file_info;

/* The camera of a face: OpenGL view matrix (column-major) and glFrustum parameters. */
typedef struct svc_camera {
  double world_to_camera[16];
  double left, right, bottom, top, near_plane, far_plane;
} svc_camera;

typedef struct svc_cell {
  int32_t index[3];
  double position[3]; /* camera centre */
  svc_camera cameras[6];
  uint8_t face_types[6];  /* 0: I-face, 1: B-face */
  uint64_t face_bytes[6]; /* coded bytes of each face */
} svc_cell;

/* File information; cells in ordinal order 0..cell_count-1, sorted by (y, z, x). Find a
   cell's ordinal by grid index or by the world point its grid cell contains
   (SVC_NOT_FOUND when absent). Never fail otherwise but for NULL arguments or an ordinal
   out of range. */
SVC_API svc_status svc_reader_info(const svc_reader* reader, svc_file_info* out);
SVC_API svc_status svc_reader_cell(const svc_reader* reader, size_t ordinal, svc_cell* out);
SVC_API svc_status svc_reader_find_cell(const svc_reader* reader, const int32_t cell[3], size_t* ordinal);
SVC_API svc_status svc_reader_find_cell_at(const svc_reader* reader, const double position[3], size_t* ordinal);

/* Decodes one face of the cell at grid index `cell` into `out`, or its six faces into
   out[0..5] (indexed by svc_face, on settings.decode_threads threads). Reads only the
   face's chunk and those of its references unless the caches hold them; once a face is
   cached this allocates nothing. SVC_INVALID_ARGUMENT when a buffer cannot hold the face
   (nothing is written then), SVC_NOT_FOUND for a cell not in the file, SVC_CORRUPT_DATA
   for damaged bytes, SVC_IO_ERROR for a failed read, SVC_CANCELLED after close; after
   those the buffers' contents are unspecified. */
SVC_API svc_status svc_reader_decode_face(svc_reader* reader, const int32_t cell[3], svc_face face,
                                          const svc_image* out);
SVC_API svc_status svc_reader_decode_cube(svc_reader* reader, const int32_t cell[3], const svc_image out[6]);

typedef enum svc_depth_format {
  /* float: eye-space depth, the distance along the face camera's view axis (positive, in
     scene units); +infinity where the face saw no geometry */
  SVC_DEPTH_EYE_Z_F32 = 0,
  /* uint16_t: the coded inverse depth, round(65535 near / z) with `near` the face
     camera's near plane, clamped to 1..65535; 0 without geometry */
  SVC_DEPTH_INVERSE_U16 = 1
} svc_depth_format;

/* A caller's buffer for a face's depth: `size` bytes at `data`, rows `stride` bytes apart
   (at least width * 4 for SVC_DEPTH_EYE_Z_F32, width * 2 for SVC_DEPTH_INVERSE_U16; any
   alignment). */
typedef struct svc_depth_image {
  svc_depth_format format;
  svc_row_order rows;
  void* data;
  size_t stride;
  size_t size;
} svc_depth_image;

/* Decodes the depth of one face of the cell at grid index `cell` into `out` (files with
   depth, svc_file_info.has_depth). Reads the face's depth chunk and, for a B-face, the
   depth of its reference cubes' faces unless the depth cache holds them; once cached
   this allocates nothing. SVC_NOT_FOUND for a file without depth or a cell not in it,
   SVC_INVALID_ARGUMENT when the buffer cannot hold the face (nothing is written then),
   other errors as svc_reader_decode_face. */
SVC_API svc_status svc_reader_decode_face_depth(svc_reader* reader, const int32_t cell[3], svc_face face,
                                                const svc_depth_image* out);

/* Tells the prefetcher where the viewer is: a grid cell, or a world position (mapped to
   the grid cell containing it, clamped into the grid); velocity in world units a second
   (NULL: none; only its direction matters). Cheap when nothing changed: call it as
   often as the viewer moves. SVC_INVALID_ARGUMENT for a cell outside the grid or values
   that are not finite. */
SVC_API svc_status svc_reader_set_viewer_cell(svc_reader* reader, const int32_t cell[3], const double velocity[3]);
SVC_API svc_status svc_reader_set_viewer_position(svc_reader* reader, const double position[3],
                                                  const double velocity[3]);
/* Waits until no prefetch work is queued or running, at most timeout_ms. 1 when idle. */
SVC_API int svc_reader_wait_for_prefetch(svc_reader* reader, uint32_t timeout_ms);

typedef struct svc_cache_counters {
  uint64_t hits, misses, in_flight_waits, prefetch_lookups, insertions, evictions;
  uint64_t entries, bytes_held, peak_bytes, budget_bytes;
} svc_cache_counters;

typedef struct svc_reader_stats {
  svc_cache_counters coefficient_cache; /* semi-decoded I-faces */
  svc_cache_counters face_cache;        /* decoded faces */
  svc_cache_counters reference_cache;   /* reference I-faces */
  uint64_t bytes_read, chunks_read;
  uint64_t intra_faces_parsed, predicted_faces_decoded;
  uint64_t prefetch_faces, prefetch_dropped;
  uint64_t thread_buffer_bytes;
  svc_cache_counters depth_cache; /* decoded depth planes */
} svc_reader_stats;

/* A snapshot of the counters (svc/reader.h, ReaderStats). Cheap; safe at any time. */
SVC_API svc_status svc_reader_get_stats(const svc_reader* reader, svc_reader_stats* out);

#ifdef __cplusplus
}
#endif

#endif /* SVC_SVC_H */
