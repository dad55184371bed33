// Encoding and decoding speed of every codec at its reference point (see svc_bench.h,
// CodecResult), measured in rounds across the codecs.
#include <algorithm>
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
};

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
  return job;
}

SpeedJob Bench::baseline_speed_job(const CodecPlan& plan, int setting, baseline::EncodedDatabase encoded) {
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
  return job;
}

Status Bench::measure_speeds(std::vector<CodecResult>* codecs) {
  const size_t count = speed_jobs_.size();
  if (count == 0) return Status::Ok();
  log("speed: " + std::to_string(kEncodeSpeedPasses) + " encodes and " + std::to_string(kDecodeSpeedPasses) +
      " decoding passes of each codec, in rounds");
  std::vector<SpeedSamples> samples(count);
  const double faces = static_cast<double>(source_.faces.size());
  for (int round = 0; round < std::max(kEncodeSpeedPasses, kDecodeSpeedPasses); ++round) {
    for (size_t turn = 0; turn < count; ++turn) {
      const size_t k = (static_cast<size_t>(round) + turn) % count;
      SpeedJob& job = speed_jobs_[k];
      if (round < kEncodeSpeedPasses) {
        SVC_ASSIGN_OR_RETURN(const double seconds, job.encode_seconds());
        samples[k].encode.push_back(seconds > 0 ? faces / seconds : 0);
      }
      if (round < kDecodeSpeedPasses) {
        SVC_ASSIGN_OR_RETURN(const double one, job.decode_one_thread());
        SVC_ASSIGN_OR_RETURN(const double all, job.decode_all_threads());
        samples[k].one_thread.push_back(one);
        samples[k].all_threads.push_back(all);
      }
    }
  }
  for (size_t k = 0; k < count; ++k) {
    auto result = std::find_if(codecs->begin(), codecs->end(),
                               [&](const CodecResult& c) { return c.name == speed_jobs_[k].codec; });
    if (result == codecs->end()) continue;
    result->encode_faces_per_second = median(samples[k].encode);
    result->decode_faces_per_second = median(samples[k].one_thread);
    result->decode_faces_per_second_all_threads = median(samples[k].all_threads);
    log_speed(*result);
  }
  speed_jobs_.clear();
  return Status::Ok();
}

}  // namespace svc::bench
