// SPDX-License-Identifier: BSD-2-Clause
#include "anchors.h"

#include <algorithm>

#include "svc/encoder.h"

namespace svc::bench {

namespace {

const std::vector<std::string> kX26xPresets = {"ultrafast", "superfast", "veryfast", "faster",   "fast",
                                               "medium",    "slow",      "slower",   "veryslow", "placebo"};

std::string preset_of(const AnchorOptions& options, const std::string& name, const std::string& fallback) {
  const auto it = options.presets.find(name);
  return it == options.presets.end() ? fallback : it->second;
}

Status check_integer_preset(const std::string& name, const std::string& value, int lowest, int highest) {
  size_t used = 0;
  int parsed = 0;
  try {
    parsed = std::stoi(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || parsed < lowest || parsed > highest) {
    return Status(ErrorCode::kInvalidArgument, "preset of " + name + " must be a number " + std::to_string(lowest) +
                                                   ".." + std::to_string(highest) + ", not '" + value + "'");
  }
  return Status::Ok();
}

Status check_x26x_preset(const std::string& name, const std::string& value) {
  if (std::find(kX26xPresets.begin(), kX26xPresets.end(), value) != kX26xPresets.end()) return Status::Ok();
  return Status(ErrorCode::kInvalidArgument, "preset of " + name +
                                                 " must be an x264/x265 preset name (ultrafast .. "
                                                 "placebo), not '" +
                                                 value + "'");
}

CodecPlan svc_plan(const std::string& name) {
  CodecPlan plan;
  plan.name = name;
  plan.is_svc = true;
  plan.svc_intra = name == "svc-intra";
  plan.svc_regular = name == "svc-regular";
  plan.svc_speed = name == "svc-fast" ? 1 : name == "svc-fastest" ? kMaxEncoderSpeed : 0;
  plan.encoder = "svc";
  plan.setting_name = "quality";
  const bool regular = plan.svc_regular || speed_layout(plan.svc_speed) == CubeLayout::kRegular;
  plan.description =
      plan.svc_intra ? "every cell an I-cube"
      : regular
          ? "I-cubes every 3x1x3 cells, nearest references, depth motion"
          : "I-cubes every 3x1x3 cells and where references see too little, references by visibility, depth motion";
  if (plan.svc_speed > 0) plan.description += ", encoder speed " + std::to_string(plan.svc_speed);
  plan.range = {5, 100, true, {75}};
  return plan;
}

CodecPlan mpeg2_plan(const std::string& name) {
  CodecPlan plan;
  plan.name = name;
  plan.encoder = "mpeg2video";
  plan.setting_name = "qscale";
  plan.force_row_starts = true;
  plan.order = name == "mpeg2" ? baseline::CellOrder::kRowMajor : baseline::CellOrder::kHilbert;
  plan.base.gop_size = 6;
  plan.base.max_b_frames = 2;
  plan.description = name == "mpeg2" ? "row-major, GOP 6 I B B P B B, open, I at each row start"
                                     : "Hilbert order, GOP 6 I B B P B B, open, I every 6 cells";
  plan.range = {1, 31, false, {4, 12}};
  return plan;
}

Result<CodecPlan> x26x_plan(const std::string& name, const AnchorOptions& options) {
  CodecPlan plan;
  plan.name = name;
  plan.encoder = name == "x264" ? "libx264" : "libx265";
  plan.setting_name = "crf";
  const std::string preset = preset_of(options, name, "medium");
  SVC_RETURN_IF_ERROR(check_x26x_preset(name, preset));
  plan.base.codec_options = {{"preset", preset}};
  plan.range = {0, 51, false, {22, 34}};
  if (name == "x265-intra") {
    plan.intra = true;
    plan.base.gop_size = 1;
    plan.base.max_b_frames = 0;
    plan.description = "each face on its own (keyint 1), preset " + preset;
    return plan;
  }
  plan.base.open_gop = true;
  plan.base.max_b_frames = 2;
  if (name == "x265-ra") {
    // svc's own random-access bound: a B-frame needs the I-frames on both sides.
    plan.base.gop_size = 3;
    plan.base.x265_params = "b-adapt=0:b-pyramid=0";
    plan.description = "keyint 3, 2 fixed B-frames, no B-pyramid, open GOP, preset " + preset;
    return plan;
  }
  plan.base.gop_size = options.gop;
  plan.description = "GOP " + std::to_string(options.gop) + ", 2 B-frames, open GOP, preset " + preset;
  return plan;
}

CodecPlan av1_base_plan(const std::string& name, const AnchorOptions& options) {
  CodecPlan plan;
  plan.name = name;
  plan.setting_name = "crf";
  plan.range = {1, 63, false, {30, 45}};
  plan.base.gop_size = options.gop;
  plan.base.max_b_frames = 0;
  return plan;
}

Status use_libaom(const std::string& name, const AnchorOptions& options, const std::string& default_cpu,
                  CodecPlan* plan) {
  plan->encoder = baseline::encoder_available("libaom-av1") ? "libaom-av1" : "";
  const std::string cpu = preset_of(options, name, default_cpu);
  SVC_RETURN_IF_ERROR(check_integer_preset(name + " (libaom)", cpu, 0, 8));
  plan->base.codec_options = {{"cpu-used", cpu}};
  plan->description = "libaom cpu-used " + cpu + ", GOP " + std::to_string(options.gop) + ", closed GOP";
  return Status::Ok();
}

Status use_svt(const std::string& name, const AnchorOptions& options, const std::string& default_preset,
               CodecPlan* plan) {
  plan->encoder = "libsvtav1";
  const std::string preset = preset_of(options, name, default_preset);
  SVC_RETURN_IF_ERROR(check_integer_preset(name + " (SVT-AV1)", preset, 0, 13));
  plan->base.codec_options = {{"preset", preset}};
  plan->parallel_faces = false;
  plan->description = "SVT-AV1 preset " + preset + ", GOP " + std::to_string(options.gop) + ", closed GOP";
  return Status::Ok();
}

// "av1": SVT-AV1 preset 6 (libaom cpu-used 4 where SVT-AV1 is missing or refuses the
// size); "av1-svt-slow": SVT-AV1 preset 2; "av1-slow": libaom cpu-used 2 in its good-
// quality mode, as AV1 is run for archival.
Result<CodecPlan> av1_plan(const std::string& name, const AnchorOptions& options, int width, int height) {
  CodecPlan plan = av1_base_plan(name, options);
  // SVT-AV1 refuses frames under 64 pixels.
  const bool svt = baseline::encoder_available("libsvtav1") && width >= 64 && height >= 64;
  if (name == "av1-slow") {
    SVC_RETURN_IF_ERROR(use_libaom(name, options, "2", &plan));
  } else if (name == "av1-svt-slow") {
    SVC_RETURN_IF_ERROR(use_svt(name, options, "2", &plan));
    if (!svt) {
      plan.unavailable = baseline::encoder_available("libsvtav1") ? "SVT-AV1 refuses faces under 64 pixels"
                                                                  : "libsvtav1 is not in this build of libavcodec";
    }
  } else if (svt) {
    SVC_RETURN_IF_ERROR(use_svt(name, options, "6", &plan));
  } else {
    SVC_RETURN_IF_ERROR(use_libaom(name, options, "4", &plan));
  }
  return plan;
}

Result<CodecPlan> intra_image_plan(const std::string& name, const AnchorOptions& options) {
  CodecPlan plan;
  plan.name = name;
  plan.intra = true;
  plan.base.gop_size = 1;
  plan.base.max_b_frames = 0;
  if (name == "jpeg") {
    plan.encoder = "mjpeg";
    plan.setting_name = "qscale";
    plan.range = {1, 31, false, {3, 10}};
    plan.description = "each face on its own (libavcodec mjpeg, 4:2:0)";
  } else if (name == "webp") {
    plan.encoder = "libwebp";
    plan.setting_name = "quality";
    plan.range = {0, 100, true, {50, 85}};
    plan.description = "each face on its own (libwebp, lossy, method 4)";
  } else if (name == "jxl") {
    plan.encoder = "libjxl";
    plan.setting_name = "quality";
    const std::string effort = preset_of(options, "jxl", "7");
    SVC_RETURN_IF_ERROR(check_integer_preset("jxl", effort, 1, 9));
    plan.base.codec_options = {{"effort", effort}};
    plan.range = {0, 100, true, {50, 85}};
    plan.description = "each face on its own (libjxl, effort " + effort + ")";
  } else if (name == "avif") {
    plan.encoder = "libaom-av1";
    plan.setting_name = "crf";
    const std::string cpu = preset_of(options, "avif", "6");
    SVC_RETURN_IF_ERROR(check_integer_preset("avif", cpu, 0, 9));
    plan.base.codec_options = {{"usage", "allintra"}, {"cpu-used", cpu}};
    plan.range = {1, 63, false, {25, 45}};
    plan.description = "each face an AV1 key frame (libaom all-intra, cpu-used " + cpu +
                       "); bytes are the raw OBUs, no AVIF container";
  } else {
    plan.encoder = "png";
    plan.setting_name = "lossless";
    plan.range = {0, 0, false, {0}};
    plan.description = "each face on its own, lossless";
  }
  return plan;
}

// The caller's encoder options for the plan's codec, named in its description.
Status apply_codec_options(const AnchorOptions& options, CodecPlan* plan) {
  const auto it = options.codec_options.find(plan->name);
  if (it == options.codec_options.end() || it->second.empty()) return Status::Ok();
  if (plan->is_svc) {
    return Status(ErrorCode::kInvalidArgument,
                  plan->name + " takes no encoder options (its coding tools are switched with --ablation)");
  }
  std::string named;
  for (const auto& [key, value] : it->second) {
    if (key.empty())
      return Status(ErrorCode::kInvalidArgument, "encoder option of " + plan->name + " without a name");
    plan->base.codec_options[key] = value;
    named += (named.empty() ? "" : " ") + key + "=" + value;
  }
  plan->description += "; encoder options " + named;
  return Status::Ok();
}

}  // namespace

bool is_svc_layout(const std::string& name) {
  return name == "svc" || name == "svc-regular" || name == "svc-intra" || name == "svc-fast" ||
         name == "svc-fastest";
}

Result<CodecPlan> make_plan(const std::string& name, const AnchorOptions& options, int width, int height) {
  if (options.gop < 1)
    return Status(ErrorCode::kInvalidArgument, "GOP must be at least 1, not " + std::to_string(options.gop));
  CodecPlan plan;
  if (is_svc_layout(name)) {
    plan = svc_plan(name);
  } else if (name == "mpeg2" || name == "mpeg2-hilbert") {
    plan = mpeg2_plan(name);
  } else if (name == "x264" || name == "x265" || name == "x265-ra" || name == "x265-intra") {
    SVC_ASSIGN_OR_RETURN(plan, x26x_plan(name, options));
  } else if (name == "av1" || name == "av1-slow" || name == "av1-svt-slow") {
    SVC_ASSIGN_OR_RETURN(plan, av1_plan(name, options, width, height));
  } else {
    SVC_ASSIGN_OR_RETURN(plan, intra_image_plan(name, options));
  }
  plan.base.codec = plan.encoder;
  plan.base.threads = 1;
  SVC_RETURN_IF_ERROR(apply_codec_options(options, &plan));
  return plan;
}

namespace {

std::string output_format(const CodecPlan& plan) {
  if (plan.encoder == "libx264") return "h264";
  if (plan.encoder == "libx265") return "hevc";
  if (plan.encoder == "libsvtav1" || plan.encoder == "libaom-av1") return "obu";
  if (plan.encoder == "mpeg2video") return "mpeg2video";
  return "image2";
}

std::string rate_arguments(const CodecPlan& plan, int setting) {
  const std::string s = std::to_string(setting);
  if (plan.setting_name == "qscale" || plan.encoder == "libwebp" || plan.encoder == "libjxl") return " -q:v " + s;
  if (plan.setting_name == "crf") return " -crf " + s;
  return "";
}

std::string structure_arguments(const CodecPlan& plan) {
  if (plan.encoder == "png" || plan.encoder == "mjpeg" || plan.encoder == "libwebp" || plan.encoder == "libjxl") {
    return "";
  }
  const int gop = plan.intra && plan.encoder == "libaom-av1" ? 0 : plan.base.gop_size;  // libaom all-intra
  std::string args = " -g " + std::to_string(gop) + " -bf " + std::to_string(plan.base.max_b_frames);
  const bool open = plan.encoder == "mpeg2video"
                        ? !plan.base.closed_gop
                        : plan.base.open_gop && (plan.encoder == "libx264" || plan.encoder == "libx265");
  if (!open && plan.base.gop_size > 1) args += " -flags +cgop";
  if (plan.encoder == "mpeg2video") args += " -sc_threshold 1000000000";
  return args;
}

}  // namespace

std::string ffmpeg_command(const CodecPlan& plan, int setting, const std::string& input, const std::string& output,
                           int row_length) {
  if (plan.is_svc) return "";
  const std::string pix_fmt = plan.encoder == "png" || plan.encoder == "libjxl" ? "rgb24"
                              : plan.encoder == "mjpeg"                         ? "yuvj420p"
                                                                                : "yuv420p";
  std::string cmd = "ffmpeg -framerate 25 -i '" + input + "' -c:v " + plan.encoder + " -pix_fmt " + pix_fmt +
                    " -threads 1" + structure_arguments(plan) + rate_arguments(plan, setting);
  for (const auto& [key, value] : plan.base.codec_options) cmd += " -" + key + " " + value;
  if (plan.encoder == "libx265") {
    std::string params = std::string("open-gop=") + (plan.base.open_gop && !plan.intra ? "1" : "0") +
                         ":log-level=error:pools=none:frame-threads=1";
    if (!plan.base.x265_params.empty()) params += ":" + plan.base.x265_params;
    cmd += " -forced-idr 1 -x265-params " + params;
  }
  if (plan.encoder == "libx264") cmd += " -forced-idr 1";
  if (plan.force_row_starts) cmd += " -force_key_frames 'expr:eq(mod(n," + std::to_string(row_length) + "),0)'";
  return cmd + " -f " + output_format(plan) + " '" + output + "'";
}

}  // namespace svc::bench
