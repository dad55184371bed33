// SPDX-License-Identifier: BSD-2-Clause
// Random access to an .svc file by cell: what a walkthrough runtime embeds.
//
// The reader opens a file without reading it whole: open() reads the header and the
// index; each face is read with positioned reads of its own chunk and those of its
// references. Two caches sit between the file and the caller (docs/runtime.md):
//   - semi-decoded I-faces: the entropy-decoded modes and quantized levels in a compact
//     packed form (about a sixth of the RGB size on photographic content at the
//     default quality). A B-face whose reference I-faces are cached skips their entropy
//     decoding and only runs their prediction and inverse transforms.
//   - decoded faces (YCbCr 4:2:0): a request for a cached face copies it out.
// In a file with depth a third cache holds decoded depth planes, and prefetch decodes
// each face's depth with its color.
// Both are least-recently-used and bounded by byte budgets that are never exceeded.
// After set_viewer(), worker threads decode the viewer's neighbourhood in the
// background; a request for a face that is being decoded (by a worker or by another
// caller) waits for that work instead of repeating it.
//
// Memory: the caches' budgets bound what they hold. Besides them, each thread that
// decodes faces (a caller's or a prefetch worker) keeps the decoder's working buffers
// (the B-face state, CDEF's widened planes) from face to face until it ends, sized for
// the largest face it has decoded for any reader: about 5 bytes a pixel of a 256x256
// face. ReaderStats::thread_buffer_bytes counts them. The reader's memory is thus the
// three budgets plus one face's worth per decoding thread: ReaderSettings::
// prefetch_threads workers, the callers' threads, and ReaderSettings::decode_threads - 1
// helpers while decode_cube runs.
//
// Errors: no call throws; failures come back as Status / Result with a message naming
// the file, cell, face and byte offset at fault. A damaged face yields an error for
// that face (and the B-faces that reference it) while every other face stays readable.
// Errors are not cached: asking again reads the file again. An allocation that fails
// anywhere in the decoder (on the caller's thread, a prefetch worker or a decode_cube
// helper) comes back as kOutOfMemory naming the call, file, cell and face; nothing of the
// failed work is cached and the reader stays usable (asking again decodes again).
//
// Threading: after open() returns, every const and non-const method of Reader may be
// called from any number of threads at once (close() included). Results are
// bit-identical to a single-threaded sequential decode, whatever the thread count,
// call order, cache budgets or prefetch settings. The destructor must not run while
// another thread is inside a method of the same reader.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "svc/byte_source.h"
#include "svc/export.h"
#include "svc/limits.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

struct VerifySettings {
  // Threads that check faces at once (the caller's among them); 0 uses the machine's
  // hardware concurrency. The result does not depend on it.
  int threads = 1;
  // Called after each face, one call at a time (from any of the threads): (faces
  // checked, faces total). Return false to stop; verify then returns kCancelled.
  std::function<bool(uint64_t done, uint64_t total)> progress;
  // When given, receives every problem found, one message each, in the order of
  // verify's report (which its Status holds the first 20 of); cleared first. The
  // caller owns the vector; verify writes it from the calling thread once the checks
  // are done, and leaves it empty on kCancelled.
  std::vector<std::string>* problems = nullptr;
};

struct ReaderSettings {
  // Caps on what the file may make the reader allocate (see svc/limits.h).
  ReaderLimits limits;
  // Byte budget of the semi-decoded I-face cache. 0 disables it. Default 64 MiB: about
  // 2,000 photographic I-faces of 256x256 or 500 of 512x512 at the default quality
  // (34 KB each at 256x256, docs/runtime.md "The semi-decoded form").
  uint64_t coefficient_cache_bytes = 64ull << 20;
  // Byte budget of the decoded-face cache (1.5 bytes a pixel plus a little per face).
  // 0 disables it, and prefetch with it (prefetched faces would have nowhere to go).
  // Default 64 MiB: 112 cubes of 256x256 faces, 28 of 512x512, so that prefetch (which
  // fills at most half) holds a whole 3x3 neighbourhood of 512x512 cubes.
  uint64_t face_cache_bytes = 64ull << 20;
  // Byte budget of the reference cache: I-faces reconstructed for the B-faces that
  // predict from them, and padded with their cube's border as cube references are
  // (docs/codec.md 5.7), so the cells around one I-cube reconstruct it once and pad
  // each face once or twice (a face padded across more edges serves B-faces that read
  // fewer).
  // 0 disables it. Default 32 MiB: the references of about 8 cells of 256x256 faces
  // (3.8 MB each: two cubes, plain and padded), 2 of 512x512.
  uint64_t reference_cache_bytes = 32ull << 20;
  // Byte budget of the decoded-depth cache (files with depth: 2 bytes a pixel plus a
  // little per face): the faces decode_face_depth returned or prefetch decoded, and the
  // reference I-faces' depth that B-faces' depth is predicted from. 0 disables it.
  // Default 32 MiB: 250 faces of 256x256, 62 of 512x512.
  uint64_t depth_cache_bytes = 32ull << 20;
  // Threads one decode_cube() call decodes on, the caller's among them: the reference
  // I-faces of the cell side by side, then its six faces; and one decode_face() (or
  // _into, _ycbcr) call: a B-face's reference I-faces that no cache holds side by side,
  // then the face. 0 (the default) means one per core; 1 decodes on the caller's thread
  // alone. 0..64. The faces are the same for any count.
  int decode_threads = 0;
  // Worker threads that decode the viewer's neighbourhood after set_viewer(); 0 turns
  // prefetch off. 0..64, default 2. Threads start on the first set_viewer() call, so a
  // reader that never calls it runs none.
  int prefetch_threads = 2;
  // Neighbourhood prefetched around the viewer's cell: the present cells within this
  // many cells along every axis (Chebyshev radius), limited to as many cubes as fit in
  // half the face cache. 0..8, default 1 (the 8 neighbours in a one-layer grid).
  int prefetch_radius = 1;
};

// Fills settings with the defaults documented on each field.
SVC_API ReaderSettings default_reader_settings();

// The faces one face needs decoded, as (cell ordinal, face), held inline: an index of
// any size costs no allocation per face. A copy owns its own entries.
class FaceDependencies {
 public:
  using value_type = std::pair<uint32_t, Face>;
  // Two references and at most the four adjacent faces of each reference cube.
  static constexpr size_t kCapacity = 10;

  // More than kCapacity is a caller's error; the extra entry is dropped.
  void push_back(const value_type& dependency) {
    if (size_ < kCapacity) items_[size_++] = dependency;
  }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const value_type& operator[](size_t i) const { return items_[i]; }
  const value_type* begin() const { return items_.data(); }
  const value_type* end() const { return items_.data() + size_; }

 private:
  std::array<value_type, kCapacity> items_{};
  uint8_t size_ = 0;
};

struct FaceEntry {
  FaceType type = FaceType::kIntra;
  uint64_t offset = 0;       // file offset of the face's chunk
  uint64_t coded_bytes = 0;  // coded payload size
  // Faces this one needs decoded; empty for an I-face. First the one or two faces it is
  // predicted from (forward, backward), then, for a B-face with cube references, the faces
  // adjacent to its face in each of those cubes whose content pads the references where
  // its predictions read them (at most four a cube; docs/codec.md 5.7).
  FaceDependencies references;
};

// How one 16x16 macroblock of a B-face was coded (svc inspect draws them).
enum class MacroblockCoding : uint8_t {
  kIntra = 0,
  kForward = 1,        // predicted from the first reference
  kBackward = 2,       // predicted from the second reference
  kBidirectional = 3,  // mean of both predictions
  kSkipped = 4,        // predicted as its neighbours, no residual
};

// How an inter macroblock of a B-face is split for prediction (each part its own mode
// and vectors); 16x16 for every other macroblock.
enum class MacroblockPartition : uint8_t {
  k16x16 = 0,
  k16x8 = 1,  // top and bottom halves
  k8x16 = 2,  // left and right halves
  k8x8 = 3,   // four quarters
};

// A face with the coding of each macroblock.
struct InspectedFace {
  FaceType type = FaceType::kIntra;
  ImageRGB8 image;
  int macroblocks_x = 0, macroblocks_y = 0;
  std::vector<MacroblockCoding> modes;  // row-major; all kIntra for an I-face
  // Row-major, as modes; a partitioned macroblock's mode is its last partition's.
  std::vector<MacroblockPartition> partitions;
  // Row-major, as modes: 1 where a forward, backward or bidirectional macroblock is
  // predicted through its corner vectors' warp (docs/codec.md 5.6), else 0.
  std::vector<uint8_t> warped;
};

struct CellEntry {
  CellIndex index;
  std::array<double, 3> position{0, 0, 0};  // camera centre
  std::array<Camera, kFaceCount> cameras;   // indexed by Face
  std::array<FaceEntry, kFaceCount> faces;  // indexed by Face
};

struct FileInfo {
  uint16_t format_major = 0;
  uint16_t format_minor = 0;
  uint64_t file_bytes = 0;
  int face_width = 0;
  int face_height = 0;
  std::array<int32_t, 3> grid_dims{0, 0, 0};
  std::array<double, 3> grid_origin{0, 0, 0};
  std::array<double, 3> grid_spacing{1, 1, 1};
  int quality = 0;  // 0 when the file was encoded with an explicit quantizer index
  int qindex = 0;   // the I-faces' quantizer index (docs/codec.md, section 5.4)
  std::array<int32_t, 3> i_spacing{1, 1, 1};
  std::string motion;  // "depth" or "logarithmic"
  char up_axis = 'y';
  // The encoder's statistics per face type (indexed by FaceType), as recorded in the index.
  std::array<FaceTypeStats, 2> face_type_stats{};
  // Whether every face's depth is stored (decode_face_depth), and the largest error of a
  // decoded inverse-depth code (svc/types.h, DepthFormat::kInverse16) against the source.
  bool has_depth = false;
  int depth_max_error = 0;
  uint64_t depth_bytes = 0;  // coded depth bytes of all faces
};

// Counters of one cache. hits, misses and in_flight_waits count lookups made for a
// caller (a decode_* / acquire_* call, including the reference I-faces such a call
// needs); lookups made by prefetch workers are counted in prefetch_lookups only.
struct CacheCounters {
  uint64_t hits = 0;             // served from the cache
  uint64_t misses = 0;           // decoded by the calling thread
  uint64_t in_flight_waits = 0;  // waited for the same decode already running elsewhere
  uint64_t prefetch_lookups = 0;
  uint64_t insertions = 0;
  uint64_t evictions = 0;   // entries dropped to stay within the budget
  uint64_t entries = 0;     // held now
  uint64_t bytes_held = 0;  // held now (values plus bookkeeping), <= budget_bytes
  uint64_t peak_bytes = 0;  // most ever held, <= budget_bytes
  uint64_t budget_bytes = 0;
};

struct ReaderStats {
  CacheCounters coefficient_cache;  // semi-decoded I-faces
  CacheCounters face_cache;         // decoded faces
  CacheCounters reference_cache;    // reference I-faces, plain and padded
  CacheCounters depth_cache;        // decoded depth planes
  uint64_t bytes_read = 0;          // face chunk bytes read from the file (with framing)
  uint64_t chunks_read = 0;
  uint64_t intra_faces_parsed = 0;       // I-face entropy decodes
  uint64_t predicted_faces_decoded = 0;  // B-face decodes
  uint64_t prefetch_faces = 0;           // faces decoded by prefetch workers
  uint64_t prefetch_dropped = 0;         // queued prefetch faces dropped (viewer moved, close)
  // Bytes held now by the decoder's per-thread working buffers, outside the caches'
  // budgets (see "Memory" at the top of this file). Process-wide: the sum over every live
  // thread that has decoded faces, for any reader or encoder.
  uint64_t thread_buffer_bytes = 0;
};

class SVC_API Reader {
 public:
  // Opens `path` and reads its header and index (not the face data). The returned
  // reader owns the file handle until destroyed. kInvalidArgument for settings out of
  // range; the container's errors otherwise.
  static Result<std::unique_ptr<Reader>> open(const std::filesystem::path& path,
                                              const ReaderSettings& settings = default_reader_settings());
  // The same from any byte source (svc/byte_source.h: a file, memory, the embedder's own
  // file access), which the reader owns from then on; kInvalidArgument when null.
  static Result<std::unique_ptr<Reader>> open(std::unique_ptr<ByteSource> source,
                                              const ReaderSettings& settings = default_reader_settings());
  // Calls close().
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  const FileInfo& info() const;
  // All cells present in the file, sorted by (y, z, x). The reference stays valid for
  // the reader's lifetime.
  const std::vector<CellEntry>& cells() const;
  // Ordinal into cells() of the cell at a grid index, if present.
  std::optional<size_t> find_cell(const CellIndex& index) const;
  // Ordinal of the present cell whose grid cell contains world point `p`, if any.
  std::optional<size_t> find_cell_at(const std::array<double, 3>& p) const;

  // Decodes one face as RGB8 (tightly packed, row 0 at the top) or as YCbCr 4:2:0
  // planes; the caller owns the copy. Reads only that face's bytes and those of its
  // references, unless the caches hold them. kNotFound for a cell or face not in the
  // file, kCorruptData for damaged bytes, kCancelled after close().
  Result<ImageRGB8> decode_face(const CellIndex& cell, Face face);
  Result<ImageYCbCr420> decode_face_ycbcr(const CellIndex& cell, Face face);
  // The face as the decoded-face cache holds it, without a copy: the image is immutable
  // and stays valid as long as the caller keeps the pointer, even after eviction or
  // close(). Errors as decode_face_ycbcr.
  Result<std::shared_ptr<const ImageYCbCr420>> acquire_face_ycbcr(const CellIndex& cell, Face face);
  // The six faces of a cell, indexed by Face, decoded on settings.decode_threads
  // threads. Errors as decode_face (the first face's, in face order, when several fail).
  Result<std::array<ImageRGB8, kFaceCount>> decode_cube(const CellIndex& cell);

  // Decodes one face straight into the caller's buffer in its pixel format and row
  // order (svc/types.h, PixelBuffer), with no intermediate image: once the face is in
  // the decoded-face cache this allocates nothing. kInvalidArgument, naming the plane and
  // the bytes it needs, when the buffer cannot hold the face (nothing is written then);
  // other errors as decode_face, after which the buffer's contents are unspecified.
  Status decode_face_into(const CellIndex& cell, Face face, const PixelBuffer& out);
  // The six faces of a cell into six buffers indexed by Face, decoded on
  // settings.decode_threads threads. Errors as decode_face_into and decode_cube.
  Status decode_cube_into(const CellIndex& cell, const std::array<PixelBuffer, kFaceCount>& out);

  // Decodes one face's depth (files with depth, FileInfo::has_depth) into the caller's
  // buffer in its format and row order, or as eye-space depth (width * height floats,
  // row 0 at the top, +infinity where the face saw no geometry). Reads the face's depth
  // chunk and, for a B-face, the depth of its reference cubes' faces (docs/codec.md 8.3)
  // unless the depth cache holds them; once the face is cached this allocates nothing
  // (the _into form). kNotFound for a file without depth or a cell not in it,
  // kInvalidArgument when the buffer cannot hold the face (nothing is written then), other
  // errors as decode_face.
  Status decode_face_depth_into(const CellIndex& cell, Face face, const DepthBuffer& out);
  Result<std::vector<float>> decode_face_depth(const CellIndex& cell, Face face);

  // Tells the prefetcher where the viewer is: its cell (or a world position, mapped to
  // the grid cell containing it, clamped into the grid) and optionally its velocity in
  // world units per second (only the direction matters: cells ahead come first among
  // cells equally near). Replaces the previous neighbourhood's pending work. Cheap when
  // nothing changed; call it as often as the viewer moves. A no-op when prefetch is off.
  // kInvalidArgument for a non-finite position or velocity; kCancelled after close().
  Status set_viewer(const CellIndex& cell, const std::array<double, 3>& velocity = {0, 0, 0});
  Status set_viewer(const std::array<double, 3>& position, const std::array<double, 3>& velocity = {0, 0, 0});
  // Waits until no prefetch work is queued or running, at most `timeout`. True when idle.
  bool wait_for_prefetch(std::chrono::milliseconds timeout);

  // A snapshot of the counters. Cheap; safe at any time.
  ReaderStats stats() const;

  // Stops prefetch: drops queued work, waits for each worker's current face (at most
  // one face decode) and joins the workers; then empties both caches. Later decode,
  // acquire and set_viewer calls fail with kCancelled; calls already running finish
  // normally. info(), cells(), find_cell*() and stats() keep working. Idempotent.
  void close();

  // Decodes one face bypassing the caches and reports how each macroblock was coded.
  // Errors as decode_face.
  Result<InspectedFace> inspect_face(const CellIndex& cell, Face face);

  // Checks the CRC of every chunk and decodes every face: each I-face on its own, each
  // B-face from its references through the reference and semi-decoded caches. Returns
  // ok when the file is intact, else kCorruptData with the first 20 problems, one a
  // line: damaged commit slots, then the damaged faces themselves (each naming its
  // chunk: offset, cell, face) in file order, then the faces that cannot be decoded only
  // because a reference is damaged; then a count of the rest. The problems reported, and
  // their order, do not depend on settings.threads. kCancelled when settings.progress
  // stops it.
  Status verify(const VerifySettings& settings = VerifySettings{});

  struct Impl;

 private:
  explicit Reader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace svc
