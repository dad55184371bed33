// Random-access cost of svc and of the libavcodec anchors (see svc_bench.h, "Cold and
// warm random access").
#include "bench_runner.h"

namespace svc::bench {

Status Bench::svc_access(const SvcRun& run, Reader& warm_reader, CodecResult* result) {
  std::vector<double> cold_ms, warm_ms;
  std::vector<int> frames;
  const auto& cells = warm_reader.cells();
  for (const Pick& p : picks_) {
    const CellIndex& cell = source_.manifest.cells[p.cell].index;
    const auto ordinal = warm_reader.find_cell(cell);
    if (!ordinal) continue;
    frames.push_back(1 + static_cast<int>(cells[*ordinal].faces[static_cast<int>(p.face)].references.size()));
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> cold, Reader::open(run.file));
    SVC_ASSIGN_OR_RETURN(ImageRGB8 image, cold->decode_face(cell, p.face));
    cold_ms.push_back(seconds_since(t0) * 1e3);
  }
  for (const Pick& p : picks_) {
    const CellIndex& cell = source_.manifest.cells[p.cell].index;
    if (!warm_reader.find_cell(cell)) continue;
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(ImageRGB8 image, warm_reader.decode_face(cell, p.face));
    warm_ms.push_back(seconds_since(t0) * 1e3);
  }
  result->access_cold = summarize_access(cold_ms, frames);
  result->access_warm = summarize_access(warm_ms, frames);
  return Status::Ok();
}

Status Bench::baseline_access(const CodecPlan& plan, const baseline::EncodedDatabase& encoded,
                              CodecResult* result) {
  // Stored as the baseline stores it: one elementary stream and index per face.
  const auto dir = work_dir_ / (plan.name + "-access");
  std::filesystem::create_directories(dir);
  std::array<std::filesystem::path, kFaceCount> paths;
  for (Face f : kAllFaces) {
    const int i = static_cast<int>(f);
    paths[i] = dir / (std::string(face_name(f)) + "." + baseline::stream_extension(plan.encoder));
    SVC_RETURN_IF_ERROR(baseline::write_sequence(encoded.faces[i], paths[i]));
  }
  std::vector<double> cold_ms, warm_ms;
  std::vector<int> cold_frames, warm_frames;
  for (const Pick& p : picks_) {
    const int frame = encoded.layout.frame_of(source_.manifest.cells[p.cell].index);
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(baseline::EncodedSequence sequence,
                         baseline::read_sequence(paths[static_cast<int>(p.face)]));
    SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame decoded, baseline::decode_frame(sequence, frame));
    cold_ms.push_back(seconds_since(t0) * 1e3);
    cold_frames.push_back(decoded.frames_decoded);
  }
  for (const Pick& p : picks_) {
    const int frame = encoded.layout.frame_of(source_.manifest.cells[p.cell].index);
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame decoded,
                         baseline::decode_frame(encoded.faces[static_cast<int>(p.face)], frame));
    warm_ms.push_back(seconds_since(t0) * 1e3);
    warm_frames.push_back(decoded.frames_decoded);
  }
  result->access_cold = summarize_access(cold_ms, cold_frames);
  result->access_warm = summarize_access(warm_ms, warm_frames);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return Status::Ok();
}

}  // namespace svc::bench
