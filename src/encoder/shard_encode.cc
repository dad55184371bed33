// SPDX-License-Identifier: BSD-2-Clause
// One shard of a sharded encode: the plan of the whole encode, this shard's faces coded
// into a part file (docs/format.md, "Shards").
#include <chrono>
#include <string>

#include "encoder/encode_plan.h"
#include "encoder/shard_fingerprint.h"
#include "encoder/shard_split.h"
#include "output/part_file.h"
#include "svc/encoder.h"

namespace svc {

Result<EncodeSummary> encode_shard(const std::filesystem::path& db_dir, const std::filesystem::path& part_path,
                                   const EncoderSettings& settings, int shard, int shard_count,
                                   const EncodeProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (shard_count < 1 || shard_count > kMaxShards || shard < 1 || shard > shard_count) {
    return Status(ErrorCode::kInvalidArgument,
                  "shard " + std::to_string(shard) + "/" + std::to_string(shard_count) +
                      " is not one of 1/N..N/N with N in 1.." + std::to_string(kMaxShards));
  }
  SVC_ASSIGN_OR_RETURN(EncodePlan plan, plan_encode(db_dir, settings));
  SVC_ASSIGN_OR_RETURN(const uint64_t fingerprint, database_fingerprint(db_dir, plan.manifest));
  SVC_ASSIGN_OR_RETURN(auto writer, PartWriter::create(part_path));
  const std::vector<uint32_t> frames =
      shard_frames(plan.index, static_cast<uint32_t>(shard), static_cast<uint32_t>(shard_count));
  FaceSink sink;
  sink.append = [&](std::span<const uint8_t> payload) { return writer->append_frame(payload); };
  sink.open_written = [&] { return writer->open_written(); };
  SVC_RETURN_IF_ERROR(code_planned_frames(plan, frames, sink, settings, progress));

  PartDescriptor descriptor;
  descriptor.svc_version = kSvcVersion;
  descriptor.fingerprint = fingerprint;
  descriptor.settings = shard_settings_text(settings);
  descriptor.shard = static_cast<uint32_t>(shard);
  descriptor.shard_count = static_cast<uint32_t>(shard_count);
  for (uint32_t frame : frames) {
    const FrameRecord& record = plan.index.frames[frame];
    descriptor.faces.push_back(
        {frame, record.chunk_offset, record.payload_size, record.depth_size, record.border_edges});
  }
  descriptor.plan = std::move(plan.index);
  // A part carries the whole plan, cameras included, for the merge.
  descriptor.plan.cameras.reserve(plan.manifest.cells.size());
  for (size_t cell = 0; cell < plan.manifest.cells.size(); ++cell) {
    SVC_ASSIGN_OR_RETURN(const CellCameras cameras, cell_cameras(plan.manifest, cell));
    descriptor.plan.cameras.push_back(cameras);
  }
  SVC_RETURN_IF_ERROR(writer->finish(descriptor));
  plan.index = std::move(descriptor.plan);

  EncodeSummary summary = summarize_encode(plan, frames.size());
  std::error_code ec;
  summary.file_bytes = std::filesystem::file_size(part_path, ec);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace svc
