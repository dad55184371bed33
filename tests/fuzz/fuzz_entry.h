// SPDX-License-Identifier: BSD-2-Clause
// Entry points shared by the libFuzzer targets (tests/fuzz/*_fuzzer.cc, built with
// clang) and the corpus replay test (tests/svc_fuzz_corpus_test.cc, built with the
// default compiler), so the test suite runs every seed through exactly the code the
// fuzzers exercise.
//
// Each entry takes arbitrary bytes and must return normally whatever they hold: a
// crash, sanitizer report, hang or unbounded allocation is a bug in the library.
// Header-only so that the test programs can use it without a library of their own.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include "codec/common/bframe.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/bframe_decoder.h"
#include "codec/decoder/depth_decoder.h"
#include "codec/decoder/intra_decoder.h"
#include "common/bytes.h"
#include "common/file_io.h"
#include "container/container.h"
#include "reader/depth_decode.h"
#include "reader/face_decode.h"
#include "svc/limits.h"
#include "svc/types.h"

namespace svc::fuzz {

// Caps far below the defaults: a fuzzer must not spend its time on legitimately huge
// (but valid) sizes. The caps themselves are what the reader enforces, so lowering them
// tests the same checks.
inline ReaderLimits fuzz_limits() {
  ReaderLimits limits;
  limits.max_face_dimension = 256;
  limits.max_face_pixels = 64 * 64 * 4;
  limits.max_cells = 64;
  limits.max_index_bytes = 1 << 20;
  limits.max_frame_bytes = 1 << 20;
  limits.max_grid_dimension = 1 << 10;
  return limits;
}

// Holds `data` in an anonymous memory file so the real file path of the reader (pread
// through ReadOnlyFile) is what gets exercised.
class MemoryFile {
 public:
  explicit MemoryFile(std::span<const uint8_t> data) {
    fd_ = static_cast<int>(::memfd_create("svc-fuzz", MFD_CLOEXEC));
    if (fd_ < 0) return;
    size_t done = 0;
    while (done < data.size()) {
      const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
      if (n <= 0) return;
      done += static_cast<size_t>(n);
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~MemoryFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  // Empty when the memory file could not be made.
  const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

// Rewrites every CRC-32 a mutated file would fail: the header's, each non-empty commit
// slot's, those of the framed chunks found by walking from the end of the prelude while
// their tags are known (older files' FACE chunks), of the index chunk each slot points
// at, and of the bare face chunks that index lists. Lets mutations reach the index and
// face parsers instead of stopping at a CRC. Returns whether anything changed.
inline bool repair_checksums(std::vector<uint8_t>& bytes) {
  auto put_u32 = [&](uint64_t at, uint32_t v) {
    bool changed = false;
    for (int i = 0; i < 4; ++i) {
      const uint8_t b = static_cast<uint8_t>(v >> (8 * i));
      changed |= bytes[at + i] != b;
      bytes[at + i] = b;
    }
    return changed;
  };
  auto get = [&](uint64_t at, int size) {
    uint64_t v = 0;
    for (int i = 0; i < size; ++i) v |= uint64_t{bytes[at + i]} << (8 * i);
    return v;
  };
  auto crc_of = [&](uint64_t from, uint64_t size) {
    return crc32_of(std::span<const uint8_t>(bytes.data() + from, size));
  };
  // The framed chunk at `at`, if it fits: its CRC repaired, its end returned.
  auto repair_framed = [&](uint64_t at, bool* changed) -> std::optional<uint64_t> {
    if (bytes.size() - at < kChunkOverhead) return std::nullopt;
    const uint64_t tag = get(at, 4), payload = get(at + 4, 8);
    if ((tag != kFaceChunkTag && tag != kIndexChunkTag) || payload > bytes.size() - at - kChunkOverhead) {
      return std::nullopt;
    }
    const uint64_t crc_at = at + 12 + payload;
    *changed |= put_u32(crc_at, crc_of(at, crc_at - at));
    return crc_at + 4;
  };
  if (bytes.size() < kPreludeSize) return false;
  bool changed = put_u32(kFileHeaderSize - 4, crc_of(0, kFileHeaderSize - 4));
  for (int slot = 0; slot < 2; ++slot) {
    const uint64_t at = kFileHeaderSize + slot * kCommitSlotSize;
    bool empty = true;
    for (uint64_t i = 0; i < kCommitSlotSize; ++i) empty &= bytes[at + i] == 0;
    if (!empty) changed |= put_u32(at + kCommitSlotSize - 4, crc_of(at, kCommitSlotSize - 4));
  }
  for (std::optional<uint64_t> at = kPreludeSize; at; at = repair_framed(*at, &changed)) {
  }
  for (int slot = 0; slot < 2; ++slot) {
    const uint64_t at = kFileHeaderSize + slot * kCommitSlotSize;
    const uint64_t index_at = get(at + 8, 8);
    if (index_at < kPreludeSize || index_at > bytes.size() || !repair_framed(index_at, &changed)) continue;
    const auto payload = std::span<const uint8_t>(bytes).subspan(index_at + 12, get(index_at + 4, 8));
    const auto index = parse_index(payload, index_at + 12, bytes.size(), fuzz_limits());
    if (!index.ok()) continue;
    for (const FrameRecord& frame : index->frames) {
      if (frame.bare_chunk) {
        changed |= put_u32(frame.chunk_offset + frame.payload_size, crc_of(frame.chunk_offset, frame.payload_size));
      }
      if (frame.depth_size != 0) {
        const uint64_t depth_at = frame.chunk_offset + color_chunk_bytes(frame);
        changed |= put_u32(depth_at + frame.depth_size, crc_of(depth_at, frame.depth_size));
      }
    }
  }
  return changed;
}

// Opens `data` as an .svc file and decodes every face (and its depth, in a file with
// depth); returns how many decoded whole.
inline int open_and_decode_all(std::span<const uint8_t> data) {
  MemoryFile memory(data);
  if (memory.path().empty()) return 0;
  auto file = ReadOnlyFile::open(memory.path());
  if (!file.ok()) return 0;
  auto opened = open_container(**file, fuzz_limits());
  if (!opened.ok()) return 0;
  const ContainerIndex& index = opened->index;
  int decoded = 0;
  for (uint32_t frame = 0; frame < index.frames.size(); ++frame) {
    auto face = decode_indexed_face(**file, index, frame);
    // A decoded face must have the size the index promised.
    if (face.ok() && ((**face).width != static_cast<int>(index.face_width) ||
                      (**face).height != static_cast<int>(index.face_height))) {
      std::fprintf(stderr, "decoded face has the wrong size\n");
      std::abort();
    }
    bool depth_ok = true;
    if (index.depth) {
      FileCodedDepthSource depth_source(**file, index);
      auto depth = decode_indexed_depth(**file, index, frame, depth_source);
      if (depth.ok() && (*depth)->size() != size_t{index.face_width} * index.face_height) {
        std::fprintf(stderr, "decoded depth has the wrong size\n");
        std::abort();
      }
      depth_ok = depth.ok();
    }
    decoded += face.ok() && depth_ok;
  }
  return decoded;
}

// Fuzz target 1: the bytes are an .svc file. Opens it (header, commit slots, index) and
// decodes every face, as given and again with its checksums repaired (repair_checksums).
// Returns the number of faces that decoded as given (for the replay test).
inline int run_container_input(std::span<const uint8_t> data) {
  const int decoded = open_and_decode_all(data);
  std::vector<uint8_t> repaired(data.begin(), data.end());
  if (repair_checksums(repaired)) open_and_decode_all(repaired);
  return decoded;
}

// A deterministic, textured reference face (what a decoded I-face might hold).
inline ImageYCbCr420 synthetic_reference(int width, int height, int seed) {
  ImageYCbCr420 image;
  image.width = width;
  image.height = height;
  const int cw = (width + 1) / 2, ch = (height + 1) / 2;
  image.y.resize(static_cast<size_t>(width) * height);
  image.cb.resize(static_cast<size_t>(cw) * ch);
  image.cr.resize(static_cast<size_t>(cw) * ch);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.y[static_cast<size_t>(y) * width + x] = static_cast<uint8_t>((x * 7 + y * 3 + seed * 40) ^ (x * y));
    }
  }
  for (size_t i = 0; i < image.cb.size(); ++i) {
    image.cb[i] = static_cast<uint8_t>(128 + (static_cast<int>(i) * 5 + seed) % 60 - 30);
    image.cr[i] = static_cast<uint8_t>(128 - (static_cast<int>(i) * 3 + seed) % 50 + 25);
  }
  return image;
}

// Frame inputs: 3 selector bytes, then the frame payload.
//   byte 0: kind: 0 intra, 1 B-face with one reference, 2 B-face with two, 3 depth plane
//           (intra or inter, from two synthetic reference planes)
//   byte 1, 2: width and height, 1 + value % 64
inline constexpr size_t kFrameInputHeader = 3;

inline std::vector<uint8_t> make_frame_input(uint8_t kind, int width, int height,
                                             std::span<const uint8_t> payload) {
  std::vector<uint8_t> input = {kind, static_cast<uint8_t>(width - 1), static_cast<uint8_t>(height - 1)};
  input.insert(input.end(), payload.begin(), payload.end());
  return input;
}

// A deterministic depth plane (codec/common/depth.h codes): a tilted plane with a
// background corner, as a decoded I-face's depth might be.
inline std::vector<uint16_t> synthetic_depth(int width, int height, int seed) {
  std::vector<uint16_t> codes(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool background = x + y < width / 4;
      codes[static_cast<size_t>(y) * width + x] =
          background ? uint16_t{0} : static_cast<uint16_t>(3000 + 40 * x + 25 * y + 300 * seed);
    }
  }
  return codes;
}

// The cameras synthetic depth planes are seen from: looking along -z, 90 degrees, at
// x = 0.1 * seed.
inline Camera synthetic_depth_camera(int seed) {
  Camera camera;
  camera.world_to_camera[12] = -0.1 * seed;
  camera.frustum = {-0.1, 0.1, -0.1, 0.1, 0.1, 100};
  return camera;
}

// Decodes a depth payload against two synthetic reference planes. True when it decoded.
inline bool decode_depth_input(std::span<const uint8_t> payload, int width, int height) {
  const std::vector<uint16_t> plane0 = synthetic_depth(width, height, 0),
                              plane1 = synthetic_depth(width, height, 1);
  const Camera camera0 = synthetic_depth_camera(0), camera1 = synthetic_depth_camera(1),
               target = synthetic_depth_camera(2);
  const codec::DepthReference references[] = {{plane0.data(), &camera0}, {plane1.data(), &camera1}};
  std::vector<uint16_t> codes(static_cast<size_t>(width) * height);
  return codec::decode_depth(payload, width, height, references, target, codes.data()).ok();
}

// Fuzz target 2: one coded frame of a small fixed size, intra or B with synthetic
// references. Returns 1 when it decoded.
inline int run_frame_input(std::span<const uint8_t> data) {
  if (data.size() < kFrameInputHeader) return 0;
  const int kind = data[0] % 4;
  const int width = 1 + data[1] % 64;
  const int height = 1 + data[2] % 64;
  const std::span<const uint8_t> payload = data.subspan(kFrameInputHeader);
  if (kind == 3) return decode_depth_input(payload, width, height) ? 1 : 0;
  ImageYCbCr420 out;
  bool ok;
  if (kind == 0) {
    codec::CoefficientFrame coefficients;
    ok = codec::parse_intra_frame(payload, width, height, &coefficients).ok();
    if (ok) codec::reconstruct_intra_frame(coefficients, &out);
  } else {
    codec::BFrameHeader header;
    (void)codec::parse_b_frame_header(payload, &header);
    const ImageYCbCr420 ref0 = synthetic_reference(width, height, 0);
    const ImageYCbCr420 ref1 = synthetic_reference(width, height, 1);
    std::vector<codec::MacroblockMode> modes;
    ok = codec::decode_b_frame(payload, width, height, ref0, kind == 2 ? &ref1 : nullptr, &out, &modes).ok();
  }
  if (ok && (out.width != width || out.height != height || out.y.size() != static_cast<size_t>(width) * height)) {
    std::fprintf(stderr, "decoded frame has the wrong size\n");
    std::abort();
  }
  return ok ? 1 : 0;
}

}  // namespace svc::fuzz
