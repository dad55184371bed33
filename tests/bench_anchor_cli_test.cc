// SPDX-License-Identifier: BSD-2-Clause
// Each anchor of `svc bench` against the ffmpeg command line that the report documents
// for it (bench/anchors.h): on a small face sequence, the bench's bytes within 1 % and its
// PSNR-Y within 0.05 dB of what `ffmpeg` makes with those arguments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "anchors.h"
#include "baseline/baseline.h"
#include "support/test_support.h"

namespace svc::bench {
namespace {

namespace fs = std::filesystem;

// A face seen from a camera moving over a textured wall: neighbours predict each other
// well but not exactly, as real impostor faces do.
ImageRGB8 moving_face(int k, int size) {
  ImageRGB8 image;
  image.width = image.height = size;
  image.pixels.resize(static_cast<size_t>(size) * size * 3);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double u = i + 3.0 * k, v = j + 1.5 * k;
      const bool block = ((static_cast<int>(u / 11) + static_cast<int>(v / 7)) & 1) != 0;
      uint8_t* p = &image.pixels[(static_cast<size_t>(j) * size + i) * 3];
      p[0] = static_cast<uint8_t>(std::clamp(120 + 60 * std::sin(u * 0.11) + (block ? 30 : 0), 0.0, 255.0));
      p[1] = static_cast<uint8_t>(std::clamp(110 + 70 * std::sin((u + v) * 0.05) - (block ? 25 : 0), 0.0, 255.0));
      p[2] = static_cast<uint8_t>(std::clamp(100 + 50 * std::cos(v * 0.09) * std::sin(u * 0.2), 0.0, 255.0));
    }
  }
  return image;
}

// The decoded frames of everything ffmpeg wrote: one video file, or numbered images.
Result<std::vector<ImageRGB8>> decode_output(const fs::path& dir, const std::string& output, bool numbered,
                                             uint64_t* bytes) {
  std::vector<ImageRGB8> frames;
  *bytes = 0;
  // The image2 muxer numbers from 1.
  for (int k = numbered ? 1 : 0;; ++k) {
    char name[256];
    std::snprintf(name, sizeof name, output.c_str(), k);
    const fs::path path = dir / name;
    if (!fs::exists(path)) break;
    *bytes += fs::file_size(path);
    SVC_ASSIGN_OR_RETURN(std::vector<ImageRGB8> decoded, baseline::decode_video_file(path));
    for (ImageRGB8& f : decoded) frames.push_back(std::move(f));
    if (!numbered) break;
  }
  return frames;
}

class BenchAnchorCliTest : public ::testing::TestWithParam<const char*> {};

TEST_P(BenchAnchorCliTest, BytesAndPsnrMatchTheDocumentedFfmpegCommand) {
  const char* ffmpeg = "/usr/bin/ffmpeg";
  if (!fs::exists(ffmpeg)) GTEST_SKIP() << ffmpeg << " is not installed";
  baseline::quiet_ffmpeg_logging();
  setenv("SVT_LOG", "1", 0);
  auto plan = make_plan(GetParam(), AnchorOptions{}, 64, 64);
  ASSERT_TRUE(plan.ok()) << plan.status().to_string();
  if (plan->encoder.empty() || !baseline::encoder_available(plan->encoder)) {
    GTEST_SKIP() << GetParam() << ": encoder not in this build";
  }
  constexpr int kFrames = 20;
  std::vector<ImageRGB8> frames;
  testing::TempDir dir("svc-anchor-cli");
  for (int k = 0; k < kFrames; ++k) {
    frames.push_back(moving_face(k, 64));
    char name[32];
    std::snprintf(name, sizeof name, "f%04d.png", k);
    ASSERT_TRUE(baseline::write_png(frames.back(), dir.path() / name).ok());
  }
  const int setting = plan->range.seeds.front();
  const bool numbered = plan->encoder == "mjpeg" || plan->encoder == "libwebp" || plan->encoder == "libjxl";
  const std::string image_extension = plan->encoder == "mjpeg"     ? "jpg"
                                      : plan->encoder == "libwebp" ? "webp"
                                                                   : "jxl";
  const std::string output = numbered ? "out%04d." + image_extension
                                      : "out." + baseline::stream_extension(plan->encoder);
  std::string command =
      ffmpeg_command(*plan, setting, (dir.path() / "f%04d.png").string(), (dir.path() / output).string());
  ASSERT_EQ(command.rfind("ffmpeg ", 0), 0u) << command;
  command = std::string(ffmpeg) + " -nostdin -hide_banner -loglevel error -y " + command.substr(7);
  ASSERT_EQ(std::system(command.c_str()), 0) << command;

  baseline::EncodeSettings settings = plan->base;
  settings.quantizer = setting;
  auto encoded = baseline::encode_sequence(baseline::frames_from_images(frames), {}, settings);
  ASSERT_TRUE(encoded.ok()) << encoded.status().to_string();
  auto ours = baseline::decode_all(*encoded);
  ASSERT_TRUE(ours.ok()) << ours.status().to_string();
  uint64_t cli_bytes = 0;
  auto theirs = decode_output(dir.path(), output, numbered, &cli_bytes);
  ASSERT_TRUE(theirs.ok()) << theirs.status().to_string();
  ASSERT_EQ(theirs->size(), frames.size()) << command;
  auto our_quality = baseline::compare_sequences(frames, *ours);
  auto cli_quality = baseline::compare_sequences(frames, *theirs);
  ASSERT_TRUE(our_quality.ok() && cli_quality.ok());
  std::cout << GetParam() << ": bench " << encoded->total_bytes() << " bytes, PSNR-Y " << our_quality->psnr_y
            << " dB; ffmpeg " << cli_bytes << " bytes, PSNR-Y " << cli_quality->psnr_y << " dB\n  " << command
            << "\n";
  EXPECT_NEAR(static_cast<double>(encoded->total_bytes()) / cli_bytes, 1.0, 0.01) << command;
  // libx265 at keyint 3 with open GOPs reads memory it never wrote (valgrind reports
  // uninitialised reads inside libx265), so inside a process that has run other encodes
  // its pictures vary by up to 0.13 dB PSNR-Y (seen over repeated runs; the size by under
  // 0.1 %) from one run to the next; a fresh ffmpeg process always gives the same. Every
  // other anchor matches the command line exactly.
  const double psnr_tolerance = std::string(GetParam()) == "x265-ra" ? 0.3 : 0.05;
  EXPECT_NEAR(our_quality->psnr_y, cli_quality->psnr_y, psnr_tolerance) << command;
}

// An anchor's encoder options (`svc bench --anchor-option`) reach its encoder, its
// description and its documented command line; an unknown one fails the encode by name.
TEST(BenchAnchorOptions, ReachTheEncoderTheDescriptionAndTheCommandLine) {
  if (!baseline::encoder_available("libx264")) GTEST_SKIP() << "libx264 not in this build";
  baseline::quiet_ffmpeg_logging();
  AnchorOptions options;
  auto plain = make_plan("x264", options, 64, 64);
  options.codec_options["x264"] = {{"x264-params", "no-deblock=1"}};
  auto unfiltered = make_plan("x264", options, 64, 64);
  ASSERT_TRUE(plain.ok() && unfiltered.ok());
  EXPECT_NE(unfiltered->description.find("x264-params=no-deblock=1"), std::string::npos) << unfiltered->description;
  EXPECT_NE(ffmpeg_command(*unfiltered, 23, "in%04d.png", "out.h264").find(" -x264-params no-deblock=1"),
            std::string::npos);
  std::vector<ImageRGB8> frames;
  for (int k = 0; k < 6; ++k) frames.push_back(moving_face(k, 64));
  auto encode = [&](const CodecPlan& plan) {
    baseline::EncodeSettings settings = plan.base;
    settings.quantizer = 30;
    return baseline::encode_sequence(baseline::frames_from_images(frames), {}, settings);
  };
  auto with_filter = encode(*plain), without_filter = encode(*unfiltered);
  ASSERT_TRUE(with_filter.ok() && without_filter.ok());
  auto decoded_with = baseline::decode_all(*with_filter), decoded_without = baseline::decode_all(*without_filter);
  ASSERT_TRUE(decoded_with.ok() && decoded_without.ok());
  EXPECT_NE(decoded_with->front().pixels, decoded_without->front().pixels);

  options.codec_options["x264"] = {{"no-such-option", "1"}};
  auto unknown = make_plan("x264", options, 64, 64);
  ASSERT_TRUE(unknown.ok());
  auto failed = encode(*unknown);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.status().message().find("no-such-option"), std::string::npos) << failed.status().to_string();

  options.codec_options = {{"svc", {{"x", "1"}}}};
  EXPECT_EQ(make_plan("svc", options, 64, 64).status().code(), ErrorCode::kInvalidArgument);
}

INSTANTIATE_TEST_SUITE_P(Anchors, BenchAnchorCliTest,
                         ::testing::Values("x264", "x265", "x265-ra", "av1", "av1-slow", "av1-svt-slow", "jpeg",
                                           "webp", "jxl", "avif", "x265-intra"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace svc::bench
