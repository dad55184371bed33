// SPDX-License-Identifier: BSD-2-Clause
// Where a reader's bytes come from: a file, a block of memory, or the embedder's own file
// access (a package, a memory-mapped archive, a virtual file system, a network cache).
// Reader::open takes any of them; the reader reads only the header, the index and the
// chunks of the faces it decodes, each with one positioned read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "svc/export.h"
#include "svc/status.h"

namespace svc {

// Implement it to read from anywhere. The reader calls read_at from several threads at
// once (the callers of its decode calls and its prefetch workers), so an implementation
// must be thread-safe; size() and name() must not change while a reader uses it.
class SVC_API ByteSource {
 public:
  virtual ~ByteSource();
  // The total number of bytes.
  virtual uint64_t size() const = 0;
  // Fills `out` with the bytes at [offset, offset + out.size()); the reader asks only for
  // ranges within size(). A failure is any non-ok Status (kIoError for a failed read);
  // the reader returns it with the face and offset that needed the bytes.
  virtual Status read_at(uint64_t offset, std::span<uint8_t> out) const = 0;
  // Names the source in error messages: a path, or what the embedder calls it.
  virtual const std::string& name() const = 0;
};

// The file at `path`, read with positioned reads of the platform (thread-safe; the file
// stays open until the source is destroyed). kNotFound when the file does not exist,
// kIoError when it cannot be opened or is not a regular file.
SVC_API Result<std::unique_ptr<ByteSource>> open_file_source(const std::filesystem::path& path);

// The `bytes` of a block of memory, not copied: the caller keeps them alive and unchanged
// while the source, and any reader given it, lives. Thread-safe.
SVC_API std::unique_ptr<ByteSource> memory_source(std::span<const uint8_t> bytes, std::string name = "memory");

}  // namespace svc
