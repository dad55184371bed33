// Runs the measurements of `svc bench` (see svc_bench.h).
#include "svc_bench.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

#include "baseline/baseline.h"
#include "common/parallel.h"
#include "database/database.h"
#include "rd_curve.h"
#include "svc/encoder.h"
#include "svc/metrics.h"
#include "svc/reader.h"

namespace svc::bench {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The database's source faces, held in memory for scoring.
struct SourceFaces {
  DatabaseManifest manifest;
  std::vector<ImageRGB8> faces;  // cell ordinal * 6 + face
  const ImageRGB8& face(size_t cell, Face f) const { return faces[cell * kFaceCount + static_cast<size_t>(f)]; }
  std::optional<size_t> ordinal(const CellIndex& cell) const { return find_cell(manifest, cell); }
};

Result<SourceFaces> load_sources(const std::filesystem::path& db_dir, int threads) {
  SourceFaces source;
  SVC_ASSIGN_OR_RETURN(source.manifest, load_manifest(db_dir));
  source.faces.resize(source.manifest.cells.size() * kFaceCount);
  SVC_RETURN_IF_ERROR(parallel_for(source.faces.size(), threads, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(FaceData data, load_face(source.manifest, i / kFaceCount, kAllFaces[i % kFaceCount]));
    source.faces[i] = std::move(data.color);
    return Status::Ok();
  }));
  return source;
}

// Scores decoded faces against their sources: summed squared error, mean SSIM.
struct Score {
  double psnr_rgb = 0;
  double psnr_y = 0;
  double ssim = 0;
};

// `pairs` holds (source, decoded) per face.
Result<Score> score_faces(const std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>>& pairs, int threads) {
  std::vector<SquaredError> rgb(pairs.size()), luma(pairs.size());
  std::vector<double> ssim(pairs.size());
  SVC_RETURN_IF_ERROR(parallel_for(pairs.size(), threads, [&](size_t i) -> Status {
    SVC_ASSIGN_OR_RETURN(rgb[i], rgb_squared_error(*pairs[i].first, *pairs[i].second));
    SVC_ASSIGN_OR_RETURN(luma[i], luma_squared_error(*pairs[i].first, *pairs[i].second));
    SVC_ASSIGN_OR_RETURN(ssim[i], luma_ssim(*pairs[i].first, *pairs[i].second));
    return Status::Ok();
  }));
  SquaredError total_rgb, total_luma;
  double ssim_sum = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    total_rgb.add(rgb[i]);
    total_luma.add(luma[i]);
    ssim_sum += ssim[i];
  }
  Score score;
  score.psnr_rgb = total_rgb.psnr();
  score.psnr_y = total_luma.psnr();
  score.ssim = pairs.empty() ? 0 : ssim_sum / pairs.size();
  return score;
}

AccessStats summarize_access(std::vector<double> ms, const std::vector<int>& frames) {
  AccessStats stats;
  stats.samples = static_cast<int>(ms.size());
  if (ms.empty()) return stats;
  double sum = 0;
  for (double v : ms) sum += v;
  stats.mean_ms = sum / ms.size();
  std::sort(ms.begin(), ms.end());
  const size_t p99 = static_cast<size_t>(std::ceil(0.99 * ms.size())) - 1;
  stats.p99_ms = ms[std::min(p99, ms.size() - 1)];
  double frame_sum = 0;
  for (int f : frames) {
    frame_sum += f;
    stats.max_frames = std::max(stats.max_frames, f);
  }
  stats.mean_frames = frame_sum / frames.size();
  return stats;
}

struct Pick {
  size_t cell = 0;  // ordinal in the manifest
  Face face = Face::kPX;
};

std::vector<Pick> random_picks(size_t cells, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> cell_dist(0, cells - 1);
  std::uniform_int_distribution<int> face_dist(0, kFaceCount - 1);
  std::vector<Pick> picks(std::max(0, count));
  for (Pick& p : picks) {
    p.cell = cell_dist(rng);
    p.face = kAllFaces[face_dist(rng)];
  }
  return picks;
}

std::string face_label(Face f) { return face_name(f); }

// The two grid axes of a layer: subsampling thins these and keeps every layer.
std::array<int, 2> horizontal_axes(UpAxis up) {
  switch (up) {
    case UpAxis::kX: return {1, 2};
    case UpAxis::kZ: return {0, 1};
    default: return {0, 2};
  }
}

int& component(CellIndex& c, int axis) { return axis == 0 ? c.x : axis == 1 ? c.y : c.z; }

// ---------------------------------------------------------------------------------------
// Codec plans

struct CodecPlan {
  std::string name;
  std::string encoder;
  std::string description;
  std::string setting_name;
  std::vector<int> settings;
  // svc
  bool is_svc = false;
  bool svc_intra = false;
  // baseline
  baseline::CellOrder order = baseline::CellOrder::kRowMajor;
  baseline::EncodeSettings base;
  // The six face sequences may be encoded at once. Off for SVT-AV1, which runs its own
  // thread pool and whose library set-up is not safe to run twice concurrently.
  bool parallel_faces = true;
};

std::string pick_av1_encoder(int width, int height) {
  // Fastest first: the run has a time budget, and SVT-AV1 at preset 12 is many times
  // faster than libaom even at cpu-used 8. SVT-AV1 refuses frames under 64 pixels.
  for (const char* name : {"libsvtav1", "libaom-av1", "librav1e"}) {
    if (std::string(name) == "libsvtav1" && (width < 64 || height < 64)) continue;
    if (baseline::encoder_available(name)) return name;
  }
  return "";
}

CodecPlan make_plan(const std::string& name, bool quick, int width, int height) {
  CodecPlan plan;
  plan.name = name;
  auto pick = [&](std::vector<int> full, std::vector<int> fast) { plan.settings = quick ? fast : full; };
  if (name == "svc" || name == "svc-intra") {
    plan.is_svc = true;
    plan.svc_intra = name == "svc-intra";
    plan.encoder = "svc";
    plan.setting_name = "quality";
    plan.description = plan.svc_intra ? "every cell an I-cube" : "I-cubes every 3x1x3 cells, depth motion";
    pick({35, 50, 65, 75, 90}, {50, 75});
    return plan;
  }
  plan.base.gop_size = 6;
  plan.base.max_b_frames = 2;
  plan.base.threads = 1;
  if (name == "mpeg2" || name == "mpeg2-hilbert") {
    plan.encoder = "mpeg2video";
    plan.setting_name = "qscale";
    plan.order = name == "mpeg2" ? baseline::CellOrder::kRowMajor : baseline::CellOrder::kHilbert;
    plan.description = name == "mpeg2" ? "row-major, GOP IBBPBB, I at each row start"
                                       : "Hilbert order, GOP IBBPBB every 6 cells";
    pick({2, 3, 5, 8, 13}, {3, 8});
  } else if (name == "x264") {
    plan.encoder = "libx264";
    plan.setting_name = "crf";
    plan.base.codec_options = {{"preset", "fast"}};
    plan.description = "row-major, GOP 6 with 2 B, preset fast";
    pick({16, 21, 26, 31}, {21, 31});
  } else if (name == "x265") {
    plan.encoder = "libx265";
    plan.setting_name = "crf";
    plan.base.codec_options = {{"preset", "fast"}};
    plan.description = "row-major, GOP 6 with 2 B, preset fast";
    pick({20, 26, 32}, {24, 32});
  } else if (name == "av1") {
    plan.encoder = pick_av1_encoder(width, height);
    plan.base.max_b_frames = 0;
    if (plan.encoder == "librav1e") {
      plan.setting_name = "qp";
      plan.base.codec_options = {{"speed", "10"}};
      pick({60, 100, 140}, {80, 140});
    } else {
      plan.setting_name = "crf";
      if (plan.encoder == "libsvtav1") {
        plan.base.codec_options = {{"preset", "12"}};
        plan.parallel_faces = false;
      }
      if (plan.encoder == "libaom-av1") plan.base.codec_options = {{"cpu-used", "8"}};
      pick({24, 34, 44}, {30, 44});
    }
    plan.description = "row-major, GOP 6, " +
                       (plan.base.codec_options.empty() ? std::string("defaults")
                                                        : plan.base.codec_options.begin()->first + " " +
                                                              plan.base.codec_options.begin()->second);
  } else if (name == "jpeg") {
    plan.encoder = "mjpeg";
    plan.setting_name = "qscale";
    plan.base.gop_size = 1;
    plan.base.max_b_frames = 0;
    plan.description = "each face on its own (libavcodec mjpeg, 4:2:0)";
    pick({2, 3, 5, 8, 13}, {3, 8});
  } else if (name == "png") {
    plan.encoder = "png";
    plan.setting_name = "lossless";
    plan.base.gop_size = 1;
    plan.base.max_b_frames = 0;
    plan.description = "each face on its own, lossless";
    plan.settings = {0};
  }
  plan.base.codec = plan.encoder;
  return plan;
}

// ---------------------------------------------------------------------------------------
// One svc encode

struct SvcRun {
  EncoderSettings settings;
  int sample_spacing = 1;
  std::filesystem::path file;
  EncodeSummary summary;
  QualityPoint point;
  std::vector<size_t> ordinals;  // source ordinal of each cell of the encoded database
};

class Bench {
 public:
  Bench(const BenchOptions& options, SourceFaces source, int threads, Clock::time_point start)
      : options_(options), source_(std::move(source)), threads_(threads), start_(start) {
    work_dir_ = options_.out_dir / "work";
    horizontal_ = horizontal_axes(source_.manifest.up_axis);
    picks_ = random_picks(source_.manifest.cells.size(), options_.random_accesses, options_.seed);
    pixels_per_face_ = static_cast<uint64_t>(source_.manifest.face_width) * source_.manifest.face_height;
    raw_bytes_ = pixels_per_face_ * 3 * source_.faces.size();
  }

  uint64_t raw_bytes() const { return raw_bytes_; }

  void log(const std::string& line) const {
    if (!options_.progress) return;
    char prefix[32];
    std::snprintf(prefix, sizeof prefix, "[%6.1f s] ", seconds_since(start_));
    options_.progress(prefix + line);
  }

  void fill_rates(QualityPoint* p, uint64_t faces) const {
    p->compression_ratio = p->bytes ? static_cast<double>(pixels_per_face_ * 3 * faces) / p->bytes : 0;
    p->bits_per_pixel = faces ? 8.0 * p->bytes / (static_cast<double>(pixels_per_face_) * faces) : 0;
  }

  // Encodes the (possibly subsampled) database with svc, decodes every face in order
  // and scores it. With `reader_out`, the reader used for the sequential pass is kept.
  Result<SvcRun> run_svc(const EncoderSettings& settings, int sample_spacing, const std::string& tag,
                         std::unique_ptr<Reader>* reader_out = nullptr) {
    SvcRun run;
    run.settings = settings;
    run.settings.threads = threads_;
    run.sample_spacing = sample_spacing;
    std::filesystem::path db = options_.db_dir;
    if (sample_spacing > 1) {
      db = work_dir_ / ("subsampled-" + std::to_string(sample_spacing));
      SVC_RETURN_IF_ERROR(write_subsampled_manifest(options_.db_dir, sample_spacing, db));
    }
    run.file = work_dir_ / (tag + ".svc");
    SVC_ASSIGN_OR_RETURN(run.summary, encode_database(db, run.file, run.settings));
    run.point.setting_name = settings.quant_scale ? "qscale" : "quality";
    run.point.setting = settings.quant_scale ? settings.quant_scale : settings.quality;
    run.point.bytes = run.summary.file_bytes;
    run.point.encode_seconds = run.summary.seconds;
    fill_rates(&run.point, run.summary.faces);

    SVC_ASSIGN_OR_RETURN(std::unique_ptr<Reader> reader, Reader::open(run.file));
    const auto& cells = reader->cells();
    std::vector<ImageRGB8> decoded(cells.size() * kFaceCount);
    const auto t0 = Clock::now();
    for (size_t c = 0; c < cells.size(); ++c) {
      for (Face f : kAllFaces) {
        SVC_ASSIGN_OR_RETURN(decoded[c * kFaceCount + static_cast<size_t>(f)], reader->decode_face(cells[c].index, f));
      }
    }
    run.point.decode_seconds = seconds_since(t0);
    std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>> pairs;
    for (size_t c = 0; c < cells.size(); ++c) {
      CellIndex original = cells[c].index;
      for (int axis : horizontal_) component(original, axis) *= sample_spacing;
      const auto ordinal = source_.ordinal(original);
      if (!ordinal) {
        return Status(ErrorCode::kInternal, "svc bench: decoded cell " + cell_label(cells[c].index) + " of " +
                                                run.file.string() + " is not in the source database");
      }
      run.ordinals.push_back(*ordinal);
      for (Face f : kAllFaces) {
        pairs.emplace_back(&source_.face(*ordinal, f), &decoded[c * kFaceCount + static_cast<size_t>(f)]);
      }
    }
    SVC_ASSIGN_OR_RETURN(Score score, score_faces(pairs, threads_));
    run.point.psnr_rgb = score.psnr_rgb;
    run.point.psnr_y = score.psnr_y;
    run.point.ssim = score.ssim;
    if (reader_out) *reader_out = std::move(reader);
    return run;
  }

  Status svc_access(const SvcRun& run, Reader& warm_reader, CodecResult* result) {
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

  // The six face sequences in a coding order, encoded in parallel.
  Result<baseline::EncodedDatabase> encode_baseline(const CodecPlan& plan, const baseline::EncodeSettings& settings) {
    baseline::EncodedDatabase encoded;
    std::vector<CellIndex> cells;
    for (const CellSource& c : source_.manifest.cells) cells.push_back(c.index);
    const auto& d = source_.manifest.grid.dims;
    SVC_ASSIGN_OR_RETURN(encoded.layout, baseline::order_cells(cells, {d[0], d[1], d[2]}, plan.order,
                                                               std::max(1, settings.gop_size)));
    std::vector<size_t> ordinals;
    for (const CellIndex& c : encoded.layout.cells) ordinals.push_back(*source_.ordinal(c));
    SVC_RETURN_IF_ERROR(parallel_for(kFaceCount, plan.parallel_faces ? threads_ : 1, [&](size_t f) -> Status {
      baseline::FrameSource frames;
      frames.frame_count = static_cast<int>(ordinals.size());
      frames.width = source_.manifest.face_width;
      frames.height = source_.manifest.face_height;
      frames.load = [&, f](int k) -> Result<ImageRGB8> { return source_.face(ordinals[k], kAllFaces[f]); };
      SVC_ASSIGN_OR_RETURN(encoded.faces[f], baseline::encode_sequence(frames, encoded.layout.gop_start, settings));
      return Status::Ok();
    }));
    return encoded;
  }

  Result<QualityPoint> measure_baseline(const CodecPlan& plan, int setting, baseline::EncodedDatabase* keep) {
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

    std::array<std::vector<ImageRGB8>, kFaceCount> decoded;
    const auto t1 = Clock::now();
    for (Face f : kAllFaces) {
      SVC_ASSIGN_OR_RETURN(decoded[static_cast<int>(f)], baseline::decode_all(encoded.faces[static_cast<int>(f)]));
    }
    point.decode_seconds = seconds_since(t1);
    std::vector<std::pair<const ImageRGB8*, const ImageRGB8*>> pairs;
    for (Face f : kAllFaces) {
      const auto& frames = decoded[static_cast<int>(f)];
      if (frames.size() != encoded.layout.cells.size()) {
        return Status(ErrorCode::kInternal, plan.name + ": decoded " + std::to_string(frames.size()) +
                                                " frames of face " + face_label(f) + ", expected " +
                                                std::to_string(encoded.layout.cells.size()));
      }
      for (size_t k = 0; k < frames.size(); ++k) {
        pairs.emplace_back(&source_.face(*source_.ordinal(encoded.layout.cells[k]), f), &frames[k]);
      }
    }
    SVC_ASSIGN_OR_RETURN(Score score, score_faces(pairs, threads_));
    point.psnr_rgb = score.psnr_rgb;
    point.psnr_y = score.psnr_y;
    point.ssim = score.ssim;
    if (keep) *keep = std::move(encoded);
    return point;
  }

  Status baseline_access(const CodecPlan& plan, const baseline::EncodedDatabase& encoded, CodecResult* result) {
    // Stored as the baseline stores it: one elementary stream and index per face.
    const auto dir = work_dir_ / (plan.name + "-access");
    std::filesystem::create_directories(dir);
    std::array<std::filesystem::path, kFaceCount> paths;
    for (Face f : kAllFaces) {
      const int i = static_cast<int>(f);
      paths[i] = dir / (face_label(f) + "." + baseline::stream_extension(plan.encoder));
      SVC_RETURN_IF_ERROR(baseline::write_sequence(encoded.faces[i], paths[i]));
    }
    std::vector<double> cold_ms, warm_ms;
    std::vector<int> cold_frames, warm_frames;
    for (const Pick& p : picks_) {
      const int frame = encoded.layout.frame_of(source_.manifest.cells[p.cell].index);
      const auto t0 = Clock::now();
      SVC_ASSIGN_OR_RETURN(baseline::EncodedSequence sequence, baseline::read_sequence(paths[static_cast<int>(p.face)]));
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

  // Index of the point whose PSNR-Y is nearest `target`, or the middle one.
  static int reference_index(const std::vector<QualityPoint>& points, std::optional<double> target) {
    if (points.empty()) return -1;
    if (!target) return static_cast<int>(points.size() / 2);
    int best = 0;
    for (size_t i = 1; i < points.size(); ++i) {
      if (std::abs(points[i].psnr_y - *target) < std::abs(points[best].psnr_y - *target)) best = static_cast<int>(i);
    }
    return best;
  }

  Result<CodecResult> run_codec(const CodecPlan& plan) {
    CodecResult result;
    result.name = plan.name;
    result.encoder = plan.encoder;
    result.description = plan.description;
    result.threads = threads_;
    if (!plan.is_svc && (plan.encoder.empty() || !baseline::encoder_available(plan.encoder))) {
      result.skipped = true;
      result.skip_reason = plan.encoder.empty() ? "no AV1 encoder in this build of libavcodec"
                                                : plan.encoder + " is not in this build of libavcodec";
      log(plan.name + ": skipped (" + result.skip_reason + ")");
      return result;
    }
    if (plan.is_svc) {
      std::unique_ptr<Reader> reference_reader;
      size_t reference_run = 0;
      for (size_t k = 0; k < plan.settings.size(); ++k) {
        const int setting = plan.settings[k];
        EncoderSettings settings = default_encoder_settings();
        settings.quality = setting;
        settings.intra_only = plan.svc_intra;
        if (plan.svc_intra) settings.i_spacing = {1, 1, 1};
        std::unique_ptr<Reader> reader;
        SVC_ASSIGN_OR_RETURN(SvcRun run, run_svc(settings, 1, plan.name + "-q" + std::to_string(setting), &reader));
        log_point(plan.name, run.point);
        result.points.push_back(run.point);
        if (setting == experiments_quality_ || (reference_reader == nullptr && k + 1 == plan.settings.size())) {
          reference_reader = std::move(reader);
          reference_run = svc_runs_.size();
        }
        svc_runs_.push_back(std::move(run));
      }
      if (!reference_reader) {
        SVC_ASSIGN_OR_RETURN(reference_reader, Reader::open(svc_runs_[reference_run].file));
      }
      const SvcRun& run = svc_runs_[reference_run];
      result.reference_point = static_cast<int>(std::find_if(result.points.begin(), result.points.end(),
                                                              [&](const QualityPoint& p) {
                                                                return p.setting == run.point.setting;
                                                              }) -
                                                 result.points.begin());
      SVC_RETURN_IF_ERROR(svc_access(run, *reference_reader, &result));
      if (plan.name == "svc") svc_reference_psnr_ = run.point.psnr_y;
    } else {
      // Every point's streams are kept (compressed, so small) until the reference point
      // for the access measurements is known.
      std::vector<baseline::EncodedDatabase> encoded(plan.settings.size());
      for (size_t k = 0; k < plan.settings.size(); ++k) {
        SVC_ASSIGN_OR_RETURN(QualityPoint point, measure_baseline(plan, plan.settings[k], &encoded[k]));
        log_point(plan.name, point);
        result.points.push_back(point);
      }
      result.reference_point = reference_index(result.points, svc_reference_psnr_);
      SVC_RETURN_IF_ERROR(baseline_access(plan, encoded[result.reference_point], &result));
    }
    const QualityPoint& ref = result.points[result.reference_point];
    const double faces = static_cast<double>(source_.faces.size());
    result.encode_faces_per_second = ref.encode_seconds > 0 ? faces / ref.encode_seconds : 0;
    result.decode_faces_per_second = ref.decode_seconds > 0 ? faces / ref.decode_seconds : 0;
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s: encode %.1f faces/s, decode %.1f faces/s, random face cold %.2f ms (%.2f frames), warm %.2f ms",
                  plan.name.c_str(), result.encode_faces_per_second, result.decode_faces_per_second,
                  result.access_cold.mean_ms, result.access_cold.mean_frames, result.access_warm.mean_ms);
    log(line);
    return result;
  }

  void log_point(const std::string& codec, const QualityPoint& p) const {
    char line[256];
    std::snprintf(line, sizeof line, "%s %s %d: %llu bytes (%.1f:1, %.3f bpp), PSNR-Y %.2f dB, RGB %.2f dB, SSIM %.4f, %.1f s",
                  codec.c_str(), p.setting_name.c_str(), p.setting, static_cast<unsigned long long>(p.bytes),
                  p.compression_ratio, p.bits_per_pixel, p.psnr_y, p.psnr_rgb, p.ssim, p.encode_seconds);
    log(line);
  }

  // A finished svc run with these settings on the full (or subsampled) database, if any.
  const SvcRun* find_run(int quality, std::array<int32_t, 3> i_spacing, MotionSearch motion, int spacing) const {
    for (const SvcRun& run : svc_runs_) {
      const auto effective = run.settings.intra_only ? std::array<int32_t, 3>{1, 1, 1} : run.settings.i_spacing;
      if (run.settings.quality == quality && run.settings.quant_scale == 0 && effective == i_spacing &&
          run.settings.motion == motion && run.sample_spacing == spacing) {
        return &run;
      }
    }
    return nullptr;
  }

  Result<const SvcRun*> get_run(int quality, std::array<int32_t, 3> i_spacing, MotionSearch motion, int spacing) {
    if (const SvcRun* run = find_run(quality, i_spacing, motion, spacing)) return run;
    EncoderSettings settings = default_encoder_settings();
    settings.quality = quality;
    settings.i_spacing = i_spacing;
    settings.motion = motion;
    std::string tag = "exp-q" + std::to_string(quality) + "-i" + std::to_string(i_spacing[0]) + "_" +
                      std::to_string(i_spacing[1]) + "_" + std::to_string(i_spacing[2]) + "-s" +
                      std::to_string(spacing) + (motion == MotionSearch::kLogarithmic ? "-log" : "");
    SVC_ASSIGN_OR_RETURN(SvcRun run, run_svc(settings, spacing, tag));
    svc_runs_.push_back(std::move(run));
    return &svc_runs_.back();
  }

  static SweepPoint sweep_point(const SvcRun& run, std::string label) {
    SweepPoint p;
    p.label = std::move(label);
    p.i_spacing = run.settings.i_spacing;
    p.sample_spacing = run.sample_spacing;
    p.cells = run.summary.cells;
    p.i_faces = run.summary.intra.faces;
    p.b_faces = run.summary.predicted.faces;
    p.b_to_i = p.i_faces ? static_cast<double>(p.b_faces) / p.i_faces : 0;
    p.bytes = run.point.bytes;
    p.compression_ratio = run.point.compression_ratio;
    p.psnr_y = run.point.psnr_y;
    return p;
  }

  Result<Experiments> run_experiments(const std::vector<CodecResult>& codecs, std::vector<PartTiming>* timings) {
    Experiments ex;
    ex.quality = experiments_quality_;
    const int q = ex.quality;
    const std::array<int32_t, 3> default_spacing{3, 1, 3};

    // Table 7.5.
    auto t0 = Clock::now();
    SVC_ASSIGN_OR_RETURN(const SvcRun* spatial, get_run(q, default_spacing, MotionSearch::kDepth, 1));
    const double target = spatial->point.psnr_y;
    ex.table_7_5.push_back({"raw", raw_bytes_, 99.0, "3 bytes per pixel"});
    auto codec = [&](const std::string& name) -> const CodecResult* {
      for (const CodecResult& c : codecs) {
        if (c.name == name && !c.skipped && !c.points.empty()) return &c;
      }
      return nullptr;
    };
    if (const CodecResult* png = codec("png")) {
      ex.table_7_5.push_back({"PNG", png->points[0].bytes, png->points[0].psnr_y, "lossless"});
    }
    for (const auto& [name, label] : std::vector<std::pair<std::string, std::string>>{
             {"jpeg", "JPEG"}, {"mpeg2", "MPEG-2 row-major"}}) {
      const CodecResult* c = codec(name);
      if (!c) continue;
      std::vector<RdPoint> rd;
      for (const QualityPoint& p : c->points) rd.push_back({p.setting, double(p.bytes), p.psnr_y, p.encode_seconds});
      const RdCurve curve(rd);
      char note[128];
      if (auto bytes = curve.bytes_at(target)) {
        std::snprintf(note, sizeof note, "at svc's PSNR-Y, interpolated on the %s curve", c->name.c_str());
        ex.table_7_5.push_back({label, static_cast<uint64_t>(std::llround(*bytes)), target, note});
      } else {
        const QualityPoint& p = c->points[reference_index(c->points, target)];
        std::snprintf(note, sizeof note, "%s %d (nearest point to svc's PSNR-Y)", p.setting_name.c_str(), p.setting);
        ex.table_7_5.push_back({label, p.bytes, p.psnr_y, note});
      }
    }
    ex.table_7_5.push_back({"spatial (svc)", spatial->point.bytes, spatial->point.psnr_y,
                            "quality " + std::to_string(q) + ", I-cubes every 3x1x3"});
    timings->push_back({"table 7.5", seconds_since(t0)});

    // Figure 7.16: B:I ratio, then sample spacing.
    t0 = Clock::now();
    const auto& dims = source_.manifest.grid.dims;
    for (std::array<int32_t, 3> spacing : std::vector<std::array<int32_t, 3>>{
             {1, 1, 1}, {3, 1, 2}, {3, 1, 3}, {6, 1, 3}, {9, 1, 3}}) {
      SVC_ASSIGN_OR_RETURN(const SvcRun* run, get_run(q, spacing, MotionSearch::kDepth, 1));
      SweepPoint p = sweep_point(*run, "");
      char label[64];
      std::snprintf(label, sizeof label, "B:I %.0f:1", p.b_to_i);
      p.label = label;
      ex.b_to_i_sweep.push_back(p);
      log("fig 7.16 " + p.label + " (I-spacing " + std::to_string(spacing[0]) + "," + std::to_string(spacing[1]) +
          "," + std::to_string(spacing[2]) + "): " + std::to_string(p.bytes) + " bytes, " +
          std::to_string(p.compression_ratio).substr(0, 5) + ":1");
    }
    for (int step : {1, 2, 3}) {
      // A step that leaves one cell per layer row has nothing to predict from.
      if (step > 1 && step >= std::max(dims[horizontal_[0]], dims[horizontal_[1]])) continue;
      SVC_ASSIGN_OR_RETURN(const SvcRun* run, get_run(q, default_spacing, MotionSearch::kDepth, step));
      ex.spacing_sweep.push_back(sweep_point(*run, "spacing " + std::to_string(step)));
      log("fig 7.16 sample spacing " + std::to_string(step) + ": " + std::to_string(run->summary.cells) + " cells, " +
          std::to_string(run->point.bytes) + " bytes, " + std::to_string(run->point.compression_ratio).substr(0, 5) +
          ":1");
    }
    timings->push_back({"figure 7.16", seconds_since(t0)});

    // Table 7.4: depth-based motion against logarithmic search, at equal PSNR-Y.
    t0 = Clock::now();
    const std::vector<int> qualities = options_.quick ? std::vector<int>{50, q} : std::vector<int>{55, q, 90};
    ex.equal_psnr_y = target;
    for (MotionSearch motion : {MotionSearch::kDepth, MotionSearch::kLogarithmic}) {
      MotionRow row;
      row.motion = motion == MotionSearch::kDepth ? "depth" : "logarithmic";
      std::vector<RdPoint> rd;
      for (int quality : qualities) {
        SVC_ASSIGN_OR_RETURN(const SvcRun* run, get_run(quality, default_spacing, motion, 1));
        row.points.push_back(run->point);
        rd.push_back({quality, double(run->point.bytes), run->point.psnr_y, run->point.encode_seconds});
        if (quality == q) {
          row.encode_seconds = run->point.encode_seconds;
          const FaceTypeStats& s = run->summary.predicted;
          row.candidates_per_macroblock =
              s.candidate_macroblocks ? static_cast<double>(s.candidate_vectors) / s.candidate_macroblocks : 0;
        }
        if (motion == MotionSearch::kLogarithmic) log_point("svc (logarithmic search)", run->point);
      }
      ex.table_7_4.push_back(std::move(row));
      curves_74_.emplace_back(rd);
    }
    // Compare at the depth run's PSNR at quality q, moved inside both curves if needed.
    double lo = std::max(curves_74_[0].min_psnr(), curves_74_[1].min_psnr());
    double hi = std::min(curves_74_[0].max_psnr(), curves_74_[1].max_psnr());
    if (hi >= lo) ex.equal_psnr_y = std::clamp(target, lo, hi);
    for (size_t i = 0; i < ex.table_7_4.size(); ++i) {
      ex.table_7_4[i].bytes_at_equal_psnr = curves_74_[i].bytes_at(ex.equal_psnr_y).value_or(0);
    }
    timings->push_back({"table 7.4", seconds_since(t0)});
    return ex;
  }

  void remove_work_dir() const {
    std::error_code ec;
    std::filesystem::remove_all(work_dir_, ec);
  }
  const std::filesystem::path& work_dir() const { return work_dir_; }

 private:
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
  std::vector<RdCurve> curves_74_;
  std::optional<double> svc_reference_psnr_;
  int experiments_quality_ = 75;
};

}  // namespace

const std::vector<std::string>& all_codec_names() {
  static const std::vector<std::string> kNames = {"svc",  "svc-intra", "mpeg2", "mpeg2-hilbert", "x264",
                                                  "x265", "av1",       "jpeg",  "png"};
  return kNames;
}

Result<BenchResults> run_bench(const BenchOptions& options) {
  const auto start = Clock::now();
  std::vector<std::string> codecs = options.codecs.empty() ? all_codec_names() : options.codecs;
  for (const std::string& name : codecs) {
    if (std::find(all_codec_names().begin(), all_codec_names().end(), name) == all_codec_names().end()) {
      return Status(ErrorCode::kInvalidArgument, "svc bench: unknown codec '" + name + "'");
    }
  }
  // Report order, svc first: the other codecs pick their reference point by svc's PSNR.
  std::vector<std::string> ordered;
  for (const std::string& name : all_codec_names()) {
    if (std::find(codecs.begin(), codecs.end(), name) != codecs.end()) ordered.push_back(name);
  }
  if (options.random_accesses < 1) {
    return Status(ErrorCode::kInvalidArgument, "svc bench: random_accesses must be at least 1");
  }
  const int threads = resolve_thread_count(options.threads);

  std::error_code ec;
  std::filesystem::create_directories(options.out_dir / "work", ec);
  if (ec) return Status(ErrorCode::kIoError, "cannot create " + (options.out_dir / "work").string() + ": " + ec.message());

  BenchResults results;
  results.database = options.db_dir.string();
  results.threads = threads;
  auto t0 = Clock::now();
  SVC_ASSIGN_OR_RETURN(SourceFaces source, load_sources(options.db_dir, threads));
  results.grid = {source.manifest.grid.dims[0], source.manifest.grid.dims[1], source.manifest.grid.dims[2]};
  results.cells = source.manifest.cells.size();
  results.faces = source.faces.size();
  results.face_width = source.manifest.face_width;
  results.face_height = source.manifest.face_height;
  results.timings.push_back({"load faces", seconds_since(t0)});

  Bench bench(options, std::move(source), threads, start);
  results.raw_bytes = bench.raw_bytes();
  bench.log("loaded " + std::to_string(results.cells) + " cells, " + std::to_string(results.faces) + " faces of " +
            std::to_string(results.face_width) + "x" + std::to_string(results.face_height) + " from " +
            options.db_dir.string());

  Status status = Status::Ok();
  for (const std::string& name : ordered) {
    t0 = Clock::now();
    bench.log(name + ": quality sweep");
    auto result = bench.run_codec(make_plan(name, options.quick, results.face_width, results.face_height));
    if (!result.ok()) {
      status = result.status().with_context("svc bench: " + name);
      break;
    }
    results.codecs.push_back(std::move(result).value());
    results.timings.push_back({name, seconds_since(t0)});
  }

  // BD-rate of svc against each other codec, on PSNR-Y.
  const CodecResult* svc = nullptr;
  for (const CodecResult& c : results.codecs) {
    if (c.name == "svc") svc = &c;
  }
  if (status.ok() && svc && svc->points.size() >= 2) {
    auto curve = [](const CodecResult& c) {
      std::vector<RdPoint> rd;
      for (const QualityPoint& p : c.points) rd.push_back({p.setting, double(p.bytes), p.psnr_y, p.encode_seconds});
      return RdCurve(rd);
    };
    const RdCurve svc_curve = curve(*svc);
    for (CodecResult& c : results.codecs) {
      if (c.skipped || c.points.size() < 2 || &c == svc) continue;
      if (auto ratio = bd_rate_ratio(curve(c), svc_curve)) c.bd_rate_svc = *ratio - 1;
    }
  }

  if (status.ok() && options.experiments && svc) {
    bench.log("dissertation experiments: table 7.5, figure 7.16, table 7.4");
    auto experiments = bench.run_experiments(results.codecs, &results.timings);
    if (experiments.ok()) {
      results.experiments = std::move(experiments).value();
    } else {
      status = experiments.status().with_context("svc bench: experiments");
    }
  } else if (status.ok() && options.experiments) {
    bench.log("dissertation experiments skipped: they need the svc codec in --codecs");
  }
  bench.remove_work_dir();
  SVC_RETURN_IF_ERROR(status);
  results.total_seconds = seconds_since(start);
  return results;
}

Status write_subsampled_manifest(const std::filesystem::path& db_dir, int step, const std::filesystem::path& out_dir) {
  if (step < 1) return Status(ErrorCode::kInvalidArgument, "subsampling step must be at least 1, not " + std::to_string(step));
  SVC_ASSIGN_OR_RETURN(DatabaseManifest manifest, load_manifest(db_dir));
  const std::filesystem::path manifest_path =
      std::filesystem::is_directory(db_dir) ? db_dir / "manifest.json" : db_dir;
  std::ifstream in(manifest_path);
  nlohmann::ordered_json doc;
  try {
    in >> doc;
  } catch (const std::exception& e) {
    return Status(ErrorCode::kBadInput, manifest_path.string() + ": " + e.what());
  }
  const auto root = std::filesystem::absolute(manifest.root);
  const std::array<int, 2> axes = horizontal_axes(manifest.up_axis);
  auto absolute = [&](const nlohmann::ordered_json& value) {
    const std::filesystem::path p = value.get<std::string>();
    return p.is_absolute() ? p.string() : (root / p).lexically_normal().string();
  };
  nlohmann::ordered_json cells = nlohmann::ordered_json::array();
  try {
    for (const auto& cell : doc.at("cells")) {
      const auto& index = cell.at("index");
      std::array<int, 3> i{index.at(0).get<int>(), index.at(1).get<int>(), index.at(2).get<int>()};
      if (i[axes[0]] % step != 0 || i[axes[1]] % step != 0) continue;
      i[axes[0]] /= step;
      i[axes[1]] /= step;
      nlohmann::ordered_json copy = cell;
      copy["index"] = i;
      for (auto& [face, entry] : copy.at("faces").items()) {
        (void)face;
        for (const char* key : {"color", "depth"}) {
          if (entry.contains(key)) entry[key] = absolute(entry[key]);
        }
      }
      cells.push_back(std::move(copy));
    }
    if (cells.empty()) {
      return Status(ErrorCode::kInvalidArgument,
                    "subsampling " + db_dir.string() + " every " + std::to_string(step) + " cells leaves no cell");
    }
    auto& grid = doc.at("grid");
    for (int axis : axes) {
      const int dim = grid.at("dims").at(axis).get<int>();
      grid["dims"][axis] = (dim + step - 1) / step;
      grid["spacing"][axis] = grid.at("spacing").at(axis).get<double>() * step;
    }
  } catch (const std::exception& e) {
    return Status(ErrorCode::kBadInput, manifest_path.string() + ": " + e.what());
  }
  doc["cells"] = std::move(cells);
  doc["subsampled_from"] = root.string();
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  std::ofstream out(out_dir / "manifest.json");
  out << doc.dump(1) << "\n";
  out.close();
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + (out_dir / "manifest.json").string());
  return Status::Ok();
}

}  // namespace svc::bench
