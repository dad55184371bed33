// SPDX-License-Identifier: BSD-2-Clause
// The quality search of each codec over the whole database, with speed and access cost
// at its reference point (see svc_bench.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "anchor_cache.h"
#include "bench_runner.h"
#include "settings_search.h"

namespace svc::bench {

Bench::Bench(const BenchOptions& options, SourceFaces source, int threads, Clock::time_point start)
    : options_(options), source_(std::move(source)), threads_(threads), start_(start) {
  work_dir_ = options_.out_dir / "work";
  horizontal_ = horizontal_axes(source_.manifest.up_axis);
  picks_ = random_picks(source_.manifest.cells.size(), options_.random_accesses, options_.seed);
  pixels_per_face_ = static_cast<uint64_t>(source_.manifest.face_width) * source_.manifest.face_height;
  raw_bytes_ = pixels_per_face_ * 3 * source_.faces.size();
}

void Bench::log(const std::string& line) const {
  if (!options_.progress) return;
  char prefix[32];
  std::snprintf(prefix, sizeof prefix, "[%6.1f s] ", seconds_since(start_));
  options_.progress(prefix + line);
}

void Bench::remove_work_dir() const {
  std::error_code ec;
  std::filesystem::remove_all(work_dir_, ec);
}

void Bench::fill_rates(QualityPoint* p, uint64_t faces) const {
  p->compression_ratio = p->bytes ? static_cast<double>(pixels_per_face_ * 3 * faces) / p->bytes : 0;
  p->bits_per_pixel = faces ? 8.0 * p->bytes / (static_cast<double>(pixels_per_face_) * faces) : 0;
}

void Bench::log_point(const std::string& codec, const QualityPoint& p) const {
  char line[256];
  std::snprintf(line, sizeof line,
                "%s %s %d: %llu bytes (%.1f:1, %.3f bpp), PSNR-Y %.2f dB, RGB %.2f dB, SSIM %.4f, %.1f s",
                codec.c_str(), p.setting_name.c_str(), p.setting, static_cast<unsigned long long>(p.bytes),
                p.compression_ratio, p.bits_per_pixel, p.psnr_y, p.psnr_rgb, p.ssim, p.encode_seconds);
  log(line);
}

Result<SvcRun> Bench::run_svc(const EncoderSettings& settings, int sample_spacing, const std::string& tag,
                              std::unique_ptr<Reader>* reader_out) {
  SvcRun run;
  run.settings = settings;
  run.settings.threads = threads_;
  run.sample_spacing = sample_spacing;
  std::filesystem::path db = options_.db_dir;
  if (sample_spacing > 1) {
    db = work_dir_ / ("subsampled-" + std::to_string(sample_spacing));
    SVC_RETURN_IF_ERROR(write_subsampled_manifest(options_.db_dir, sample_spacing, db));
    run.settings.allow_outside_paths = true;  // the thinned manifest names the source's images
  }
  run.file = work_dir_ / (tag + ".svc");
  SVC_ASSIGN_OR_RETURN(run.summary, encode_database(db, run.file, run.settings));
  run.point.setting_name = settings.qindex >= 0 ? "qindex" : "quality";
  run.point.setting = settings.qindex >= 0 ? settings.qindex : settings.quality;
  run.point.bytes = run.summary.file_bytes;
  run.point.encode_seconds = run.summary.seconds;
  fill_rates(&run.point, run.summary.faces);

  SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(run.file));
  const auto& cells = reader->cells();
  const auto t0 = Clock::now();
  SVC_ASSIGN_OR_RETURN(const std::vector<ImageRGB8> decoded, decode_every_face(*reader));
  run.point.decode_seconds = seconds_since(t0);
  std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>> pairs, b_face_pairs;
  for (size_t c = 0; c < cells.size(); ++c) {
    CellIndex original = cells[c].index;
    for (int axis : horizontal_) component(original, axis) *= sample_spacing;
    const auto ordinal = source_.ordinal(original);
    if (!ordinal) {
      return Status(ErrorCode::kInternal, "svc bench: decoded cell " + cell_label(cells[c].index) + " of " +
                                              run.file.string() + " is not in the source database");
    }
    for (Face f : kAllFaces) {
      pairs.emplace_back(&source_.face(*ordinal, f), &decoded[c * kFaceCount + static_cast<size_t>(f)]);
      const FaceEntry& entry = cells[c].faces[static_cast<size_t>(f)];
      if (entry.type != FaceType::kPredicted) continue;
      b_face_pairs.push_back(pairs.back());
      run.point.b_face_bytes += entry.coded_bytes;
    }
  }
  SVC_ASSIGN_OR_RETURN(Score score, score_faces(pairs, threads_));
  run.point.psnr_rgb = score.psnr_rgb;
  run.point.psnr_y = score.psnr_y;
  run.point.ssim = score.ssim;
  if (!b_face_pairs.empty()) {
    SVC_ASSIGN_OR_RETURN(Score b_faces, score_faces(b_face_pairs, threads_));
    run.point.b_face_psnr_y = b_faces.psnr_y;
  }
  if (reader_out) *reader_out = std::move(reader);
  return run;
}

Status Bench::run_svc_codec(const CodecPlan& plan, CodecResult* result) {
  std::unique_ptr<Reader> reference_reader;
  const SvcRun* reference_run = nullptr;
  double reference_distance = 0;
  auto measure = [&](int quality) -> Result<double> {
    EncoderSettings settings = default_encoder_settings();
    settings.quality = quality;
    settings.intra_only = plan.svc_intra;
    if (plan.svc_intra) settings.i_spacing = {1, 1, 1};
    SVC_RETURN_IF_ERROR(apply_encoder_speed(&settings, plan.svc_speed));
    if (plan.svc_regular) {
      settings.layout = CubeLayout::kRegular;
      settings.tools.visibility_references = false;
    }
    std::unique_ptr<Reader> reader;
    SVC_ASSIGN_OR_RETURN(SvcRun run, run_svc(settings, 1, plan.name + "-q" + std::to_string(quality), &reader));
    log_point(plan.name, run.point);
    result->points.push_back(run.point);
    const double distance = std::abs(run.point.psnr_y - kReferencePsnrY);
    svc_runs_.push_back(std::move(run));
    if (!reference_reader || distance < reference_distance) {  // ties keep the earlier point
      reference_reader = std::move(reader);
      reference_run = &svc_runs_.back();
      reference_distance = distance;
    }
    return svc_runs_.back().point.psnr_y;
  };
  SVC_RETURN_IF_ERROR(search_settings(plan.range, default_targets(options_.quick), measure).status());
  std::sort(result->points.begin(), result->points.end(),
            [](const QualityPoint& a, const QualityPoint& b) { return a.setting < b.setting; });
  for (size_t i = 0; i < result->points.size(); ++i) {
    if (result->points[i].setting == reference_run->point.setting) result->reference_point = static_cast<int>(i);
  }
  if (options_.measure_speed) {
    SVC_RETURN_IF_ERROR(svc_access(*reference_run, *reference_reader, result));
    speed_jobs_.push_back(svc_speed_job(plan.name, *reference_run));
  }
  // The svc layouts run first, svc before the others: the first to run sets the PSNR-Y
  // at which the anchors' speed and access are measured.
  if (!svc_reference_psnr_) svc_reference_psnr_ = reference_run->point.psnr_y;
  return Status::Ok();
}

Result<baseline::EncodedDatabase> Bench::encode_baseline(const CodecPlan& plan,
                                                         const baseline::EncodeSettings& settings) {
  baseline::EncodedDatabase encoded;
  std::vector<CellIndex> cells;
  for (const ManifestCell& c : source_.manifest.cells) cells.push_back(c.index);
  const auto& d = source_.manifest.grid.dims;
  SVC_ASSIGN_OR_RETURN(encoded.layout, baseline::order_cells(cells, {d[0], d[1], d[2]}, plan.order,
                                                             std::max(1, settings.gop_size)));
  if (!plan.force_row_starts) std::fill(encoded.layout.gop_start.begin(), encoded.layout.gop_start.end(), 0);
  std::vector<size_t> ordinals;
  for (const CellIndex& c : encoded.layout.cells) ordinals.push_back(*source_.ordinal(c));
  SVC_RETURN_IF_ERROR(parallel_for(kFaceCount, plan.parallel_faces ? threads_ : 1, [&](size_t f) -> Status {
    baseline::FrameSource frames;
    frames.frame_count = static_cast<int>(ordinals.size());
    frames.width = source_.manifest.face_width;
    frames.height = source_.manifest.face_height;
    // Each frame read from its file inside the timed encode, as svc's encode reads its
    // faces: both codecs' encode times start from the database on disk.
    frames.load = [&, f](int k) -> Result<ImageRGB8> {
      return load_face_color(source_.manifest, ordinals[k], kAllFaces[f]);
    };
    std::span<const uint8_t> force;
    if (plan.force_row_starts) force = encoded.layout.gop_start;
    SVC_ASSIGN_OR_RETURN(encoded.faces[f], baseline::encode_sequence(frames, force, settings));
    return Status::Ok();
  }));
  return encoded;
}

Result<QualityPoint> Bench::measure_baseline(const CodecPlan& plan, int setting, baseline::EncodedDatabase* keep) {
  baseline::EncodeSettings settings = plan.base;
  settings.quantizer = setting;
  QualityPoint point;
  point.setting_name = plan.setting_name;
  point.setting = setting;
  const auto t0 = Clock::now();
  SVC_ASSIGN_OR_RETURN(baseline::EncodedDatabase encoded, encode_baseline(plan, settings));
  point.encode_seconds = seconds_since(t0);
  point.bytes = encoded.total_bytes();
  fill_rates(&point, source_.faces.size());

  const auto t1 = Clock::now();
  SVC_ASSIGN_OR_RETURN(const auto decoded, decode_every_face(encoded));
  point.decode_seconds = seconds_since(t1);
  std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>> pairs, predicted_pairs;
  for (Face f : kAllFaces) {
    const auto& frames = decoded[static_cast<int>(f)];
    const baseline::EncodedSequence& sequence = encoded.faces[static_cast<size_t>(f)];
    if (frames.size() != encoded.layout.cells.size()) {
      return Status(ErrorCode::kInternal, plan.name + ": decoded " + std::to_string(frames.size()) +
                                              " frames of face " + face_name(f) + ", expected " +
                                              std::to_string(encoded.layout.cells.size()));
    }
    for (size_t k = 0; k < frames.size(); ++k) {
      pairs.emplace_back(&source_.face(*source_.ordinal(encoded.layout.cells[k]), f), &frames[k]);
      const baseline::FrameRecord& record = sequence.frames[static_cast<size_t>(sequence.decode_position[k])];
      if (record.type == baseline::PictureType::kI) continue;
      predicted_pairs.push_back(pairs.back());
      point.b_face_bytes += record.size;
    }
  }
  SVC_ASSIGN_OR_RETURN(Score score, score_faces(pairs, threads_));
  point.psnr_rgb = score.psnr_rgb;
  point.psnr_y = score.psnr_y;
  point.ssim = score.ssim;
  if (!predicted_pairs.empty()) {
    SVC_ASSIGN_OR_RETURN(Score predicted, score_faces(predicted_pairs, threads_));
    point.b_face_psnr_y = predicted.psnr_y;
  }
  if (keep) *keep = std::move(encoded);
  return point;
}

int Bench::reference_index(const std::vector<QualityPoint>& points, std::optional<double> target) {
  if (points.empty()) return -1;
  if (!target) return static_cast<int>(points.size() / 2);
  int best = 0;
  for (size_t i = 1; i < points.size(); ++i) {
    if (std::abs(points[i].psnr_y - *target) < std::abs(points[best].psnr_y - *target)) best = static_cast<int>(i);
  }
  return best;
}

std::string Bench::reference_command(const CodecPlan& plan, int setting) const {
  return ffmpeg_command(plan, setting, "face/%04d.png", "out." + baseline::stream_extension(plan.encoder),
                        source_.manifest.grid.dims[0]);
}

std::string Bench::cache_key(const CodecPlan& plan) {
  if (source_fingerprint_.empty()) source_fingerprint_ = source_fingerprint(source_);
  return anchor_cache_key(source_fingerprint_, plan, options_.quick);
}

bool Bench::points_from_cache(const CodecPlan& plan, CodecResult* result) {
  if (options_.anchor_cache.empty()) return false;
  std::optional<std::vector<QualityPoint>> points = load_cached_points(options_.anchor_cache, cache_key(plan));
  if (!points) return false;
  result->points = std::move(*points);
  result->from_cache = true;
  result->reference_point = reference_index(result->points, svc_reference_psnr_);
  result->ffmpeg_command = reference_command(plan, result->points[result->reference_point].setting);
  for (const QualityPoint& p : result->points) log_point(plan.name + " (cached)", p);
  return true;
}

void Bench::store_in_cache(const CodecPlan& plan, const CodecResult& result) {
  if (options_.anchor_cache.empty()) return;
  const Status stored = store_cached_points(options_.anchor_cache, cache_key(plan), result.points);
  if (!stored.ok()) log(plan.name + ": not cached (" + stored.message() + ")");
}

Status Bench::run_baseline_codec(const CodecPlan& plan, CodecResult* result) {
  if (points_from_cache(plan, result)) return Status::Ok();
  // Every point's streams are kept (compressed, so small) until the reference point for
  // the access measurements is known.
  std::map<int, baseline::EncodedDatabase> encoded;
  auto measure = [&](int setting) -> Result<double> {
    SVC_ASSIGN_OR_RETURN(QualityPoint point, measure_baseline(plan, setting, &encoded[setting]));
    log_point(plan.name, point);
    result->points.push_back(point);
    return point.psnr_y;
  };
  SVC_RETURN_IF_ERROR(search_settings(plan.range, default_targets(options_.quick), measure).status());
  std::sort(result->points.begin(), result->points.end(),
            [](const QualityPoint& a, const QualityPoint& b) { return a.setting < b.setting; });
  store_in_cache(plan, *result);
  result->reference_point = reference_index(result->points, svc_reference_psnr_);
  const int setting = result->points[result->reference_point].setting;
  result->ffmpeg_command = reference_command(plan, setting);
  if (options_.measure_speed) {
    SVC_ASSIGN_OR_RETURN(const auto paths, baseline_access(plan, encoded.at(setting), result));
    speed_jobs_.push_back(baseline_speed_job(plan, setting, std::move(encoded.at(setting)), paths));
  }
  return Status::Ok();
}

Result<std::vector<ImageRGB8>> Bench::decode_every_face(Reader& reader) {
  const auto& cells = reader.cells();
  std::vector<ImageRGB8> decoded(cells.size() * kFaceCount);
  for (size_t frame = 0; frame < decoded.size(); ++frame) {
    SVC_ASSIGN_OR_RETURN(decoded[frame],
                         reader.decode_face(cells[frame / kFaceCount].index, kAllFaces[frame % kFaceCount]));
  }
  return decoded;
}

Result<std::array<std::vector<ImageRGB8>, kFaceCount>> Bench::decode_every_face(
    const baseline::EncodedDatabase& encoded) {
  std::array<std::vector<ImageRGB8>, kFaceCount> decoded;
  for (size_t f = 0; f < kFaceCount; ++f) {
    SVC_ASSIGN_OR_RETURN(decoded[f], baseline::decode_all(encoded.faces[f]));
  }
  return decoded;
}

void Bench::log_speed(const CodecResult& result) const {
  char line[384];
  std::snprintf(line, sizeof line,
                "%s: encode %.1f faces/s, decode %.1f faces/s (1 thread) %.1f (%d threads), random face cold %.2f "
                "ms (%.2f frames), warm %.2f ms, random cell cold %.2f ms (%.1f frames), warm %.2f ms",
                result.name.c_str(), result.encode_faces_per_second, result.decode_faces_per_second,
                result.decode_faces_per_second_all_threads, result.threads, result.access_cold.mean_ms,
                result.access_cold.mean_frames, result.access_warm.mean_ms, result.cell_cold.mean_ms,
                result.cell_cold.mean_frames, result.cell_warm.mean_ms);
  log(line);
}

Result<CodecResult> Bench::run_codec(const CodecPlan& plan) {
  CodecResult result;
  result.name = plan.name;
  result.encoder = plan.encoder;
  result.description = plan.description;
  result.threads = threads_;
  if (!plan.is_svc &&
      (!plan.unavailable.empty() || plan.encoder.empty() || !baseline::encoder_available(plan.encoder))) {
    result.skipped = true;
    result.skip_reason = !plan.unavailable.empty() ? plan.unavailable
                         : plan.encoder.empty()    ? "no AV1 encoder in this build of libavcodec"
                                                   : plan.encoder + " is not in this build of libavcodec";
    log(plan.name + ": skipped (" + result.skip_reason + ")");
    return result;
  }
  SVC_RETURN_IF_ERROR(plan.is_svc ? run_svc_codec(plan, &result) : run_baseline_codec(plan, &result));
  return result;
}

}  // namespace svc::bench
