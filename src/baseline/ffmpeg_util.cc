// SPDX-License-Identifier: BSD-2-Clause
#include "baseline/ffmpeg_util.h"

#include <cstring>

extern "C" {
#include <libavutil/error.h>
#include <libavutil/pixdesc.h>
}

namespace svc::baseline::detail {

Status av_error(const std::string& what, int errnum) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(errnum, text, sizeof(text));
  return Status(ErrorCode::kInternal, what + ": " + text);
}

namespace {

// Formats libswscale knows as "full range by name" are read as their plain twins with
// the range given explicitly, which avoids swscale's deprecation path.
AVPixelFormat plain_format(AVPixelFormat format, bool* full_range) {
  switch (format) {
    case AV_PIX_FMT_YUVJ420P: *full_range = true; return AV_PIX_FMT_YUV420P;
    case AV_PIX_FMT_YUVJ422P: *full_range = true; return AV_PIX_FMT_YUV422P;
    case AV_PIX_FMT_YUVJ444P: *full_range = true; return AV_PIX_FMT_YUV444P;
    case AV_PIX_FMT_YUVJ440P: *full_range = true; return AV_PIX_FMT_YUV440P;
    case AV_PIX_FMT_YUVJ411P: *full_range = true; return AV_PIX_FMT_YUV411P;
    default: return format;
  }
}

// Sets the YUV side's range to full on `sws` (source or destination), keeping the
// default BT.601 matrices.
Status set_full_range(SwsContext* sws, bool source_side) {
  int* inv_table = nullptr;
  int* table = nullptr;
  int src_range = 0, dst_range = 0, brightness = 0, contrast = 0, saturation = 0;
  if (sws_getColorspaceDetails(sws, &inv_table, &src_range, &table, &dst_range, &brightness, &contrast,
                               &saturation) < 0) {
    return Status(ErrorCode::kInternal, "libswscale: cannot read color-space details");
  }
  if (source_side)
    src_range = 1;
  else
    dst_range = 1;
  if (sws_setColorspaceDetails(sws, inv_table, src_range, table, dst_range, brightness, contrast, saturation) < 0) {
    return Status(ErrorCode::kInternal, "libswscale: cannot select full-range YUV");
  }
  return Status::Ok();
}

}  // namespace

Result<FramePtr> rgb_to_frame(const ImageRGB8& image, AVPixelFormat format, bool full_range) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height * 3) {
    return Status(ErrorCode::kInvalidArgument,
                  "RGB image " + std::to_string(image.width) + "x" + std::to_string(image.height) + " has " +
                      std::to_string(image.pixels.size()) + " bytes, not width*height*3");
  }
  // The RGB pixels go into an aligned frame first: libswscale picks its SIMD paths by
  // alignment, and the ffmpeg tool's decoded PNG frames are aligned too.
  FramePtr rgb(av_frame_alloc());
  if (!rgb) return Status(ErrorCode::kInternal, "out of memory allocating a frame");
  rgb->format = AV_PIX_FMT_RGB24;
  rgb->width = image.width;
  rgb->height = image.height;
  if (int err = av_frame_get_buffer(rgb.get(), 0); err < 0) {
    return av_error("allocating an RGB frame", err);
  }
  for (AVBufferRef* buffer : rgb->buf) {
    if (buffer) std::memset(buffer->data, 0, buffer->size);
  }
  const size_t row_bytes = static_cast<size_t>(image.width) * 3;
  for (int y = 0; y < image.height; ++y) {
    std::memcpy(rgb->data[0] + static_cast<ptrdiff_t>(y) * rgb->linesize[0], image.pixels.data() + y * row_bytes,
                row_bytes);
  }
  if (format == AV_PIX_FMT_RGB24) return rgb;

  FramePtr out(av_frame_alloc());
  if (!out) return Status(ErrorCode::kInternal, "out of memory allocating a frame");
  out->format = format;
  out->width = image.width;
  out->height = image.height;
  if (int err = av_frame_get_buffer(out.get(), 0); err < 0) {
    return av_error("allocating a YUV frame", err);
  }
  // Encoders may read the padding past each row (x265 does): zero it, so the bytes do
  // not depend on what the heap held before.
  for (AVBufferRef* buffer : out->buf) {
    if (buffer) std::memset(buffer->data, 0, buffer->size);
  }
  bool named_full = false;
  const AVPixelFormat sws_format = plain_format(format, &named_full);
  full_range = full_range || named_full;
  SwsPtr sws(sws_getContext(image.width, image.height, AV_PIX_FMT_RGB24, image.width, image.height, sws_format,
                            kSwsFlags, nullptr, nullptr, nullptr));
  if (!sws) {
    return Status(ErrorCode::kInternal,
                  std::string("libswscale cannot convert rgb24 to ") + av_get_pix_fmt_name(format));
  }
  if (full_range) SVC_RETURN_IF_ERROR(set_full_range(sws.get(), /*source_side=*/false));
  sws_scale(sws.get(), rgb->data, rgb->linesize, 0, image.height, out->data, out->linesize);
  out->color_range = full_range ? AVCOL_RANGE_JPEG : AVCOL_RANGE_MPEG;
  return out;
}

Result<ImageRGB8> frame_to_rgb(const AVFrame& frame) {
  if (frame.width <= 0 || frame.height <= 0) {
    return Status(ErrorCode::kCorruptData, "decoded frame has no size");
  }
  bool full_range = frame.color_range == AVCOL_RANGE_JPEG;
  const AVPixelFormat source = plain_format(static_cast<AVPixelFormat>(frame.format), &full_range);
  FramePtr rgb(av_frame_alloc());
  if (!rgb) return Status(ErrorCode::kInternal, "out of memory allocating a frame");
  rgb->format = AV_PIX_FMT_RGB24;
  rgb->width = frame.width;
  rgb->height = frame.height;
  if (int err = av_frame_get_buffer(rgb.get(), 0); err < 0) {
    return av_error("allocating an RGB frame", err);
  }
  if (source == AV_PIX_FMT_RGB24) {
    if (int err = av_frame_copy(rgb.get(), &frame); err < 0) return av_error("copying RGB", err);
  } else {
    SwsPtr sws(sws_getContext(frame.width, frame.height, source, frame.width, frame.height, AV_PIX_FMT_RGB24,
                              kSwsFlags, nullptr, nullptr, nullptr));
    if (!sws) {
      const char* name = av_get_pix_fmt_name(source);
      return Status(ErrorCode::kUnsupported,
                    std::string("libswscale cannot convert ") + (name ? name : "?") + " to rgb24");
    }
    const bool is_rgb_source = (av_pix_fmt_desc_get(source)->flags & AV_PIX_FMT_FLAG_RGB) != 0;
    if (full_range && !is_rgb_source) {
      SVC_RETURN_IF_ERROR(set_full_range(sws.get(), /*source_side=*/true));
    }
    sws_scale(sws.get(), frame.data, frame.linesize, 0, frame.height, rgb->data, rgb->linesize);
  }
  ImageRGB8 image;
  image.width = frame.width;
  image.height = frame.height;
  const size_t row_bytes = static_cast<size_t>(frame.width) * 3;
  image.pixels.resize(row_bytes * frame.height);
  for (int y = 0; y < frame.height; ++y) {
    std::memcpy(image.pixels.data() + y * row_bytes, rgb->data[0] + static_cast<ptrdiff_t>(y) * rgb->linesize[0],
                row_bytes);
  }
  return image;
}

Result<CodecContextPtr> open_decoder(const std::string& codec_name, const uint8_t* extradata,
                                     size_t extradata_size) {
  const AVCodecDescriptor* descriptor = avcodec_descriptor_get_by_name(codec_name.c_str());
  if (!descriptor) {
    return Status(ErrorCode::kUnsupported, "libavcodec knows no codec named '" + codec_name + "'");
  }
  const AVCodec* decoder = nullptr;
  // The native AV1 decoder only drives hardware; prefer the software ones.
  if (descriptor->id == AV_CODEC_ID_AV1) {
    decoder = avcodec_find_decoder_by_name("libdav1d");
    if (!decoder) decoder = avcodec_find_decoder_by_name("libaom-av1");
  }
  if (!decoder) decoder = avcodec_find_decoder(descriptor->id);
  if (!decoder) {
    return Status(ErrorCode::kUnsupported, "this build of libavcodec has no decoder for '" + codec_name + "'");
  }
  CodecContextPtr context(avcodec_alloc_context3(decoder));
  if (!context) return Status(ErrorCode::kInternal, "out of memory allocating a decoder");
  context->thread_count = 1;
  if (extradata_size > 0) {
    context->extradata = static_cast<uint8_t*>(av_mallocz(extradata_size + AV_INPUT_BUFFER_PADDING_SIZE));
    if (!context->extradata) return Status(ErrorCode::kInternal, "out of memory (extradata)");
    std::memcpy(context->extradata, extradata, extradata_size);
    context->extradata_size = static_cast<int>(extradata_size);
  }
  if (int err = avcodec_open2(context.get(), decoder, nullptr); err < 0) {
    return av_error("opening decoder " + std::string(decoder->name), err);
  }
  return context;
}

}  // namespace svc::baseline::detail
