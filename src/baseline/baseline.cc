// SPDX-License-Identifier: BSD-2-Clause
// Encoding and random-access decoding of the baseline's face sequences with libavcodec.
#include "baseline/baseline.h"

#include <algorithm>
#include <cstring>
#include <set>

#include "baseline/ffmpeg_util.h"
#include "baseline/references.h"

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/avutil.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

namespace svc::baseline {

using detail::av_error;
using detail::CodecContextPtr;
using detail::FramePtr;
using detail::PacketPtr;

namespace {

// The frame rate given to encoders; it only matters under bit-rate control (bits/frame)
// and matches the ffmpeg tool's default for image sequences.
constexpr AVRational kTimeBase{1, 25};

bool is_image_codec(AVCodecID id) {
  return id == AV_CODEC_ID_MJPEG || id == AV_CODEC_ID_PNG || id == AV_CODEC_ID_WEBP || id == AV_CODEC_ID_JPEGXL;
}

// Image encoders whose quality (0..100, higher is better) is read from global_quality,
// as `ffmpeg -q:v` sets it.
bool uses_global_quality(AVCodecID id) { return id == AV_CODEC_ID_WEBP || id == AV_CODEC_ID_JPEGXL; }

// Native libavcodec encoders whose quantizer is the qscale (lambda) of mpegvideo.
bool uses_qscale(AVCodecID id) {
  return id == AV_CODEC_ID_MPEG2VIDEO || id == AV_CODEC_ID_MPEG1VIDEO || id == AV_CODEC_ID_MPEG4 ||
         id == AV_CODEC_ID_MJPEG;
}

PictureType picture_type_from_av(int av_type, bool keyframe) {
  switch (av_type) {
    case AV_PICTURE_TYPE_I:
    case AV_PICTURE_TYPE_SI: return PictureType::kI;
    case AV_PICTURE_TYPE_P:
    case AV_PICTURE_TYPE_S:
    case AV_PICTURE_TYPE_SP: return PictureType::kP;
    case AV_PICTURE_TYPE_B:
    case AV_PICTURE_TYPE_BI: return PictureType::kB;
    default: return keyframe ? PictureType::kI : PictureType::kP;
  }
}

Status set_private_option(AVCodecContext* context, const std::string& key, const std::string& value,
                          const std::string& encoder) {
  const int err = av_opt_set(context->priv_data, key.c_str(), value.c_str(), 0);
  if (err == AVERROR_OPTION_NOT_FOUND) {
    return Status(ErrorCode::kInvalidArgument, "encoder " + encoder + " has no option '" + key + "'");
  }
  if (err < 0) {
    return Status(ErrorCode::kInvalidArgument, "encoder " + encoder + " rejects " + key + "=" + value);
  }
  return Status::Ok();
}

bool supports_open_gop(const std::string& codec) { return codec == "libx264" || codec == "libx265"; }

bool has_private_option(AVCodecContext* context, const char* key) {
  return context->priv_data && av_opt_find(context->priv_data, key, nullptr, 0, AV_OPT_SEARCH_CHILDREN) != nullptr;
}

// Collects the encoder's packets in decode order.
struct PacketSink {
  EncodedSequence* sequence;
  std::vector<int> av_types;  // AVPictureType per packet, 0 when the encoder did not say

  Status drain(AVCodecContext* context, AVPacket* packet) {
    for (;;) {
      const int err = avcodec_receive_packet(context, packet);
      if (err == AVERROR(EAGAIN) || err == AVERROR_EOF) return Status::Ok();
      if (err < 0) return av_error("encoder " + sequence->encoder + " failed", err);
      FrameRecord record;
      record.display_index = static_cast<int>(packet->pts);
      record.offset = sequence->stream.size();
      record.size = static_cast<uint32_t>(packet->size);
      record.keyframe = (packet->flags & AV_PKT_FLAG_KEY) != 0;
      size_t stats_size = 0;
      const uint8_t* stats = av_packet_get_side_data(packet, AV_PKT_DATA_QUALITY_STATS, &stats_size);
      av_types.push_back(stats && stats_size >= 5 ? stats[4] : 0);
      sequence->stream.insert(sequence->stream.end(), packet->data, packet->data + packet->size);
      sequence->frames.push_back(std::move(record));
      av_packet_unref(packet);
    }
  }
};

// Fills picture types, references and the display -> decode map once all packets are in.
Status finish_index(EncodedSequence* sequence, const std::vector<int>& av_types, bool intra_only,
                    bool mpeg2_structure, int frame_count) {
  if (sequence->frame_count() != frame_count) {
    return Status(ErrorCode::kInternal, "encoder " + sequence->encoder + " returned " +
                                            std::to_string(sequence->frame_count()) + " packets for " +
                                            std::to_string(frame_count) + " frames");
  }
  sequence->decode_position.assign(frame_count, -1);
  for (int position = 0; position < frame_count; ++position) {
    FrameRecord& record = sequence->frames[position];
    if (record.display_index < 0 || record.display_index >= frame_count ||
        sequence->decode_position[record.display_index] != -1) {
      return Status(ErrorCode::kInternal, "encoder " + sequence->encoder + " returned a packet with bad pts " +
                                              std::to_string(record.display_index));
    }
    sequence->decode_position[record.display_index] = position;
    if (intra_only) record.keyframe = true;
    record.type = intra_only ? PictureType::kI : picture_type_from_av(av_types[position], record.keyframe);
  }
  if (intra_only) return Status::Ok();
  if (mpeg2_structure) {
    detail::link_mpeg2_references(sequence);
  } else {
    detail::link_chained_references(sequence);
  }
  return Status::Ok();
}

// Sends one packet of `sequence` and passes every frame that comes out to `on_frame`.
template <typename OnFrame>
Status decode_packet(AVCodecContext* context, const EncodedSequence& sequence, const FrameRecord* record,
                     AVPacket* packet, AVFrame* frame, OnFrame&& on_frame) {
  int err = 0;
  if (record) {
    if (record->offset + record->size > sequence.stream.size()) {
      return Status(ErrorCode::kCorruptData,
                    "frame " + std::to_string(record->display_index) + " lies outside the stream (offset " +
                        std::to_string(record->offset) + ", size " + std::to_string(record->size) + ")");
    }
    av_packet_unref(packet);
    if ((err = av_new_packet(packet, static_cast<int>(record->size))) < 0) {
      return av_error("allocating a packet", err);
    }
    std::memcpy(packet->data, sequence.stream.data() + record->offset, record->size);
    packet->pts = record->display_index;
    if (record->keyframe) packet->flags |= AV_PKT_FLAG_KEY;
    err = avcodec_send_packet(context, packet);
  } else {
    err = avcodec_send_packet(context, nullptr);
  }
  if (err < 0 && err != AVERROR_EOF) {
    return av_error("decoder rejected frame " +
                        (record ? std::to_string(record->display_index) : std::string("flush")),
                    err);
  }
  for (;;) {
    err = avcodec_receive_frame(context, frame);
    if (err == AVERROR(EAGAIN) || err == AVERROR_EOF) return Status::Ok();
    if (err < 0) return av_error("decoding " + sequence.decoder, err);
    const int64_t pts = frame->pts != AV_NOPTS_VALUE ? frame->pts : frame->best_effort_timestamp;
    Status status = on_frame(pts, *frame);
    av_frame_unref(frame);
    SVC_RETURN_IF_ERROR(status);
  }
}

}  // namespace

FrameSource frames_from_images(const std::vector<ImageRGB8>& images) {
  FrameSource source;
  source.frame_count = static_cast<int>(images.size());
  source.width = images.empty() ? 0 : images.front().width;
  source.height = images.empty() ? 0 : images.front().height;
  source.load = [&images](int index) -> Result<ImageRGB8> {
    if (index < 0 || index >= static_cast<int>(images.size())) {
      return Status(ErrorCode::kInvalidArgument, "frame " + std::to_string(index) + " is out of range");
    }
    return images[index];
  };
  return source;
}

EncodeSettings mpeg2_intra_only_settings(int qscale) {
  EncodeSettings settings;
  settings.codec = "mpeg2video";
  settings.gop_size = 1;
  settings.max_b_frames = 0;
  settings.quantizer = qscale;
  return settings;
}

char picture_type_letter(PictureType type) {
  switch (type) {
    case PictureType::kI: return 'I';
    case PictureType::kP: return 'P';
    case PictureType::kB: return 'B';
  }
  return '?';
}

std::vector<int> EncodedSequence::frames_needed(int display_index) const {
  std::set<int> needed_positions;
  std::vector<int> pending = {display_index};
  while (!pending.empty()) {
    const int display = pending.back();
    pending.pop_back();
    if (display < 0 || display >= static_cast<int>(decode_position.size())) continue;
    const int position = decode_position[display];
    if (position < 0 || !needed_positions.insert(position).second) continue;
    for (int reference : frames[position].references) pending.push_back(reference);
  }
  return {needed_positions.begin(), needed_positions.end()};
}

bool encoder_available(const std::string& name) { return avcodec_find_encoder_by_name(name.c_str()) != nullptr; }

std::string library_version() {
  const unsigned v = avcodec_version();
  return std::string("FFmpeg ") + av_version_info() + ", libavcodec " + std::to_string(v >> 16) + "." +
         std::to_string((v >> 8) & 0xFF) + "." + std::to_string(v & 0xFF);
}

std::vector<CodecProbe> probe_codecs() {
  std::vector<CodecProbe> probes;
  for (const char* name : {"mpeg2video", "libx264", "libx265", "libaom-av1", "libsvtav1", "librav1e", "mjpeg",
                           "png", "libwebp", "libjxl"}) {
    const AVCodec* encoder = avcodec_find_encoder_by_name(name);
    probes.push_back({name, encoder && avcodec_find_decoder(encoder->id) != nullptr});
  }
  return probes;
}

Result<EncodedSequence> encode_sequence(const FrameSource& source, std::span<const uint8_t> force_intra,
                                        const EncodeSettings& settings) {
  const AVCodec* encoder = avcodec_find_encoder_by_name(settings.codec.c_str());
  if (!encoder) {
    return Status(ErrorCode::kUnsupported, "encoder '" + settings.codec + "' is not in this build of libavcodec");
  }
  if (!avcodec_find_decoder(encoder->id)) {
    return Status(ErrorCode::kUnsupported,
                  "this build of libavcodec has no decoder for " + std::string(avcodec_get_name(encoder->id)));
  }
  if (source.frame_count <= 0 || source.width <= 0 || source.height <= 0 || !source.load) {
    return Status(ErrorCode::kInvalidArgument, "frame source is empty (" + std::to_string(source.frame_count) +
                                                   " frames of " + std::to_string(source.width) + "x" +
                                                   std::to_string(source.height) + ")");
  }
  if (!force_intra.empty() && force_intra.size() != static_cast<size_t>(source.frame_count)) {
    return Status(ErrorCode::kInvalidArgument, "force_intra has " + std::to_string(force_intra.size()) +
                                                   " entries for " + std::to_string(source.frame_count) +
                                                   " frames");
  }
  if (settings.gop_size < 1 || settings.max_b_frames < 0 || settings.threads < 1 || settings.bit_rate < 0) {
    return Status(ErrorCode::kInvalidArgument, "encode settings out of range: gop_size " +
                                                   std::to_string(settings.gop_size) + ", max_b_frames " +
                                                   std::to_string(settings.max_b_frames) + ", threads " +
                                                   std::to_string(settings.threads));
  }
  const bool qscale = uses_qscale(encoder->id);
  if (settings.bit_rate == 0 && qscale && (settings.quantizer < 1 || settings.quantizer > 31)) {
    return Status(ErrorCode::kInvalidArgument,
                  settings.codec + " qscale must be 1..31, got " + std::to_string(settings.quantizer));
  }
  if (uses_global_quality(encoder->id) && (settings.quantizer < 0 || settings.quantizer > 100)) {
    return Status(ErrorCode::kInvalidArgument,
                  settings.codec + " quality must be 0..100, got " + std::to_string(settings.quantizer));
  }

  const bool image_codec = is_image_codec(encoder->id);
  const bool intra_only = image_codec || settings.gop_size <= 1;
  CodecContextPtr context(avcodec_alloc_context3(encoder));
  if (!context) return Status(ErrorCode::kInternal, "out of memory allocating an encoder");
  context->width = source.width;
  context->height = source.height;
  context->time_base = kTimeBase;
  context->framerate = av_inv_q(kTimeBase);
  context->thread_count = settings.threads;
  AVPixelFormat format = AV_PIX_FMT_YUV420P;
  bool full_range = false;
  if (encoder->id == AV_CODEC_ID_PNG || encoder->id == AV_CODEC_ID_JPEGXL) {
    format = AV_PIX_FMT_RGB24;
  } else if (encoder->id == AV_CODEC_ID_MJPEG) {
    format = AV_PIX_FMT_YUVJ420P;  // JFIF: full-range BT.601
    full_range = true;
    context->color_range = AVCOL_RANGE_JPEG;
  }
  context->pix_fmt = format;
  if (!image_codec) {
    context->gop_size = intra_only ? 1 : settings.gop_size;
    // libaom codes every frame a key frame with a key-frame distance of 0 (its all-intra
    // mode refuses anything else).
    if (intra_only && encoder->id == AV_CODEC_ID_AV1 && settings.codec == "libaom-av1") context->gop_size = 0;
    context->max_b_frames = intra_only ? 0 : settings.max_b_frames;
    // MPEG-2 follows closed_gop; libx264 and libx265 follow open_gop; every other inter
    // codec is kept to closed GOPs.
    const bool mpeg2 = encoder->id == AV_CODEC_ID_MPEG2VIDEO;
    const bool open = mpeg2 ? !settings.closed_gop : settings.open_gop && supports_open_gop(settings.codec);
    if (!open) context->flags |= AV_CODEC_FLAG_CLOSED_GOP;
    // No scene-change I-frames: the GOP structure comes from the GOP size and the forced
    // row starts alone (mpegvideo also refuses closed GOPs with scene-change detection).
    if (uses_qscale(encoder->id) && has_private_option(context.get(), "sc_threshold")) {
      SVC_RETURN_IF_ERROR(set_private_option(context.get(), "sc_threshold", "1000000000", settings.codec));
    }
  }
  if (settings.bit_rate > 0 && encoder->id != AV_CODEC_ID_PNG) {
    context->bit_rate = settings.bit_rate;
  } else if (qscale || uses_global_quality(encoder->id)) {
    context->flags |= AV_CODEC_FLAG_QSCALE;
    context->global_quality = settings.quantizer * FF_QP2LAMBDA;
  } else if (encoder->id != AV_CODEC_ID_PNG) {
    const char* key = has_private_option(context.get(), "crf") ? "crf" : "qp";
    SVC_RETURN_IF_ERROR(set_private_option(context.get(), key, std::to_string(settings.quantizer), settings.codec));
  }
  // Forced I-frames become IDR/closed keyframes, so decoding can start at them.
  if (encoder->id == AV_CODEC_ID_H264 && has_private_option(context.get(), "forced-idr")) {
    SVC_RETURN_IF_ERROR(set_private_option(context.get(), "forced-idr", "1", settings.codec));
  }
  if (settings.codec == "libx265") {
    SVC_RETURN_IF_ERROR(set_private_option(context.get(), "forced-idr", "1", settings.codec));
    std::string params = std::string("open-gop=") + (settings.open_gop ? "1" : "0") + ":log-level=error";
    if (settings.threads == 1) params += ":pools=none:frame-threads=1";
    if (!settings.x265_params.empty()) params += ":" + settings.x265_params;
    SVC_RETURN_IF_ERROR(set_private_option(context.get(), "x265-params", params, settings.codec));
  }
  for (const auto& [key, value] : settings.codec_options) {
    SVC_RETURN_IF_ERROR(set_private_option(context.get(), key, value, settings.codec));
  }
  if (int err = avcodec_open2(context.get(), encoder, nullptr); err < 0) {
    return av_error("opening encoder " + settings.codec, err);
  }

  EncodedSequence sequence;
  sequence.encoder = settings.codec;
  sequence.decoder = avcodec_get_name(encoder->id);
  sequence.width = source.width;
  sequence.height = source.height;
  PacketPtr packet(av_packet_alloc());
  if (!packet) return Status(ErrorCode::kInternal, "out of memory allocating a packet");
  PacketSink sink{&sequence, {}};

  for (int index = 0; index < source.frame_count; ++index) {
    auto loaded = source.load(index);
    if (!loaded.ok()) return loaded.status().with_context("frame " + std::to_string(index));
    const ImageRGB8& image = loaded.value();
    if (image.width != source.width || image.height != source.height) {
      return Status(ErrorCode::kInvalidArgument,
                    "frame " + std::to_string(index) + " is " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + ", the sequence is " + std::to_string(source.width) + "x" +
                        std::to_string(source.height));
    }
    SVC_ASSIGN_OR_RETURN(FramePtr frame, detail::rgb_to_frame(image, format, full_range));
    frame->pts = index;
    // As the ffmpeg tool does: mpegvideo's fixed-qscale mode reads each frame's quality.
    frame->quality = context->global_quality;
    const bool forced = intra_only || (!force_intra.empty() && force_intra[index] != 0);
    frame->pict_type = forced ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
    if (int err = avcodec_send_frame(context.get(), frame.get()); err < 0) {
      return av_error("encoder " + settings.codec + " rejected frame " + std::to_string(index), err);
    }
    SVC_RETURN_IF_ERROR(sink.drain(context.get(), packet.get()));
  }
  if (int err = avcodec_send_frame(context.get(), nullptr); err < 0) {
    return av_error("flushing encoder " + settings.codec, err);
  }
  SVC_RETURN_IF_ERROR(sink.drain(context.get(), packet.get()));
  if (context->extradata_size > 0) {
    sequence.extradata.assign(context->extradata, context->extradata + context->extradata_size);
  }
  SVC_RETURN_IF_ERROR(finish_index(&sequence, sink.av_types, intra_only, encoder->id == AV_CODEC_ID_MPEG2VIDEO,
                                   source.frame_count));
  return sequence;
}

Result<DecodedFrame> decode_frame(const EncodedSequence& sequence, int display_index) {
  if (display_index < 0 || display_index >= sequence.frame_count() ||
      sequence.decode_position.size() != sequence.frames.size()) {
    return Status(ErrorCode::kInvalidArgument, "frame " + std::to_string(display_index) +
                                                   " is not in the sequence of " +
                                                   std::to_string(sequence.frame_count()) + " frames");
  }
  const std::vector<int> needed = sequence.frames_needed(display_index);
  SVC_ASSIGN_OR_RETURN(CodecContextPtr context, detail::open_decoder(sequence.decoder, sequence.extradata.data(),
                                                                     sequence.extradata.size()));
  PacketPtr packet(av_packet_alloc());
  FramePtr frame(av_frame_alloc());
  if (!packet || !frame) return Status(ErrorCode::kInternal, "out of memory (decoder)");
  DecodedFrame result;
  bool found = false;
  auto on_frame = [&](int64_t pts, const AVFrame& decoded) -> Status {
    if (pts != display_index || found) return Status::Ok();
    SVC_ASSIGN_OR_RETURN(result.image, detail::frame_to_rgb(decoded));
    found = true;
    return Status::Ok();
  };
  for (int position : needed) {
    SVC_RETURN_IF_ERROR(
        decode_packet(context.get(), sequence, &sequence.frames[position], packet.get(), frame.get(), on_frame));
    ++result.frames_decoded;
  }
  SVC_RETURN_IF_ERROR(decode_packet(context.get(), sequence, nullptr, packet.get(), frame.get(), on_frame));
  if (!found) {
    return Status(ErrorCode::kCorruptData,
                  "decoder produced no picture for frame " + std::to_string(display_index));
  }
  return result;
}

Result<std::vector<ImageRGB8>> decode_all(const EncodedSequence& sequence) {
  const int count = sequence.frame_count();
  SVC_ASSIGN_OR_RETURN(CodecContextPtr context, detail::open_decoder(sequence.decoder, sequence.extradata.data(),
                                                                     sequence.extradata.size()));
  PacketPtr packet(av_packet_alloc());
  FramePtr frame(av_frame_alloc());
  if (!packet || !frame) return Status(ErrorCode::kInternal, "out of memory (decoder)");
  std::vector<ImageRGB8> images(count);
  std::vector<uint8_t> filled(count, 0);
  auto on_frame = [&](int64_t pts, const AVFrame& decoded) -> Status {
    if (pts < 0 || pts >= count || filled[pts]) {
      return Status(ErrorCode::kCorruptData,
                    "decoder returned a picture with unexpected pts " + std::to_string(pts));
    }
    SVC_ASSIGN_OR_RETURN(images[pts], detail::frame_to_rgb(decoded));
    filled[pts] = 1;
    return Status::Ok();
  };
  for (const FrameRecord& record : sequence.frames) {
    SVC_RETURN_IF_ERROR(decode_packet(context.get(), sequence, &record, packet.get(), frame.get(), on_frame));
  }
  SVC_RETURN_IF_ERROR(decode_packet(context.get(), sequence, nullptr, packet.get(), frame.get(), on_frame));
  for (int k = 0; k < count; ++k) {
    if (!filled[k]) {
      return Status(ErrorCode::kCorruptData, "decoder produced no picture for frame " + std::to_string(k));
    }
  }
  return images;
}

Result<std::vector<ImageRGB8>> decode_video_file(const std::filesystem::path& path) {
  AVFormatContext* raw_format = nullptr;
  if (int err = avformat_open_input(&raw_format, path.c_str(), nullptr, nullptr); err < 0) {
    Status status = av_error("opening " + path.string(), err);
    return Status(err == AVERROR(ENOENT) ? ErrorCode::kNotFound : ErrorCode::kIoError, status.message());
  }
  std::unique_ptr<AVFormatContext, void (*)(AVFormatContext*)> format(raw_format, [](AVFormatContext* f) {
    avformat_close_input(&f);
  });
  if (int err = avformat_find_stream_info(format.get(), nullptr); err < 0) {
    return av_error("reading stream info of " + path.string(), err);
  }
  const int stream_index = av_find_best_stream(format.get(), AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (stream_index < 0) {
    return Status(ErrorCode::kBadInput, path.string() + " has no video stream");
  }
  const AVCodecParameters* parameters = format->streams[stream_index]->codecpar;
  SVC_ASSIGN_OR_RETURN(CodecContextPtr context,
                       detail::open_decoder(avcodec_get_name(parameters->codec_id), parameters->extradata,
                                            static_cast<size_t>(parameters->extradata_size)));
  PacketPtr packet(av_packet_alloc());
  FramePtr frame(av_frame_alloc());
  if (!packet || !frame) return Status(ErrorCode::kInternal, "out of memory (decoder)");
  std::vector<ImageRGB8> images;
  auto receive_all = [&]() -> Status {
    for (;;) {
      const int err = avcodec_receive_frame(context.get(), frame.get());
      if (err == AVERROR(EAGAIN) || err == AVERROR_EOF) return Status::Ok();
      if (err < 0) return av_error("decoding " + path.string(), err);
      auto image = detail::frame_to_rgb(*frame);
      av_frame_unref(frame.get());
      if (!image.ok()) return image.status();
      images.push_back(std::move(image).value());
    }
  };
  for (;;) {
    const int err = av_read_frame(format.get(), packet.get());
    if (err == AVERROR_EOF) break;
    if (err < 0) return av_error("reading " + path.string(), err);
    if (packet->stream_index == stream_index) {
      const int sent = avcodec_send_packet(context.get(), packet.get());
      av_packet_unref(packet.get());
      if (sent < 0) return av_error("decoding " + path.string(), sent);
      SVC_RETURN_IF_ERROR(receive_all());
    } else {
      av_packet_unref(packet.get());
    }
  }
  avcodec_send_packet(context.get(), nullptr);
  SVC_RETURN_IF_ERROR(receive_all());
  return images;
}

uint64_t EncodedDatabase::total_bytes() const {
  uint64_t total = 0;
  for (const EncodedSequence& face : faces) total += face.total_bytes();
  return total;
}

Result<EncodedDatabase> encode_database(const DatabaseFrames& input, CellOrder order,
                                        const EncodeSettings& settings) {
  if (!input.load) return Status(ErrorCode::kInvalidArgument, "database has no face loader");
  EncodedDatabase database;
  SVC_ASSIGN_OR_RETURN(database.layout, order_cells(input.cells, input.dims, order, settings.gop_size));
  const CellSequence& layout = database.layout;
  for (Face face : kAllFaces) {
    FrameSource source;
    source.frame_count = static_cast<int>(layout.cells.size());
    source.width = input.width;
    source.height = input.height;
    source.load = [&](int index) -> Result<ImageRGB8> {
      const CellIndex cell = layout.cells[index];
      auto image = input.load(cell, face);
      if (!image.ok()) {
        return image.status().with_context(face_label(cell, face));
      }
      return image;
    };
    auto encoded = encode_sequence(source, layout.gop_start, settings);
    if (!encoded.ok()) {
      return encoded.status().with_context(std::string("face ") + face_name(face));
    }
    database.faces[static_cast<int>(face)] = std::move(encoded).value();
  }
  return database;
}

Result<DecodedFrame> decode_cell_face(const EncodedDatabase& database, CellIndex cell, Face face) {
  const int frame = database.layout.frame_of(cell);
  if (frame < 0) {
    return Status(ErrorCode::kNotFound, cell_label(cell) + " is not in the database");
  }
  auto decoded = decode_frame(database.faces[static_cast<int>(face)], frame);
  if (!decoded.ok()) return decoded.status().with_context(std::string("face ") + face_name(face));
  return decoded;
}

void quiet_ffmpeg_logging() { av_log_set_level(AV_LOG_ERROR); }

}  // namespace svc::baseline
