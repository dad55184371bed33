// SPDX-License-Identifier: BSD-2-Clause
// Decoding one face of an opened container with its references: the single path shared
// by the reader (cached and uncached), svc add (old references), svc inspect and the
// fuzz targets. Where the bytes and the reference pixels come from is up to a
// CodedFaceSource, so the reader can put its caches in between.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "codec/common/bframe.h"
#include "codec/decoder/bframe_decoder.h"
#include "common/file_io.h"
#include "container/container.h"
#include "svc/status.h"
#include "svc/types.h"

namespace svc {

using FacePointer = std::shared_ptr<const ImageYCbCr420>;

// "cell (x,y,z) face px" for frame `frame` of `index`.
std::string frame_label(const ContainerIndex& index, uint32_t frame);

// `status` with the file, face and chunk offset of frame `frame` as context.
Status frame_error(const Status& status, const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame);

// The bytes and reference pixels a face decode needs.
class CodedFaceSource {
 public:
  virtual ~CodedFaceSource() = default;
  // The coded payload of `frame` (chunk tag, size and CRC checked).
  virtual Result<std::vector<uint8_t>> payload(uint32_t frame) = 0;
  // The decoded pixels of I-face `frame`.
  virtual Result<FacePointer> intra_face(uint32_t frame) = 0;
  // I-face `frame` padded with `units` of cube border from the adjacent faces of its cube
  // across the border edges `edges` (codec::FaceEdge bits; docs/codec.md 5.7), those
  // faces from intra_face(); the border across the other edges is left 0. The caller has
  // checked that those faces are I-faces. A source with a cache overrides this to keep
  // the result: B-faces predicting from this face of the cube need the same padded face.
  virtual Result<FacePointer> padded_intra_face(uint32_t frame, int units, uint8_t edges);
};

// Reads every chunk from the file and keeps nothing.
class FileCodedFaceSource : public CodedFaceSource {
 public:
  FileCodedFaceSource(const ReadOnlyFile& file, const ContainerIndex& index) : file_(file), index_(index) {}
  Result<std::vector<uint8_t>> payload(uint32_t frame) override;
  Result<FacePointer> intra_face(uint32_t frame) override;

 protected:
  const ReadOnlyFile& file_;
  const ContainerIndex& index_;
};

// Decodes frame `frame` of `index`: an I-face through source.intra_face, a B-face from
// its payload and its reference I-faces. `modes` (optional) receives a B-face's
// macroblock modes, `partitions` their partitions and `warped` which are warped (each
// left empty for an I-face). Errors name the file, face and chunk offset, and for a
// failed reference, the face that needed it.
Result<FacePointer> decode_indexed_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                        CodedFaceSource& source,
                                        std::vector<codec::MacroblockMode>* modes = nullptr,
                                        std::vector<codec::Partition>* partitions = nullptr,
                                        std::vector<uint8_t>* warped = nullptr);

// The same, reading straight from the file.
Result<FacePointer> decode_indexed_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                        std::vector<codec::MacroblockMode>* modes = nullptr);

}  // namespace svc
