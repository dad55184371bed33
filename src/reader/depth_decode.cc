// SPDX-License-Identifier: BSD-2-Clause
#include "reader/depth_decode.h"

#include <array>

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

Result<DepthPointer> decode_indexed_depth(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                          CodedDepthSource& source) {
  const FrameRecord& record = index.frames[frame];
  SVC_ASSIGN_OR_RETURN(const std::vector<uint8_t> payload, source.depth_payload(frame));
  const int width = static_cast<int>(index.face_width), height = static_cast<int>(index.face_height);
  SVC_ASSIGN_OR_RETURN(const Camera camera, source.camera(frame));
  // The reference planes stay held while the decoder reads them.
  std::vector<DepthPointer> held;
  std::vector<Camera> cameras;
  const bool inter = codec::depth_payload_is_inter(payload);
  const std::vector<uint32_t> dependencies = inter ? depth_dependencies(record) : std::vector<uint32_t>{};
  cameras.reserve(dependencies.size());
  for (uint32_t dependency : dependencies) {
    Result<DepthPointer> plane = source.intra_depth(dependency);
    if (!plane.ok()) {
      return plane.status().with_context(frame_label(index, frame) + " depth needs " +
                                         frame_label(index, dependency));
    }
    SVC_ASSIGN_OR_RETURN(Camera dependency_camera, source.camera(dependency));
    held.push_back(*plane);
    cameras.push_back(dependency_camera);
  }
  std::vector<codec::DepthReference> references;
  for (size_t i = 0; i < held.size(); ++i) references.push_back({held[i]->data(), &cameras[i]});
  auto codes = std::make_shared<std::vector<uint16_t>>(static_cast<size_t>(width) * height);
  const Status status = codec::decode_depth(payload, width, height, references, camera, codes->data());
  if (!status.ok()) return depth_error(status, file, index, frame);
  return DepthPointer(std::move(codes));
}

}  // namespace svc
