// SPDX-License-Identifier: BSD-2-Clause
// Internal to `svc bench`: the state of one run over one database, shared by the codec
// sweeps (codec_runs.cc), the access measurements (access_measure.cc) and the
// dissertation's experiments (experiments.cc).
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "anchors.h"
#include "baseline/baseline.h"
#include "bench_util.h"
#include "rd_curve.h"
#include "source_faces.h"
#include "svc/encoder.h"
#include "svc/reader.h"
#include "svc_bench.h"

namespace svc::bench {

// One svc encode of the (possibly subsampled) database, decoded and scored.
struct SvcRun {
  EncoderSettings settings;
  int sample_spacing = 1;
  std::filesystem::path file;
  EncodeSummary summary;
  QualityPoint point;
};

// Whole cells at random on one thread, one sample per cell and pass.
struct CellAccessSamples {
  std::vector<double> cold_ms, warm_ms;
  std::vector<int> frames;  // faces decoded for the cell, cold
};

// One codec's speed passes at its reference point, registered by its sweep and run by
// Bench::measure_speeds in turns with every other codec's. Each call runs one pass.
struct SpeedJob {
  std::string codec;                                      // CodecResult::name
  std::function<Result<double>()> encode_seconds;         // one encode from the database on disk
  std::function<Result<double>()> decode_one_thread;      // faces/s, every face on the caller's thread
  std::function<Result<double>()> decode_all_threads;     // faces/s, every face on all threads
  std::function<Status(CellAccessSamples*)> cell_access;  // every picked cell, cold then warm
};

class Bench {
 public:
  Bench(const BenchOptions& options, SourceFaces source, int threads, Clock::time_point start);

  uint64_t raw_bytes() const { return raw_bytes_; }
  void log(const std::string& line) const;
  void remove_work_dir() const;

  // The quality search and random access of one codec; its speed passes wait for
  // measure_speeds().
  Result<CodecResult> run_codec(const CodecPlan& plan);
  // The encoding and decoding speeds and the random access to a cell of every codec run
  // so far (svc_bench.h, CodecResult), measured in rounds, the encodes first: each round
  // runs one pass of every codec, starting one codec later than the round before, so
  // that a shared machine's slow minutes fall on all of them alike. Fills `codecs`'
  // speeds by name and frees the kept streams.
  Status measure_speeds(std::vector<CodecResult>* codecs);
  Result<Experiments> run_experiments(const std::vector<CodecResult>& codecs, std::vector<PartTiming>* timings);
  // ablation.cc
  Result<std::vector<AblationRow>> run_ablation(const CodecResult& svc);

 private:
  void fill_rates(QualityPoint* p, uint64_t faces) const;
  void log_point(const std::string& codec, const QualityPoint& p) const;
  void log_speed(const CodecResult& result) const;

  Result<SvcRun> run_svc(const EncoderSettings& settings, int sample_spacing, const std::string& tag,
                         std::unique_ptr<Reader>* reader_out = nullptr);
  Status run_svc_codec(const CodecPlan& plan, CodecResult* result);
  Status run_baseline_codec(const CodecPlan& plan, CodecResult* result);
  Result<baseline::EncodedDatabase> encode_baseline(const CodecPlan& plan,
                                                    const baseline::EncodeSettings& settings);
  Result<QualityPoint> measure_baseline(const CodecPlan& plan, int setting, baseline::EncodedDatabase* keep);
  // The anchor's points from the cache, when it holds them (then true).
  bool points_from_cache(const CodecPlan& plan, CodecResult* result);
  void store_in_cache(const CodecPlan& plan, const CodecResult& result);
  std::string cache_key(const CodecPlan& plan);
  // The ffmpeg command the report gives for `plan` at `setting`.
  std::string reference_command(const CodecPlan& plan, int setting) const;
  static int reference_index(const std::vector<QualityPoint>& points, std::optional<double> target);

  // Every face decoded on the calling thread: an .svc file's in cell order (index
  // 6 cell + face), an anchor's six face streams one after another.
  static Result<std::vector<ImageRGB8>> decode_every_face(Reader& reader);
  static Result<std::array<std::vector<ImageRGB8>, kFaceCount>> decode_every_face(
      const baseline::EncodedDatabase& encoded);

  // access_measure.cc
  // Random faces; an anchor's streams are written as the baseline stores them, one file
  // a face, and their paths returned for its cell access.
  Status svc_access(const SvcRun& run, Reader& warm_reader, CodecResult* result);
  Result<std::array<std::filesystem::path, kFaceCount>> baseline_access(const CodecPlan& plan,
                                                                        const baseline::EncodedDatabase& encoded,
                                                                        CodecResult* result);
  // One pass of whole cells at random on one thread (a SpeedJob's cell_access).
  Status svc_cell_access(const SvcRun& run, CellAccessSamples* samples);
  Status baseline_cell_access(const baseline::EncodedDatabase& encoded,
                              const std::array<std::filesystem::path, kFaceCount>& paths,
                              CellAccessSamples* samples);
  // The speed passes of an svc layout at `run` and of an anchor at `encoded` (its streams
  // kept until measure_speeds() ends).
  SpeedJob svc_speed_job(const std::string& codec, const SvcRun& run);
  SpeedJob baseline_speed_job(const CodecPlan& plan, int setting, baseline::EncodedDatabase encoded,
                              const std::array<std::filesystem::path, kFaceCount>& paths);
  // The distinct cells of picks_, in pick order.
  std::vector<size_t> pick_cells() const;

  // experiments.cc
  const SvcRun* find_run(int quality, std::array<int32_t, 3> i_spacing, MotionSearch motion, int spacing) const;
  Result<const SvcRun*> get_run(int quality, std::array<int32_t, 3> i_spacing, MotionSearch motion, int spacing);
  Status table_7_5(const std::vector<CodecResult>& codecs, Experiments* ex);
  Status figure_7_16(Experiments* ex);
  Status table_7_4(Experiments* ex);

  const BenchOptions& options_;
  SourceFaces source_;
  int threads_ = 1;
  std::filesystem::path work_dir_;
  std::vector<Pick> picks_;
  std::array<int, 2> horizontal_{0, 2};
  uint64_t pixels_per_face_ = 0;
  uint64_t raw_bytes_ = 0;
  Clock::time_point start_;
  std::deque<SvcRun> svc_runs_;
  std::vector<SpeedJob> speed_jobs_;
  std::optional<double> svc_reference_psnr_;
  std::string source_fingerprint_;  // of source_, once an anchor looks in the cache
  int experiments_quality_ = 75;
};

}  // namespace svc::bench
