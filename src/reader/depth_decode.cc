// SPDX-License-Identifier: BSD-2-Clause
#include "reader/depth_decode.h"

#include <utility>

#include "codec/decoder/depth_decoder.h"
#include "reader/face_decode.h"

namespace svc {

namespace {

Status depth_error(const Status& status, const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame) {
  const FrameRecord& record = index.frames[frame];
  return status.with_context(file.name() + ": " + frame_label(index, frame) + " depth (chunk at byte offset " +
                             std::to_string(record.chunk_offset + color_chunk_bytes(record)) + ")");
}

}  // namespace

Result<std::vector<uint8_t>> FileCodedDepthSource::depth_payload(uint32_t frame) {
  return read_frame_depth(file_, index_.frames[frame], frame_label(index_, frame));
}

Result<Camera> FileCodedDepthSource::camera(uint32_t frame) {
  const size_t cell = frame / kFaceCount;
  if (cell >= index_.cameras.size()) return Status(ErrorCode::kInternal, "the index holds no cameras");
  return index_.cameras[cell][frame % kFaceCount];
}

Result<DepthPointer> CodedDepthSource::intra_depth(uint32_t frame) {
  return decode_indexed_depth(file_, index_, frame, *this);
}

Result<ReferenceDepths> reference_depths(const ContainerIndex& index, uint32_t frame, CodedDepthSource& source) {
  ReferenceDepths out;
  for (uint32_t dependency : depth_dependencies(index.frames[frame])) {
    Result<DepthPointer> plane = source.intra_depth(dependency);
    if (!plane.ok()) {
      return plane.status().with_context(frame_label(index, frame) + " depth needs " +
                                         frame_label(index, dependency));
    }
    SVC_ASSIGN_OR_RETURN(Camera camera, source.camera(dependency));
    out.planes.push_back(*std::move(plane));
    out.cameras.push_back(camera);
  }
  for (size_t i = 0; i < out.planes.size(); ++i) out.references.push_back({out.planes[i]->data(), &out.cameras[i]});
  return out;
}

Result<DepthPointer> decode_indexed_depth(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                          CodedDepthSource& source) {
  SVC_ASSIGN_OR_RETURN(const std::vector<uint8_t> payload, source.depth_payload(frame));
  const int width = static_cast<int>(index.face_width), height = static_cast<int>(index.face_height);
  SVC_ASSIGN_OR_RETURN(const Camera camera, source.camera(frame));
  ReferenceDepths references;
  if (codec::depth_payload_is_inter(payload)) {
    SVC_ASSIGN_OR_RETURN(references, reference_depths(index, frame, source));
  }
  auto codes = std::make_shared<std::vector<uint16_t>>(static_cast<size_t>(width) * height);
  const Status status = codec::decode_depth(payload, width, height, references.references, camera, codes->data());
  if (!status.ok()) return depth_error(status, file, index, frame);
  return DepthPointer(std::move(codes));
}

}  // namespace svc
