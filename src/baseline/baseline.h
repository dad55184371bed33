// SPDX-License-Identifier: BSD-2-Clause
// The strict-MPEG-compatibility baseline of the dissertation's section 4.2.2 (and the
// comparison codecs around it), built on FFmpeg's libavcodec.
//
// The database is split into six face sequences. Each sequence is the list of cells in a
// coding order (row-major or Hilbert, see order_cells), one frame per cell, encoded with
// a libavcodec video encoder: MPEG-2 with GOP I B B P B B and an I-frame at every row
// start, or libx264, libx265, an AV1 encoder, or the per-frame image codecs mjpeg (JPEG)
// and png. An index records, per frame, its display index, byte range, picture type and
// the frames it depends on, so that one (cell, face) can be decoded on its own: from the
// GOP's I-frame through the frames it depends on, as the MPL library did in the
// dissertation's MPEGWALK system (section 7.2.1.2).
//
// Color: frames are converted RGB24 -> YUV 4:2:0 and back with libswscale, flags
// SWS_BICUBIC, BT.601 matrix, limited ("MPEG") range; these are the defaults of the ffmpeg
// command-line tool, so that its output on the same PNG sequence is comparable. mjpeg uses
// full ("JPEG") range BT.601 as JFIF does; png codes RGB24 losslessly.
//
// Determinism: encoders and decoders run with one thread; the same frames and settings
// give the same bytes.
//
// Error behaviour: nothing here throws. An encoder or decoder that this build of
// libavcodec lacks gives ErrorCode::kUnsupported (callers report that codec as skipped,
// see probe_codecs); bad settings or frames of the wrong size give kInvalidArgument;
// libavcodec failures give kInternal with FFmpeg's error text; malformed index or stream
// files give kCorruptData; files that cannot be read or written give kIoError/kNotFound.
//
// Threading: all functions are reentrant; distinct calls share no mutable state (each
// creates its own codec contexts). An EncodedSequence/EncodedDatabase may be decoded from
// any number of threads at once.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "svc/status.h"
#include "svc/types.h"

namespace svc::baseline {

// ---------------------------------------------------------------------------------------
// Frame sources

// Produces frame `index` (0-based, in coding order). Encoding calls it once per frame, in
// increasing order, so a large database need not be held in memory.
using FrameLoader = std::function<Result<ImageRGB8>(int index)>;

struct FrameSource {
  int frame_count = 0;
  int width = 0;  // every frame must have this size
  int height = 0;
  FrameLoader load;
};

// A source over images held by the caller. Borrows `images`: it must outlive the source.
// All images must have the size of the first (checked when each frame is loaded).
FrameSource frames_from_images(const std::vector<ImageRGB8>& images);

// ---------------------------------------------------------------------------------------
// Cell orders (2-D grid layers to a 1-D sequence)

enum class CellOrder : uint8_t {
  // Within each layer y (ascending), rows z ascending, and within a row x ascending: x
  // varies fastest, then z, then y. Layers are concatenated. The first present cell of
  // each (y, z) row starts a GOP (a forced I-frame): the dissertation's Figure 4.1.
  kRowMajor = 0,
  // Within each layer y (ascending), cells sorted by their distance along a 2-D Hilbert
  // curve over (x, z) on the n x n grid, n the next power of two >= max(dims x, dims z);
  // missing cells are skipped. Layers are concatenated. A GOP starts at each layer's first
  // cell and after every `hilbert_gop_length` cells of a layer: section 8.2.2.1.
  kHilbert = 1,
};

const char* cell_order_name(CellOrder order);  // "row-major", "hilbert"
bool parse_cell_order(const std::string& name, CellOrder* out);

// A coding order over a set of cells.
struct CellSequence {
  std::array<int, 3> dims{1, 1, 1};
  CellOrder order = CellOrder::kRowMajor;
  std::vector<CellIndex> cells;    // coding order: frame k of every face sequence is cells[k]
  std::vector<uint8_t> gop_start;  // same length as cells; 1 where an I-frame is forced
  // Frame index of `cell`, or -1 when the cell is not in the sequence.
  int frame_of(CellIndex cell) const;
};

// Orders `cells` (any order, no duplicates, each inside `dims`). A sparse set (holes) is
// fine. `hilbert_gop_length` (>= 1) is only used by kHilbert.
Result<CellSequence> order_cells(std::span<const CellIndex> cells, std::array<int, 3> dims, CellOrder order,
                                 int hilbert_gop_length = 6);

// Distance of (x, z) along the 2-D Hilbert curve filling an n x n grid (n a power of two,
// 0 <= x, z < n). Consecutive distances are grid neighbours (differ by 1 in x or z).
uint64_t hilbert_distance(uint32_t n, uint32_t x, uint32_t z);

// ---------------------------------------------------------------------------------------
// Encoding

struct EncodeSettings {
  // libavcodec encoder name: "mpeg2video", "libx264", "libx265", "libaom-av1",
  // "libsvtav1", "librav1e", or per frame "mjpeg" (JPEG), "png", "libwebp" (WebP),
  // "libjxl" (JPEG XL). gop_size 1 codes an inter codec intra-only (AVIF: libaom-av1).
  std::string codec = "mpeg2video";
  // Frames from one I-frame to the next at most (the encoder's gop_size); 1 = every frame
  // an I-frame (intra-only). Ignored by mjpeg and png, which are always intra.
  int gop_size = 6;
  // B-frames between anchors (MPEG-2 I B B P B B: 2). 0 for intra-only.
  int max_b_frames = 2;
  // Constant quantizer when bit_rate == 0. Its meaning is the codec's:
  //   mpeg2video, mjpeg: qscale 1..31 (as `ffmpeg -qscale:v`);
  //   libx264, libx265, libaom-av1, libsvtav1: CRF (private option "crf");
  //   librav1e: quantizer 0..255 (private option "qp"); png: ignored (lossless);
  //   libwebp, libjxl: quality 0..100, higher is better (as `ffmpeg -q:v`).
  int quantizer = 4;
  // Target bit rate in bits/s (25 frames/s); > 0 selects rate control instead of the
  // quantizer. Not used by png.
  int64_t bit_rate = 0;
  // false (the default): open GOPs, the classic MPEG-2 I B B P B B | I ...: the last
  // B-frames of a GOP are predicted from the next GOP's I-frame too, so random access to
  // them also decodes that I-frame (the index records it).
  // true: AV_CODEC_FLAG_CLOSED_GOP, no frame refers across a GOP start. FFmpeg's MPEG-2
  // encoder then ends every GOP on a P-frame, so gop_size 6 codes as I B B P | I B B P P.
  // For mpeg2video, scene-change detection is off either way (sc_threshold 1e9), so the
  // GOP structure follows gop_size and force_intra alone. Other inter codecs follow
  // open_gop.
  bool closed_gop = false;
  // libx264 and libx265 only: open GOPs (as their users run them: the B-frames shown just
  // before an I-frame are coded after it and predicted from the previous GOP too; the
  // index records that dependency). false: closed GOPs. Other codecs: always closed.
  bool open_gop = false;
  // libx265 only: appended to the default "x265-params", e.g. "b-pyramid=0".
  std::string x265_params;
  // Private options passed to the encoder last, e.g. {"cpu-used", "8"} for libaom-av1,
  // {"preset", "ultrafast"} for libx264. An entry replaces any default set here (for
  // libx265 the default "x265-params" is "open-gop=0:log-level=error").
  std::map<std::string, std::string> codec_options;
  int threads = 1;  // 1 keeps the output deterministic
};

// MPEG-2 intra-only at a fixed qscale: gop_size 1, no B-frames, every frame an I-frame.
EncodeSettings mpeg2_intra_only_settings(int qscale);

enum class PictureType : uint8_t { kI = 0, kP = 1, kB = 2 };
char picture_type_letter(PictureType type);  // 'I', 'P', 'B'

// One coded frame. Records are kept in decode (bitstream) order.
struct FrameRecord {
  int display_index = 0;  // position in the coding order of cells (frame k = cells[k])
  uint64_t offset = 0;    // byte offset of the frame's packet in EncodedSequence::stream
  uint32_t size = 0;      // bytes of the packet
  PictureType type = PictureType::kI;
  bool keyframe = false;  // decoding may start here with a fresh decoder
  // Display indices of the frames this one is predicted from directly. MPEG-2: P ->
  // previous anchor (I/P) in decode order; B -> the two anchors before it in decode order
  // (the anchors around it in display order). Other inter codecs, whose reference
  // structure is not parsed: the latest reference frame before it in decode order (H.264
  // and HEVC frames marked non-reference are skipped), and for the leading frames of an
  // open GOP also the latest reference before their keyframe; so every reference frame
  // from the keyframe on is needed. Intra frames: none.
  std::vector<int> references;
};

struct EncodedSequence {
  std::string encoder;  // encoder name, as EncodeSettings::codec
  std::string decoder;  // libavcodec codec name of the bitstream: "mpeg2video", "h264", ...
  int width = 0;
  int height = 0;
  std::vector<uint8_t> extradata;    // codec global header, if the encoder made one
  std::vector<uint8_t> stream;       // packets concatenated in decode order
  std::vector<FrameRecord> frames;   // decode order
  std::vector<int> decode_position;  // display index -> position in `frames`

  uint64_t total_bytes() const { return stream.size(); }
  int frame_count() const { return static_cast<int>(frames.size()); }
  // Positions in `frames` (decode order, ascending) that must be decoded to obtain
  // display frame `display_index`: its references, transitively, and itself.
  // Precondition: 0 <= display_index < frame_count().
  std::vector<int> frames_needed(int display_index) const;
};

// True when this build of libavcodec has an encoder of that name.
bool encoder_available(const std::string& name);

// "FFmpeg 5.1.6-0+deb12u1, libavcodec 59.37.100": the libraries the anchors run on.
std::string library_version();

struct CodecProbe {
  std::string name;
  bool available = false;  // false: report as skipped
};
// mpeg2video, libx264, libx265, the AV1 encoders, mjpeg, png, libwebp and libjxl with their availability
// (encoder and matching decoder).
std::vector<CodecProbe> probe_codecs();

// Encodes `source` frame by frame. `force_intra`, when not empty, has one entry per frame:
// nonzero forces an I-frame there (AVFrame pict_type I), which starts a new GOP (an IDR
// frame for libx264/libx265). kUnsupported when the encoder (or its decoder) is missing.
Result<EncodedSequence> encode_sequence(const FrameSource& source, std::span<const uint8_t> force_intra,
                                        const EncodeSettings& settings);

// ---------------------------------------------------------------------------------------
// Decoding

struct DecodedFrame {
  ImageRGB8 image;
  int frames_decoded = 0;  // packets fed to the (fresh) decoder to obtain this frame
};

// Random access: decodes frames_needed(display_index) with a fresh decoder and returns
// the requested frame as RGB. Like MPL in the dissertation this starts at the GOP's
// I-frame; B-frames that are not references (MPEG-2) are skipped, so for I B B P B B
// the counts are I:1, P:2, B1/B2:3, B4/B5:4 (open GOP: I0 P3 I6 B), 2nd-GOP I:1, ...
// kInvalidArgument when display_index is out of range.
Result<DecodedFrame> decode_frame(const EncodedSequence& sequence, int display_index);

// Decodes the whole sequence with one decoder, in decode order; frames in display order.
Result<std::vector<ImageRGB8>> decode_all(const EncodedSequence& sequence);

// Decodes every video frame of a file that libavformat can read (e.g. the ffmpeg tool's
// .m2v output), in output order, to RGB with the same conversion as decode_all.
Result<std::vector<ImageRGB8>> decode_video_file(const std::filesystem::path& path);

// ---------------------------------------------------------------------------------------
// The six-face database

// Loads the face `face` of cell `cell`; every image must be width x height.
using FaceLoader = std::function<Result<ImageRGB8>(CellIndex cell, Face face)>;

struct DatabaseFrames {
  std::array<int, 3> dims{1, 1, 1};
  std::vector<CellIndex> cells;  // present cells, any order
  int width = 0;
  int height = 0;
  FaceLoader load;
};

struct EncodedDatabase {
  CellSequence layout;
  std::array<EncodedSequence, kFaceCount> faces;  // indexed by Face
  uint64_t total_bytes() const;
};

// Orders the cells (Hilbert: a GOP every settings.gop_size cells of a layer) and encodes
// the six face sequences, forcing an I-frame where layout.gop_start is set. Loads each
// face once, one at a time. kUnsupported when the encoder is missing.
Result<EncodedDatabase> encode_database(const DatabaseFrames& input, CellOrder order,
                                        const EncodeSettings& settings);

// Random access to one face of one cell; kNotFound when the cell is not in the database.
Result<DecodedFrame> decode_cell_face(const EncodedDatabase& database, CellIndex cell, Face face);

// ---------------------------------------------------------------------------------------
// Files
//
// A sequence is stored as its elementary stream (packets concatenated in decode order, a
// file that ffmpeg/ffprobe can also read for MPEG-2, H.264, HEVC) at `stream_path`, plus
// an index at `stream_path` + ".index.json":
//   { "format": "svc-baseline-index", "version": 1, "encoder": "mpeg2video",
//     "decoder": "mpeg2video", "width": W, "height": H, "extradata": "<hex>",
//     "frames": [ { "display": 0, "offset": 0, "size": 1234, "type": "I", "key": true,
//                   "refs": [] }, ... ] }          (frames in decode order)
// A database is a directory with "baseline.json":
//   { "format": "svc-baseline", "version": 1, "order": "row-major", "dims": [X, Y, Z],
//     "cells": [[x, y, z], ...] (coding order), "gop_start": [1, 0, ...],
//     "faces": { "px": "px.m2v", ... } }
// and the six face sequences beside it.

// File name extension for an encoder's elementary stream: "m2v", "h264", "hevc", "obu",
// "mjpeg", "pngs", "webps", "jxls", or "bin".
std::string stream_extension(const std::string& encoder);

Status write_sequence(const EncodedSequence& sequence, const std::filesystem::path& stream_path);
Result<EncodedSequence> read_sequence(const std::filesystem::path& stream_path);

Status write_database(const EncodedDatabase& database, const std::filesystem::path& directory);
Result<EncodedDatabase> read_database(const std::filesystem::path& directory);

// ---------------------------------------------------------------------------------------
// Images and quality

// PNG through libavcodec's png codec (RGB24; other PNG layouts are converted).
Status write_png(const ImageRGB8& image, const std::filesystem::path& path);
Result<ImageRGB8> read_png(const std::filesystem::path& path);

// Mean squared error over all samples; PSNR = 10 log10(255^2 / MSE), +infinity when the
// MSE is 0. "Y" is BT.601 luma computed from RGB in double precision,
// Y = 0.299 R + 0.587 G + 0.114 B (full range), so any two coders are measured alike.
struct Quality {
  double mse_rgb = 0;
  double mse_y = 0;
  double psnr_rgb = 0;
  double psnr_y = 0;
};
double psnr_from_mse(double mse);
// kInvalidArgument when the sizes differ or the images are empty.
Result<Quality> compare_images(const ImageRGB8& reference, const ImageRGB8& decoded);
// PSNR of the MSE over all frames (frames of one size, so the mean of per-frame MSEs).
Result<Quality> compare_sequences(std::span<const ImageRGB8> reference, std::span<const ImageRGB8> decoded);

// Lowers libav*'s global log level to errors only (FFmpeg's logging is process-wide; call
// from a program's main or a test, not from library code).
void quiet_ffmpeg_logging();

}  // namespace svc::baseline
