// SPDX-License-Identifier: BSD-2-Clause
#include "reader/face_decode.h"

#include <array>

#include "codec/common/cube_padding.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/intra_decoder.h"

namespace svc {

std::string frame_label(const ContainerIndex& index, uint32_t frame) {
  const FrameRecord& record = index.frames[frame];
  return face_label(index.cells[record.cell].index, record.face);
}

Status frame_error(const Status& status, const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame) {
  return status.with_context(file.name() + ": " + frame_label(index, frame) + " (chunk at byte offset " +
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

Result<FacePointer> CodedFaceSource::padded_intra_face(uint32_t frame, int units, uint8_t edges) {
  const Face face = static_cast<Face>(frame % kFaceCount);
  const uint32_t cube_first = frame - frame % kFaceCount;
  std::array<FacePointer, kFaceCount> held;
  codec::CubeFaces cube{};
  SVC_ASSIGN_OR_RETURN(held[static_cast<int>(face)], intra_face(frame));
  for (Face g : codec::adjacent_faces(face)) {
    if (!codec::border_edges_show(face, edges, g)) continue;
    SVC_ASSIGN_OR_RETURN(held[static_cast<int>(g)], intra_face(cube_first + static_cast<uint32_t>(g)));
  }
  for (int k = 0; k < kFaceCount; ++k) cube[k] = held[k].get();
  auto padded = std::make_shared<ImageYCbCr420>();
  const Status status = codec::pad_cube_face(cube, face, units, padded.get());
  if (!status.ok()) return Status(ErrorCode::kCorruptData, status.message());
  return FacePointer(std::move(padded));
}

namespace {

// A reference I-face of B-face `frame`, with context naming the face that needed it.
Result<FacePointer> reference_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                   uint32_t ref, CodedFaceSource& source) {
  // parse_index admits only I-faces as dependencies: one level at most.
  Result<FacePointer> image =
      index.frames[ref].type == FaceType::kIntra
          ? source.intra_face(ref)
          : Result<FacePointer>(
                frame_error(Status(ErrorCode::kCorruptData, "reference is not an I-face"), file, index, ref));
  if (!image.ok())
    return image.status().with_context(frame_label(index, frame) + " cannot be decoded: its reference");
  return image;
}

// Reference `ref` of B-face `frame` padded with `units` of cube border across `edges`:
// the faces it is built from must be I-faces (docs/codec.md 5.7).
Result<FacePointer> padded_reference(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                     uint32_t ref, int units, uint8_t edges, CodedFaceSource& source) {
  const FrameRecord& record = index.frames[frame];
  if (!codec::cube_padding_possible(static_cast<int>(index.face_width), static_cast<int>(index.face_height))) {
    return frame_error(Status(ErrorCode::kCorruptData, "cube references need square faces"), file, index, frame);
  }
  const uint32_t cube_first = ref - ref % kFaceCount;
  std::vector<uint32_t> needed{ref};
  for (Face g : codec::adjacent_faces(record.face)) {
    if (codec::border_edges_show(record.face, edges, g)) needed.push_back(cube_first + static_cast<uint32_t>(g));
  }
  for (uint32_t face : needed) {
    if (index.frames[face].type == FaceType::kIntra) continue;
    return frame_error(Status(ErrorCode::kCorruptData, "reference is not an I-face"), file, index, face)
        .with_context(frame_label(index, frame) + " cannot be decoded: its reference");
  }
  Result<FacePointer> padded = source.padded_intra_face(ref, units, edges);
  if (!padded.ok()) {
    return padded.status().with_context(frame_label(index, frame) + " cannot be decoded: its reference");
  }
  return padded;
}

}  // namespace

Result<FacePointer> decode_indexed_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                        CodedFaceSource& source, std::vector<codec::MacroblockMode>* modes,
                                        std::vector<codec::Partition>* partitions, std::vector<uint8_t>* warped) {
  const FrameRecord& record = index.frames[frame];
  if (modes) modes->clear();
  if (partitions) partitions->clear();
  if (warped) warped->clear();
  if (record.type == FaceType::kIntra) return source.intra_face(frame);
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, source.payload(frame));
  codec::BFrameHeader header;
  if (const Status status = codec::parse_b_frame_header(payload, &header); !status.ok()) {
    return frame_error(status, file, index, frame);
  }
  if ((header.border_units > 0) != record.cube_references) {
    return frame_error(Status(ErrorCode::kCorruptData,
                              "payload has a reference border of " + std::to_string(header.border_units) +
                                  " units but the index " + (record.cube_references ? "lists" : "does not list") +
                                  " cube references"),
                       file, index, frame);
  }
  std::array<FacePointer, 2> refs;
  codec::BorderEdges edges;
  for (size_t r = 0; r < record.references.size() && r < refs.size(); ++r) {
    const uint32_t ref = record.references[r];
    edges.allowed[r] = reference_border_edges(record, r);
    SVC_ASSIGN_OR_RETURN(refs[r], record.cube_references
                                      ? padded_reference(file, index, frame, ref, header.border_units,
                                                         edges.allowed[r], source)
                                      : reference_face(file, index, frame, ref, source));
  }
  if (!refs[0])
    return frame_error(Status(ErrorCode::kCorruptData, "B-face without references"), file, index, frame);
  auto image = std::make_shared<ImageYCbCr420>();
  const Status status = codec::decode_b_frame(payload, static_cast<int>(index.face_width),
                                              static_cast<int>(index.face_height), *refs[0], refs[1].get(),
                                              image.get(), modes, partitions, warped, &edges);
  if (!status.ok()) return frame_error(status, file, index, frame);
  return FacePointer(std::move(image));
}

Result<FacePointer> decode_indexed_face(const ReadOnlyFile& file, const ContainerIndex& index, uint32_t frame,
                                        std::vector<codec::MacroblockMode>* modes) {
  FileCodedFaceSource source(file, index);
  return decode_indexed_face(file, index, frame, source, modes);
}

}  // namespace svc
