// SPDX-License-Identifier: BSD-2-Clause
// `svc bench`: svc against the MPEG-2 row-major baseline and the codecs users would
// otherwise pick, measured the same way on one svc-input database.
//
// For every codec: a quality sweep (bytes, compression ratio, bits per pixel, PSNR in RGB
// and Y, SSIM) whose settings are searched to cover PSNR-Y 30..42 dB (settings_search.h),
// speed (encode and sequential decode faces/s) and random-access cost (time and frames
// decoded to obtain one random face, cold and warm); BD-rate of svc against each on
// PSNR-Y and PSNR-RGB (bd_rate.h). Anchors run as their users run them (anchors.h). Then the dissertation's
// experiments on the database at hand: Table 7.5 (sizes), Figure 7.16 (compression against B:I ratio and sample
// spacing) and Table 7.4 (depth motion against logarithmic search).
//
// Measurement: every codec is scored on the decoded 8-bit RGB faces against the source
// faces with svc::rgb_squared_error, svc::luma_squared_error and svc::luma_ssim, so the
// numbers are comparable whatever color conversion a codec uses internally. PSNR is
// taken over the summed squared error of all faces; SSIM is the mean over faces.
//
// Cold and warm random access:
//   svc      cold: Reader::open on the file, then decode_face (nothing cached);
//            warm: one Reader kept open for all accesses, after a full sequential pass.
//   others   cold: the face's stored sequence read from disk (index and stream), then
//            baseline::decode_frame; warm: the sequence already in memory. libavcodec
//            keeps no cache: each access decodes from the GOP's I-frame with a fresh
//            decoder, as the dissertation's MPL library did.
// Frames decoded: svc 1 + the face's references (an upper bound when warm: the reader
// may serve references from its caches); others as baseline::decode_frame counts.
//
// Error behaviour: no exceptions. A codec missing from this build of libavcodec is
// recorded as skipped with the reason; any other failure stops the run with a Status
// naming the codec and setting. Threading: run_bench uses `threads` worker threads
// internally; call it from one thread.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "svc/status.h"

namespace svc::bench {

// svc's reference point, where speed and random access are measured and the summary
// table compares, is its point nearest this PSNR-Y: inside every codec's sweep (quick
// or full), so each anchor's nearest point matches it within a dB or two, as an equal-
// quality comparison needs.
inline constexpr double kReferencePsnrY = 38.0;

// Passes behind each decoding speed: one pass of a few hundred faces takes well under a
// second, and on a shared machine one pass can be a fifth off the next.
inline constexpr int kDecodeSpeedPasses = 5;
// Encodes behind each encoding speed, at the reference point: an encode takes seconds,
// so fewer passes. Both counts are run in rounds across the codecs (Bench::measure_speeds).
inline constexpr int kEncodeSpeedPasses = 3;

// Every codec name `svc bench` knows, in report order.
const std::vector<std::string>& all_codec_names();
// The codecs a run without a list runs: all but the slow AV1 anchors (av1-slow,
// av1-svt-slow), which take longer than the rest together.
const std::vector<std::string>& default_codec_names();

struct BenchOptions {
  std::filesystem::path db_dir;     // the svc-input database
  std::filesystem::path out_dir;    // results.json, results.csv, report.md, *.png
  std::vector<std::string> codecs;  // subset of all_codec_names(); empty: default_codec_names()
  // Worker threads for encoding (svc's encoder, the six baseline face sequences at once)
  // and quality measurement; 0: the machine's hardware concurrency.
  int threads = 0;
  int random_accesses = 120;  // random (cell, face) picks per codec and mode
  uint32_t seed = 1;          // for the random picks
  bool experiments = true;    // Table 7.5, Figure 7.16, Table 7.4 (need svc)
  // svc without each coding tool (svc::CodingTools) at svc's quality settings, and the
  // BD-rate of each against svc with every tool (needs svc).
  bool ablation = false;
  // results.json of an earlier run on the same database: svc's curve (and its B-faces')
  // is compared with that run's by BD-rate. Empty: no comparison.
  std::filesystem::path before_results;
  // Two PSNR targets and at most four encodes per codec: for tests and quick looks.
  bool quick = false;
  // Speed and random access at each codec's reference point; off: quality points and
  // BD-rates only (the corpus loop, bench/corpus.py --quick).
  bool measure_speed = true;
  // GOP of x264, x265 and AV1, presets replacing the defaults and private encoder
  // options per codec (see anchors.h, AnchorOptions).
  int gop = 9;
  std::map<std::string, std::string> anchor_presets;
  std::map<std::string, std::map<std::string, std::string>> anchor_options;
  // Folder of anchors' quality points kept between runs (anchor_cache.h); empty: none.
  std::filesystem::path anchor_cache;
  // Progress lines ("[  12.3 s] x264 crf 23: ..."). Unset: nothing is printed.
  std::function<void(const std::string&)> progress;
};

// One encode of the whole database at one setting.
struct QualityPoint {
  std::string setting_name;  // "quality", "qscale", "crf", "lossless"
  int setting = 0;
  uint64_t bytes = 0;            // everything needed to decode (streams; svc: the .svc file)
  double compression_ratio = 0;  // raw RGB bytes / bytes
  double bits_per_pixel = 0;     // 8 * bytes / pixels over all faces
  double psnr_rgb = 0;           // dB, 99 when lossless
  double psnr_y = 0;
  double ssim = 0;  // mean luma SSIM over faces
  double encode_seconds = 0;
  double decode_seconds = 0;  // sequential decode of every face
  // The predicted faces' coded bytes and their PSNR-Y alone (0 when there are none), to
  // follow them apart from the intra faces they lean on: svc's B-faces, the video
  // anchors' P- and B-frames.
  uint64_t b_face_bytes = 0;
  double b_face_psnr_y = 0;
};

struct AccessStats {
  int samples = 0;
  double mean_ms = 0;
  double p99_ms = 0;
  double mean_frames = 0;  // frames decoded per random face
  int max_frames = 0;
};

struct CodecResult {
  std::string name;         // as in all_codec_names(): "svc", "mpeg2", "x264", ...
  std::string encoder;      // "svc", "mpeg2video", "libx264", "libaom-av1", "mjpeg", ...
  std::string description;  // GOP, order and preset in words
  bool skipped = false;
  std::string skip_reason;
  // The quality points came from the anchor cache: speed and access were not measured.
  bool from_cache = false;
  std::vector<QualityPoint> points;  // ascending setting order as run
  int reference_point = -1;          // index in points where speed and access were measured
  int threads = 1;
  // Faces over the wall time of an encode at the reference point from the database on
  // disk, the median of kEncodeSpeedPasses encodes.
  double encode_faces_per_second = 0;
  // Every face decoded once at the reference point on one thread (svc: in cell order
  // through a new reader; an anchor: its six face streams one after another), and on all
  // `threads` (svc's faces side by side through one reader, an anchor's six streams side
  // by side). Each the median of kDecodeSpeedPasses passes, one of each in turn. The
  // passes of all codecs run in rounds, one pass of each codec a round.
  double decode_faces_per_second = 0;
  double decode_faces_per_second_all_threads = 0;
  AccessStats access_cold;
  AccessStats access_warm;
  // A whole cell (its six faces) at random, on one thread: cold from a newly opened file,
  // warm the same cell again. Frames: faces decoded for the cell. One sample per picked
  // cell in each of the kDecodeSpeedPasses rounds of decoding passes.
  AccessStats cell_cold;
  AccessStats cell_warm;
  // Bjontegaard rate of svc against this codec on PSNR-Y: svc bytes / these bytes - 1 at
  // equal quality, averaged over the overlapping PSNR range (negative: svc smaller).
  std::optional<double> bd_rate_svc;
  std::array<double, 2> bd_range_y{0, 0};  // PSNR-Y range it was averaged over (dB)
  // The same over PSNR-Y 32-40 dB only (kTargetPsnrRange), the range the project's
  // targets are stated over; nullopt where the curves do not both cover part of it.
  std::optional<double> bd_rate_svc_target;
  std::array<double, 2> bd_range_target{0, 0};
  // BD-rate of svc-intra (when it ran) against this codec over kTargetPsnrRange.
  std::optional<double> bd_rate_svc_intra_target;
  // The same on PSNR-RGB.
  std::optional<double> bd_rate_svc_rgb;
  std::array<double, 2> bd_range_rgb{0, 0};
  // The ffmpeg command that encodes one face sequence as this anchor did at its reference
  // point (input: the face's PNGs in coding order). Empty for svc.
  std::string ffmpeg_command;
};

// Table 7.5: database sizes.
struct SizeRow {
  std::string name;  // "raw", "PNG", "JPEG", "MPEG-2 row-major", "spatial (svc)"
  uint64_t bytes = 0;
  double psnr_y = 0;  // of the point used; 99 for raw and PNG
  std::string note;
};

// Figure 7.16: one encode of the spatial codec.
struct SweepPoint {
  std::string label;  // "B:I 8:1", "spacing 2"
  std::array<int32_t, 3> i_spacing{3, 1, 3};
  int sample_spacing = 1;  // every n-th cell along x and z
  uint64_t cells = 0;
  uint64_t i_faces = 0;
  uint64_t b_faces = 0;
  double b_to_i = 0;  // b_faces / i_faces
  uint64_t bytes = 0;
  double compression_ratio = 0;
  double psnr_y = 0;
};

// Table 7.4: one motion source.
struct MotionRow {
  std::string motion;  // "depth", "logarithmic"
  std::vector<QualityPoint> points;
  double bytes_at_equal_psnr = 0;  // at `equal_psnr_y` on this motion's RD curve
  double encode_seconds = 0;       // at the default quality
  double candidates_per_macroblock = 0;
};

struct Experiments {
  int quality = 75;  // svc quality used for the sweeps and Table 7.5
  std::vector<SizeRow> table_7_5;
  std::vector<SweepPoint> b_to_i_sweep;
  std::vector<SweepPoint> spacing_sweep;
  std::vector<MotionRow> table_7_4;
  double equal_psnr_y = 0;  // Table 7.4 comparison point
};

// svc with one coding tool switched off ("all" switches every tool off).
struct AblationRow {
  std::string tool;
  std::vector<QualityPoint> points;  // at the settings of svc's own points
  // Bytes without the tool / bytes with every tool, at equal PSNR-Y, minus 1: what the
  // tool saves. Unset when the curves share no PSNR range.
  std::optional<double> bd_rate_y;
  double encode_seconds = 0;  // summed over the points
};

// svc against the svc of an earlier run (BenchOptions::before_results).
struct BeforeComparison {
  std::string results;                    // the earlier results.json
  std::optional<double> bd_rate_y;        // whole database, PSNR-Y: now / before - 1
  std::optional<double> b_faces_bd_rate;  // B-faces' bytes against their PSNR-Y
};

struct PartTiming {
  std::string part;
  double seconds = 0;
};

inline constexpr std::array<double, 2> kTargetPsnrRange{32, 40};

// What the faces look like, to set databases side by side (docs/bench.md, "The corpus").
struct ContentStats {
  double mean_luma = 0;         // BT.601 full-range luma from RGB, 0..255, over every pixel
  double luma_contrast = 0;     // standard deviation of that luma
  double mean_gradient = 0;     // mean absolute luma difference of horizontally adjacent pixels
  double background_share = 0;  // pixels whose depth saw no geometry (sky)
};

struct BenchResults {
  std::string database;  // db_dir as given
  ContentStats content;
  // The codec every BD-rate is against: the first svc layout (is_svc_layout) that ran, in
  // report order, so svc when it ran (empty: none ran, no BD-rate). The fields named
  // bd_rate_svc hold its BD-rate.
  std::string bd_reference;
  std::array<int, 3> grid{1, 1, 1};
  uint64_t cells = 0;
  uint64_t faces = 0;
  int face_width = 0;
  int face_height = 0;
  uint64_t raw_bytes = 0;  // 3 bytes per pixel over all faces
  int threads = 1;
  std::vector<CodecResult> codecs;
  std::optional<Experiments> experiments;
  std::vector<AblationRow> ablation;
  std::optional<BeforeComparison> before;
  std::vector<PartTiming> timings;
  double total_seconds = 0;
};

// Runs everything `options` asks for. Scratch files go to out_dir/work and are removed.
Result<BenchResults> run_bench(const BenchOptions& options);

// Writers (each creates or replaces one file; kIoError naming the path on failure).
Status write_results_json(const BenchResults& results, const std::filesystem::path& path);
// One row per codec quality point:
// codec,encoder,setting_name,setting,bytes,compression_ratio,bits_per_pixel,psnr_rgb,
// psnr_y,ssim,encode_seconds,decode_seconds
Status write_results_csv(const BenchResults& results, const std::filesystem::path& path);
// rd_curves.png, access_cost.png, fig7_16.png (when experiments ran) in `directory`.
Status write_plots(const BenchResults& results, const std::filesystem::path& directory);
// report.md embedding the plots written by write_plots.
Status write_report(const BenchResults& results, const std::filesystem::path& path);
// The first table of report.md (Markdown): codecs ranked by svc's BD-rate against them
// (PSNR-Y and PSNR-RGB, with the range), settings and random-access cost, then a
// sentence naming the anchors svc loses to.
std::string ranking_markdown(const BenchResults& results);
// The summary table of report.md (Markdown): one row per codec at its reference point.
std::string summary_table_markdown(const BenchResults& results);

// Writes all of the above into options.out_dir.
Status write_all(const BenchResults& results, const std::filesystem::path& out_dir);

// Writes an svc-input manifest in `out_dir` over every `step`-th cell along x and z of
// the database in `db_dir` (cells whose x and z indices are multiples of `step`), with
// the grid dims and spacing scaled accordingly. Face files are referenced by absolute
// path, not copied. kInvalidArgument when step < 1 or no cell remains.
Status write_subsampled_manifest(const std::filesystem::path& db_dir, int step,
                                 const std::filesystem::path& out_dir);

}  // namespace svc::bench
