// SPDX-License-Identifier: BSD-2-Clause
// Decoding one face's depth plane of an opened container: the single path shared by the
// reader, the encoder (reference depth of B-faces) and the fuzz targets. Where the bytes,
// the reference planes and the cameras come from is up to a CodedDepthSource.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "codec/common/depth.h"
#include "common/file_io.h"
#include "container/container.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

// A face's inverse-depth codes (codec/common/depth.h), width * height, row 0 at the top.
using DepthPointer = std::shared_ptr<const std::vector<uint16_t>>;

// The bytes, reference planes and cameras a depth decode needs.
class CodedDepthSource {
 public:
  // Both must outlive the source.
  CodedDepthSource(const ReadOnlyFile& file, const ContainerIndex& index) : file_(file), index_(index) {}
  virtual ~CodedDepthSource() = default;
  // The depth payload of `frame` (CRC checked).
  virtual Result<std::vector<uint8_t>> depth_payload(uint32_t frame) = 0;
  // The decoded depth of I-face `frame`: decode_indexed_depth, uncached, unless a
  // source with a cache overrides it.
  virtual Result<DepthPointer> intra_depth(uint32_t frame);
  // The camera of `frame`'s face.
  virtual Result<Camera> camera(uint32_t frame) = 0;

 protected:
  const ReadOnlyFile& file_;
  const ContainerIndex& index_;
};

// Reads every depth chunk from the file and keeps nothing; cameras from index.cameras
// (an index as open_container returns it).
class FileCodedDepthSource : public CodedDepthSource {
 public:
  using CodedDepthSource::CodedDepthSource;
  Result<std::vector<uint8_t>> depth_payload(uint32_t frame) override;
  Result<Camera> camera(uint32_t frame) override;
};

// The depth planes a B-face's depth is predicted from (depth_dependencies, through
// source.intra_depth) with their cameras; `references` points into the other two, so
// the whole is moved, never copied, while a predict_depth reads it.
struct ReferenceDepths {
  ReferenceDepths() = default;
  ReferenceDepths(ReferenceDepths&&) = default;
  ReferenceDepths& operator=(ReferenceDepths&&) = default;
  ReferenceDepths(const ReferenceDepths&) = delete;
  ReferenceDepths& operator=(const ReferenceDepths&) = delete;

  std::vector<DepthPointer> planes;
  std::vector<Camera> cameras;
  std::vector<codec::DepthReference> references;
};
// Errors name the face that needed a failed reference.
Result<ReferenceDepths> reference_depths(const ContainerIndex& index, uint32_t frame, CodedDepthSource& source);

// Decodes the depth of frame `frame` of `index` (which must have depth): an I-face's on
// its own, a B-face's from the depth of depth_dependencies(frame) through
// source.intra_depth. Errors name the file, face and the depth chunk's offset, and for a
// failed reference, the face that needed it.
Result<DepthPointer> decode_indexed_depth(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                          CodedDepthSource& source);

}  // namespace svc
