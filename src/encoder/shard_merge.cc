// SPDX-License-Identifier: BSD-2-Clause
// svc merge: the part files of a sharded encode checked against each other and joined
// into the file a one-process encode writes (docs/format.md, "Shards").
#include <algorithm>
#include <chrono>
#include <map>
#include <string>

#include "encoder/shard_fingerprint.h"
#include "encoder/shard_split.h"
#include "output/part_file.h"
#include "output/writer.h"
#include "svc/encoder.h"

namespace svc {

namespace {

Status refuse(const std::filesystem::path& part, const std::string& what) {
  return Status(ErrorCode::kBadInput, "cannot merge " + part.string() + ": " + what);
}

// The plan without what differs between parts (statistics) or is unset (offsets).
std::vector<uint8_t> plan_bytes(ContainerIndex plan) {
  plan.stats = {};
  return serialize_index(plan);
}

std::string settings_text(const CodingRecord& c) {
  return "quantizer index " + std::to_string(c.qindex) + ", quality " + std::to_string(c.quality) + ", I-spacing " +
         std::to_string(c.i_spacing[0]) + "," + std::to_string(c.i_spacing[1]) + "," +
         std::to_string(c.i_spacing[2]) + ", motion " + (c.motion == MotionSearch::kDepth ? "depth" : "log");
}

// The same database, settings, version and shard count as `first`.
Status check_matches(const OpenedPart& part, const OpenedPart& first, const std::vector<uint8_t>& first_plan) {
  const PartDescriptor& d = part.descriptor;
  const PartDescriptor& f = first.descriptor;
  const std::filesystem::path path = part.file->name();
  if (d.fingerprint != f.fingerprint) {
    return refuse(path, "it belongs to a different database than " + first.file->name());
  }
  if (d.shard_count != f.shard_count) {
    return refuse(path, "it is a part of " + std::to_string(d.shard_count) + ", " + first.file->name() +
                            " a part of " + std::to_string(f.shard_count));
  }
  const CodingRecord& a = d.plan.coding;
  const CodingRecord& b = f.plan.coding;
  if (a.qindex != b.qindex || a.quality != b.quality || a.i_spacing != b.i_spacing || a.motion != b.motion) {
    return refuse(path, "it was encoded with " + settings_text(a) + ", " + first.file->name() + " with " +
                            settings_text(b));
  }
  if (d.settings != f.settings) {
    auto text = [](const std::string& settings) { return settings.empty() ? "the default settings" : settings; };
    return refuse(path, "it was encoded with " + text(d.settings) + ", " + first.file->name() + " with " +
                            text(f.settings));
  }
  if (plan_bytes(d.plan) != first_plan) {
    return refuse(path, "its plan of cells and references differs from " + first.file->name());
  }
  return Status::Ok();
}

// Every part valid on its own and like the others, each of 1..N exactly once; returns
// them ordered by shard.
Result<std::vector<const OpenedPart*>> check_parts(const std::vector<OpenedPart>& parts) {
  const OpenedPart& first = parts.front();
  const std::vector<uint8_t> first_plan = plan_bytes(first.descriptor.plan);
  const uint32_t count = first.descriptor.shard_count;
  std::vector<const OpenedPart*> by_shard(count, nullptr);
  for (const OpenedPart& part : parts) {
    const PartDescriptor& d = part.descriptor;
    const std::filesystem::path path = part.file->name();
    if (d.svc_version != kSvcVersion) {
      return refuse(path, "it was written by svc " + d.svc_version + ", this is svc " + kSvcVersion);
    }
    SVC_RETURN_IF_ERROR(check_matches(part, first, first_plan));
    if (d.shard < 1 || d.shard > count) {
      return refuse(path, "it calls itself part " + std::to_string(d.shard) + " of " + std::to_string(count));
    }
    const OpenedPart*& slot = by_shard[d.shard - 1];
    if (slot != nullptr) {
      return refuse(path, "it is part " + std::to_string(d.shard) + " of " + std::to_string(count) + ", as is " +
                              slot->file->name());
    }
    const std::vector<uint32_t> expected = shard_frames(d.plan, d.shard, count);
    if (d.faces.size() != expected.size() ||
        !std::equal(expected.begin(), expected.end(), d.faces.begin(),
                    [](uint32_t frame, const PartFace& face) { return frame == face.frame; })) {
      return refuse(path, "its face table is not that of part " + std::to_string(d.shard) + " of " +
                              std::to_string(count));
    }
    slot = &part;
  }
  std::string missing;
  for (uint32_t k = 0; k < count; ++k) {
    if (by_shard[k] == nullptr) missing += (missing.empty() ? "" : ", ") + std::to_string(k + 1);
  }
  if (!missing.empty()) {
    return Status(ErrorCode::kBadInput, "cannot merge: part(s) " + missing + " of " + std::to_string(count) +
                                            " missing (" + std::to_string(parts.size()) + " given)");
  }
  return by_shard;
}

// Where each frame's coded bytes are: part and position in its face table.
struct FaceSource {
  const OpenedPart* part = nullptr;
  size_t face = 0;
};

// Copies every face into `writer` in the canonical order (I-faces, then B-faces, each in
// frame order, as encode_database writes them) and fills in `index`.
Status copy_faces(const std::vector<const OpenedPart*>& parts, ContainerWriter& writer, ContainerIndex& index) {
  std::vector<FaceSource> sources(index.frames.size());
  for (const OpenedPart* part : parts) {
    for (size_t i = 0; i < part->descriptor.faces.size(); ++i) sources[part->descriptor.faces[i].frame] = {part, i};
  }
  for (FaceType type : {FaceType::kIntra, FaceType::kPredicted}) {
    for (size_t frame = 0; frame < index.frames.size(); ++frame) {
      FrameRecord& record = index.frames[frame];
      if (record.type != type) continue;
      const PartFace& face = sources[frame].part->descriptor.faces[sources[frame].face];
      FrameRecord stored = record;
      stored.chunk_offset = face.chunk_offset;
      stored.payload_size = face.payload_size;
      stored.depth_size = face.depth_size;
      const ReadOnlyFile& file = *sources[frame].part->file;
      const std::string what = face_label(index.cells[record.cell].index, record.face);
      auto payload = read_frame_payload(file, stored, what);
      if (!payload.ok()) return payload.status().with_context("cannot merge " + file.name());
      SVC_ASSIGN_OR_RETURN(record.chunk_offset, writer.append_frame(*payload));
      record.payload_size = face.payload_size;
      record.border_edges = face.border_edges;
      if (index.depth) {
        auto depth = read_frame_depth(file, stored, what);
        if (!depth.ok()) return depth.status().with_context("cannot merge " + file.name());
        SVC_RETURN_IF_ERROR(writer.append_frame(*depth).status());
        record.depth_size = face.depth_size;
      }
    }
  }
  return Status::Ok();
}

}  // namespace

Result<MergeSummary> merge_shards(const std::vector<std::filesystem::path>& parts,
                                  const std::filesystem::path& out_path) {
  const auto start = std::chrono::steady_clock::now();
  if (parts.empty()) return Status(ErrorCode::kInvalidArgument, "no part files to merge");
  std::vector<OpenedPart> opened;
  for (const std::filesystem::path& path : parts) {
    auto part = open_part(path);
    if (!part.ok()) return part.status().with_context("cannot merge");
    opened.push_back(std::move(part).value());
  }
  SVC_ASSIGN_OR_RETURN(std::vector<const OpenedPart*> ordered, check_parts(opened));

  ContainerIndex index = ordered.front()->descriptor.plan;
  index.stats = {};
  for (const OpenedPart* part : ordered) {
    for (int type = 0; type < 2; ++type) {
      const FaceTypeStats& s = part->descriptor.plan.stats[type];
      FaceTypeStats& t = index.stats[type];
      t.faces += s.faces;
      t.bytes += s.bytes;
      t.mb_intra += s.mb_intra;
      t.mb_forward += s.mb_forward;
      t.mb_backward += s.mb_backward;
      t.mb_bidirectional += s.mb_bidirectional;
      t.mb_skipped += s.mb_skipped;
      t.candidate_vectors += s.candidate_vectors;
      t.candidate_macroblocks += s.candidate_macroblocks;
    }
  }
  SVC_ASSIGN_OR_RETURN(auto writer, ContainerWriter::create(out_path));
  SVC_RETURN_IF_ERROR(copy_faces(ordered, *writer, index));
  SVC_RETURN_IF_ERROR(writer->finish(index));

  MergeSummary summary;
  summary.parts = ordered.size();
  summary.cells = index.cells.size();
  summary.faces = index.frames.size();
  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(out_path, ec);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
