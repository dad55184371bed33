// SPDX-License-Identifier: BSD-2-Clause
// Internal to svc_baseline: owning wrappers for libav* objects, error conversion and the
// RGB <-> YUV conversion shared by every baseline codec.
#pragma once

#include <memory>
#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/frame.h>
#include <libavutil/pixfmt.h>
#include <libswscale/swscale.h>
}

#include "svc/status.h"
#include "svc/types.h"

namespace svc::baseline::detail {

struct CodecContextDeleter {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameDeleter {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketDeleter {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct SwsDeleter {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};
using CodecContextPtr = std::unique_ptr<AVCodecContext, CodecContextDeleter>;
using FramePtr = std::unique_ptr<AVFrame, FrameDeleter>;
using PacketPtr = std::unique_ptr<AVPacket, PacketDeleter>;
using SwsPtr = std::unique_ptr<SwsContext, SwsDeleter>;

// "<what>: <FFmpeg's text for errnum>" as kInternal.
Status av_error(const std::string& what, int errnum);

// The scaler flags of the ffmpeg tool's automatically inserted conversions.
inline constexpr int kSwsFlags = SWS_BICUBIC;

// Converts `image` into a newly allocated frame of `format` (yuv420p and yuvj420p:
// BT.601; yuvj420p or full_range: full range, otherwise limited; rgb24: a copy).
Result<FramePtr> rgb_to_frame(const ImageRGB8& image, AVPixelFormat format, bool full_range);

// Converts a decoded frame of any format libswscale reads to RGB24, honouring the frame's
// color range (yuvj* formats count as full range).
Result<ImageRGB8> frame_to_rgb(const AVFrame& frame);

// A fresh decoder for the codec named `codec_name` (libavcodec codec name, e.g. "h264"),
// one thread, with `extradata` (may be empty). kUnsupported when absent.
Result<CodecContextPtr> open_decoder(const std::string& codec_name, const uint8_t* extradata,
                                     size_t extradata_size);

}  // namespace svc::baseline::detail
