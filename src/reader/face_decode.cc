#include "reader/face_decode.h"

#include <array>

#include "codec/intra_codec.h"

namespace svc {

std::string frame_label(const ContainerIndex& index, uint32_t frame) {
  const FrameRecord& record = index.frames[frame];
  return face_label(index.cells[record.cell].index, record.face);
}

Status frame_error(const Status& status, const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame) {
  return status.with_context(file.path().string() + ": " + frame_label(index, frame) + " (chunk at byte offset " +
                             std::to_string(index.frames[frame].chunk_offset) + ")");
}

Result<std::vector<uint8_t>> FileCodedFaceSource::payload(uint32_t frame) {
  return read_frame_payload(file_, index_.frames[frame], frame_label(index_, frame));
}

Result<FacePointer> FileCodedFaceSource::intra_face(uint32_t frame) {
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, payload(frame));
  auto image = std::make_shared<ImageYCbCr420>();
  const Status status = codec::decode_intra_frame(bytes, static_cast<int>(index_.face_width),
                                                  static_cast<int>(index_.face_height), image.get());
  if (!status.ok()) return frame_error(status, file_, index_, frame);
  return FacePointer(std::move(image));
}

Result<FacePointer> decode_indexed_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                        CodedFaceSource& source, std::vector<codec::MacroblockMode>* modes) {
  const FrameRecord& record = index.frames[frame];
  if (modes) modes->clear();
  if (record.type == FaceType::kIntra) return source.intra_face(frame);
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, source.payload(frame));
  std::array<FacePointer, 2> refs;
  for (size_t r = 0; r < record.references.size() && r < refs.size(); ++r) {
    // parse_index admits only I-faces as references: one level at most.
    const uint32_t ref = record.references[r];
    Result<FacePointer> image =
        index.frames[ref].type == FaceType::kIntra
            ? source.intra_face(ref)
            : Result<FacePointer>(
                  frame_error(Status(ErrorCode::kCorruptData, "reference is not an I-face"), file, index, ref));
    if (!image.ok())
      return image.status().with_context(frame_label(index, frame) + " cannot be decoded: its reference");
    refs[r] = std::move(image).value();
  }
  if (!refs[0])
    return frame_error(Status(ErrorCode::kCorruptData, "B-face without references"), file, index, frame);
  auto image = std::make_shared<ImageYCbCr420>();
  const Status status = codec::decode_b_frame(payload, static_cast<int>(index.face_width),
                                              static_cast<int>(index.face_height), *refs[0], refs[1].get(),
                                              image.get(), modes);
  if (!status.ok()) return frame_error(status, file, index, frame);
  return FacePointer(std::move(image));
}

Result<FacePointer> decode_indexed_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                        std::vector<codec::MacroblockMode>* modes) {
  FileCodedFaceSource source(file, index);
  return decode_indexed_face(file, index, frame, source, modes);
}

}  // namespace svc
