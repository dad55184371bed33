// SPDX-License-Identifier: BSD-2-Clause
// The byte sources every platform has: a block of memory.
#include <algorithm>

#include "svc/byte_source.h"

namespace svc {

ByteSource::~ByteSource() = default;

namespace {

class MemorySource final : public ByteSource {
 public:
  MemorySource(std::span<const uint8_t> bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}
  uint64_t size() const override { return bytes_.size(); }
  Status read_at(uint64_t offset, std::span<uint8_t> out) const override {
    if (offset > bytes_.size() || out.size() > bytes_.size() - offset) {
      return Status(ErrorCode::kIoError, "read past the end of the memory block");
    }
    std::copy_n(bytes_.data() + offset, out.size(), out.data());
    return Status::Ok();
  }
  const std::string& name() const override { return name_; }

 private:
  std::span<const uint8_t> bytes_;
  std::string name_;
};

}  // namespace

std::unique_ptr<ByteSource> memory_source(std::span<const uint8_t> bytes, std::string name) {
  return std::make_unique<MemorySource>(bytes, std::move(name));
}

}  // namespace svc
