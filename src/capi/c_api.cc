// SPDX-License-Identifier: BSD-2-Clause
// The C API (svc/svc.h) over the C++ reader: handles, status codes, the messages kept
// per reader and thread, and no exception past the boundary.
#include "svc/svc.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <unordered_map>

#include "codec/common/thread_slot.h"
#include "svc/byte_source.h"
#include "svc/reader.h"

struct svc_reader {
  std::unique_ptr<svc::Reader> reader;
  mutable std::mutex errors_mutex;
  mutable std::unordered_map<std::thread::id, std::string> errors;  // last failure per thread
};

namespace {

using svc::ErrorCode;
using svc::Status;

// The calling thread's last open error (svc_last_open_error), kept until the thread ends.
struct OpenError {
  std::string message;
  bool lost = false;  // the last failure's message could not be stored
};

constexpr const char* kOpenErrorLost = "out of memory: the open call's error message could not be kept";

// Keeps "CALL: DETAIL" (or CALL alone when DETAIL is empty) as the thread's open error.
void set_open_error(std::string_view call, std::string_view detail = {}) noexcept {
  OpenError* error = nullptr;
  try {
    error = &svc::codec::thread_object<OpenError>();
    error->message.assign(call);
    if (!detail.empty()) error->message.append(": ").append(detail);
    error->lost = false;
  } catch (...) {
    if (error != nullptr) error->lost = true;
  }
}

void clear_open_error() noexcept {
  try {
    OpenError& error = svc::codec::thread_object<OpenError>();
    error.message.clear();
    error.lost = false;
  } catch (...) {
    // svc_last_open_error makes the thread's record again or says it could not.
  }
}

static_assert(static_cast<int>(ErrorCode::kOutOfMemory) == SVC_OUT_OF_MEMORY &&
              static_cast<int>(ErrorCode::kInternal) == SVC_INTERNAL);

svc_status status_code(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk: return SVC_OK;
    case ErrorCode::kInvalidArgument: return SVC_INVALID_ARGUMENT;
    case ErrorCode::kNotFound: return SVC_NOT_FOUND;
    case ErrorCode::kIoError: return SVC_IO_ERROR;
    case ErrorCode::kBadInput: return SVC_BAD_INPUT;
    case ErrorCode::kCorruptData: return SVC_CORRUPT_DATA;
    case ErrorCode::kLimitExceeded: return SVC_LIMIT_EXCEEDED;
    case ErrorCode::kUnsupported: return SVC_UNSUPPORTED;
    case ErrorCode::kCancelled: return SVC_CANCELLED;
    case ErrorCode::kInternal: return SVC_INTERNAL;
    case ErrorCode::kOutOfMemory: return SVC_OUT_OF_MEMORY;
  }
  return SVC_INTERNAL;
}

// Keeps the message where svc_reader_last_error finds it and returns the code.
svc_status record(const svc_reader* reader, svc_status code, const std::string& message) {
  if (code == SVC_OK || reader == nullptr) return code;
  try {
    std::lock_guard<std::mutex> lock(reader->errors_mutex);
    reader->errors[std::this_thread::get_id()] = message;
  } catch (...) {
    // The code still says what failed when the message cannot be kept.
  }
  return code;
}

svc_status record(const svc_reader* reader, const Status& status) {
  return record(reader, status_code(status.code()), status.message());
}

// Runs `body` (returning a Status) with every exception turned into a status.
template <class Body>
svc_status guarded(const svc_reader* reader, const char* call, Body&& body) {
  try {
    return record(reader, body());
  } catch (const std::bad_alloc&) {
    return record(reader, SVC_OUT_OF_MEMORY, std::string(call) + ": out of memory");
  } catch (const std::exception& e) {
    return record(reader, SVC_INTERNAL, std::string(call) + ": " + e.what());
  } catch (...) {
    return record(reader, SVC_INTERNAL, std::string(call) + ": unknown failure");
  }
}

Status invalid(const char* call, const char* what) {
  return Status(ErrorCode::kInvalidArgument, std::string(call) + ": " + what + " is NULL");
}

// UTF-8 on every platform: on Windows a char path would otherwise be read in the ANSI
// code page. The conversion to Windows' UTF-16 throws on bytes that are not UTF-8.
svc::Result<std::filesystem::path> utf8_path(const char* path) {
  try {
    return std::filesystem::path(std::u8string_view(reinterpret_cast<const char8_t*>(path)));
  } catch (const std::system_error&) {
    return Status(ErrorCode::kInvalidArgument, "svc_reader_open_file: the path is not UTF-8");
  }
}

svc::CellIndex cell_index(const int32_t cell[3]) { return svc::CellIndex{cell[0], cell[1], cell[2]}; }

svc::ReaderSettings reader_settings(const svc_reader_settings* given) {
  svc::ReaderSettings settings = svc::default_reader_settings();
  if (given == nullptr) return settings;
  settings.coefficient_cache_bytes = given->coefficient_cache_bytes;
  settings.face_cache_bytes = given->face_cache_bytes;
  settings.reference_cache_bytes = given->reference_cache_bytes;
  settings.decode_threads = given->decode_threads;
  settings.prefetch_threads = given->prefetch_threads;
  settings.prefetch_radius = given->prefetch_radius;
  settings.depth_cache_bytes = given->depth_cache_bytes;
  return settings;
}

svc::PixelBuffer pixel_buffer(const svc_image& image) {
  svc::PixelBuffer buffer;
  buffer.format = static_cast<svc::PixelFormat>(image.format);
  buffer.rows = static_cast<svc::RowOrder>(image.rows);
  for (size_t p = 0; p < 3; ++p) {
    if (image.planes[p] != nullptr) buffer.planes[p] = std::span<uint8_t>(image.planes[p], image.plane_sizes[p]);
    buffer.strides[p] = image.strides[p];
  }
  return buffer;
}

// A byte source over the embedder's read callbacks; releases them when destroyed.
class CallbackSource final : public svc::ByteSource {
 public:
  explicit CallbackSource(const svc_read_callbacks& callbacks)
      : callbacks_(callbacks), name_(callbacks.name != nullptr ? callbacks.name : "callbacks") {}
  ~CallbackSource() override {
    if (callbacks_.release != nullptr) callbacks_.release(callbacks_.user);
  }
  uint64_t size() const override { return callbacks_.size; }
  const std::string& name() const override { return name_; }
  Status read_at(uint64_t offset, std::span<uint8_t> out) const override {
    const int result = callbacks_.read(callbacks_.user, offset, out.data(), out.size());
    if (result == 0) return Status::Ok();
    return Status(ErrorCode::kIoError, "the read callback returned " + std::to_string(result));
  }

 private:
  svc_read_callbacks callbacks_;
  std::string name_;
};

// Opens a reader on the source `make` returns and fills *out; keeps the open error.
template <class MakeSource>
svc_status open_reader(const svc_reader_settings* settings, svc_reader** out, const char* call, MakeSource&& make) {
  clear_open_error();
  if (out == nullptr) {
    set_open_error(call, "out is NULL");
    return SVC_INVALID_ARGUMENT;
  }
  *out = nullptr;
  try {
    Status status;
    svc::Result<std::unique_ptr<svc::ByteSource>> source = make();
    if (!source.ok()) status = source.status();
    if (status.ok()) {
      auto reader = svc::Reader::open(std::move(*source), reader_settings(settings));
      if (!reader.ok()) status = reader.status();
      if (status.ok()) {
        auto handle = std::make_unique<svc_reader>();
        handle->reader = std::move(*reader);
        *out = handle.release();
        return SVC_OK;
      }
    }
    set_open_error(status.message());
    return status_code(status.code());
  } catch (const std::bad_alloc&) {
    set_open_error(call, "out of memory");
    return SVC_OUT_OF_MEMORY;
  } catch (...) {
    set_open_error(call, "unknown failure");
    return SVC_INTERNAL;
  }
}

void copy_counters(const svc::CacheCounters& in, svc_cache_counters* out) {
  *out = svc_cache_counters{in.hits,      in.misses,  in.in_flight_waits, in.prefetch_lookups, in.insertions,
                            in.evictions, in.entries, in.bytes_held,      in.peak_bytes,       in.budget_bytes};
}

// A caller's optional 3-vector; none is zero.
std::array<double, 3> vector3(const double v[3]) {
  return v != nullptr ? std::array<double, 3>{v[0], v[1], v[2]} : std::array<double, 3>{0, 0, 0};
}

bool finite3(const double v[3]) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

extern "C" {

uint32_t svc_abi_version(void) { return SVC_ABI_VERSION; }

const char* svc_version_string(void) { return SVC_VERSION; }

const char* svc_status_name(svc_status status) {
  switch (status) {
    case SVC_OK: return "ok";
    case SVC_INVALID_ARGUMENT: return "invalid argument";
    case SVC_NOT_FOUND: return "not found";
    case SVC_IO_ERROR: return "I/O error";
    case SVC_BAD_INPUT: return "bad input";
    case SVC_CORRUPT_DATA: return "corrupt data";
    case SVC_LIMIT_EXCEEDED: return "limit exceeded";
    case SVC_UNSUPPORTED: return "unsupported";
    case SVC_CANCELLED: return "cancelled";
    case SVC_INTERNAL: return "internal error";
    case SVC_OUT_OF_MEMORY: return "out of memory";
  }
  return "unknown";
}

size_t svc_pixel_row_bytes(svc_pixel_format format, int32_t width, int32_t plane) {
  return svc::pixel_row_bytes(static_cast<svc::PixelFormat>(format), width, plane);
}

size_t svc_pixel_plane_rows(svc_pixel_format format, int32_t height, int32_t plane) {
  return svc::pixel_plane_rows(static_cast<svc::PixelFormat>(format), height, plane);
}

void svc_reader_settings_default(svc_reader_settings* settings) {
  if (settings == nullptr) return;
  const svc::ReaderSettings d = svc::default_reader_settings();
  *settings = svc_reader_settings{d.coefficient_cache_bytes, d.face_cache_bytes, d.reference_cache_bytes,
                                  d.decode_threads,          d.prefetch_threads, d.prefetch_radius,
                                  d.depth_cache_bytes};
}

svc_status svc_reader_open_file(const char* path, const svc_reader_settings* settings, svc_reader** out) {
  return open_reader(settings, out, "svc_reader_open_file", [&]() -> svc::Result<std::unique_ptr<svc::ByteSource>> {
    if (path == nullptr) return invalid("svc_reader_open_file", "path");
    SVC_ASSIGN_OR_RETURN(const std::filesystem::path file, utf8_path(path));
    return svc::open_file_source(file);
  });
}

svc_status svc_reader_open_memory(const void* data, size_t size, const svc_reader_settings* settings,
                                  svc_reader** out) {
  return open_reader(settings, out, "svc_reader_open_memory",
                     [&]() -> svc::Result<std::unique_ptr<svc::ByteSource>> {
                       if (data == nullptr) return invalid("svc_reader_open_memory", "data");
                       return svc::memory_source(std::span<const uint8_t>(static_cast<const uint8_t*>(data), size));
                     });
}

svc_status svc_reader_open_callbacks(const svc_read_callbacks* callbacks, const svc_reader_settings* settings,
                                     svc_reader** out) {
  // The source takes the callbacks first, so that release runs on every failure.
  std::unique_ptr<svc::ByteSource> taken;
  if (callbacks != nullptr && callbacks->read != nullptr) {
    try {
      taken = std::make_unique<CallbackSource>(*callbacks);
    } catch (...) {
      if (callbacks->release != nullptr) callbacks->release(callbacks->user);
      set_open_error("svc_reader_open_callbacks", "out of memory");
      return SVC_OUT_OF_MEMORY;
    }
  } else if (callbacks != nullptr && callbacks->release != nullptr) {
    callbacks->release(callbacks->user);
  }
  return open_reader(settings, out, "svc_reader_open_callbacks",
                     [&]() -> svc::Result<std::unique_ptr<svc::ByteSource>> {
                       if (callbacks == nullptr) return invalid("svc_reader_open_callbacks", "callbacks");
                       if (taken == nullptr) return invalid("svc_reader_open_callbacks", "callbacks->read");
                       return std::move(taken);
                     });
}

const char* svc_last_open_error(void) {
  try {
    const OpenError& error = svc::codec::thread_object<OpenError>();
    return error.lost ? kOpenErrorLost : error.message.c_str();
  } catch (...) {
    return kOpenErrorLost;
  }
}

void svc_reader_destroy(svc_reader* reader) { delete reader; }

void svc_reader_close(svc_reader* reader) {
  if (reader != nullptr) reader->reader->close();
}

const char* svc_reader_last_error(const svc_reader* reader) {
  if (reader == nullptr) return "svc_reader_last_error: reader is NULL";
  std::lock_guard<std::mutex> lock(reader->errors_mutex);
  const auto found = reader->errors.find(std::this_thread::get_id());
  return found == reader->errors.end() ? "" : found->second.c_str();
}

svc_status svc_reader_info(const svc_reader* reader, svc_file_info* out) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_info", [&]() -> Status {
    if (out == nullptr) return invalid("svc_reader_info", "out");
    const svc::FileInfo& info = reader->reader->info();
    svc_file_info result{};
    result.format_major = info.format_major;
    result.format_minor = info.format_minor;
    result.file_bytes = info.file_bytes;
    result.face_width = info.face_width;
    result.face_height = info.face_height;
    for (size_t a = 0; a < 3; ++a) {
      result.grid_dims[a] = info.grid_dims[a];
      result.grid_origin[a] = info.grid_origin[a];
      result.grid_spacing[a] = info.grid_spacing[a];
      result.i_spacing[a] = info.i_spacing[a];
    }
    result.quality = info.quality;
    result.qindex = info.qindex;
    result.up_axis = info.up_axis;
    result.cell_count = reader->reader->cells().size();
    result.has_depth = info.has_depth ? 1 : 0;
    result.depth_max_error = info.depth_max_error;
    result.depth_bytes = info.depth_bytes;
    *out = result;
    return Status::Ok();
  });
}

svc_status svc_reader_cell(const svc_reader* reader, size_t ordinal, svc_cell* out) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_cell", [&]() -> Status {
    if (out == nullptr) return invalid("svc_reader_cell", "out");
    const auto& cells = reader->reader->cells();
    if (ordinal >= cells.size()) {
      return Status(ErrorCode::kInvalidArgument, "svc_reader_cell: ordinal " + std::to_string(ordinal) +
                                                     " outside 0.." + std::to_string(cells.size()) +
                                                     " (exclusive)");
    }
    const svc::CellEntry& cell = cells[ordinal];
    svc_cell result{};
    result.index[0] = cell.index.x;
    result.index[1] = cell.index.y;
    result.index[2] = cell.index.z;
    std::copy(cell.position.begin(), cell.position.end(), result.position);
    for (size_t f = 0; f < svc::kFaceCount; ++f) {
      const svc::Camera& camera = cell.cameras[f];
      svc_camera& c = result.cameras[f];
      std::copy(camera.world_to_camera.begin(), camera.world_to_camera.end(), c.world_to_camera);
      c.left = camera.frustum.left;
      c.right = camera.frustum.right;
      c.bottom = camera.frustum.bottom;
      c.top = camera.frustum.top;
      c.near_plane = camera.frustum.near_plane;
      c.far_plane = camera.frustum.far_plane;
      result.face_types[f] = static_cast<uint8_t>(cell.faces[f].type);
      result.face_bytes[f] = cell.faces[f].coded_bytes;
    }
    *out = result;
    return Status::Ok();
  });
}

svc_status svc_reader_find_cell(const svc_reader* reader, const int32_t cell[3], size_t* ordinal) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_find_cell", [&]() -> Status {
    if (cell == nullptr) return invalid("svc_reader_find_cell", "cell");
    if (ordinal == nullptr) return invalid("svc_reader_find_cell", "ordinal");
    const std::optional<size_t> found = reader->reader->find_cell(cell_index(cell));
    if (!found) return Status(ErrorCode::kNotFound, "no " + svc::cell_label(cell_index(cell)) + " in the file");
    *ordinal = *found;
    return Status::Ok();
  });
}

svc_status svc_reader_find_cell_at(const svc_reader* reader, const double position[3], size_t* ordinal) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_find_cell_at", [&]() -> Status {
    if (position == nullptr) return invalid("svc_reader_find_cell_at", "position");
    if (ordinal == nullptr) return invalid("svc_reader_find_cell_at", "ordinal");
    if (!finite3(position))
      return Status(ErrorCode::kInvalidArgument, "svc_reader_find_cell_at: position is not finite");
    const std::optional<size_t> found = reader->reader->find_cell_at(vector3(position));
    if (!found) return Status(ErrorCode::kNotFound, "no cell of the file contains the position");
    *ordinal = *found;
    return Status::Ok();
  });
}

svc_status svc_reader_decode_face(svc_reader* reader, const int32_t cell[3], svc_face face, const svc_image* out) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_decode_face", [&]() -> Status {
    if (cell == nullptr) return invalid("svc_reader_decode_face", "cell");
    if (out == nullptr) return invalid("svc_reader_decode_face", "out");
    if (static_cast<int>(face) < 0 || static_cast<int>(face) >= svc::kFaceCount) {
      return Status(ErrorCode::kInvalidArgument,
                    "svc_reader_decode_face: face " + std::to_string(static_cast<int>(face)) + " outside 0..5");
    }
    return reader->reader->decode_face_into(cell_index(cell), static_cast<svc::Face>(face), pixel_buffer(*out));
  });
}

svc_status svc_reader_decode_face_depth(svc_reader* reader, const int32_t cell[3], svc_face face,
                                        const svc_depth_image* out) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_decode_face_depth", [&]() -> Status {
    if (cell == nullptr) return invalid("svc_reader_decode_face_depth", "cell");
    if (out == nullptr) return invalid("svc_reader_decode_face_depth", "out");
    if (static_cast<int>(face) < 0 || static_cast<int>(face) >= svc::kFaceCount) {
      return Status(ErrorCode::kInvalidArgument, "svc_reader_decode_face_depth: face " +
                                                     std::to_string(static_cast<int>(face)) + " outside 0..5");
    }
    svc::DepthBuffer buffer;
    buffer.format = static_cast<svc::DepthFormat>(out->format);
    buffer.rows = static_cast<svc::RowOrder>(out->rows);
    buffer.data = out->data;
    buffer.stride = out->stride;
    buffer.size = out->size;
    return reader->reader->decode_face_depth_into(cell_index(cell), static_cast<svc::Face>(face), buffer);
  });
}

svc_status svc_reader_decode_cube(svc_reader* reader, const int32_t cell[3], const svc_image out[6]) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_decode_cube", [&]() -> Status {
    if (cell == nullptr) return invalid("svc_reader_decode_cube", "cell");
    if (out == nullptr) return invalid("svc_reader_decode_cube", "out");
    std::array<svc::PixelBuffer, svc::kFaceCount> buffers;
    for (size_t f = 0; f < svc::kFaceCount; ++f) buffers[f] = pixel_buffer(out[f]);
    return reader->reader->decode_cube_into(cell_index(cell), buffers);
  });
}

svc_status svc_reader_set_viewer_cell(svc_reader* reader, const int32_t cell[3], const double velocity[3]) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_set_viewer_cell", [&]() -> Status {
    if (cell == nullptr) return invalid("svc_reader_set_viewer_cell", "cell");
    return reader->reader->set_viewer(cell_index(cell), vector3(velocity));
  });
}

svc_status svc_reader_set_viewer_position(svc_reader* reader, const double position[3], const double velocity[3]) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_set_viewer_position", [&]() -> Status {
    if (position == nullptr) return invalid("svc_reader_set_viewer_position", "position");
    return reader->reader->set_viewer(vector3(position), vector3(velocity));
  });
}

int svc_reader_wait_for_prefetch(svc_reader* reader, uint32_t timeout_ms) {
  if (reader == nullptr) return 1;
  try {
    return reader->reader->wait_for_prefetch(std::chrono::milliseconds(timeout_ms)) ? 1 : 0;
  } catch (...) {
    return 0;
  }
}

svc_status svc_reader_get_stats(const svc_reader* reader, svc_reader_stats* out) {
  if (reader == nullptr) return SVC_INVALID_ARGUMENT;
  return guarded(reader, "svc_reader_get_stats", [&]() -> Status {
    if (out == nullptr) return invalid("svc_reader_get_stats", "out");
    const svc::ReaderStats s = reader->reader->stats();
    svc_reader_stats result{};
    copy_counters(s.coefficient_cache, &result.coefficient_cache);
    copy_counters(s.face_cache, &result.face_cache);
    copy_counters(s.reference_cache, &result.reference_cache);
    result.bytes_read = s.bytes_read;
    result.chunks_read = s.chunks_read;
    result.intra_faces_parsed = s.intra_faces_parsed;
    result.predicted_faces_decoded = s.predicted_faces_decoded;
    result.prefetch_faces = s.prefetch_faces;
    result.prefetch_dropped = s.prefetch_dropped;
    result.thread_buffer_bytes = s.thread_buffer_bytes;
    copy_counters(s.depth_cache, &result.depth_cache);
    *out = result;
    return Status::Ok();
  });
}

}  // extern "C"
