// SPDX-License-Identifier: BSD-2-Clause
#include "svc/reader.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>
#include <tuple>

#include "codec/common/bframe.h"
#include "codec/common/color.h"
#include "codec/common/cube_padding.h"
#include "codec/common/intra_frame.h"
#include "codec/common/thread_buffers.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "common/exception_status.h"
#include "common/file_io.h"
#include "common/parallel.h"
#include "common/thread_priority.h"
#include "container/container.h"
#include "reader/depth_decode.h"
#include "reader/face_decode.h"
#include "reader/pixel_buffer.h"
#include "reader/prefetch_order.h"
#include "reader/shared_cache.h"

namespace svc {

namespace {

using reader_internal::Origin;
using reader_internal::Outcome;
static_assert(static_cast<int>(MacroblockCoding::kSkipped) == static_cast<int>(codec::MacroblockMode::kSkipped) &&
              static_cast<int>(MacroblockCoding::kBidirectional) ==
                  static_cast<int>(codec::MacroblockMode::kBidirectional) &&
              static_cast<int>(MacroblockCoding::kBackward) == static_cast<int>(codec::MacroblockMode::kBackward) &&
              static_cast<int>(MacroblockCoding::kForward) == static_cast<int>(codec::MacroblockMode::kForward) &&
              static_cast<int>(MacroblockCoding::kIntra) == static_cast<int>(codec::MacroblockMode::kIntra));
using CoefficientPointer = std::shared_ptr<const codec::CoefficientFrame>;
using ImagePointer = std::shared_ptr<const ImageYCbCr420>;

// The index's cell order, which parse_index checks.
bool cell_before(const CellIndex& a, const CellIndex& b) {
  return std::tie(a.y, a.z, a.x) < std::tie(b.y, b.z, b.x);
}

uint64_t coefficient_bytes(const codec::CoefficientFrame& frame) { return frame.memory_bytes(); }

uint64_t image_bytes(const ImageYCbCr420& image) {
  return sizeof(ImageYCbCr420) + image.y.capacity() + image.cb.capacity() + image.cr.capacity();
}

uint64_t depth_plane_bytes(const std::vector<uint16_t>& codes) {
  return sizeof(codes) + codes.capacity() * sizeof(uint16_t);
}

bool finite3(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

Status cancelled() { return Status(ErrorCode::kCancelled, "the reader was closed"); }

// The allocating RGB8 form of decode_face_into (same conversion).
ImageRGB8 to_rgb(const ImageYCbCr420& ycc) {
  ImageRGB8 rgb;
  rgb.width = ycc.width;
  rgb.height = ycc.height;
  rgb.pixels.resize(static_cast<size_t>(rgb.width) * rgb.height * 3);
  codec::ycbcr420_to_rgb(ycc, rgb.pixels.data());
  return rgb;
}

}  // namespace

struct Reader::Impl {
  Impl(const ReaderSettings& s)
      : settings(s),
        coefficients(s.coefficient_cache_bytes, &coefficient_bytes),
        faces(s.face_cache_bytes, &image_bytes),
        references(s.reference_cache_bytes, &image_bytes),
        depths(s.depth_cache_bytes, &depth_plane_bytes) {}

  std::unique_ptr<ReadOnlyFile> file;
  ReaderSettings settings;
  ContainerIndex index;
  FileInfo info;
  std::vector<CellEntry> cells;
  std::array<bool, 2> slot_damaged{false, false};
  reader_internal::GridGeometry grid;

  reader_internal::SharedCache<codec::CoefficientFrame> coefficients;
  reader_internal::SharedCache<ImageYCbCr420> faces;
  // Reference I-faces as B-faces use them: reconstructed, and padded with their cube's
  // border (key: reference_key). A padded entry's computation waits on plain entries of
  // this cache, whose computations wait on nothing in it, so waits form no cycle.
  reader_internal::SharedCache<ImageYCbCr420> references;
  // Decoded depth planes, of the faces asked for and of the reference I-faces B-faces'
  // depth predicts from. A B-face's computation waits on I-face entries, whose
  // computations wait on nothing in it: no cycle.
  reader_internal::SharedCache<std::vector<uint16_t>> depths;
  // Whether every frame has its own reference keys (false only for indexes of more
  // frames than 2^32 / 80, which limits wider than the defaults can admit): without
  // them, references are computed and not cached.
  bool reference_keys_fit = true;

  std::atomic<bool> closed{false};
  std::atomic<uint64_t> bytes_read{0}, chunks_read{0}, intra_parsed{0}, predicted_decoded{0};
  std::atomic<uint64_t> prefetch_faces{0}, prefetch_dropped{0};

  // Prefetch state, guarded by prefetch_mutex.
  std::mutex prefetch_mutex;
  std::condition_variable work_ready;
  std::condition_variable work_idle;
  std::deque<uint32_t> queue;  // frames, most urgent first
  int active = 0;              // faces being decoded by workers
  bool stopping = false;
  std::vector<std::thread> workers;
  std::vector<size_t> scheduled_cells;  // the last neighbourhood queued

  std::string frame_name(uint32_t frame) const { return frame_label(index, frame); }

  Status frame_error(const Status& status, uint32_t frame) const {
    return svc::frame_error(status, *file, index, frame);
  }

  // `compute` (a cache's computation for face `frame`) with any exception it throws,
  // such as a failed allocation, turned into an error naming the face. (The caches turn
  // one into an error too, but know no face.)
  template <typename Compute>
  auto naming(uint32_t frame, Compute compute) {
    return [this, frame, compute]() {
      return status_guarded([&] { return file->name() + ": decoding " + frame_name(frame); }, compute);
    };
  }

  // body(), the work of public call `call`, with any exception it throws turned into an
  // error naming the call, the file and, where given, the cell and face.
  template <typename Body>
  auto guarded(const char* call, std::optional<CellIndex> cell, std::optional<Face> face, Body&& body) noexcept {
    const auto context = [&] {
      std::string subject = cell ? (face ? face_label(*cell, *face) : cell_label(*cell)) : std::string();
      return std::string(call) + (subject.empty() ? "" : " of " + subject) + " in " + file->name();
    };
    return status_guarded(context, std::forward<Body>(body));
  }

  Result<std::vector<uint8_t>> read_payload(uint32_t frame) {
    const FrameRecord& record = index.frames[frame];
    bytes_read.fetch_add(color_chunk_bytes(record), std::memory_order_relaxed);
    chunks_read.fetch_add(1, std::memory_order_relaxed);
    return read_frame_payload(*file, record, frame_name(frame));
  }

  // Ordinal of the cell at `index`: a binary search of the sorted cells, no table to hold.
  std::optional<size_t> cell_ordinal(const CellIndex& index) const {
    const auto it =
        std::lower_bound(cells.begin(), cells.end(), index,
                         [](const CellEntry& entry, const CellIndex& c) { return cell_before(entry.index, c); });
    if (it == cells.end() || cell_before(index, it->index)) return std::nullopt;
    return static_cast<size_t>(it - cells.begin());
  }

  Result<uint32_t> frame_of(const CellIndex& cell, Face face) const {
    const std::optional<size_t> ordinal = cell_ordinal(cell);
    if (!ordinal || static_cast<unsigned>(face) >= kFaceCount) {
      return Status(ErrorCode::kNotFound, file->name() + " has no " + face_label(cell, face));
    }
    return static_cast<uint32_t>(*ordinal * kFaceCount + static_cast<unsigned>(face));
  }

  // --- The cached path -------------------------------------------------------------

  // The semi-decoded form of I-face `frame`: read and entropy-decoded once, then shared.
  // When this call parses it, `decoded` (optional) receives its levels unpacked too.
  Result<CoefficientPointer> coefficients_of(uint32_t frame, Origin origin,
                                             codec::DecodedLevels* decoded = nullptr) {
    return coefficients.get(frame, origin, naming(frame, [&]() -> Result<CoefficientPointer> {
                              SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, read_payload(frame));
                              auto parsed = std::make_shared<codec::CoefficientFrame>();
                              Status status = codec::parse_intra_frame(payload, static_cast<int>(index.face_width),
                                                                       static_cast<int>(index.face_height),
                                                                       parsed.get(), decoded);
                              if (!status.ok()) return frame_error(status, frame);
                              // Parsing grows the vectors by doubling; the cache is charged for what is held.
                              parsed->levels.shrink_to_fit();
                              parsed->block_counts.shrink_to_fit();
                              intra_parsed.fetch_add(1, std::memory_order_relaxed);
                              return CoefficientPointer(std::move(parsed));
                            }));
  }

  // Key of I-face `frame` in the reference cache: padded with `units` of border across
  // `edges`, or plain (0, 0); distinct for every frame when reference_keys_fit.
  static constexpr uint32_t kReferenceKeysPerFrame = (codec::kMaxCubeBorderUnits + 1) << codec::kFaceEdgeCount;
  static uint32_t reference_key(uint32_t frame, int units, uint8_t edges) {
    return frame * kReferenceKeysPerFrame + (static_cast<uint32_t>(units) << codec::kFaceEdgeCount) + edges;
  }

  // The edges of the reference cache's entry of I-face `frame` padded with `units`
  // across `edges` or a superset of them (`edges` itself first), if it has one.
  std::optional<uint8_t> cached_padded_edges(uint32_t frame, int units, uint8_t edges) const {
    for (unsigned wider = edges; wider <= codec::kAllFaceEdges; ++wider) {
      const auto mask = static_cast<uint8_t>(wider);
      if ((mask & edges) == edges && references.contains(reference_key(frame, units, mask))) return mask;
    }
    return std::nullopt;
  }

  // The edges of I-face `frame` whose faces across are I-faces decoded already (in
  // either cache).
  uint8_t decoded_edges(uint32_t frame) const {
    const Face face = static_cast<Face>(frame % kFaceCount);
    const uint32_t cube_first = frame - frame % kFaceCount;
    uint8_t edges = 0;
    for (int e = 0; e < codec::kFaceEdgeCount; ++e) {
      const auto across =
          cube_first + static_cast<uint32_t>(codec::face_across(face, static_cast<codec::FaceEdge>(e)));
      const bool decoded = faces.contains(across) || references.contains(reference_key(across, 0, 0));
      if (decoded && index.frames[across].type == FaceType::kIntra) edges |= uint8_t(1u << e);
    }
    return edges;
  }

  // Pixels of an I-face: a cache's when one holds them, else reconstructed from its
  // (cached) coefficients and kept as a reference.
  Result<ImagePointer> intra_image(uint32_t frame, Origin origin) {
    if (ImagePointer cached = faces.peek(frame)) return cached;
    auto reconstruct = [&]() -> Result<ImagePointer> {
      // A frame parsed just now is reconstructed from its levels as decoded, not unpacked
      // again from the cached form; after a cache hit `decoded` is empty, does not match
      // the frame and is ignored.
      codec::DecodedLevels decoded;
      SVC_ASSIGN_OR_RETURN(CoefficientPointer coefficients, coefficients_of(frame, origin, &decoded));
      auto image = std::make_shared<ImageYCbCr420>();
      codec::reconstruct_intra_frame(*coefficients, image.get(), &decoded);
      return ImagePointer(std::move(image));
    };
    if (!reference_keys_fit) return reconstruct();
    return references.get(reference_key(frame, 0, 0), origin, naming(frame, reconstruct));
  }

  // Chunks read through the reader's counters; I-faces and padded references through the
  // caches.
  class CachedSource : public CodedFaceSource {
   public:
    CachedSource(Impl& impl, Origin origin) : impl_(impl), origin_(origin) {}
    Result<std::vector<uint8_t>> payload(uint32_t frame) override { return impl_.read_payload(frame); }
    Result<FacePointer> intra_face(uint32_t frame) override { return impl_.intra_image(frame, origin_); }
    Result<FacePointer> padded_intra_face(uint32_t frame, int units, uint8_t edges) override {
      if (units == 0) return intra_face(frame);
      if (!impl_.reference_keys_fit) return CodedFaceSource::padded_intra_face(frame, units, edges);
      // Samples across edges a B-face may not read never reach its output (docs/codec.md
      // 5.7), so a face padded across more edges serves it as well. B-faces list
      // different edges of the same reference, so an entry is found among the supersets
      // of `edges`, and one computed is padded across every edge whose face is decoded
      // already: later B-faces find it instead of padding the face again.
      const uint8_t padded_edges =
          impl_.cached_padded_edges(frame, units, edges).value_or(edges | impl_.decoded_edges(frame));
      return impl_.references.get(reference_key(frame, units, padded_edges), origin_, impl_.naming(frame, [&] {
        return CodedFaceSource::padded_intra_face(frame, units, padded_edges);
      }));
    }

   private:
    Impl& impl_;
    Origin origin_;
  };

  // Chunks read through the reader's counters; nothing cached (verify, inspect).
  class UncachedSource : public FileCodedFaceSource {
   public:
    explicit UncachedSource(Impl& impl) : FileCodedFaceSource(*impl.file, impl.index), impl_(impl) {}
    Result<std::vector<uint8_t>> payload(uint32_t frame) override { return impl_.read_payload(frame); }

   private:
    Impl& impl_;
  };

  Result<ImagePointer> decode_through_caches(uint32_t frame, Origin origin) {
    CachedSource source(*this, origin);
    auto image = decode_indexed_face(*file, index, frame, source);
    if (image.ok() && index.frames[frame].type == FaceType::kPredicted) {
      predicted_decoded.fetch_add(1, std::memory_order_relaxed);
    }
    return image;
  }

  Result<ImagePointer> face_of(uint32_t frame, Origin origin, Outcome* outcome = nullptr) {
    return faces.get(frame, origin, naming(frame, [&] { return decode_through_caches(frame, origin); }), outcome);
  }

  Result<ImagePointer> decode_uncached(uint32_t frame, std::vector<codec::MacroblockMode>* modes = nullptr,
                                       std::vector<codec::Partition>* partitions = nullptr,
                                       std::vector<uint8_t>* warped = nullptr) {
    UncachedSource source(*this);
    return decode_indexed_face(*file, index, frame, source, modes, partitions, warped);
  }

  // The reference I-faces that frames first .. first + count - 1 need and neither the
  // face cache (the frame) nor the reference cache (the I-face) holds, decoded side by
  // side on `threads` threads into the reference cache (without one, nothing: they
  // would be decoded twice). Errors are left to the decodes that follow, so which one
  // comes back does not depend on the threads.
  void decode_dependencies(uint32_t first, uint32_t count, int threads) {
    if (!reference_keys_fit || settings.reference_cache_bytes == 0) return;
    std::vector<uint32_t> needed;
    for (uint32_t frame = first; frame < first + count; ++frame) {
      if (faces.contains(frame)) continue;
      for (uint32_t ref : frame_dependencies(index.frames[frame])) {
        if (!references.contains(reference_key(ref, 0, 0))) needed.push_back(ref);
      }
    }
    std::sort(needed.begin(), needed.end());
    needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    if (needed.size() < 2) return;
    (void)parallel_for(needed.size(), threads, [&](size_t i) {
      (void)intra_image(needed[i], Origin::kCaller);
      return Status::Ok();
    });
  }

  // One face for the caller: a B-face's reference I-faces first decoded side by side on
  // settings.decode_threads threads when the caches lack it.
  Result<ImagePointer> caller_face(uint32_t frame) {
    const int threads = resolve_thread_count(settings.decode_threads);
    if (threads > 1) decode_dependencies(frame, 1, threads);
    return face_of(frame, Origin::kCaller);
  }

  // The six faces from frame `first` on, decoded on settings.decode_threads threads:
  // first the reference I-faces they need, then the faces themselves, each B-face
  // padding its references from those. The second step reports any error, so which
  // one comes back does not depend on the threads.
  // Decodes the six faces from `first` on and passes each to emit(face, image), from
  // up to settings.decode_threads threads at once.
  Status decode_cube(uint32_t first, const std::function<void(size_t, const ImageYCbCr420&)>& emit) {
    const int threads = resolve_thread_count(settings.decode_threads);
    if (threads > 1) decode_dependencies(first, kFaceCount, threads);
    return parallel_for(kFaceCount, threads, [&](size_t f) -> Status {
      const auto frame = first + static_cast<uint32_t>(f);
      return naming(frame, [&]() -> Status {
        SVC_ASSIGN_OR_RETURN(ImagePointer image, face_of(frame, Origin::kCaller));
        emit(f, *image);
        return Status::Ok();
      })();
    });
  }

  // The face for a caller, through the caches.
  Result<ImagePointer> acquire(const CellIndex& cell, Face face) {
    if (closed.load()) return cancelled();
    SVC_ASSIGN_OR_RETURN(uint32_t frame, frame_of(cell, face));
    return caller_face(frame);
  }

  // --- Depth -----------------------------------------------------------------------------

  const Camera& camera_of(uint32_t frame) const { return cells[frame / kFaceCount].cameras[frame % kFaceCount]; }

  class CachedDepthSource : public CodedDepthSource {
   public:
    CachedDepthSource(Impl& impl, Origin origin)
        : CodedDepthSource(*impl.file, impl.index), impl_(impl), origin_(origin) {}
    Result<std::vector<uint8_t>> depth_payload(uint32_t frame) override {
      const FrameRecord& record = impl_.index.frames[frame];
      impl_.bytes_read.fetch_add(depth_chunk_bytes(record), std::memory_order_relaxed);
      impl_.chunks_read.fetch_add(1, std::memory_order_relaxed);
      return read_frame_depth(*impl_.file, record, impl_.frame_name(frame));
    }
    Result<DepthPointer> intra_depth(uint32_t frame) override { return impl_.depth_of(frame, origin_); }
    Result<Camera> camera(uint32_t frame) override { return impl_.camera_of(frame); }

   private:
    Impl& impl_;
    Origin origin_;
  };

  Result<DepthPointer> depth_of(uint32_t frame, Origin origin, Outcome* outcome = nullptr) {
    return depths.get(frame, origin,
                      naming(frame,
                             [&] {
                               CachedDepthSource source(*this, origin);
                               return decode_indexed_depth(*file, index, frame, source);
                             }),
                      outcome);
  }

  Result<uint32_t> depth_frame_of(const CellIndex& cell, Face face) const {
    if (!index.depth)
      return Status(ErrorCode::kNotFound, file->name() + " holds no depth (encoded without --depth)");
    return frame_of(cell, face);
  }

  // --- Prefetch --------------------------------------------------------------------------

  uint64_t cube_bytes() const {
    const uint64_t w = index.face_width, h = index.face_height;
    const uint64_t chroma = ((w + 1) / 2) * ((h + 1) / 2);
    return kFaceCount * (w * h + 2 * chroma + sizeof(ImageYCbCr420) +
                         reader_internal::SharedCache<ImageYCbCr420>::kEntryOverhead);
  }

  void worker_loop() {
    // Background work yields to the threads that need a face now.
    lower_current_thread_priority();
    std::unique_lock<std::mutex> lock(prefetch_mutex);
    for (;;) {
      work_ready.wait(lock, [&] { return stopping || !queue.empty(); });
      if (stopping) return;
      const uint32_t frame = queue.front();
      queue.pop_front();
      ++active;
      lock.unlock();
      // Errors (an allocation failure among them) are not cached; the caller who asks for
      // the face gets them.
      (void)status_guarded([] { return std::string("prefetch"); }, [&] { return prefetch(frame); });
      lock.lock();
      --active;
      if (queue.empty() && active == 0) work_idle.notify_all();
    }
  }

  Status prefetch(uint32_t frame) {
    Outcome outcome = Outcome::kHit;
    auto result = face_of(frame, Origin::kPrefetch, &outcome);
    if (result.ok() && outcome == Outcome::kComputed) prefetch_faces.fetch_add(1, std::memory_order_relaxed);
    if (index.depth) (void)depth_of(frame, Origin::kPrefetch);
    return Status::Ok();
  }

  Status schedule(const CellIndex& viewer_cell, const std::array<double, 3>& position,
                  const std::array<double, 3>& velocity) {
    if (closed.load()) return cancelled();
    if (settings.prefetch_threads <= 0 || settings.face_cache_bytes == 0) return Status::Ok();
    const uint64_t fit = settings.face_cache_bytes / 2 / std::max<uint64_t>(cube_bytes(), 1);
    const size_t max_cells = static_cast<size_t>(std::clamp<uint64_t>(fit, 1, 1u << 20));
    std::vector<size_t> order =
        reader_internal::prefetch_order(grid, viewer_cell, position, velocity, settings.prefetch_radius, max_cells,
                                        [&](const CellIndex& c) { return cell_ordinal(c); });
    std::lock_guard<std::mutex> lock(prefetch_mutex);
    if (stopping) return cancelled();
    if (order == scheduled_cells) return Status::Ok();
    prefetch_dropped.fetch_add(queue.size(), std::memory_order_relaxed);
    queue.clear();
    for (size_t cell : order) {
      for (int f = 0; f < kFaceCount; ++f) {
        const uint32_t frame = static_cast<uint32_t>(cell * kFaceCount + f);
        if (!faces.contains(frame)) queue.push_back(frame);
      }
    }
    // Only once queued: after an allocation failure above, the same viewer queues again.
    scheduled_cells = std::move(order);
    if (workers.empty()) {
      for (int t = 0; t < settings.prefetch_threads; ++t) workers.emplace_back([this] { worker_loop(); });
    }
    work_ready.notify_all();
    return Status::Ok();
  }

  void close() {
    std::vector<std::thread> joining;
    {
      std::lock_guard<std::mutex> lock(prefetch_mutex);
      closed.store(true);
      stopping = true;
      prefetch_dropped.fetch_add(queue.size(), std::memory_order_relaxed);
      queue.clear();
      joining.swap(workers);
    }
    work_ready.notify_all();
    work_idle.notify_all();
    for (std::thread& worker : joining) worker.join();
    coefficients.set_budget(0);
    faces.set_budget(0);
    references.set_budget(0);
    depths.set_budget(0);
  }
};

namespace {

Status check_settings(const ReaderSettings& settings) {
  if (settings.prefetch_threads < 0 || settings.prefetch_threads > 64) {
    return Status(ErrorCode::kInvalidArgument, "reader settings: prefetch_threads " +
                                                   std::to_string(settings.prefetch_threads) + " outside 0..64");
  }
  if (settings.decode_threads < 0 || settings.decode_threads > 64) {
    return Status(ErrorCode::kInvalidArgument,
                  "reader settings: decode_threads " + std::to_string(settings.decode_threads) + " outside 0..64");
  }
  if (settings.prefetch_radius < 0 || settings.prefetch_radius > 8) {
    return Status(ErrorCode::kInvalidArgument,
                  "reader settings: prefetch_radius " + std::to_string(settings.prefetch_radius) + " outside 0..8");
  }
  return Status::Ok();
}

void fill_info(Reader::Impl& impl) {
  const ContainerIndex& index = impl.index;
  FileInfo& info = impl.info;
  info.format_major = kFormatMajor;
  info.format_minor = kFormatMinor;
  info.file_bytes = impl.file->size();
  info.face_width = static_cast<int>(index.face_width);
  info.face_height = static_cast<int>(index.face_height);
  info.grid_dims = index.grid.dims;
  info.grid_origin = index.grid.origin;
  info.grid_spacing = index.grid.spacing;
  info.quality = static_cast<int>(index.coding.quality);
  info.qindex = static_cast<int>(index.coding.qindex);
  info.i_spacing = index.coding.i_spacing;
  info.motion = index.coding.motion == MotionSearch::kDepth ? "depth" : "logarithmic";
  info.up_axis = "xyz"[static_cast<int>(index.up_axis)];
  info.face_type_stats = index.stats;
  info.has_depth = index.depth;
  info.depth_max_error = index.depth_max_error;
  for (const FrameRecord& frame : index.frames) info.depth_bytes += frame.depth_size;
}

// The cells' entries, which take over the index's cameras.
void fill_cells(Reader::Impl& impl) {
  const ContainerIndex& index = impl.index;
  impl.cells.resize(index.cells.size());
  for (size_t c = 0; c < index.cells.size(); ++c) {
    CellEntry& entry = impl.cells[c];
    entry.index = index.cells[c].index;
    entry.position = index.cells[c].position;
    entry.cameras = index.cameras[c];
    for (int f = 0; f < kFaceCount; ++f) {
      const FrameRecord& frame = index.frames[c * kFaceCount + f];
      FaceEntry& face = entry.faces[f];
      face.type = frame.type;
      face.offset = frame.chunk_offset;
      face.coded_bytes = frame.payload_size;
      for (uint32_t ref : frame_dependencies(frame)) {
        face.references.push_back({index.frames[ref].cell, index.frames[ref].face});
      }
    }
  }
  // The entries hold the cameras now; decoding never needs them.
  impl.index.cameras = {};
}

// The reader's state for `source`: its header and index read and checked.
Result<std::unique_ptr<Reader::Impl>> load(std::unique_ptr<ByteSource> source, const ReaderSettings& settings) {
  auto impl = std::make_unique<Reader::Impl>(settings);
  impl->file = std::make_unique<ReadOnlyFile>(std::move(source));
  SVC_ASSIGN_OR_RETURN(OpenedContainer opened, open_container(*impl->file, settings.limits));
  impl->index = std::move(opened.index);
  impl->reference_keys_fit = impl->index.frames.size() <=
                             std::numeric_limits<uint32_t>::max() / Reader::Impl::kReferenceKeysPerFrame;
  impl->slot_damaged = opened.slot_damaged;
  impl->grid.dims = impl->index.grid.dims;
  impl->grid.origin = impl->index.grid.origin;
  impl->grid.spacing = impl->index.grid.spacing;
  fill_info(*impl);
  fill_cells(*impl);
  return impl;
}

// inspect_face's work.
Result<InspectedFace> inspect(Reader::Impl& impl, const CellIndex& cell, Face face) {
  if (impl.closed.load()) return cancelled();
  SVC_ASSIGN_OR_RETURN(uint32_t frame, impl.frame_of(cell, face));
  std::vector<codec::MacroblockMode> modes;
  std::vector<codec::Partition> partitions;
  std::vector<uint8_t> warped;
  SVC_ASSIGN_OR_RETURN(ImagePointer ycc, impl.decode_uncached(frame, &modes, &partitions, &warped));
  InspectedFace out;
  out.type = impl.index.frames[frame].type;
  out.image = to_rgb(*ycc);
  out.macroblocks_x = (ycc->width + codec::kMacroblockSize - 1) / codec::kMacroblockSize;
  out.macroblocks_y = (ycc->height + codec::kMacroblockSize - 1) / codec::kMacroblockSize;
  out.modes.assign(static_cast<size_t>(out.macroblocks_x) * out.macroblocks_y, MacroblockCoding::kIntra);
  for (size_t i = 0; i < modes.size() && i < out.modes.size(); ++i) {
    out.modes[i] = static_cast<MacroblockCoding>(modes[i]);
  }
  out.partitions.assign(out.modes.size(), MacroblockPartition::k16x16);
  for (size_t i = 0; i < partitions.size() && i < out.partitions.size(); ++i) {
    out.partitions[i] = static_cast<MacroblockPartition>(partitions[i]);
  }
  out.warped.assign(out.modes.size(), 0);
  std::copy_n(warped.begin(), std::min(warped.size(), out.warped.size()), out.warped.begin());
  return out;
}

// verify's work.
Status verify_all(Reader::Impl& impl, const VerifySettings& settings) {
  std::vector<std::string> problems;
  for (int slot = 0; slot < 2; ++slot) {
    if (impl.slot_damaged[slot]) {
      problems.push_back(impl.file->name() + ": commit slot " + std::to_string(slot) + " (bytes " +
                         std::to_string(kFileHeaderSize + slot * kCommitSlotSize) + "-" +
                         std::to_string(kFileHeaderSize + (slot + 1) * kCommitSlotSize - 1) +
                         ") fails its CRC-32 check; the other slot's index is in use");
    }
  }
  const size_t frames = impl.index.frames.size();
  // Every face's outcome is kept and reported in frame order, whatever the threads did.
  std::vector<Status> outcomes(frames);
  std::vector<uint8_t> chunk_damaged(frames, 0);
  std::mutex progress_mutex;
  uint64_t checked = 0;
  const Status run = parallel_for(frames, resolve_thread_count(settings.threads), [&](size_t frame) -> Status {
    auto payload = impl.read_payload(static_cast<uint32_t>(frame));
    outcomes[frame] = payload.status();
    chunk_damaged[frame] = payload.ok() ? 0 : 1;
    // An I-face is decoded on its own; a B-face from its references as the caches hold
    // them, so the I-faces around it are reconstructed and padded once, not once a face.
    const auto f = static_cast<uint32_t>(frame);
    if (outcomes[frame].ok()) {
      outcomes[frame] = impl.index.frames[f].type == FaceType::kIntra
                            ? impl.decode_uncached(f).status()
                            : impl.decode_through_caches(f, Origin::kCaller).status();
    }
    if (outcomes[frame].ok() && impl.index.depth) {
      outcomes[frame] = impl.depth_of(f, Origin::kCaller).status();
    }
    if (!settings.progress) return Status::Ok();
    std::lock_guard<std::mutex> lock(progress_mutex);
    if (settings.progress(++checked, frames)) return Status::Ok();
    return Status(ErrorCode::kCancelled, "verify of " + impl.file->name() + " cancelled");
  });
  if (settings.problems != nullptr) settings.problems->clear();
  if (!run.ok()) return run;
  // The damaged faces first, then those that fail only because a reference they need
  // failed: the first line names a damaged chunk, not one of the faces that use it.
  const auto fails_through_reference = [&](size_t frame) {
    if (chunk_damaged[frame] || impl.index.frames[frame].type == FaceType::kIntra) return false;
    const FrameRecord& record = impl.index.frames[frame];
    for (uint32_t ref : impl.index.depth ? depth_dependencies(record) : frame_dependencies(record)) {
      if (ref < frames && !outcomes[ref].ok()) return true;
    }
    return false;
  };
  for (bool dependent : {false, true}) {
    for (size_t frame = 0; frame < frames; ++frame) {
      if (!outcomes[frame].ok() && fails_through_reference(frame) == dependent) {
        problems.push_back(outcomes[frame].message());
      }
    }
  }
  if (settings.problems != nullptr) *settings.problems = problems;
  if (problems.empty()) return Status::Ok();
  constexpr size_t kReported = 20;
  std::string message;
  for (size_t i = 0; i < problems.size() && i < kReported; ++i) message += (i ? "\n" : "") + problems[i];
  if (problems.size() > kReported) {
    message += "\n... and " + std::to_string(problems.size() - kReported) + " more damaged faces";
  }
  return Status(ErrorCode::kCorruptData, message);
}

}  // namespace

ReaderSettings default_reader_settings() { return ReaderSettings{}; }

Reader::Reader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Reader::~Reader() {
  if (impl_) impl_->close();
}

Result<std::unique_ptr<Reader>> Reader::open(const std::filesystem::path& path, const ReaderSettings& settings) {
  return status_guarded([&] { return "Reader::open of " + path.string(); },
                        [&]() -> Result<std::unique_ptr<Reader>> {
                          SVC_ASSIGN_OR_RETURN(std::unique_ptr<ByteSource> source, open_file_source(path));
                          return open(std::move(source), settings);
                        });
}

Result<std::unique_ptr<Reader>> Reader::open(std::unique_ptr<ByteSource> source, const ReaderSettings& settings) {
  std::string name;
  return status_guarded([&] { return "Reader::open of " + (name.empty() ? std::string("a byte source") : name); },
                        [&]() -> Result<std::unique_ptr<Reader>> {
                          if (source == nullptr)
                            return Status(ErrorCode::kInvalidArgument, "no byte source to read");
                          name = source->name();
                          SVC_RETURN_IF_ERROR(check_settings(settings));
                          SVC_ASSIGN_OR_RETURN(std::unique_ptr<Impl> impl, load(std::move(source), settings));
                          return std::unique_ptr<Reader>(new Reader(std::move(impl)));
                        });
}

const FileInfo& Reader::info() const { return impl_->info; }
const std::vector<CellEntry>& Reader::cells() const { return impl_->cells; }

std::optional<size_t> Reader::find_cell(const CellIndex& index) const { return impl_->cell_ordinal(index); }

std::optional<size_t> Reader::find_cell_at(const std::array<double, 3>& p) const {
  const GridSpec& grid = impl_->index.grid;
  int32_t idx[3];
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(p[axis])) return std::nullopt;
    // Cell i covers centre +- spacing/2 along each axis.
    const double t = std::floor((p[axis] - grid.origin[axis]) / grid.spacing[axis] + 0.5);
    if (t < 0 || t >= grid.dims[axis]) return std::nullopt;
    idx[axis] = static_cast<int32_t>(t);
  }
  return find_cell(CellIndex{idx[0], idx[1], idx[2]});
}

Result<std::shared_ptr<const ImageYCbCr420>> Reader::acquire_face_ycbcr(const CellIndex& cell, Face face) {
  return impl_->guarded("acquire_face_ycbcr", cell, face, [&] { return impl_->acquire(cell, face); });
}

Result<ImageYCbCr420> Reader::decode_face_ycbcr(const CellIndex& cell, Face face) {
  return impl_->guarded("decode_face_ycbcr", cell, face, [&]() -> Result<ImageYCbCr420> {
    SVC_ASSIGN_OR_RETURN(ImagePointer image, impl_->acquire(cell, face));
    return *image;
  });
}

Result<ImageRGB8> Reader::decode_face(const CellIndex& cell, Face face) {
  return impl_->guarded("decode_face", cell, face, [&]() -> Result<ImageRGB8> {
    SVC_ASSIGN_OR_RETURN(ImagePointer ycc, impl_->acquire(cell, face));
    return to_rgb(*ycc);
  });
}

Result<InspectedFace> Reader::inspect_face(const CellIndex& cell, Face face) {
  return impl_->guarded("inspect_face", cell, face, [&] { return inspect(*impl_, cell, face); });
}

Result<std::array<ImageRGB8, kFaceCount>> Reader::decode_cube(const CellIndex& cell) {
  return impl_->guarded("decode_cube", cell, std::nullopt, [&]() -> Result<std::array<ImageRGB8, kFaceCount>> {
    if (impl_->closed.load()) return cancelled();
    SVC_ASSIGN_OR_RETURN(uint32_t first, impl_->frame_of(cell, Face::kPX));
    std::array<ImageRGB8, kFaceCount> cube;
    SVC_RETURN_IF_ERROR(
        impl_->decode_cube(first, [&](size_t f, const ImageYCbCr420& image) { cube[f] = to_rgb(image); }));
    return cube;
  });
}

Status Reader::decode_face_into(const CellIndex& cell, Face face, const PixelBuffer& out) {
  return impl_->guarded("decode_face_into", cell, face, [&]() -> Status {
    SVC_RETURN_IF_ERROR(reader_internal::check_pixel_buffer(out, impl_->info.face_width, impl_->info.face_height));
    SVC_ASSIGN_OR_RETURN(ImagePointer image, impl_->acquire(cell, face));
    reader_internal::write_pixels(*image, out);
    return Status::Ok();
  });
}

Status Reader::decode_cube_into(const CellIndex& cell, const std::array<PixelBuffer, kFaceCount>& out) {
  return impl_->guarded("decode_cube_into", cell, std::nullopt, [&]() -> Status {
    for (size_t f = 0; f < kFaceCount; ++f) {
      const Status checked =
          reader_internal::check_pixel_buffer(out[f], impl_->info.face_width, impl_->info.face_height);
      if (!checked.ok()) return checked.with_context(std::string("face ") + face_name(kAllFaces[f]));
    }
    if (impl_->closed.load()) return cancelled();
    SVC_ASSIGN_OR_RETURN(uint32_t first, impl_->frame_of(cell, Face::kPX));
    return impl_->decode_cube(first, [&](size_t f, const ImageYCbCr420& image) {
      reader_internal::write_pixels(image, out[f]);
    });
  });
}

Status Reader::decode_face_depth_into(const CellIndex& cell, Face face, const DepthBuffer& out) {
  return impl_->guarded("decode_face_depth_into", cell, face, [&]() -> Status {
    if (impl_->closed.load()) return cancelled();
    SVC_ASSIGN_OR_RETURN(uint32_t frame, impl_->depth_frame_of(cell, face));
    SVC_RETURN_IF_ERROR(reader_internal::check_depth_buffer(out, impl_->info.face_width, impl_->info.face_height));
    SVC_ASSIGN_OR_RETURN(DepthPointer codes, impl_->depth_of(frame, Origin::kCaller));
    reader_internal::write_depth(*codes, impl_->info.face_width, impl_->info.face_height,
                                 impl_->camera_of(frame).frustum.near_plane, out);
    return Status::Ok();
  });
}

Result<std::vector<float>> Reader::decode_face_depth(const CellIndex& cell, Face face) {
  return impl_->guarded("decode_face_depth", cell, face, [&]() -> Result<std::vector<float>> {
    std::vector<float> depth(static_cast<size_t>(impl_->info.face_width) * impl_->info.face_height);
    DepthBuffer out;
    out.data = depth.data();
    out.stride = static_cast<size_t>(impl_->info.face_width) * sizeof(float);
    out.size = depth.size() * sizeof(float);
    SVC_RETURN_IF_ERROR(decode_face_depth_into(cell, face, out));
    return depth;
  });
}

Status Reader::set_viewer(const CellIndex& cell, const std::array<double, 3>& velocity) {
  return impl_->guarded("set_viewer", cell, std::nullopt, [&]() -> Status {
    if (!finite3(velocity)) return Status(ErrorCode::kInvalidArgument, "set_viewer: velocity is not finite");
    const auto& dims = impl_->grid.dims;
    if (cell.x < 0 || cell.y < 0 || cell.z < 0 || cell.x >= dims[0] || cell.y >= dims[1] || cell.z >= dims[2]) {
      return Status(ErrorCode::kInvalidArgument, "set_viewer: " + cell_label(cell) + " lies outside the grid");
    }
    return impl_->schedule(cell, impl_->grid.centre(cell), velocity);
  });
}

Status Reader::set_viewer(const std::array<double, 3>& position, const std::array<double, 3>& velocity) {
  return impl_->guarded("set_viewer", std::nullopt, std::nullopt, [&]() -> Status {
    if (!finite3(position)) return Status(ErrorCode::kInvalidArgument, "set_viewer: position is not finite");
    if (!finite3(velocity)) return Status(ErrorCode::kInvalidArgument, "set_viewer: velocity is not finite");
    return impl_->schedule(impl_->grid.cell_at(position), position, velocity);
  });
}

bool Reader::wait_for_prefetch(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(impl_->prefetch_mutex);
  return impl_->work_idle.wait_for(lock, timeout,
                                   [&] { return impl_->stopping || (impl_->queue.empty() && impl_->active == 0); });
}

ReaderStats Reader::stats() const {
  ReaderStats s;
  s.coefficient_cache = impl_->coefficients.counters();
  s.face_cache = impl_->faces.counters();
  s.reference_cache = impl_->references.counters();
  s.depth_cache = impl_->depths.counters();
  s.bytes_read = impl_->bytes_read.load(std::memory_order_relaxed);
  s.chunks_read = impl_->chunks_read.load(std::memory_order_relaxed);
  s.intra_faces_parsed = impl_->intra_parsed.load(std::memory_order_relaxed);
  s.predicted_faces_decoded = impl_->predicted_decoded.load(std::memory_order_relaxed);
  s.prefetch_faces = impl_->prefetch_faces.load(std::memory_order_relaxed);
  s.prefetch_dropped = impl_->prefetch_dropped.load(std::memory_order_relaxed);
  s.thread_buffer_bytes = codec::thread_buffer_bytes();
  return s;
}

void Reader::close() { impl_->close(); }

Status Reader::verify(const VerifySettings& settings) {
  return impl_->guarded("verify", std::nullopt, std::nullopt, [&] { return verify_all(*impl_, settings); });
}

}  // namespace svc
