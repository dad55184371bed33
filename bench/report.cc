// SPDX-License-Identifier: BSD-2-Clause
// results.json, results.csv, plots and report.md of `svc bench` (see svc_bench.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plot.h"
#include "point_json.h"
#include "svc_bench.h"

namespace svc::bench {

namespace {

using json = nlohmann::ordered_json;

std::string format(const char* fmt, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
}

std::string human_bytes(double bytes) {
  if (bytes >= 1024.0 * 1024.0) return format("%.2f MiB", bytes / (1024.0 * 1024.0));
  if (bytes >= 1024.0) return format("%.1f KiB", bytes / 1024.0);
  return format("%.0f B", bytes);
}

json access_json(const AccessStats& a) {
  return {{"samples", a.samples},
          {"mean_ms", a.mean_ms},
          {"p99_ms", a.p99_ms},
          {"mean_frames_decoded", a.mean_frames},
          {"max_frames_decoded", a.max_frames}};
}

json sweep_json(const SweepPoint& p) {
  return {{"label", p.label},   {"i_spacing", p.i_spacing}, {"sample_spacing", p.sample_spacing},
          {"cells", p.cells},   {"i_faces", p.i_faces},     {"b_faces", p.b_faces},
          {"b_to_i", p.b_to_i}, {"bytes", p.bytes},         {"compression_ratio", p.compression_ratio},
          {"psnr_y", p.psnr_y}};
}

Status write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) return Status(ErrorCode::kIoError, "cannot write " + path.string());
  return Status::Ok();
}

bool plottable(const CodecResult& c) {
  if (c.skipped || c.points.empty()) return false;
  for (const QualityPoint& p : c.points) {
    if (p.psnr_y >= 99.0) return false;  // lossless: no place on a PSNR axis
  }
  return true;
}

std::string setting_text(const QualityPoint& p) {
  return p.setting_name == "lossless" ? "lossless" : p.setting_name + " " + std::to_string(p.setting);
}

// Speed and access were measured: not read from the anchor cache, not run with --no-speed.
bool speed_measured(const CodecResult& c) { return !c.from_cache && c.access_cold.samples > 0; }

std::string psnr_text(double psnr) { return psnr >= 99.0 ? "lossless" : format("%.2f", psnr); }

}  // namespace

Status write_results_json(const BenchResults& r, const std::filesystem::path& path) {
  json j;
  j["format"] = "svc-bench";
  j["version"] = 1;
  j["database"] = {{"path", r.database},
                   {"grid", r.grid},
                   {"cells", r.cells},
                   {"faces", r.faces},
                   {"face_size", {r.face_width, r.face_height}},
                   {"raw_bytes", r.raw_bytes}};
  j["content"] = {{"mean_luma", r.content.mean_luma},
                  {"luma_contrast", r.content.luma_contrast},
                  {"mean_gradient", r.content.mean_gradient},
                  {"background_share", r.content.background_share}};
  j["threads"] = r.threads;
  j["bd_reference"] = r.bd_reference.empty() ? json(nullptr) : json(r.bd_reference);
  j["total_seconds"] = r.total_seconds;
  json timings = json::array();
  for (const PartTiming& t : r.timings) timings.push_back({{"part", t.part}, {"seconds", t.seconds}});
  j["timings"] = timings;
  json codecs = json::array();
  for (const CodecResult& c : r.codecs) {
    json cj;
    cj["name"] = c.name;
    cj["encoder"] = c.encoder;
    cj["description"] = c.description;
    cj["skipped"] = c.skipped;
    if (c.skipped) {
      cj["skip_reason"] = c.skip_reason;
      codecs.push_back(cj);
      continue;
    }
    json points = json::array();
    for (const QualityPoint& p : c.points) points.push_back(point_json(p));
    cj["points"] = points;
    cj["reference_point"] = c.reference_point;
    cj["from_cache"] = c.from_cache;
    cj["threads"] = c.threads;
    cj["speed"] = {{"encode_faces_per_second", c.encode_faces_per_second},
                   {"decode_faces_per_second", c.decode_faces_per_second},
                   {"decode_faces_per_second_all_threads", c.decode_faces_per_second_all_threads}};
    cj["random_access"] = {{"cold", access_json(c.access_cold)}, {"warm", access_json(c.access_warm)}};
    cj["random_cell_access"] = {{"cold", access_json(c.cell_cold)}, {"warm", access_json(c.cell_warm)}};
    cj["bd_rate_svc"] = c.bd_rate_svc ? json(*c.bd_rate_svc) : json(nullptr);
    cj["bd_range_psnr_y"] = c.bd_rate_svc ? json(c.bd_range_y) : json(nullptr);
    cj["bd_rate_svc_target"] = c.bd_rate_svc_target ? json(*c.bd_rate_svc_target) : json(nullptr);
    cj["bd_range_target"] = c.bd_rate_svc_target ? json(c.bd_range_target) : json(nullptr);
    cj["bd_rate_svc_intra_target"] = c.bd_rate_svc_intra_target ? json(*c.bd_rate_svc_intra_target) : json(nullptr);
    cj["bd_rate_svc_rgb"] = c.bd_rate_svc_rgb ? json(*c.bd_rate_svc_rgb) : json(nullptr);
    cj["bd_range_psnr_rgb"] = c.bd_rate_svc_rgb ? json(c.bd_range_rgb) : json(nullptr);
    cj["ffmpeg_command"] = c.ffmpeg_command;
    codecs.push_back(cj);
  }
  j["codecs"] = codecs;
  if (r.experiments) {
    const Experiments& e = *r.experiments;
    json ej;
    ej["quality"] = e.quality;
    json sizes = json::array();
    for (const SizeRow& row : e.table_7_5) {
      sizes.push_back({{"name", row.name}, {"bytes", row.bytes}, {"psnr_y", row.psnr_y}, {"note", row.note}});
    }
    ej["table_7_5"] = sizes;
    json b = json::array(), s = json::array();
    for (const SweepPoint& p : e.b_to_i_sweep) b.push_back(sweep_json(p));
    for (const SweepPoint& p : e.spacing_sweep) s.push_back(sweep_json(p));
    ej["figure_7_16"] = {{"b_to_i", b}, {"sample_spacing", s}};
    json rows = json::array();
    for (const MotionRow& row : e.table_7_4) {
      json points = json::array();
      for (const QualityPoint& p : row.points) points.push_back(point_json(p));
      rows.push_back({{"motion", row.motion},
                      {"bytes_at_equal_psnr", row.bytes_at_equal_psnr},
                      {"encode_seconds", row.encode_seconds},
                      {"candidates_per_macroblock", row.candidates_per_macroblock},
                      {"points", points}});
    }
    ej["table_7_4"] = {{"equal_psnr_y", e.equal_psnr_y}, {"rows", rows}};
    j["experiments"] = ej;
  } else {
    j["experiments"] = nullptr;
  }
  json ablation = json::array();
  for (const AblationRow& row : r.ablation) {
    json points = json::array();
    for (const QualityPoint& p : row.points) points.push_back(point_json(p));
    ablation.push_back({{"tool", row.tool},
                        {"bd_rate_psnr_y", row.bd_rate_y ? json(*row.bd_rate_y) : json(nullptr)},
                        {"encode_seconds", row.encode_seconds},
                        {"points", points}});
  }
  j["ablation"] = ablation;
  if (r.before) {
    auto optional_json = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
    j["before"] = {{"results", r.before->results},
                   {"bd_rate_psnr_y", optional_json(r.before->bd_rate_y)},
                   {"b_faces_bd_rate_psnr_y", optional_json(r.before->b_faces_bd_rate)}};
  } else {
    j["before"] = nullptr;
  }
  return write_text(path, j.dump(2) + "\n");
}

Status write_results_csv(const BenchResults& r, const std::filesystem::path& path) {
  std::ostringstream out;
  out << "codec,encoder,setting_name,setting,bytes,compression_ratio,bits_per_pixel,psnr_rgb,psnr_y,ssim,"
         "encode_seconds,decode_seconds\n";
  char line[512];
  for (const CodecResult& c : r.codecs) {
    for (const QualityPoint& p : c.points) {
      std::snprintf(line, sizeof line, "%s,%s,%s,%d,%llu,%.4f,%.5f,%.4f,%.4f,%.5f,%.4f,%.4f\n", c.name.c_str(),
                    c.encoder.c_str(), p.setting_name.c_str(), p.setting, static_cast<unsigned long long>(p.bytes),
                    p.compression_ratio, p.bits_per_pixel, p.psnr_rgb, p.psnr_y, p.ssim, p.encode_seconds,
                    p.decode_seconds);
      out << line;
    }
  }
  return write_text(path, out.str());
}

Status write_plots(const BenchResults& r, const std::filesystem::path& directory) {
  // Rate-distortion: PSNR-Y and SSIM against bits per pixel.
  {
    plot::LineChart psnr, ssim;
    psnr.title = "PSNR-Y against rate";
    psnr.x = {"bits per pixel", true, {}, {}};
    psnr.y = {"PSNR-Y (dB)", false, {}, {}};
    ssim.title = "SSIM against rate";
    ssim.x = psnr.x;
    ssim.y = {"SSIM (luma)", false, {}, {}};
    for (size_t i = 0; i < r.codecs.size(); ++i) {
      const CodecResult& c = r.codecs[i];
      if (!plottable(c)) continue;
      plot::Series a, b;
      a.label = b.label = c.name;
      a.color = b.color = plot::palette(i);
      a.dashed = b.dashed = c.name.rfind("svc", 0) != 0 && c.name.rfind("mpeg2", 0) != 0;
      for (const QualityPoint& p : c.points) {
        a.points.emplace_back(p.bits_per_pixel, p.psnr_y);
        b.points.emplace_back(p.bits_per_pixel, p.ssim);
      }
      std::sort(a.points.begin(), a.points.end());
      std::sort(b.points.begin(), b.points.end());
      psnr.series.push_back(a);
      ssim.series.push_back(b);
    }
    plot::Canvas canvas(1600, 640);
    plot::draw_line_chart(canvas, {0, 0, 800, 640}, psnr);
    plot::draw_line_chart(canvas, {800, 0, 800, 640}, ssim);
    SVC_RETURN_IF_ERROR(plot::write_png(canvas, directory / "rd_curves.png"));
  }
  // Random access: mean time per random face, cold and warm, frames decoded above.
  {
    plot::BarChart chart;
    chart.title = "Random access: one random face (bars: mean ms; labels: frames decoded)";
    chart.y_label = "mean time per face (ms)";
    chart.log_y = true;
    chart.series_labels = {"cold", "warm"};
    for (const CodecResult& c : r.codecs) {
      if (c.skipped || c.points.empty() || !speed_measured(c)) continue;
      plot::BarGroup g;
      g.label = c.name;
      g.values = {c.access_cold.mean_ms, c.access_warm.mean_ms};
      g.annotations = {format("%.2f f", c.access_cold.mean_frames), format("%.2f f", c.access_warm.mean_frames)};
      chart.groups.push_back(g);
    }
    plot::Canvas canvas(1400, 640);
    plot::draw_bar_chart(canvas, {0, 0, 1400, 640}, chart);
    SVC_RETURN_IF_ERROR(plot::write_png(canvas, directory / "access_cost.png"));
  }
  // Figure 7.16: compression against B:I ratio and against sample spacing.
  if (r.experiments) {
    const Experiments& e = *r.experiments;
    plot::LineChart bi, spacing;
    bi.title = "Compression against B:I ratio (quality " + std::to_string(e.quality) + ")";
    bi.x = {"B-faces per I-face", false, {}, {}};
    bi.y = {"compression ratio (x:1)", false, 0.0, {}};
    plot::Series s{"svc", {}, false, plot::palette(0)};
    for (const SweepPoint& p : e.b_to_i_sweep) s.points.emplace_back(p.b_to_i, p.compression_ratio);
    std::sort(s.points.begin(), s.points.end());
    bi.series.push_back(s);
    spacing.title = "Compression against sample spacing";
    spacing.x = {"sample spacing (cells)", false, 0.5, {}};
    spacing.y = {"compression ratio (x:1)", false, 0.0, {}};
    plot::Series t{"svc, I every 3x1x3", {}, false, plot::palette(1)};
    for (const SweepPoint& p : e.spacing_sweep) t.points.emplace_back(p.sample_spacing, p.compression_ratio);
    spacing.series.push_back(t);
    if (!spacing.series[0].points.empty()) {
      spacing.x.max = spacing.series[0].points.back().first + 0.5;
    }
    plot::Canvas canvas(1500, 600);
    plot::draw_line_chart(canvas, {0, 0, 750, 600}, bi);
    plot::draw_line_chart(canvas, {750, 0, 750, 600}, spacing);
    SVC_RETURN_IF_ERROR(plot::write_png(canvas, directory / "fig7_16.png"));
  }
  return Status::Ok();
}

std::string summary_table_markdown(const BenchResults& r) {
  std::ostringstream md;
  md << "| codec | setting | size | ratio | bpp | PSNR-Y dB | PSNR-RGB dB | SSIM | BD-rate of "
     << (r.bd_reference.empty() ? std::string("svc") : r.bd_reference)
     << " | encode faces/s "
        "|"
        " decode faces/s | random face cold ms (frames) | warm ms (frames) |\n";
  md << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const CodecResult& c : r.codecs) {
    if (c.skipped) {
      md << "| " << c.name << " | skipped: " << c.skip_reason << " | | | | | | | | | | | |\n";
      continue;
    }
    if (c.reference_point < 0) continue;
    const QualityPoint& p = c.points[c.reference_point];
    md << "| " << c.name << " | " << setting_text(p) << " | " << human_bytes(double(p.bytes)) << " | "
       << format("%.1f", p.compression_ratio) << ":1 | " << format("%.3f", p.bits_per_pixel) << " | "
       << psnr_text(p.psnr_y) << " | " << psnr_text(p.psnr_rgb) << " | " << format("%.4f", p.ssim) << " | "
       << (c.name == r.bd_reference ? std::string("-")
           : c.bd_rate_svc          ? format("%+.1f%%", *c.bd_rate_svc * 100)
                                    : "n/a")
       << " | ";
    if (!speed_measured(c)) {
      const char* why = c.from_cache ? "cached" : "not measured";
      md << why << " | " << why << " | " << why << " | " << why << " |\n";
      continue;
    }
    md << format("%.1f", c.encode_faces_per_second) << " | " << format("%.1f", c.decode_faces_per_second) << " | "
       << format("%.2f", c.access_cold.mean_ms) << " (" << format("%.2f", c.access_cold.mean_frames) << ") | "
       << format("%.2f", c.access_warm.mean_ms) << " (" << format("%.2f", c.access_warm.mean_frames) << ") |\n";
  }
  return md.str();
}

Status write_report(const BenchResults& r, const std::filesystem::path& path) {
  std::ostringstream md;
  md << "# svc bench\n\n";
  md << "Database `" << r.database << "`: grid " << r.grid[0] << " x " << r.grid[1] << " x " << r.grid[2] << ", "
     << r.cells << " cells, " << r.faces << " faces of " << r.face_width << " x " << r.face_height << ", raw RGB "
     << human_bytes(double(r.raw_bytes)) << ". " << r.threads << " worker thread(s); whole run "
     << format("%.1f", r.total_seconds) << " s.\n\n";
  md << "Content: mean luma " << format("%.1f", r.content.mean_luma) << ", luma contrast (standard deviation) "
     << format("%.1f", r.content.luma_contrast) << ", mean horizontal luma gradient "
     << format("%.2f", r.content.mean_gradient) << " per pixel, background (sky) "
     << format("%.1f", r.content.background_share * 100) << " % of the pixels.\n\n";
  md << "## Ranking by BD-rate\n\n"
        "BD-rate of svc (or, where svc did not run, of the svc layout named): its bytes against the codec's at "
        "equal PSNR, by piecewise cubic (PCHIP) "
        "interpolation of log-rate against PSNR, averaged over the PSNR range both curves cover (stated), and "
        "over the part of PSNR-Y 32-40 dB both cover; "
        "positive: svc needs more bytes, the codec is better. Frames per random face: mean (max) frames "
        "decoded to obtain one random face, counting what the GOP structure forces (an open GOP's leading "
        "B-frames need the previous GOP).\n\n";
  md << ranking_markdown(r) << "\n";
  md << "## Summary at svc's reference quality\n\n";
  md << "Every codec is scored on its decoded 8-bit RGB faces against the source faces with the same code "
        "(PSNR over all faces' summed squared error, SSIM the mean of per-face luma SSIM). Each row below is "
        "svc and svc-intra at their point nearest PSNR-Y "
     << format("%.0f", kReferencePsnrY)
     << " dB, every other codec at its setting nearest svc's PSNR-Y there; speed and random access were "
        "measured at that setting. "
        "BD-rate of svc: svc's bytes against the codec's at equal PSNR-Y, averaged over the PSNR-Y range both "
        "cover (negative: svc smaller). Random access: mean time and frames decoded for one random face; cold "
        "opens the stored file for every access, warm reuses the open reader (svc) or the sequence in memory.\n\n";
  md << summary_table_markdown(r) << "\n";
  md << "![rate-distortion curves](rd_curves.png)\n\n";

  md << "## Quality sweep\n\n";
  md << "| codec | setting | bytes | ratio | bpp | PSNR-RGB dB | PSNR-Y dB | SSIM | encode s | decode s |\n";
  md << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const CodecResult& c : r.codecs) {
    for (const QualityPoint& p : c.points) {
      md << "| " << c.name << " | " << setting_text(p) << " | " << p.bytes << " | "
         << format("%.1f", p.compression_ratio) << ":1 | " << format("%.3f", p.bits_per_pixel) << " | "
         << psnr_text(p.psnr_rgb) << " | " << psnr_text(p.psnr_y) << " | " << format("%.4f", p.ssim) << " | "
         << format("%.2f", p.encode_seconds) << " | " << format("%.2f", p.decode_seconds) << " |\n";
    }
  }
  md << "\nCodec settings:\n\n";
  for (const CodecResult& c : r.codecs) {
    md << "- **" << c.name << "** (" << c.encoder
       << "): " << (c.skipped ? "skipped: " + c.skip_reason : c.description) << "\n";
    if (!c.ffmpeg_command.empty()) md << "  `" << c.ffmpeg_command << "`\n";
  }

  md << "\n## Decoding speed and random access to a cell\n\n";
  md << "Every face decoded once at each codec's reference point (the point nearest svc's PSNR-Y): on one "
        "thread, and on all threads (svc: faces side by side through one reader; an anchor: its six face "
        "streams side by side). A random cell is its six faces on one thread: cold from a newly opened file, "
        "warm the same cell again.\n\n";
  md << "| codec | PSNR-Y dB | decode faces/s, 1 thread | decode faces/s, all threads | threads | cell cold ms | "
        "cell warm ms | faces decoded per cell |\n";
  md << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const CodecResult& c : r.codecs) {
    if (c.skipped || c.reference_point < 0 || !speed_measured(c)) continue;
    md << "| " << c.name << " | " << psnr_text(c.points[c.reference_point].psnr_y) << " | "
       << format("%.1f", c.decode_faces_per_second) << " | "
       << format("%.1f", c.decode_faces_per_second_all_threads) << " | " << c.threads << " | "
       << format("%.2f", c.cell_cold.mean_ms) << " | " << format("%.2f", c.cell_warm.mean_ms) << " | "
       << format("%.1f", c.cell_cold.mean_frames) << " |\n";
  }

  md << "\n## Random access\n\n";
  md << "| codec | cold mean ms | cold p99 ms | warm mean ms | warm p99 ms | frames per face (mean) | frames (max) "
        "|\n";
  md << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const CodecResult& c : r.codecs) {
    if (c.skipped || c.points.empty() || !speed_measured(c)) continue;
    md << "| " << c.name << " | " << format("%.3f", c.access_cold.mean_ms) << " | "
       << format("%.3f", c.access_cold.p99_ms) << " | " << format("%.3f", c.access_warm.mean_ms) << " | "
       << format("%.3f", c.access_warm.p99_ms) << " | " << format("%.2f", c.access_cold.mean_frames) << " | "
       << c.access_cold.max_frames << " |\n";
  }
  md << "\nFor svc the frame count is the face plus its references; with warm caches the reader may serve the "
        "references without decoding them again, so the warm count is an upper bound.\n\n";
  md << "![random access cost](access_cost.png)\n";

  if (r.before) {
    auto percent = [](const std::optional<double>& v) { return v ? format("%+.1f%%", *v * 100) : "n/a"; };
    md << "\n## svc against an earlier run\n\nBD-rate (PSNR-Y) of this run's svc against the svc of `"
       << r.before->results << "` on the same database: whole database " << percent(r.before->bd_rate_y)
       << ", B-faces alone (their bytes against their PSNR-Y) " << percent(r.before->b_faces_bd_rate) << ".\n";
  }

  if (!r.ablation.empty()) {
    md << "\n## Ablation: svc without each coding tool\n\nBD-rate (PSNR-Y) of svc with the tool switched off "
          "against svc with every tool, at svc's quality settings: what the tool saves at equal quality. "
          "\"all\" switches every listed tool off.\n\n| tool off | BD-rate | encode s |\n|---|---:|---:|\n";
    for (const AblationRow& row : r.ablation) {
      md << "| " << row.tool << " | " << (row.bd_rate_y ? format("%+.1f%%", *row.bd_rate_y * 100) : "n/a") << " | "
         << format("%.1f", row.encode_seconds) << " |\n";
    }
  }

  if (r.experiments) {
    const Experiments& e = *r.experiments;
    md << "\n## The dissertation's experiments on this database\n\n";
    md << "### Table 7.5: database sizes\n\n| format | size | ratio | PSNR-Y dB | note "
          "|\n|---|---:|---:|---:|---|\n";
    for (const SizeRow& row : e.table_7_5) {
      md << "| " << row.name << " | " << human_bytes(double(row.bytes)) << " | "
         << format("%.1f", row.bytes ? double(r.raw_bytes) / row.bytes : 0.0) << ":1 | " << psnr_text(row.psnr_y)
         << " | " << row.note << " |\n";
    }
    md << "\n### Figure 7.16: compression against B:I ratio and sample spacing (svc quality " << e.quality
       << ")\n\n";
    md << "| sweep | I-cube spacing | sample spacing | cells | I-faces | B-faces | B:I | size | ratio | PSNR-Y dB "
          "|\n";
    md << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    auto sweep_rows = [&](const std::vector<SweepPoint>& points, const char* name) {
      for (const SweepPoint& p : points) {
        md << "| " << name << " | " << p.i_spacing[0] << "," << p.i_spacing[1] << "," << p.i_spacing[2] << " | "
           << p.sample_spacing << " | " << p.cells << " | " << p.i_faces << " | " << p.b_faces << " | "
           << format("%.1f", p.b_to_i) << ":1 | " << human_bytes(double(p.bytes)) << " | "
           << format("%.1f", p.compression_ratio) << ":1 | " << format("%.2f", p.psnr_y) << " |\n";
      }
    };
    sweep_rows(e.b_to_i_sweep, "B:I ratio");
    sweep_rows(e.spacing_sweep, "sample spacing");
    md << "\nSample spacing n keeps every n-th cell along both horizontal axes (a subsampled manifest over the "
          "same face files).\n\n![figure 7.16](fig7_16.png)\n";
    md << "\n### Table 7.4: motion from depth against logarithmic search\n\n";
    md << "| motion | size at PSNR-Y " << format("%.2f", e.equal_psnr_y) << " dB | encode s (quality " << e.quality
       << ") | candidates per macroblock |\n|---|---:|---:|---:|\n";
    for (const MotionRow& row : e.table_7_4) {
      md << "| " << row.motion << " | " << human_bytes(row.bytes_at_equal_psnr) << " | "
         << format("%.2f", row.encode_seconds) << " | " << format("%.2f", row.candidates_per_macroblock) << " |\n";
    }
  }

  md << "\n## Timings\n\n| part | seconds |\n|---|---:|\n";
  for (const PartTiming& t : r.timings) md << "| " << t.part << " | " << format("%.1f", t.seconds) << " |\n";
  md << "| total | " << format("%.1f", r.total_seconds) << " |\n";
  return write_text(path, md.str());
}

Status write_all(const BenchResults& results, const std::filesystem::path& out_dir) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) return Status(ErrorCode::kIoError, "cannot create " + out_dir.string() + ": " + ec.message());
  SVC_RETURN_IF_ERROR(write_results_json(results, out_dir / "results.json"));
  SVC_RETURN_IF_ERROR(write_results_csv(results, out_dir / "results.csv"));
  SVC_RETURN_IF_ERROR(write_plots(results, out_dir));
  return write_report(results, out_dir / "report.md");
}

}  // namespace svc::bench
