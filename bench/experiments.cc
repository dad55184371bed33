// SPDX-License-Identifier: BSD-2-Clause
// The dissertation's experiments on the database at hand: Table 7.5 (sizes), Figure 7.16
// (compression against B:I ratio and sample spacing) and Table 7.4 (depth motion against
// logarithmic search).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bench_runner.h"

namespace svc::bench {

namespace {

SweepPoint sweep_point(const SvcRun& run, std::string label) {
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

const CodecResult* find_codec(const std::vector<CodecResult>& codecs, const std::string& name) {
  for (const CodecResult& c : codecs) {
    if (c.name == name && !c.skipped && !c.points.empty()) return &c;
  }
  return nullptr;
}

constexpr std::array<int32_t, 3> kDefaultISpacing{3, 1, 3};

}  // namespace

const SvcRun* Bench::find_run(int quality, std::array<int32_t, 3> i_spacing, MotionSearch motion,
                              int spacing) const {
  for (const SvcRun& run : svc_runs_) {
    const auto effective = run.settings.intra_only ? std::array<int32_t, 3>{1, 1, 1} : run.settings.i_spacing;
    if (run.settings.quality == quality && run.settings.qindex < 0 && effective == i_spacing &&
        run.settings.motion == motion && run.sample_spacing == spacing) {
      return &run;
    }
  }
  return nullptr;
}

Result<const SvcRun*> Bench::get_run(int quality, std::array<int32_t, 3> i_spacing, MotionSearch motion,
                                     int spacing) {
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

Status Bench::table_7_5(const std::vector<CodecResult>& codecs, Experiments* ex) {
  SVC_ASSIGN_OR_RETURN(const SvcRun* spatial, get_run(ex->quality, kDefaultISpacing, MotionSearch::kDepth, 1));
  const double target = spatial->point.psnr_y;
  ex->table_7_5.push_back({"raw", raw_bytes_, 99.0, "3 bytes per pixel"});
  if (const CodecResult* png = find_codec(codecs, "png")) {
    ex->table_7_5.push_back({"PNG", png->points[0].bytes, png->points[0].psnr_y, "lossless"});
  }
  for (const auto& [name, label] :
       std::vector<std::pair<std::string, std::string>>{{"jpeg", "JPEG"}, {"mpeg2", "MPEG-2 row-major"}}) {
    const CodecResult* c = find_codec(codecs, name);
    if (!c) continue;
    std::vector<RdPoint> rd;
    for (const QualityPoint& p : c->points) rd.push_back({p.setting, double(p.bytes), p.psnr_y, p.encode_seconds});
    const RdCurve curve(rd);
    char note[128];
    if (auto bytes = curve.bytes_at(target)) {
      std::snprintf(note, sizeof note, "at svc's PSNR-Y, interpolated on the %s curve", c->name.c_str());
      ex->table_7_5.push_back({label, static_cast<uint64_t>(std::llround(*bytes)), target, note});
    } else {
      const QualityPoint& p = c->points[reference_index(c->points, target)];
      std::snprintf(note, sizeof note, "%s %d (nearest point to svc's PSNR-Y)", p.setting_name.c_str(), p.setting);
      ex->table_7_5.push_back({label, p.bytes, p.psnr_y, note});
    }
  }
  ex->table_7_5.push_back({"spatial (svc)", spatial->point.bytes, spatial->point.psnr_y,
                           "quality " + std::to_string(ex->quality) + ", I-cubes every 3x1x3"});
  return Status::Ok();
}

Status Bench::figure_7_16(Experiments* ex) {
  const auto& dims = source_.manifest.grid.dims;
  for (std::array<int32_t, 3> spacing :
       std::vector<std::array<int32_t, 3>>{{1, 1, 1}, {3, 1, 2}, {3, 1, 3}, {6, 1, 3}, {9, 1, 3}}) {
    SVC_ASSIGN_OR_RETURN(const SvcRun* run, get_run(ex->quality, spacing, MotionSearch::kDepth, 1));
    SweepPoint p = sweep_point(*run, "");
    char label[64];
    std::snprintf(label, sizeof label, "B:I %.0f:1", p.b_to_i);
    p.label = label;
    ex->b_to_i_sweep.push_back(p);
    log("fig 7.16 " + p.label + " (I-spacing " + std::to_string(spacing[0]) + "," + std::to_string(spacing[1]) +
        "," + std::to_string(spacing[2]) + "): " + std::to_string(p.bytes) + " bytes, " +
        std::to_string(p.compression_ratio).substr(0, 5) + ":1");
  }
  for (int step : {1, 2, 3}) {
    // A step that leaves one cell per layer row has nothing to predict from.
    if (step > 1 && step >= std::max(dims[horizontal_[0]], dims[horizontal_[1]])) continue;
    SVC_ASSIGN_OR_RETURN(const SvcRun* run, get_run(ex->quality, kDefaultISpacing, MotionSearch::kDepth, step));
    ex->spacing_sweep.push_back(sweep_point(*run, "spacing " + std::to_string(step)));
    log("fig 7.16 sample spacing " + std::to_string(step) + ": " + std::to_string(run->summary.cells) + " cells, " +
        std::to_string(run->point.bytes) + " bytes, " + std::to_string(run->point.compression_ratio).substr(0, 5) +
        ":1");
  }
  return Status::Ok();
}

// Depth-based motion against logarithmic search, at equal PSNR-Y.
Status Bench::table_7_4(Experiments* ex) {
  const int q = ex->quality;
  const std::vector<int> qualities = options_.quick ? std::vector<int>{50, q} : std::vector<int>{55, q, 90};
  std::vector<RdCurve> curves;
  for (MotionSearch motion : {MotionSearch::kDepth, MotionSearch::kLogarithmic}) {
    MotionRow row;
    row.motion = motion == MotionSearch::kDepth ? "depth" : "logarithmic";
    std::vector<RdPoint> rd;
    for (int quality : qualities) {
      SVC_ASSIGN_OR_RETURN(const SvcRun* run, get_run(quality, kDefaultISpacing, motion, 1));
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
    ex->table_7_4.push_back(std::move(row));
    curves.emplace_back(rd);
  }
  // Compare at the depth run's PSNR at quality q, moved inside both curves if needed.
  const double lo = std::max(curves[0].min_psnr(), curves[1].min_psnr());
  const double hi = std::min(curves[0].max_psnr(), curves[1].max_psnr());
  if (hi >= lo) ex->equal_psnr_y = std::clamp(ex->equal_psnr_y, lo, hi);
  for (size_t i = 0; i < ex->table_7_4.size(); ++i) {
    ex->table_7_4[i].bytes_at_equal_psnr = curves[i].bytes_at(ex->equal_psnr_y).value_or(0);
  }
  return Status::Ok();
}

Result<Experiments> Bench::run_experiments(const std::vector<CodecResult>& codecs,
                                           std::vector<PartTiming>* timings) {
  Experiments ex;
  ex.quality = experiments_quality_;
  auto t0 = Clock::now();
  SVC_RETURN_IF_ERROR(table_7_5(codecs, &ex));
  ex.equal_psnr_y = ex.table_7_5.back().psnr_y;
  timings->push_back({"table 7.5", seconds_since(t0)});
  t0 = Clock::now();
  SVC_RETURN_IF_ERROR(figure_7_16(&ex));
  timings->push_back({"figure 7.16", seconds_since(t0)});
  t0 = Clock::now();
  SVC_RETURN_IF_ERROR(table_7_4(&ex));
  timings->push_back({"table 7.4", seconds_since(t0)});
  return ex;
}

}  // namespace svc::bench
