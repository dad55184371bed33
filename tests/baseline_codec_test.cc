// SPDX-License-Identifier: BSD-2-Clause
// The libavcodec baseline: MPEG-2 GOP structure, random access against sequential decode,
// intra-only mode, the comparison codecs, files, and agreement with the ffmpeg tool.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "baseline/baseline.h"
#include "support/test_support.h"

namespace svc::baseline {
namespace {

// A face of a cell as seen by a camera translating over a textured wall: smooth shading,
// a few frequencies and hard block edges, shifting a few pixels from cell to cell, so that
// neighbouring cells predict each other well (as real impostor faces do) but not exactly.
ImageRGB8 procedural_face(CellIndex cell, Face face, int width, int height) {
  ImageRGB8 image;
  image.width = width;
  image.height = height;
  image.pixels.resize(static_cast<size_t>(width) * height * 3);
  const int f = static_cast<int>(face);
  const double shift_u = cell.x * 5.0 + f * 37.0;
  const double shift_v = cell.z * 4.0 + cell.y * 11.0 + f * 13.0;
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const double u = i + shift_u, v = j + shift_v;
      const bool block = ((static_cast<int>(std::floor(u / 16)) + static_cast<int>(std::floor(v / 12))) & 1) != 0;
      const double r = 120 + 60 * std::sin(u * 0.09) + 35 * std::cos(v * 0.13 + u * 0.02) + (block ? 30 : 0);
      const double g = 110 + 70 * std::sin((u + v) * 0.05 + f) + (block ? -25 : 10);
      const double b = 100 + 50 * std::cos(v * 0.07) + 40 * std::sin(u * 0.21) * std::cos(v * 0.17);
      uint8_t* p = &image.pixels[(static_cast<size_t>(j) * width + i) * 3];
      p[0] = static_cast<uint8_t>(std::clamp(std::lround(r), 0L, 255L));
      p[1] = static_cast<uint8_t>(std::clamp(std::lround(g), 0L, 255L));
      p[2] = static_cast<uint8_t>(std::clamp(std::lround(b), 0L, 255L));
    }
  }
  return image;
}

struct FaceSequence {
  CellSequence layout;
  std::vector<ImageRGB8> frames;  // coding order
};

FaceSequence make_face_sequence(std::array<int, 3> dims, CellOrder order, Face face, int width, int height) {
  std::vector<CellIndex> cells;
  for (int y = 0; y < dims[1]; ++y)
    for (int z = 0; z < dims[2]; ++z)
      for (int x = 0; x < dims[0]; ++x) cells.push_back({x, y, z});
  FaceSequence sequence;
  sequence.layout = order_cells(cells, dims, order).value();
  for (const CellIndex& cell : sequence.layout.cells) {
    sequence.frames.push_back(procedural_face(cell, face, width, height));
  }
  return sequence;
}

std::string type_string(const EncodedSequence& sequence) {
  std::string types(sequence.frame_count(), '?');
  for (const FrameRecord& record : sequence.frames) {
    types[record.display_index] = picture_type_letter(record.type);
  }
  return types;
}

// Expected number of frames an IBBP decoder needs for each display frame: the anchors of
// its GOP up to the frame (anchors) or up to the next anchor, plus the B-frame itself.
std::vector<int> expected_mpeg2_counts(const std::string& types) {
  const int n = static_cast<int>(types.size());
  std::vector<int> counts(n, 0);
  for (int d = 0; d < n; ++d) {
    int gop = d;
    while (types[gop] != 'I') --gop;
    int last = d;
    if (types[d] == 'B') {
      while (types[last] == 'B') ++last;
    }
    int anchors = 0;
    for (int k = gop; k <= last; ++k) anchors += types[k] != 'B';
    counts[d] = anchors + (types[d] == 'B' ? 1 : 0);
  }
  return counts;
}

void expect_random_access_matches_sequential(const EncodedSequence& encoded,
                                             const std::vector<ImageRGB8>& sequential) {
  ASSERT_EQ(static_cast<int>(sequential.size()), encoded.frame_count());
  for (int d = 0; d < encoded.frame_count(); ++d) {
    auto random = decode_frame(encoded, d);
    ASSERT_TRUE(random.ok()) << "frame " << d << ": " << random.status().to_string();
    EXPECT_EQ(random->image.width, sequential[d].width);
    EXPECT_TRUE(random->image.pixels == sequential[d].pixels)
        << encoded.encoder << ": random access to frame " << d << " differs from sequential";
    EXPECT_EQ(random->frames_decoded, static_cast<int>(encoded.frames_needed(d).size()));
  }
}

class BaselineCodecTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    quiet_ffmpeg_logging();
    setenv("SVT_LOG", "1", /*overwrite=*/0);  // SVT-AV1 logs through its own channel
  }
};

TEST_F(BaselineCodecTest, Mpeg2RowMajorFollowsIbbpbbWithIFrameAtEveryRowStart) {
  // Rows of 9 cells: each row is I B B P B B I B B (I at the row start, and again after 6);
  // open GOPs, so a row's last B-frames also refer to the next row's I-frame.
  const auto face = make_face_sequence({9, 1, 3}, CellOrder::kRowMajor, Face::kPX, 96, 64);
  EncodeSettings settings;  // mpeg2video, gop 6, 2 B-frames, closed GOPs, qscale 4
  auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, settings);
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  const std::string types = type_string(*encoded);
  std::cout << "mpeg2 row-major picture types: " << types << "\n";
  for (int d = 0; d < encoded->frame_count(); ++d) {
    if (face.layout.gop_start[d]) EXPECT_EQ(types[d], 'I') << "row start " << d;
  }
  // The stream ends on an anchor: the last row closes with P instead of B.
  EXPECT_EQ(types, "IBBPBBIBBIBBPBBIBBIBBPBBIBP");

  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok()) << sequential.status().to_string();
  expect_random_access_matches_sequential(*encoded, *sequential);
  const std::vector<int> expected = expected_mpeg2_counts(types);
  for (int d = 0; d < encoded->frame_count(); ++d) {
    EXPECT_EQ(decode_frame(*encoded, d)->frames_decoded, expected[d]) << "frame " << d;
  }

  auto quality = compare_sequences(face.frames, *sequential);
  ASSERT_TRUE(quality.ok());
  std::cout << "mpeg2 qscale 4, 27 frames 96x64: " << encoded->total_bytes() << " bytes, PSNR-RGB "
            << quality->psnr_rgb << " dB, PSNR-Y " << quality->psnr_y << " dB\n";
  EXPECT_GT(quality->psnr_y, 30.0);
  EXPECT_LT(encoded->total_bytes(), 27u * 96 * 64 * 3 / 8);
}

TEST_F(BaselineCodecTest, Mpeg2ClosedGopsKeepEveryRowSelfContained) {
  const auto face = make_face_sequence({9, 1, 2}, CellOrder::kRowMajor, Face::kNY, 64, 48);
  EncodeSettings settings;
  settings.closed_gop = true;
  auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, settings);
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  const std::string types = type_string(*encoded);
  // FFmpeg closes each GOP on a P-frame, so GOPs of at most 6 frames become I B B P.
  EXPECT_EQ(types, "IBBPIBBPPIBBPIBBPP");
  for (int d = 0; d < encoded->frame_count(); ++d) {
    for (int position : encoded->frames_needed(d)) {
      EXPECT_EQ(encoded->frames[position].display_index / 9, d / 9)
          << "frame " << d << " needs a frame of another row";
    }
  }
  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok());
  expect_random_access_matches_sequential(*encoded, *sequential);
  const std::vector<int> expected = expected_mpeg2_counts(types);
  for (int d = 0; d < encoded->frame_count(); ++d) {
    EXPECT_EQ(decode_frame(*encoded, d)->frames_decoded, expected[d]) << "frame " << d;
  }
}

TEST_F(BaselineCodecTest, Mpeg2CoarserQuantizerGivesFewerBytesAndLowerPsnr) {
  const auto face = make_face_sequence({6, 1, 2}, CellOrder::kRowMajor, Face::kNZ, 64, 48);
  uint64_t previous_bytes = UINT64_MAX;
  double previous_psnr = 1e9;
  for (int qscale : {2, 6, 16}) {
    EncodeSettings settings;
    settings.quantizer = qscale;
    auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, settings);
    ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
    auto decoded = decode_all(*encoded);
    ASSERT_TRUE(decoded.ok());
    const double psnr = compare_sequences(face.frames, *decoded)->psnr_rgb;
    EXPECT_LT(encoded->total_bytes(), previous_bytes) << "qscale " << qscale;
    EXPECT_LT(psnr, previous_psnr) << "qscale " << qscale;
    previous_bytes = encoded->total_bytes();
    previous_psnr = psnr;
  }
}

TEST_F(BaselineCodecTest, Mpeg2IntraOnlyDecodesEveryFrameAlone) {
  const auto face = make_face_sequence({5, 1, 2}, CellOrder::kRowMajor, Face::kPY, 64, 48);
  auto encoded = encode_sequence(frames_from_images(face.frames), {}, mpeg2_intra_only_settings(5));
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  EXPECT_EQ(type_string(*encoded), std::string(10, 'I'));
  for (int d = 0; d < encoded->frame_count(); ++d) {
    EXPECT_EQ(encoded->frames[d].display_index, d) << "intra-only needs no reordering";
    EXPECT_TRUE(encoded->frames[d].keyframe);
  }
  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok());
  expect_random_access_matches_sequential(*encoded, *sequential);
  for (int d = 0; d < encoded->frame_count(); ++d) {
    EXPECT_EQ(decode_frame(*encoded, d)->frames_decoded, 1);
  }
  // Intra-only costs more than IBBPBB at the same qscale on correlated frames.
  EncodeSettings inter;
  inter.quantizer = 5;
  auto predicted = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, inter);
  ASSERT_TRUE(predicted.ok());
  EXPECT_GT(encoded->total_bytes(), predicted->total_bytes());
}

TEST_F(BaselineCodecTest, HilbertOrderEncodesAndDecodesWithRandomAccess) {
  const auto face = make_face_sequence({4, 1, 4}, CellOrder::kHilbert, Face::kNX, 64, 48);
  auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, EncodeSettings{});
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  const std::string types = type_string(*encoded);
  for (int d = 0; d < encoded->frame_count(); ++d) {
    if (face.layout.gop_start[d]) EXPECT_EQ(types[d], 'I') << "GOP start " << d;
  }
  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok());
  expect_random_access_matches_sequential(*encoded, *sequential);
}

class BaselineOtherCodecsTest : public BaselineCodecTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(BaselineOtherCodecsTest, RandomAccessMatchesSequentialDecode) {
  const std::string codec = GetParam();
  if (!encoder_available(codec)) GTEST_SKIP() << codec << " is not in this build (skipped)";
  // Rows of 10 and a GOP of 4: keyframes both forced (row starts) and from the GOP size.
  const auto face = make_face_sequence({10, 1, 2}, CellOrder::kRowMajor, Face::kPX, 64, 64);
  EncodeSettings settings;
  settings.codec = codec;
  settings.gop_size = 4;
  settings.quantizer = codec == "librav1e" ? 100 : (codec == "mjpeg" ? 4 : 28);
  if (codec == "libx264") settings.codec_options = {{"preset", "veryfast"}};
  if (codec == "libaom-av1") settings.codec_options = {{"cpu-used", "8"}};
  if (codec == "libsvtav1") settings.codec_options = {{"preset", "12"}};
  if (codec == "librav1e") settings.codec_options = {{"speed", "10"}};
  auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, settings);
  if (!encoded.ok() && encoded.status().code() == ErrorCode::kUnsupported) {
    GTEST_SKIP() << encoded.status().to_string();
  }
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  ASSERT_EQ(encoded->frame_count(), 20);
  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok()) << sequential.status().to_string();
  expect_random_access_matches_sequential(*encoded, *sequential);
  auto quality = compare_sequences(face.frames, *sequential);
  ASSERT_TRUE(quality.ok());
  std::cout << codec << ": " << encoded->total_bytes() << " bytes, PSNR-RGB " << quality->psnr_rgb << " dB, types "
            << type_string(*encoded) << "\n";
  if (codec == "png") {
    EXPECT_TRUE(std::isinf(quality->psnr_rgb)) << "PNG is lossless";
  } else {
    EXPECT_GT(quality->psnr_rgb, 25.0);
  }
  if (codec == "png" || codec == "mjpeg") {
    for (int d = 0; d < 20; ++d) EXPECT_EQ(decode_frame(*encoded, d)->frames_decoded, 1);
  } else {
    // Bounded GOP: no frame needs more than the GOP's frames.
    for (int d = 0; d < 20; ++d) EXPECT_LE(encoded->frames_needed(d).size(), 4u) << d;
  }
}

INSTANTIATE_TEST_SUITE_P(Codecs, BaselineOtherCodecsTest,
                         ::testing::Values("libx264", "libx265", "libaom-av1", "libsvtav1", "librav1e", "mjpeg",
                                           "png"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// Open GOPs as x264 and x265 users run them: the B-frames shown before an I-frame are
// coded after it and predicted from the previous GOP too. Random access must still give
// the sequential decode's pictures, and the leading frames must count the previous GOP.
class BaselineOpenGopTest : public BaselineCodecTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(BaselineOpenGopTest, LeadingFramesDecodeFromThePreviousGop) {
  const std::string codec = GetParam();
  if (!encoder_available(codec)) GTEST_SKIP() << codec << " is not in this build (skipped)";
  const auto face = make_face_sequence({12, 1, 2}, CellOrder::kRowMajor, Face::kPX, 64, 64);
  EncodeSettings settings;
  settings.codec = codec;
  settings.gop_size = 3;
  settings.max_b_frames = 2;
  settings.open_gop = true;
  settings.quantizer = 28;
  settings.codec_options = {{"preset", "medium"}};
  // Fixed B-frames, no B-pyramid, no scene cuts: exactly I B B I B B ..., B-frames never
  // references.
  if (codec == "libx265") settings.x265_params = "b-adapt=0:b-pyramid=0:scenecut=0";
  auto encoded = encode_sequence(frames_from_images(face.frames), {}, settings);
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  const std::string types = type_string(*encoded);
  std::cout << codec << " types " << types << "\n";
  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok()) << sequential.status().to_string();
  expect_random_access_matches_sequential(*encoded, *sequential);
  // I-frames every 3 frames, each decodable alone; a frame coded after the next I-frame
  // (a leading frame) needs the I-frame before it as well.
  int leading = 0;
  for (int d = 0; d < 24; ++d) {
    const auto needed = encoded->frames_needed(d);
    if (d % 3 == 0) {
      EXPECT_EQ(types[d], 'I') << d;
      EXPECT_EQ(needed.size(), 1u) << d;
      continue;
    }
    const int next_i = d - d % 3 + 3;
    if (next_i >= 24 || encoded->decode_position[d] < encoded->decode_position[next_i]) continue;
    ++leading;
    const int previous_i_position = encoded->decode_position[d - d % 3];
    EXPECT_NE(std::find(needed.begin(), needed.end(), previous_i_position), needed.end()) << d;
    EXPECT_NE(std::find(needed.begin(), needed.end(), encoded->decode_position[next_i]), needed.end()) << d;
  }
  EXPECT_GE(leading, 8);
}

INSTANTIATE_TEST_SUITE_P(Codecs, BaselineOpenGopTest, ::testing::Values("libx265"));

// x264 and x265 at their users' settings (preset medium, GOP 9, 2 B-frames, open GOP):
// every face decodes alone exactly as in sequence, and no frame needs more than its GOP
// and the previous one.
class BaselineUsersGopTest : public BaselineCodecTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(BaselineUsersGopTest, OpenGopRandomAccessMatchesSequentialDecode) {
  const std::string codec = GetParam();
  if (!encoder_available(codec)) GTEST_SKIP() << codec << " is not in this build (skipped)";
  const auto face = make_face_sequence({12, 1, 3}, CellOrder::kRowMajor, Face::kPX, 64, 64);
  EncodeSettings settings;
  settings.codec = codec;
  settings.gop_size = 9;
  settings.max_b_frames = 2;
  settings.open_gop = true;
  settings.quantizer = 26;
  settings.codec_options = {{"preset", "medium"}};
  auto encoded = encode_sequence(frames_from_images(face.frames), {}, settings);
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  auto sequential = decode_all(*encoded);
  ASSERT_TRUE(sequential.ok()) << sequential.status().to_string();
  expect_random_access_matches_sequential(*encoded, *sequential);
  std::string needed;
  for (int d = 0; d < encoded->frame_count(); ++d) {
    needed += std::to_string(encoded->frames_needed(d).size()) + " ";
    EXPECT_LE(encoded->frames_needed(d).size(), 18u) << d;
  }
  std::cout << codec << " types " << type_string(*encoded) << "\n  frames needed " << needed << "\n";
}

INSTANTIATE_TEST_SUITE_P(Codecs, BaselineUsersGopTest, ::testing::Values("libx264", "libx265"));

TEST_F(BaselineCodecTest, MissingEncoderIsUnsupportedNotAFailure) {
  const auto face = make_face_sequence({2, 1, 1}, CellOrder::kRowMajor, Face::kPX, 32, 32);
  EncodeSettings settings;
  settings.codec = "no-such-encoder";
  auto encoded = encode_sequence(frames_from_images(face.frames), {}, settings);
  ASSERT_FALSE(encoded.ok());
  EXPECT_EQ(encoded.status().code(), ErrorCode::kUnsupported);
  EXPECT_FALSE(encoder_available("no-such-encoder"));
  const auto probes = probe_codecs();
  ASSERT_FALSE(probes.empty());
  EXPECT_EQ(probes.front().name, "mpeg2video");
  EXPECT_TRUE(probes.front().available);
}

TEST_F(BaselineCodecTest, RejectsFramesOfTheWrongSizeAndBadSettings) {
  auto face = make_face_sequence({3, 1, 1}, CellOrder::kRowMajor, Face::kPX, 32, 32);
  face.frames[2] = procedural_face({2, 0, 0}, Face::kPX, 48, 32);
  auto encoded = encode_sequence(frames_from_images(face.frames), {}, EncodeSettings{});
  ASSERT_FALSE(encoded.ok());
  EXPECT_EQ(encoded.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(encoded.status().message().find("frame 2"), std::string::npos) << encoded.status().message();

  face.frames[2] = face.frames[1];
  EncodeSettings bad;
  bad.quantizer = 0;
  EXPECT_EQ(encode_sequence(frames_from_images(face.frames), {}, bad).status().code(), ErrorCode::kInvalidArgument);
  const std::vector<uint8_t> wrong_length(2, 1);
  EXPECT_EQ(encode_sequence(frames_from_images(face.frames), wrong_length, EncodeSettings{}).status().code(),
            ErrorCode::kInvalidArgument);
}

TEST_F(BaselineCodecTest, DatabaseOfSixFacesRoundTripsThroughFiles) {
  const std::array<int, 3> dims{4, 1, 3};
  DatabaseFrames input;
  input.dims = dims;
  for (int z = 0; z < 3; ++z)
    for (int x = 0; x < 4; ++x)
      if (!(x == 2 && z == 1)) input.cells.push_back({x, 0, z});  // one hole
  input.width = 48;
  input.height = 32;
  int loads = 0;
  input.load = [&](CellIndex cell, Face face) -> Result<ImageRGB8> {
    ++loads;
    return procedural_face(cell, face, 48, 32);
  };
  auto database = encode_database(input, CellOrder::kRowMajor, EncodeSettings{});
  ASSERT_TRUE(database.ok()) << database.status().to_string();
  EXPECT_EQ(loads, 11 * 6);
  EXPECT_EQ(database->layout.cells.size(), 11u);

  testing::TempDir dir("svc-baseline");
  ASSERT_TRUE(write_database(*database, dir.path() / "db").ok());
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "db" / "px.m2v"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "db" / "px.m2v.index.json"));
  auto reread = read_database(dir.path() / "db");
  ASSERT_TRUE(reread.ok()) << reread.status().to_string();
  EXPECT_EQ(reread->total_bytes(), database->total_bytes());
  EXPECT_EQ(reread->layout.cells, database->layout.cells);
  EXPECT_EQ(reread->layout.gop_start, database->layout.gop_start);

  for (Face face : {Face::kPX, Face::kNY}) {
    for (const CellIndex& cell : input.cells) {
      auto a = decode_cell_face(*database, cell, face);
      auto b = decode_cell_face(*reread, cell, face);
      ASSERT_TRUE(a.ok() && b.ok());
      EXPECT_EQ(a->image.pixels, b->image.pixels);
      EXPECT_EQ(a->frames_decoded, b->frames_decoded);
      EXPECT_GT(compare_images(procedural_face(cell, face, 48, 32), a->image)->psnr_rgb, 28.0);
    }
  }
  EXPECT_EQ(decode_cell_face(*database, {2, 0, 1}, Face::kPX).status().code(), ErrorCode::kNotFound);
}

TEST_F(BaselineCodecTest, CorruptIndexIsRejected) {
  const auto face = make_face_sequence({3, 1, 1}, CellOrder::kRowMajor, Face::kPX, 32, 32);
  auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, EncodeSettings{});
  ASSERT_TRUE(encoded.ok());
  testing::TempDir dir("svc-baseline");
  const auto path = dir.path() / "seq.m2v";
  ASSERT_TRUE(write_sequence(*encoded, path).ok());
  ASSERT_TRUE(read_sequence(path).ok());

  // Truncate the stream: the last frame's bytes now lie outside it.
  std::filesystem::resize_file(path, encoded->total_bytes() - 10);
  auto truncated = read_sequence(path);
  ASSERT_FALSE(truncated.ok());
  EXPECT_EQ(truncated.status().code(), ErrorCode::kCorruptData);

  std::ofstream(path.string() + ".index.json") << "{\"format\": \"svc-baseline-index\"";
  EXPECT_EQ(read_sequence(path).status().code(), ErrorCode::kCorruptData);
  EXPECT_EQ(read_sequence(dir.path() / "missing.m2v").status().code(), ErrorCode::kNotFound);
}

TEST_F(BaselineCodecTest, PngFilesRoundTripExactly) {
  const ImageRGB8 image = procedural_face({1, 0, 2}, Face::kPZ, 37, 21);
  testing::TempDir dir("svc-baseline");
  ASSERT_TRUE(write_png(image, dir.path() / "a.png").ok());
  auto back = read_png(dir.path() / "a.png");
  ASSERT_TRUE(back.ok()) << back.status().to_string();
  EXPECT_EQ(back->width, 37);
  EXPECT_EQ(back->height, 21);
  EXPECT_EQ(back->pixels, image.pixels);
}

TEST_F(BaselineCodecTest, PsnrOfKnownError) {
  ImageRGB8 a;
  a.width = 2;
  a.height = 1;
  a.pixels = {10, 20, 30, 40, 50, 60};
  ImageRGB8 b = a;
  auto same = compare_images(a, b);
  ASSERT_TRUE(same.ok());
  EXPECT_TRUE(std::isinf(same->psnr_rgb));
  b.pixels[0] += 6;  // one sample off by 6: MSE 36/6 = 6; luma error 0.299*6 at one pixel
  auto q = compare_images(a, b);
  ASSERT_TRUE(q.ok());
  EXPECT_NEAR(q->mse_rgb, 6.0, 1e-12);
  EXPECT_NEAR(q->psnr_rgb, 10 * std::log10(255.0 * 255.0 / 6.0), 1e-9);
  EXPECT_NEAR(q->mse_y, (0.299 * 6) * (0.299 * 6) / 2, 1e-9);
  b.width = 1;
  EXPECT_EQ(compare_images(a, b).status().code(), ErrorCode::kInvalidArgument);
}

// The baseline's numbers against the ffmpeg tool run on the same ordered PNG sequence with
// the same settings: total bytes within 5%, PSNR (computed here, on both decodes, against
// the same source) within 0.1 dB.
struct CliCase {
  const char* name;
  EncodeSettings settings;
  std::string ffmpeg_rate_args;  // the same settings, as ffmpeg options
};

void PrintTo(const CliCase& c, std::ostream* out) { *out << c.name; }

class BaselineCliAgreementTest : public BaselineCodecTest, public ::testing::WithParamInterface<CliCase> {};

TEST_P(BaselineCliAgreementTest, AgreesWithTheFfmpegCommandLineTool) {
  const char* ffmpeg = "/usr/bin/ffmpeg";
  if (!std::filesystem::exists(ffmpeg)) GTEST_SKIP() << ffmpeg << " is not installed";
  const CliCase& c = GetParam();
  constexpr int kRow = 9;
  const auto face = make_face_sequence({kRow, 1, 3}, CellOrder::kRowMajor, Face::kPX, 128, 96);
  testing::TempDir dir("svc-baseline-cli");
  for (size_t k = 0; k < face.frames.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "f%04zu.png", k);
    ASSERT_TRUE(write_png(face.frames[k], dir.path() / name).ok());
  }
  const auto cli_output = dir.path() / "cli.m2v";
  const std::string command = std::string(ffmpeg) + " -nostdin -hide_banner -loglevel error -y -framerate 25 -i '" +
                              (dir.path() / "f%04d.png").string() + "' -c:v mpeg2video -pix_fmt yuv420p " +
                              c.ffmpeg_rate_args + " -g " + std::to_string(c.settings.gop_size) + " -bf " +
                              std::to_string(c.settings.max_b_frames) +
                              " -sc_threshold 1000000000 -threads 1 -force_key_frames 'expr:eq(mod(n," +
                              std::to_string(kRow) + "),0)' -f mpeg2video '" + cli_output.string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  auto encoded = encode_sequence(frames_from_images(face.frames), face.layout.gop_start, c.settings);
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  auto ours = decode_all(*encoded);
  ASSERT_TRUE(ours.ok());
  auto theirs = decode_video_file(cli_output);
  ASSERT_TRUE(theirs.ok()) << theirs.status().to_string();
  ASSERT_EQ(theirs->size(), face.frames.size());

  const double our_bytes = static_cast<double>(encoded->total_bytes());
  const double cli_bytes = static_cast<double>(std::filesystem::file_size(cli_output));
  auto our_quality = compare_sequences(face.frames, *ours);
  auto cli_quality = compare_sequences(face.frames, *theirs);
  ASSERT_TRUE(our_quality.ok() && cli_quality.ok());
  std::cout << c.name << " (27 frames 128x96)\n  baseline: " << our_bytes << " bytes, PSNR-RGB "
            << our_quality->psnr_rgb << " dB, PSNR-Y " << our_quality->psnr_y << " dB\n"
            << "  ffmpeg:   " << cli_bytes << " bytes, PSNR-RGB " << cli_quality->psnr_rgb << " dB, PSNR-Y "
            << cli_quality->psnr_y << " dB\n";
  EXPECT_NEAR(our_bytes / cli_bytes, 1.0, 0.05);
  EXPECT_NEAR(our_quality->psnr_rgb, cli_quality->psnr_rgb, 0.1);
  EXPECT_NEAR(our_quality->psnr_y, cli_quality->psnr_y, 0.1);
}

CliCase qscale_case() {
  EncodeSettings settings;
  settings.quantizer = 5;
  return {"ibbpbb_qscale5", settings, "-qscale:v 5"};
}
CliCase bit_rate_case() {
  EncodeSettings settings;
  settings.bit_rate = 300000;
  return {"ibbpbb_300kbps", settings, "-b:v 300000"};
}
CliCase intra_case() { return {"intra_qscale8", mpeg2_intra_only_settings(8), "-qscale:v 8"}; }

INSTANTIATE_TEST_SUITE_P(Mpeg2, BaselineCliAgreementTest,
                         ::testing::Values(qscale_case(), bit_rate_case(), intra_case()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace svc::baseline
