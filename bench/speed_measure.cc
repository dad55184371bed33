// SPDX-License-Identifier: BSD-2-Clause
// Encoding and decoding speed and random access to a cell of every codec at its
// reference point (see svc_bench.h, CodecResult), measured in rounds across the codecs.
#include <algorithm>
#include <functional>
#include <memory>

#include "bench_runner.h"
#include "support/statistics.h"

namespace svc::bench {

namespace {

double faces_per_second(size_t faces, double seconds) {
  return seconds > 0 ? static_cast<double>(faces) / seconds : 0;
}

// Speed samples of one codec, one per round that ran its pass.
struct SpeedSamples {
  std::vector<double> encode, one_thread, all_threads;
  CellAccessSamples cells;
};

// Calls pass(k) `rounds` times for each of `count` codecs: each round once per codec,
// starting one codec later than the round before.
Status in_rounds(int rounds, size_t count, const std::function<Status(size_t)>& pass) {
  for (int round = 0; round < rounds; ++round) {
    for (size_t turn = 0; turn < count; ++turn)
      SVC_RETURN_IF_ERROR(pass((static_cast<size_t>(round) + turn) % count));
  }
  return Status::Ok();
}

}  // namespace

SpeedJob Bench::svc_speed_job(const std::string& codec, const SvcRun& run) {
  SpeedJob job;
  job.codec = codec;
  // `run` lives in svc_runs_, a deque: its address holds while the bench does.
  job.encode_seconds = [this, &run, codec]() -> Result<double> {
    const std::filesystem::path file = work_dir_ / (codec + "-speed.svc");
    const auto encoded = encode_database(options_.db_dir, file, run.settings);
    std::error_code ec;
    std::filesystem::remove(file, ec);
    if (!encoded.ok()) return encoded.status();
    return encoded->seconds;
  };
  // One thread: in cell order through a new reader, as run_svc decodes.
  job.decode_one_thread = [&run]() -> Result<double> {
    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(run.file));
    const auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(const std::vector<ImageRGB8> decoded, decode_every_face(*reader));
    return faces_per_second(decoded.size(), seconds_since(t0));
  };
  // All threads: the faces side by side through one reader.
  job.decode_all_threads = [this, &run]() -> Result<double> {
    ReaderSettings settings;
    settings.prefetch_threads = 0;
    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(run.file, settings));
    const auto& cells = reader->cells();
    const size_t faces = cells.size() * kFaceCount;
    const auto t0 = Clock::now();
    SVC_RETURN_IF_ERROR(parallel_for(faces, threads_, [&](size_t frame) -> Status {
      return reader->decode_face(cells[frame / kFaceCount].index, kAllFaces[frame % kFaceCount]).status();
    }));
    return faces_per_second(faces, seconds_since(t0));
  };
  job.cell_access = [this, &run](CellAccessSamples* samples) { return svc_cell_access(run, samples); };
  return job;
}

SpeedJob Bench::baseline_speed_job(const CodecPlan& plan, int setting, baseline::EncodedDatabase encoded,
                                   const std::array<std::filesystem::path, kFaceCount>& paths) {
  auto streams = std::make_shared<const baseline::EncodedDatabase>(std::move(encoded));
  const size_t faces = streams->layout.cells.size() * kFaceCount;
  SpeedJob job;
  job.codec = plan.name;
  job.encode_seconds = [this, plan, setting]() -> Result<double> {
    baseline::EncodeSettings settings = plan.base;
    settings.quantizer = setting;
    const auto t0 = Clock::now();
    SVC_RETURN_IF_ERROR(encode_baseline(plan, settings).status());
    return seconds_since(t0);
  };
  // One thread: the six face streams one after another, as measure_baseline decodes.
  job.decode_one_thread = [streams, faces]() -> Result<double> {
    const auto t0 = Clock::now();
    SVC_RETURN_IF_ERROR(decode_every_face(*streams).status());
    return faces_per_second(faces, seconds_since(t0));
  };
  // All threads: the six streams side by side, one decoder each.
  job.decode_all_threads = [this, streams, faces]() -> Result<double> {
    const auto t0 = Clock::now();
    SVC_RETURN_IF_ERROR(parallel_for(kFaceCount, threads_, [&](size_t f) -> Status {
      return baseline::decode_all(streams->faces[f]).status();
    }));
    return faces_per_second(faces, seconds_since(t0));
  };
  job.cell_access = [this, streams, paths](CellAccessSamples* samples) {
    return baseline_cell_access(*streams, paths, samples);
  };
  return job;
}

Status Bench::measure_speeds(std::vector<CodecResult>* codecs) {
  const size_t count = speed_jobs_.size();
  if (count == 0) return Status::Ok();
  log("speed: " + std::to_string(kEncodeSpeedPasses) + " encodes, then " + std::to_string(kDecodeSpeedPasses) +
      " passes of decoding and random cells, of each codec in rounds");
  std::vector<SpeedSamples> samples(count);
  // All the encodes first, then the decoding: no decoding pass follows an encode of its
  // own codec where the others' follow another codec's.
  SVC_RETURN_IF_ERROR(in_rounds(kEncodeSpeedPasses, count, [&](size_t k) -> Status {
    SVC_ASSIGN_OR_RETURN(const double seconds, speed_jobs_[k].encode_seconds());
    samples[k].encode.push_back(faces_per_second(source_.faces.size(), seconds));
    return Status::Ok();
  }));
  SVC_RETURN_IF_ERROR(in_rounds(kDecodeSpeedPasses, count, [&](size_t k) -> Status {
    SVC_ASSIGN_OR_RETURN(const double one, speed_jobs_[k].decode_one_thread());
    SVC_ASSIGN_OR_RETURN(const double all, speed_jobs_[k].decode_all_threads());
    samples[k].one_thread.push_back(one);
    samples[k].all_threads.push_back(all);
    return speed_jobs_[k].cell_access(&samples[k].cells);
  }));
  for (size_t k = 0; k < count; ++k) {
    auto result = std::find_if(codecs->begin(), codecs->end(),
                               [&](const CodecResult& c) { return c.name == speed_jobs_[k].codec; });
    if (result == codecs->end()) continue;
    result->encode_faces_per_second = median(samples[k].encode);
    result->decode_faces_per_second = median(samples[k].one_thread);
    result->decode_faces_per_second_all_threads = median(samples[k].all_threads);
    const CellAccessSamples& cells = samples[k].cells;
    result->cell_cold = summarize_access(cells.cold_ms, cells.frames);
    result->cell_warm = summarize_access(cells.warm_ms, cells.frames);
    log_speed(*result);
  }
  speed_jobs_.clear();
  return Status::Ok();
}

}  // namespace svc::bench
