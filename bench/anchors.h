// SPDX-License-Identifier: BSD-2-Clause
// The codecs `svc bench` runs and how: for every anchor the settings its users pick, the
// range its quality search may use, and the ffmpeg command line that gives the same
// bytes.
//
// The MPEG-2 baselines keep the dissertation's structure (row-major or Hilbert order,
// GOP I B B P B B, an I-frame at every row start). Every other inter anchor runs as its
// users run it: x264 and x265 at preset medium, a GOP of `gop` frames (9), 2 B-frames,
// open GOPs; AV1 with SVT-AV1 preset 6 (libaom cpu-used 4 where SVT-AV1 is missing or
// the faces are under 64 pixels), same GOP, its default closed GOP; the slower AV1 that
// archives are made with, libaom cpu-used 2 ("av1-slow") and SVT-AV1 preset 2
// ("av1-svt-slow"), same GOP; and x265 at svc's
// random-access bound (keyint 3, 2 fixed B-frames, no B-pyramid, open GOP: I B B I B B,
// B-frames never references). Intra anchors code each face on its own.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "baseline/baseline.h"

namespace svc::bench {

struct AnchorOptions {
  int gop = 9;  // frames from one I-frame to the next for x264, x265 and AV1
  // Preset per codec name, replacing the defaults: "x264", "x265", "x265-ra",
  // "x265-intra" (x264/x265 preset names), "av1" (SVT-AV1 preset, or libaom cpu-used),
  // "av1-slow" (libaom cpu-used), "av1-svt-slow" (SVT-AV1 preset),
  // "avif" (libaom cpu-used), "webp" (compression level 0..6), "jxl" (effort 1..9).
  std::map<std::string, std::string> presets;
  // Private encoder options per codec name, set after the plan's own (replacing one of
  // the same key): what an ablation of an anchor's tools needs, e.g. for "avif"
  // {"aom-params", "enable-rect-partitions=0"}. Not for svc, whose tools are its own
  // (`--ablation`). The encoder rejects an unknown key when it opens.
  std::map<std::string, std::map<std::string, std::string>> codec_options;
};

// Where the quality search may look, and which way quality goes.
struct SettingRange {
  int lowest = 0;
  int highest = 0;
  bool higher_is_better = false;  // quality settings; false for quantizers and CRF
  std::vector<int> seeds;         // measured first
};

struct CodecPlan {
  std::string name;          // as in all_codec_names()
  std::string encoder;       // "svc" or the libavcodec encoder
  std::string description;   // settings in words, for the report
  std::string setting_name;  // "quality", "qscale", "crf", "lossless"
  SettingRange range;
  bool is_svc = false;
  bool svc_intra = false;
  bool svc_regular = false;       // the i_spacing lattice alone, nearest references
  int svc_speed = 0;              // svc encode --speed (svc-fast: 1, svc-fastest: the highest)
  bool intra = false;             // every face coded on its own
  bool force_row_starts = false;  // the dissertation's I-frame at every row start
  baseline::CellOrder order = baseline::CellOrder::kRowMajor;
  baseline::EncodeSettings base;
  // The six face sequences may be encoded at once. Off for SVT-AV1, which runs its own
  // thread pool and whose library set-up is not safe to run twice concurrently.
  bool parallel_faces = true;
  // Why this anchor cannot run here (the run records it as skipped); empty when it can.
  std::string unavailable;
};

// Whether `name` (of all_codec_names) is one of svc's own layouts: svc, svc-regular,
// svc-intra, svc-fast, svc-fastest.
bool is_svc_layout(const std::string& name);

// kInvalidArgument for a preset that the codec does not take, or encoder options for svc;
// names the codec.
Result<CodecPlan> make_plan(const std::string& name, const AnchorOptions& options, int width, int height);

// The ffmpeg command line that encodes one face sequence as `plan` does at `setting`:
// `input` a PNG sequence pattern in coding order, `output` the stream (for intra codecs
// an image pattern); `row_length` cells per row for the MPEG-2 row-start I-frames. Empty
// for svc.
std::string ffmpeg_command(const CodecPlan& plan, int setting, const std::string& input, const std::string& output,
                           int row_length = 1);

}  // namespace svc::bench
