// SPDX-License-Identifier: BSD-2-Clause
// Random-access cost of svc and of the libavcodec anchors (see svc_bench.h, "Cold and
// warm random access").
#include <algorithm>

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

Status Bench::svc_cell_access(const SvcRun& run, CellAccessSamples* samples) {
  ReaderSettings one_thread;
  one_thread.decode_threads = 1;
  one_thread.prefetch_threads = 0;
  for (size_t cell : pick_cells()) {
    const CellIndex& index = source_.manifest.cells[cell].index;
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(run.file, one_thread));
    if (!reader->find_cell(index)) continue;
    SVC_ASSIGN_OR_RETURN(auto cold, reader->decode_cube(index));
    samples->cold_ms.push_back(seconds_since(t0) * 1e3);
    const ReaderStats stats = reader->stats();
    samples->frames.push_back(static_cast<int>(stats.intra_faces_parsed + stats.predicted_faces_decoded));
    const auto t1 = Clock::now();
    SVC_ASSIGN_OR_RETURN(auto warm, reader->decode_cube(index));
    samples->warm_ms.push_back(seconds_since(t1) * 1e3);
  }
  return Status::Ok();
}

Result<std::array<std::filesystem::path, kFaceCount>> Bench::baseline_access(
    const CodecPlan& plan, const baseline::EncodedDatabase& encoded, CodecResult* result) {
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
  return paths;
}

Status Bench::baseline_cell_access(const baseline::EncodedDatabase& encoded,
                                   const std::array<std::filesystem::path, kFaceCount>& paths,
                                   CellAccessSamples* samples) {
  for (size_t cell : pick_cells()) {
    const int frame = encoded.layout.frame_of(source_.manifest.cells[cell].index);
    int decoded_frames = 0;
    const auto t0 = Clock::now();
    for (Face f : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(baseline::EncodedSequence sequence, baseline::read_sequence(paths[static_cast<int>(f)]));
      SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame decoded, baseline::decode_frame(sequence, frame));
      decoded_frames += decoded.frames_decoded;
    }
    samples->cold_ms.push_back(seconds_since(t0) * 1e3);
    samples->frames.push_back(decoded_frames);
    const auto t1 = Clock::now();
    for (Face f : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(baseline::DecodedFrame decoded,
                           baseline::decode_frame(encoded.faces[static_cast<int>(f)], frame));
    }
    samples->warm_ms.push_back(seconds_since(t1) * 1e3);
  }
  return Status::Ok();
}

std::vector<size_t> Bench::pick_cells() const {
  std::vector<size_t> cells;
  for (const Pick& p : picks_) {
    if (std::find(cells.begin(), cells.end(), p.cell) == cells.end()) cells.push_back(p.cell);
  }
  return cells;
}

}  // namespace svc::bench
