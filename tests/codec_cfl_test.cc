// SPDX-License-Identifier: BSD-2-Clause
// Chroma from luma: the prediction against its definition (docs/codec.md 3.3), the mode
// syntax for every mode and alpha, and intra frames whose chroma follows their luma.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "codec/common/cfl.h"
#include "codec/common/intra_frame.h"
#include "codec/decoder/intra_decoder.h"
#include "codec/decoder/intra_syntax_reader.h"
#include "codec/decoder/range_decoder.h"
#include "codec/encoder/intra_encoder.h"
#include "codec/encoder/intra_syntax_writer.h"
#include "codec/encoder/range_encoder.h"

namespace svc::codec {
namespace {

TEST(Cfl, PredictionFollowsItsDefinition) {
  std::mt19937 rng(3);
  std::vector<uint8_t> luma(16 * 24);
  for (int n = 0; n < 200; ++n) {
    for (uint8_t& v : luma) v = static_cast<uint8_t>(n % 3 == 0 ? (rng() % 2) * 255 : rng() % 256);
    const int x0 = 0, y0 = 0, stride = 24;
    int16_t ac[64];
    cfl_luma_ac(luma.data(), stride, x0, y0, ac);
    int sums[64], total = 0;
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 8; ++x) {
        const uint8_t* p = luma.data() + 2 * y * stride + 2 * x;
        sums[8 * y + x] = p[0] + p[1] + p[stride] + p[stride + 1];
        total += sums[8 * y + x];
      }
    }
    const int mean = (total + 32) / 64;  // total >= 0: the shift of the definition
    const int dc = static_cast<int>(rng() % 256), alpha = static_cast<int>(rng() % 33) - 16;
    uint8_t prediction[64];
    predict_cfl(ac, dc, alpha, prediction);
    for (int i = 0; i < 64; ++i) {
      ASSERT_EQ(ac[i], sums[i] - mean);
      const int scaled = static_cast<int>(std::floor((alpha * ac[i] + 16) / 32.0));
      ASSERT_EQ(prediction[i], std::clamp(dc + scaled, 0, 255)) << "alpha " << alpha << ", sample " << i;
    }
  }
}

TEST(Cfl, ModeByteCarriesTheAlpha) {
  for (int alpha = -kCflMaxAlpha; alpha <= kCflMaxAlpha; ++alpha) {
    const ChromaMode mode{kCflMode, alpha};
    EXPECT_TRUE(is_cfl_mode_byte(mode.mode_byte()));
    EXPECT_EQ(cfl_alpha_of_mode_byte(mode.mode_byte()), alpha);
  }
  for (int regular = 0; regular < kIntraModes; ++regular) EXPECT_FALSE(is_cfl_mode_byte(regular));
  EXPECT_FALSE(is_cfl_mode_byte(kCflMode + 2 * kCflMaxAlpha + 1));
}

// Every Cb mode (the 35 regular ones, CfL at every non-zero alpha) and every Cr alpha
// after every Cb alpha sign decode as written, and the estimated bits are near the
// coded ones.
TEST(Cfl, ChromaModesRoundTrip) {
  std::vector<std::pair<ChromaMode, ChromaMode>> blocks;  // (Cb, Cr)
  for (int mode = 0; mode < kIntraModes; ++mode) blocks.push_back({{mode, 0}, {mode, 0}});
  for (int cb = -kCflMaxAlpha; cb <= kCflMaxAlpha; ++cb) {
    if (cb == 0) continue;
    for (int cr = -kCflMaxAlpha; cr <= kCflMaxAlpha; cr += 3) blocks.push_back({{kCflMode, cb}, {kCflMode, cr}});
  }
  const ModeCandidates candidates = most_probable_modes(kPlanarMode, kPlanarMode);
  std::vector<uint8_t> bytes;
  RangeEncoder encoder(&bytes);
  CflContexts cfl;
  IntraModeContexts modes;
  for (size_t i = 0; i < blocks.size(); ++i) {
    const int context = static_cast<int>(i % 3);
    encode_chroma_mode(encoder, cfl, modes, context, candidates, ChromaPlane::kCb, {}, blocks[i].first);
    encode_chroma_mode(encoder, cfl, modes, context, candidates, ChromaPlane::kCr, blocks[i].first,
                       blocks[i].second);
  }
  encoder.finish();
  RangeDecoder decoder(bytes);
  CflContexts read_cfl;
  IntraModeContexts read_modes;
  for (size_t i = 0; i < blocks.size(); ++i) {
    const int context = static_cast<int>(i % 3);
    const ChromaMode cb =
        decode_chroma_mode(decoder, read_cfl, read_modes, context, candidates, ChromaPlane::kCb, {});
    const ChromaMode cr =
        decode_chroma_mode(decoder, read_cfl, read_modes, context, candidates, ChromaPlane::kCr, cb);
    ASSERT_EQ(cb.mode, blocks[i].first.mode) << i;
    ASSERT_EQ(cb.alpha, blocks[i].first.alpha) << i;
    ASSERT_EQ(cr.mode, blocks[i].second.mode) << i;
    ASSERT_EQ(cr.alpha, blocks[i].second.alpha) << i;
  }
  EXPECT_LE(decoder.overrun(), kImplicitZeroBytes);  // the final zeros left out
  const CflContexts fresh;
  EXPECT_NEAR(cfl_alpha_bits(fresh, ChromaPlane::kCr, 1, 0), 1.0, 0.01);
  EXPECT_NEAR(cfl_alpha_bits(fresh, ChromaPlane::kCb, 0, -2), 3.0, 0.03);  // sign, two magnitude bins
}

// A 96x64 frame whose chroma is a linear function of its textured luma (opposite signs
// in Cb and Cr): CfL predicts it where no spatial mode can, the encoder uses it, and the
// decoder reproduces the encoder's reconstruction; without the tool no block uses it and
// the frame costs more at a worse chroma error.
TEST(Cfl, EncoderUsesCflForChromaThatFollowsLuma) {
  ImageYCbCr420 image;
  image.width = 96;
  image.height = 64;
  std::mt19937 rng(5);
  image.y.resize(96 * 64);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 96; ++x) {
      image.y[static_cast<size_t>(96 * y + x)] =
          static_cast<uint8_t>(128 + 50 * std::sin(x * 0.7) * std::cos(y * 0.5) + rng() % 5);
    }
  }
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 48; ++x) {
      const uint8_t* p = image.y.data() + 2 * y * 96 + 2 * x;
      const double mean = (p[0] + p[1] + p[96] + p[97]) / 4.0 - 128;
      image.cb.push_back(static_cast<uint8_t>(std::lround(120 + 0.75 * mean)));
      image.cr.push_back(static_cast<uint8_t>(std::lround(140 - 0.5 * mean)));
    }
  }
  size_t sizes[2] = {};
  double chroma_error[2] = {};
  for (bool cfl : {true, false}) {
    CodingParams params;
    params.qindex = 120;
    params.cfl = cfl;
    ImageYCbCr420 reconstruction, decoded;
    const auto bytes = encode_intra_frame(image, params, &reconstruction);
    CoefficientFrame parsed;
    ASSERT_TRUE(parse_intra_frame(bytes, image.width, image.height, &parsed).ok());
    reconstruct_intra_frame(parsed, &decoded);
    EXPECT_TRUE(decoded.y == reconstruction.y && decoded.cb == reconstruction.cb &&
                decoded.cr == reconstruction.cr);
    const size_t chroma_blocks = 2 * 6 * 4, first = parsed.block_modes.size() - chroma_blocks;
    const auto cfl_blocks = std::count_if(parsed.block_modes.begin() + static_cast<ptrdiff_t>(first),
                                          parsed.block_modes.end(),
                                          [](uint8_t mode) { return is_cfl_mode_byte(mode); });
    if (cfl) {
      EXPECT_GE(cfl_blocks, static_cast<ptrdiff_t>(chroma_blocks / 2));
    } else {
      EXPECT_EQ(cfl_blocks, 0);
    }
    sizes[cfl ? 0 : 1] = bytes.size();
    for (size_t i = 0; i < image.cb.size(); ++i) {
      chroma_error[cfl ? 0 : 1] +=
          std::pow(image.cb[i] - decoded.cb[i], 2.0) + std::pow(image.cr[i] - decoded.cr[i], 2.0);
    }
  }
  EXPECT_LT(sizes[0], sizes[1]);
  EXPECT_LE(chroma_error[0], chroma_error[1] * 1.5);
}

// Mode bytes a parser never produces (CfL on luma, bytes past the CfL range) give some
// pixels, never a crash.
TEST(Cfl, ReconstructionToleratesForeignModeBytes) {
  ImageYCbCr420 image;
  image.width = image.height = 32;
  image.y.assign(32 * 32, 90);
  image.cb.assign(16 * 16, 100);
  image.cr.assign(16 * 16, 160);
  CodingParams params;
  const auto bytes = encode_intra_frame(image, params, nullptr);
  CoefficientFrame parsed;
  ASSERT_TRUE(parse_intra_frame(bytes, 32, 32, &parsed).ok());
  for (uint8_t byte : {uint8_t{kCflMode}, uint8_t{67}, uint8_t{68}, uint8_t{255}}) {
    CoefficientFrame damaged = parsed;
    std::fill(damaged.block_modes.begin(), damaged.block_modes.end(), byte);
    ImageYCbCr420 out;
    reconstruct_intra_frame(damaged, &out);
    EXPECT_EQ(out.y.size(), image.y.size());
    EXPECT_EQ(out.cb.size(), image.cb.size());
  }
}

}  // namespace
}  // namespace svc::codec
