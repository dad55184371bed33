// SPDX-License-Identifier: BSD-2-Clause
#include "output/part_file.h"

#include <algorithm>
#include <cstring>

#include "common/bytes.h"

namespace svc {

namespace {

// 2: bare face chunks; 3: depth sizes; 4: border edges; 5: encoder settings
constexpr uint8_t kPartFormatVersion = 5;
constexpr uint32_t kMaxSettingsText = 4096;
constexpr char kHeaderMagic[8] = {'S', 'V', 'C', 'P', 'A', 'R', 'T', kPartFormatVersion};
constexpr char kTrailerMagic[8] = {'S', 'V', 'C', 'P', 'E', 'N', 'D', kPartFormatVersion};
constexpr uint64_t kPartFaceRecordSize = 21;  // frame, chunk offset, payload size, depth size, border edges

// parse_index wants every chunk inside a file; the plan's frames all point at one empty
// chunk right after an imaginary prelude (and a one-byte depth chunk after it, which a
// plan with depth needs).
constexpr uint64_t kPlanFileSize = kPreludeSize + 2 * kBareChunkOverhead + 1;

std::span<const uint8_t> magic_bytes(const char (&magic)[8]) {
  return {reinterpret_cast<const uint8_t*>(magic), sizeof magic};
}

std::vector<uint8_t> serialize_plan(ContainerIndex plan) {
  for (FrameRecord& frame : plan.frames) {
    frame.chunk_offset = kPreludeSize;
    frame.payload_size = 0;
    frame.depth_size = plan.depth ? 1 : 0;
    frame.border_edges = kEveryBorderEdge;  // each part's faces' own are in its face table
  }
  return serialize_index(plan);
}

std::vector<uint8_t> serialize_descriptor(const PartDescriptor& d) {
  ByteWriter w;
  w.u32(static_cast<uint32_t>(d.svc_version.size()));
  w.raw({reinterpret_cast<const uint8_t*>(d.svc_version.data()), d.svc_version.size()});
  w.u64(d.fingerprint);
  w.u32(d.shard);
  w.u32(d.shard_count);
  w.u32(static_cast<uint32_t>(d.settings.size()));
  w.raw({reinterpret_cast<const uint8_t*>(d.settings.data()), d.settings.size()});
  w.u64(d.faces.size());
  for (const PartFace& face : d.faces) {
    w.u32(face.frame);
    w.u64(face.chunk_offset);
    w.u32(face.payload_size);
    w.u32(face.depth_size);
    w.u8(face.border_edges);
  }
  const std::vector<uint8_t> plan = serialize_plan(d.plan);
  w.u64(plan.size());
  w.raw(plan);
  return w.take();
}

Status check_faces(const PartDescriptor& d, uint64_t faces_end) {
  for (const PartFace& face : d.faces) {
    const std::string what = "face record for frame " + std::to_string(face.frame);
    if (face.frame >= d.plan.frames.size()) {
      return Status(ErrorCode::kCorruptData,
                    what + " lies outside the plan's " + std::to_string(d.plan.frames.size()) + " frames");
    }
    const uint64_t bytes = uint64_t{face.payload_size} + kBareChunkOverhead +
                           (face.depth_size ? uint64_t{face.depth_size} + kBareChunkOverhead : 0);
    if (face.chunk_offset < kPartHeaderSize || face.chunk_offset > faces_end ||
        bytes > faces_end - face.chunk_offset || (face.depth_size != 0) != d.plan.depth) {
      return corrupt_at(what + " points outside the face chunks", face.chunk_offset);
    }
    const FrameRecord& planned = d.plan.frames[face.frame];
    if (planned.cube_references && planned.references.size() < 2 && (face.border_edges & 0xF0) != 0) {
      return Status(ErrorCode::kCorruptData, what + " has border edges " + std::to_string(face.border_edges) +
                                                 " for a second reference it does not have");
    }
  }
  return Status::Ok();
}

Result<PartDescriptor> parse_descriptor(std::span<const uint8_t> payload, uint64_t payload_offset,
                                        uint64_t faces_end, const ReaderLimits& limits) {
  ByteReader r(payload, payload_offset);
  PartDescriptor d;
  const uint32_t version_size = r.u32();
  if (!r.ok() || version_size > 64 || version_size > r.remaining()) {
    return corrupt_at("part descriptor's version string does not fit", r.file_offset());
  }
  d.svc_version.assign(reinterpret_cast<const char*>(payload.data() + r.position()), version_size);
  r.skip(version_size);
  d.fingerprint = r.u64();
  d.shard = r.u32();
  d.shard_count = r.u32();
  const uint32_t settings_size = r.u32();
  if (!r.ok() || settings_size > kMaxSettingsText || settings_size > r.remaining()) {
    return corrupt_at("part descriptor's settings text does not fit", r.file_offset());
  }
  d.settings.assign(reinterpret_cast<const char*>(payload.data() + r.position()), settings_size);
  r.skip(settings_size);
  const uint64_t face_count = r.u64();
  if (!r.ok() || face_count > r.remaining() / kPartFaceRecordSize) {
    return corrupt_at("part descriptor's face table does not fit", r.file_offset());
  }
  d.faces.resize(static_cast<size_t>(face_count));
  for (PartFace& face : d.faces) {
    face.frame = r.u32();
    face.chunk_offset = r.u64();
    face.payload_size = r.u32();
    face.depth_size = r.u32();
    face.border_edges = r.u8();
  }
  const uint64_t plan_size = r.u64();
  if (!r.ok() || plan_size != r.remaining()) {
    return corrupt_at("part descriptor's plan size does not match its chunk", r.file_offset());
  }
  SVC_ASSIGN_OR_RETURN(d.plan, parse_index(payload.subspan(r.position()), r.file_offset(), kPlanFileSize, limits));
  for (FrameRecord& frame : d.plan.frames) {
    frame.chunk_offset = 0;
    frame.depth_size = 0;
  }
  SVC_RETURN_IF_ERROR(check_faces(d, faces_end));
  return d;
}

}  // namespace

Result<std::unique_ptr<PartWriter>> PartWriter::create(const std::filesystem::path& path) {
  SVC_ASSIGN_OR_RETURN(auto out, AtomicOutputFile::create(path));
  SVC_RETURN_IF_ERROR(out->write(magic_bytes(kHeaderMagic)));
  return std::unique_ptr<PartWriter>(new PartWriter(std::move(out)));
}

Result<uint64_t> PartWriter::append_frame(std::span<const uint8_t> payload) {
  const uint64_t offset = out_->position();
  SVC_RETURN_IF_ERROR(out_->write(make_bare_chunk(payload)));
  return offset;
}

Status PartWriter::finish(const PartDescriptor& descriptor) {
  const uint64_t part_offset = out_->position();
  SVC_RETURN_IF_ERROR(out_->write(make_chunk(kPartChunkTag, serialize_descriptor(descriptor))));
  ByteWriter trailer;
  trailer.u64(part_offset);
  trailer.raw(magic_bytes(kTrailerMagic));
  SVC_RETURN_IF_ERROR(out_->write(trailer.bytes()));
  return out_->commit();
}

Result<OpenedPart> open_part(const std::filesystem::path& path, const ReaderLimits& limits) {
  OpenedPart part;
  SVC_ASSIGN_OR_RETURN(part.file, ReadOnlyFile::open(path));
  const ReadOnlyFile& file = *part.file;
  auto fail = [&](const Status& status) { return status.with_context(path.string()); };
  if (file.size() < kPartHeaderSize + kPartTrailerSize + kChunkOverhead) {
    return fail(
        Status(ErrorCode::kCorruptData, "not a part file: " + std::to_string(file.size()) + " bytes is too short"));
  }
  std::array<uint8_t, kPartHeaderSize> header{};
  SVC_RETURN_IF_ERROR(file.read_at(0, header));
  if (std::memcmp(header.data(), kHeaderMagic, 7) != 0) {
    return fail(
        Status(ErrorCode::kCorruptData, "not a part file (no SVCPART header; `svc encode --shard` makes them)"));
  }
  if (header[7] != kPartFormatVersion) {
    return fail(Status(ErrorCode::kUnsupported, "part format version " + std::to_string(header[7]) +
                                                    " (this svc reads version " +
                                                    std::to_string(kPartFormatVersion) + ")"));
  }
  const uint64_t trailer_offset = file.size() - kPartTrailerSize;
  SVC_ASSIGN_OR_RETURN(std::vector<uint8_t> trailer, file.read_vector(trailer_offset, kPartTrailerSize));
  ByteReader r(trailer, trailer_offset);
  const uint64_t part_offset = r.u64();
  if (std::memcmp(trailer.data() + 8, kTrailerMagic, 8) != 0) {
    return fail(corrupt_at("part file has no trailer (cut short or damaged)", trailer_offset));
  }
  if (part_offset < kPartHeaderSize || part_offset > trailer_offset) {
    return fail(corrupt_at("trailer points at a PART chunk outside the file", trailer_offset));
  }
  auto payload = read_chunk(file, part_offset, trailer_offset - part_offset, kPartChunkTag, "part descriptor");
  if (!payload.ok()) return fail(payload.status());
  auto descriptor = parse_descriptor(*payload, part_offset + 12, part_offset, limits);
  if (!descriptor.ok()) return fail(descriptor.status());
  part.descriptor = std::move(descriptor).value();
  return part;
}

}  // namespace svc
